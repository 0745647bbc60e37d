"""The ``radiation`` stage on the quick study: artefacts, WAV, summary columns, report section,
figure, and the energy bookkeeping on a squealing case. Slow (runs two quick cases: about a
minute on an idle machine): ``pytest -m slow tests/test_radiation_stage.py``."""

import math

import h5py
import numpy as np
import pytest

import pipeline
from interaction.frame import to_contact_frame
from radiation.plots import plot_band_spectra
from stages.radiation_report import radiation_section
from radiation.wheel_vibration import contact_response
from stages.radiation import radiation_levels, read_radiation
from stages.wheel import read_greens

pytestmark = pytest.mark.slow

SWEEP = """
[sweep]
"contact.friction" = [0.6]
"contact.lateral_creepage" = [-0.01]
"simulation.wheel_model" = ["stationary", "eulerian"]
"""


@pytest.fixture(scope="module")
def study(copy_quick_structures, tmp_path_factory):
    root = tmp_path_factory.mktemp("radiation")
    config = root / "study.toml"
    config.write_text(SWEEP)
    out = copy_quick_structures(root / "out")  # the quick study's structures: fresh for this sweep
    assert pipeline.main(["run", "--quick", "--quiet", "--config", str(config), "--out", str(out),
                          "--until", "radiation"]) == 0
    return out


def test_every_case_has_its_radiation_and_the_squealing_one_its_receiver_wav(study):
    cases = sorted((study / "cases").glob("*.h5"))
    assert len(cases) == 2
    for case in cases:
        levels = read_radiation(study / "radiation" / case.name)
        columns = radiation_levels(case)
        assert set(columns) == {"L_W", "L_pA"} and all(math.isfinite(v) for v in columns.values())
        assert columns["L_W"] == pytest.approx(levels["L_W"])
        with h5py.File(case, "r") as f:
            if f.attrs["squeal"]:
                assert (study / "sounds" / f"{case.stem}_receiver.wav").stat().st_size > 1000


def test_a_squealing_wheel_radiates_less_than_the_contact_puts_in(study):
    for case in sorted((study / "cases").glob("*.h5")):
        levels = read_radiation(study / "radiation" / case.name)
        with h5py.File(case, "r") as f:
            squeal = bool(f.attrs["squeal"])
        if squeal:
            assert 0.0 < levels["wheel_power"] <= levels["input_power"]


def test_the_poles_reproduce_the_stored_contact_displacement(study):
    case = next(p for p in sorted((study / "cases").glob("*.h5")) if "stationary" in p.name)
    with h5py.File(case, "r") as f:
        # the case's contact: its wheel model at that point, in its frame inclined by its angle,
        # forces as deviations from its static normal force
        geometry, angle = str(f.attrs["contact_geometry"]), float(f.attrs["contact_angle"])
        force = f["force"][:] - np.array([0.0, 0.0, float(f.attrs["normal_force"])])
        stored = f["wheel/displacement"][:]
    wheel = read_greens(study / "wheel_greens.h5", "stationary", geometry)
    residues = to_contact_frame(wheel["residues"], angle)
    got = contact_response(wheel["poles"], residues, force, wheel["time_step"], quantity="displacement")
    assert np.max(np.abs(got - stored)) <= 1e-9 * np.max(np.abs(stored))


def test_report_section_and_figure(study, tmp_path):
    paths = sorted((study / "radiation").glob("*.h5"))
    text = radiation_section(paths)
    assert "## Radiated sound" in text and "eulerian" in text and "ΔL_pA" in text
    figure = plot_band_spectra([read_radiation(p) for p in paths], tmp_path / "spectra.png")
    assert figure.stat().st_size > 10000
