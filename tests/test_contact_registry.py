"""The contact-model registry (contact/registry.py): the two models registered once, and
a toy third one — a linear creep law without saturation — registered in this file only, running in
a study, the stability screen and ``export case`` without a change anywhere else."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

import contact.registry as registry
import pipeline
from contact.factory import create_model
from contact.kalker import creep_coefficients
from contact.model import ContactResult, Diagnostics
from contact.params import ContactParams
from contact.registry import ContactModelSpec, contact_model_names, contact_spec, register
from squealcore.errors import InputError
from stability.linearised_contact import LinearisedContact


def test_the_two_models_and_their_capabilities():
    assert contact_model_names() == ("halfspace", "point")
    assert contact_spec("halfspace").traction_fields and contact_spec("halfspace").solves_on_grid
    assert not contact_spec("point").traction_fields and contact_spec("point").fast
    assert "shift" in contact_spec("halfspace").kinds and "shift" not in contact_spec("point").kinds
    with pytest.raises(InputError, match="contact.model.*'halfspace', 'point'.*'rigid'"):
        contact_spec("rigid")
    with pytest.raises(ValueError, match="registered already"):
        register(contact_spec("point"))
    with pytest.raises(InputError, match="model"):
        create_model("rigid")


class LinearCreep:
    """A toy contact model: Hertz's normal spring and Kalker's linear creep law, never saturated
    (so it is not a friction law: a test model only)."""

    def __init__(self, setup):
        self.hertz = setup.hertz
        self.time_step = setup.time_step
        self.shear_modulus = setup.material.shear_modulus
        self.c11, self.c22, _ = creep_coefficients(setup.hertz.a / setup.hertz.b, setup.material.poisson_ratio)

    def initial_state(self):
        return None

    def force(self, normal_force, creepage):
        """(Fx, Fy) of the linear law at a normal force (N) and creepages (ξ, η, φ)."""
        h = self.hertz.scaled(normal_force)
        gab = self.shear_modulus * h.a * h.b
        return -gab * self.c11 * creepage[0], -gab * self.c22 * creepage[1]

    def solve(self, state, *, approach=None, normal_force=None, creepage=(0.0, 0.0, 0.0), shift=None):
        if normal_force is None:
            normal_force = self.hertz.normal_force * (max(approach, 0.0) / self.hertz.approach) ** 1.5
        delta = self.hertz.scaled(normal_force).approach if normal_force > 0 else 0.0
        fx, fy = self.force(normal_force, creepage) if normal_force > 0 else (0.0, 0.0)
        diagnostics = Diagnostics(1, 1, 0, 0.0, 1, 0.0, 0.0, delta)
        return ContactResult(np.array([fx, fy, normal_force]), 0.0, None, diagnostics)


def _linearised(setup, normal_force, creepage):
    model = LinearCreep(setup)
    gab = model.shear_modulus * model.hertz.scaled(normal_force).a * model.hertz.scaled(normal_force).b
    approach = model.hertz.scaled(normal_force).approach
    # dFy/dFz at constant creepage: G a b ∝ Fz^(2/3)
    mu_s = (2.0 / 3.0) * model.force(normal_force, creepage)[1] / normal_force
    return LinearisedContact(1.5 * normal_force / approach, mu_s, (gab * model.c11, gab * model.c22), None, 0.0)


@pytest.fixture
def linear_creep():
    spec = register(ContactModelSpec("linear_creep", "toy: Kalker's linear creep law without saturation.",
                                     model_class=LinearCreep, build=LinearCreep, linearise=_linearised,
                                     command=lambda setup, grid, gap, kind: LinearCreep(setup)))
    yield spec
    del registry._REGISTRY[spec.name]


def test_a_toy_model_runs_in_a_study_the_screen_and_export_case(linear_creep, tmp_path, copy_quick_structures):
    # One case of the quick structures with the toy model (in this process: the CLI's `run` puts
    # cases in a spawned worker, which imports the registry afresh — a model for the CLI is
    # registered in contact/registry.py). Independent check: at every step the force
    # is the linear law (written here) at that step's normal force and total creepage, and it
    # grows beyond the friction bound μQ that the paper's models would cap it at.
    from stages import engine
    from stages.cases import contact_setup
    from stages.config import load_study
    from stages.screen import linear_contact

    assert ContactParams.from_mapping({"model": "linear_creep"}, "contact").model == "linear_creep"
    study_file = tmp_path / "toy.toml"
    study_file.write_text('[time]\nduration = 0.05\n\n[contact]\nmodel = "linear_creep"\nfriction = 0.3\n\n'
                          '[sweep]\n"contact.lateral_creepage" = [-0.01]\n"simulation.wheel_model" = ["stationary"]\n')
    study = load_study(study_file, quick=True)
    out = copy_quick_structures(tmp_path / "out")  # the quick structures: only the case is built here
    engine.run(study, out, progress=False)
    (case,) = list((out / "cases").glob("*.h5"))
    with h5py.File(case, "r") as f:
        force, creepage = f["force"][()], f["creepage"][()]
    law = LinearCreep(contact_setup(study))
    expected = np.array([law.force(fz, c) for fz, c in zip(force[:, 2], creepage)])
    # the recorded creepage is that of the converged force, the force the law's value one coupling
    # iteration earlier: they differ by the coupling tolerance (1e-6 Q) times the loop gain, which
    # this stiff unsaturated law makes large (measured 2e-5 of the largest force)
    assert np.abs(force[:, :2] - expected).max() <= 1e-4 * np.abs(expected).max()
    assert np.abs(force[:, 1]).max() > 0.3 * force[0, 2]  # unsaturated: beyond μ Q
    linear = linear_contact(study)  # the screen's linearisation through the registry
    assert linear.creep_stiffness[1] > 0 and math.isfinite(linear.normal_stiffness)
    # export case: the histories export; a traction field is refused by the capability, naming the models that have one
    assert pipeline.main(["export", "case", "--config", str(study_file), "--quick", "--out", str(out),
                          "--case", case.stem, "--dir", str(tmp_path / "exported"), "-q"]) == 0
    assert any((tmp_path / "exported").iterdir())
    assert pipeline.main(["export", "case", "--config", str(study_file), "--quick", "--out", str(out),
                          "--case", case.stem, "--steps", "10", "-q"]) == 2
