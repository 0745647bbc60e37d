"""The wheel-model registry (interaction/wheel_models.py, the models' code in fe/wheel_models.py): the paper's three models registered once, and a
fourth joining with one ``register`` call, through the schema, the wheel-greens stage, a case,
the report and the exports, without a change anywhere else."""

from __future__ import annotations

import dataclasses

import h5py
import numpy as np
import pytest

import interaction.wheel_models as registry
import pipeline
from fe.greens import modal_poles_residues
from interaction.wheel_models import REFERENCE, WheelModel, register, rotating_names, wheel_model, wheel_model_names
from interaction.params import SimulationParams
from squealcore.errors import InputError


def test_the_papers_three_models_with_the_reference_first():
    assert wheel_model_names() == ("stationary", "moving_load", "eulerian")
    assert REFERENCE == "stationary" and not wheel_model(REFERENCE).rotating
    assert rotating_names() == ("moving_load", "eulerian")
    with pytest.raises(ValueError, match="registered already"):
        register(wheel_model("eulerian"))
    with pytest.raises(KeyError, match="known: stationary, moving_load, eulerian"):
        wheel_model("rigid")


def _doubly_damped(state):
    """A toy model: the wheel at rest with twice its modal damping."""
    return modal_poles_residues(state.frequency, 2.0 * np.asarray(state.damping_ratio), state.contact_shape)


@pytest.fixture
def toy_model():
    """A fourth wheel model, registered for the test and removed after it."""
    model = register(WheelModel("doubly_damped", "stationary wheel, damping doubled", "damping x 2", False,
                                _doubly_damped, curve_style=dict(color="tab:green", ls=":", label="damping x 2"),
                                spectrum_style=("tab:green", "-."), receptance_style=dict(color="tab:green")))
    yield model
    del registry._REGISTRY[model.name]


def test_a_registered_model_is_a_choice_of_the_study(toy_model):
    assert SimulationParams.from_mapping({"wheel_model": "doubly_damped"}).wheel_model == "doubly_damped"
    with pytest.raises(InputError, match="doubly_damped"):  # the message lists it among the choices
        SimulationParams.from_mapping({"wheel_model": "undamped"})


def test_a_fourth_model_runs_through_the_pipeline(toy_model, tmp_path, copy_quick_structures):
    # The quick structures, one case of the toy model (0.1 s): its group in wheel_greens.h5 is
    # the stationary model's poles with twice the decay rate (an independent check: Re p = -ζω,
    # Im p unchanged to first order, here exactly sqrt(1 - 4ζ²) ω), the case runs, the report
    # and summary name it, and the receptance export writes it.
    # The engine runs in this process (the CLI's `run` puts cases in a spawned worker, which
    # imports the registry afresh: a model for the CLI is registered in interaction/wheel_models.py).
    from stages import engine
    from stages.config import load_study
    study_file = tmp_path / "toy.toml"
    study_file.write_text('[time]\nduration = 0.1\n\n[sweep]\n"contact.lateral_creepage" = [-0.015]\n'
                          '"simulation.wheel_model" = ["stationary", "doubly_damped"]\n')
    out = copy_quick_structures(tmp_path / "out")
    (out / "wheel_greens.h5").unlink()  # rebuilt with the registry's four models; mesh, modes and rail reused
    engine.run(load_study(study_file, quick=True), out, progress=False)
    with h5py.File(out / "wheel_greens.h5", "r") as f:
        toy = f["doubly_damped/poles"][()]
        stationary = f["stationary/poles"][()]
        assert f["doubly_damped"].attrs["time_stepping"] == "recursion"
    assert toy.shape == stationary.shape
    assert np.allclose(toy.real, 2.0 * stationary.real, rtol=1e-12)
    omega = np.abs(stationary)  # the undamped natural frequency of each pole
    zeta = -stationary.real / omega
    assert np.allclose(toy.imag, omega * np.sqrt(1.0 - 4.0 * zeta**2), rtol=1e-12)
    summary = (out / "summary.csv").read_text()
    assert "wheel_model=doubly_damped" in summary
    assert "doubly_damped" in (out / "report.md").read_text()
    assert pipeline.main(["export", "receptances", "--quick", "--config", str(study_file), "--out", str(out), "-q"]) == 0
    assert any("doubly_damped" in p.name for p in (out / "exports").iterdir())


def test_the_state_rebuilds_every_model_at_another_spin(tmp_path):
    # read_wheel_state gives back what the models were built from: at the artefact's own spin the
    # rotating models' poles are those the stage wrote (the exact moving-load path, the Eulerian
    # model), so the report's Campbell diagram can rebuild any model at any speed.
    from stages.wheel import read_wheel_state
    out = tmp_path / "out"
    assert pipeline.main(["run", "--quick", "--out", str(out), "--until", "wheel-greens", "-q"]) == 0
    with h5py.File(out / "wheel_greens.h5", "r") as f:
        state = read_wheel_state(f)
        written = {name: f[f"{name}/poles"][()] for name in wheel_model_names()}
    for name in rotating_names():
        rebuilt = wheel_model(name).poles_residues(state)[0]
        assert np.allclose(np.sort_complex(rebuilt), np.sort_complex(written[name]), rtol=1e-12)
    slower = wheel_model("eulerian").poles_residues(dataclasses.replace(state, spin=0.0))[0]
    at_rest = wheel_model(REFERENCE).poles_residues(state)[0]
    assert np.allclose(np.sort(np.abs(slower.imag)), np.sort(np.abs(at_rest.imag)), rtol=1e-9)
