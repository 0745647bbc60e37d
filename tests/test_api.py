"""The Python API (``curve_squeal``): each function against what it wraps, its errors, and the
runnable scripts of ``examples/`` (run as scikit-fem runs its examples)."""

from __future__ import annotations

import csv
import json
import runpy
import sys
from pathlib import Path

import numpy as np
import pytest

import curve_squeal as cs
from interaction.wheel_models import REFERENCE
from stages import config
from exports.case import read_histories
from stages.folder import FolderLock, read_record
from stages.summary import read_case_summary
from stages.wheel import read_greens

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "examples"


# --------------------------------------------------------------------------- load_study


def test_load_study_is_the_command_lines_study():
    """Overrides as Python values give the study of the same --set assignments, and remember them."""
    study = cs.load_study(quick=True, overrides={"contact.friction": 0.5, "contact.model": "halfspace",
                                                 "simulation.write_wav": False, "track.max_frequency": 2500,
                                                 "sweep.contact.lateral_creepage": np.array([-0.01, -0.02])})
    assignments = ["contact.friction=0.5", 'contact.model="halfspace"', "simulation.write_wav=false",
                   "track.max_frequency=2500", 'sweep."contact.lateral_creepage"=[-0.01, -0.02]']
    assert study == config.load_study(quick=True, assignments=assignments)
    assert isinstance(study, dict) and not study.edited
    assert study.given["quick"] is True and study.given["config"] is None
    assert study.given["set"][0] == "contact.friction=0.5"
    assert cs.load_study() == config.load_study()


def test_load_study_errors_name_the_field(tmp_path):
    with pytest.raises(cs.InputError) as info:
        cs.load_study(overrides={"contact.friction": -1.0})
    assert info.value.field == "contact.friction"
    with pytest.raises(cs.InputError, match="unknown key"):
        cs.load_study(overrides={"contact.no_such_key": 1})
    with pytest.raises(cs.InputError) as info:
        cs.load_study(overrides={"contact.friction": object()})
    assert info.value.field == "contact.friction"
    with pytest.raises(cs.InputError, match="dotted keys"):
        cs.load_study(overrides={"contact.friction=0.5": 1})
    with pytest.raises(cs.InputError, match="mapping"):
        cs.load_study(overrides=["contact.friction=0.5"])
    with pytest.raises(cs.InputError, match="file not found"):
        cs.load_study(tmp_path / "missing.toml")


# --------------------------------------------------------------------------- run


def test_run_records_the_study_and_refuses_another(tmp_path, copy_quick_structures):
    """run behaves like ``pipeline.py run``: the folder records its study, another one is refused
    (unless change_study), and a folder another run holds is busy."""
    out = copy_quick_structures(tmp_path / "out")
    study = cs.load_study(quick=True)
    assert cs.run(study, out, until="rail-greens") == []  # the copied artefacts are fresh
    record = read_record(out)
    assert record["given"] == study.given and record["study"] == json.loads(json.dumps(study))
    assert cs.study_of(out) == study

    other = cs.load_study(quick=True, overrides={"contact.friction": 0.5})
    with pytest.raises(cs.InputError, match="holds another study.*contact.friction is 0.3 there, 0.5 here") as info:
        cs.run(other, out, until="rail-greens")
    assert info.value.field == "out"
    assert read_record(out) == record
    assert cs.run(other, out, until="rail-greens", change_study=True) == []
    assert read_record(out)["study"]["contact"]["friction"] == 0.5

    edited = cs.study_of(out)
    edited["contact"]["friction"] = 0.4  # an edited study is validated and recorded, how it was given unknown
    cs.run(edited, out, until="contact-geometry", change_study=True)
    assert read_record(out)["given"] is None and cs.study_of(out)["contact"]["friction"] == 0.4
    edited["contact"]["friction"] = 7.0
    with pytest.raises(cs.InputError) as info:
        cs.run(edited, out, until="contact-geometry", change_study=True)
    assert info.value.field == "contact.friction"

    with FolderLock(out, "another run"):
        with pytest.raises(cs.FolderBusy, match="another run holds this folder"):
            cs.run(cs.study_of(out), out, until="contact-geometry")
    assert not (out / ".lock").exists()


def test_run_argument_errors(tmp_path):
    study = cs.load_study(quick=True)
    for kwargs, field in (({"jobs": 0}, "jobs"), ({"jobs": 1.5}, "jobs"), ({"until": "nope"}, "until")):
        with pytest.raises(cs.InputError) as info:
            cs.run(study, tmp_path / "out", **kwargs)
        assert info.value.field == field
    (tmp_path / "file").write_text("x")
    with pytest.raises(cs.InputError, match="is a file"):
        cs.run(study, tmp_path / "file")
    with pytest.raises(cs.InputError, match="must be a study"):
        cs.run(["not", "a", "study"], tmp_path / "out")
    assert not (tmp_path / "out").exists()  # nothing written before the checks


# --------------------------------------------------------------------------- results of the quick study


def _summary_csv(path):
    lines = [line for line in path.read_text(encoding="utf-8").splitlines() if not line.startswith("#")]
    return list(csv.DictReader(lines))


def test_summary_is_summary_csv(quick_run):
    rows = cs.summary(quick_run)
    table = _summary_csv(quick_run / "summary.csv")
    assert [row["case_id"] for row in rows] == [row["case_id"] for row in table]
    for row, line in zip(rows, table):
        assert list(row) == list(line)
        assert {k: f"{v:.6g}" if isinstance(v, float) else str(v) for k, v in row.items()} == line
        assert isinstance(row["L_F2"], float) and isinstance(row["squeal"], bool)
    assert any(row["squeal"] for row in rows)  # the quick study names its squealing case
    assert repr(cs.summary(quick_run, study=cs.study_of(quick_run))) == repr(rows)  # (NaN != NaN)


def test_summary_as_frame(quick_run):
    pandas = pytest.importorskip("pandas")
    frame = cs.summary(quick_run, as_frame=True)
    assert isinstance(frame, pandas.DataFrame) and len(frame) == len(cs.summary(quick_run))
    assert frame.attrs["units"]["L_F2"] == "dB re 1 N"


def test_read_case_is_the_case_artefact(quick_run):
    study = cs.study_of(quick_run)
    for row in cs.summary(quick_run):
        case = cs.read_case(quick_run, row["case_id"])
        path = quick_run / "cases" / f"{row['case_id']}.h5"
        data, _ = read_histories(path)
        assert np.array_equal(case.time, data["time"]) and np.array_equal(case.force, data["force"])
        assert np.array_equal(case.creepage, data["creepage"])
        assert np.array_equal(case.wheel_velocity, data["wheel/velocity"])
        assert np.array_equal(case.rail_displacement, data["rail/displacement"])
        assert case.force.shape == (case.time.size, 3) and not case.force.flags.writeable
        assert repr(dict(case.summary)) == repr(read_case_summary(path, study["simulation"]))
        assert case.L_F2 == row["L_F2"] and case.squeal == row["squeal"]
        assert case.time_step == pytest.approx(study["time"]["time_step"])
        assert case.verdict.startswith("quiet" if row["oscillation"] == "none" else row["oscillation"])


def test_read_case_and_summary_errors(quick_run, tmp_path):
    with pytest.raises(cs.InputError, match="its cases: friction=") as info:
        cs.read_case(quick_run, "no-such-case")
    assert info.value.field == "case_id"
    with pytest.raises(cs.InputError):
        cs.read_case(quick_run, "../study")
    with pytest.raises(cs.InputError, match="no such study folder") as info:
        cs.read_case(tmp_path / "missing", "x")
    assert info.value.field == "out"
    with pytest.raises(cs.InputError, match="no study record"):
        cs.summary(tmp_path)
    assert cs.summary(tmp_path, study=cs.load_study(quick=True)) == []  # nothing simulated yet
    with pytest.raises(cs.InputError, match="none \\(run the study first\\)"):
        cs.read_case(tmp_path, "x")


def test_read_wheel_is_read_greens(quick_structures, tmp_path):
    path = quick_structures / "wheel_greens.h5"
    for model in cs.wheel_model_names():
        wheel = cs.read_wheel(quick_structures, model)
        greens = read_greens(path, model)
        assert wheel.model == model and wheel.spin == greens["spin"] and wheel.time_step == greens["time_step"]
        for name in ("poles", "residues", "contact_shape", "frequency", "receptance", "kernel"):
            assert np.array_equal(getattr(wheel, name), greens[name]), name
            assert not getattr(wheel, name).flags.writeable
    assert cs.read_wheel(quick_structures).model == REFERENCE
    with pytest.raises(cs.InputError) as info:
        cs.read_wheel(quick_structures, "no_such_model")
    assert info.value.field == "model"
    with pytest.raises(cs.InputError) as info:
        cs.read_wheel(quick_structures, variant="nope")
    assert info.value.field == "variant"
    with pytest.raises(cs.ArtefactError):
        cs.read_wheel(tmp_path)  # not built


# --------------------------------------------------------------------------- the examples


def _run_example(name, argv, monkeypatch):
    monkeypatch.setattr(sys, "argv", [str(EXAMPLES / name), *argv])
    runpy.run_path(str(EXAMPLES / name), run_name="__main__")


def test_example_quick_study(tmp_path, copy_quick_structures, monkeypatch, capsys):
    """examples/quick_study.py on the quick study's structures, with short cases."""
    out = copy_quick_structures(tmp_path / "out")
    _run_example("quick_study.py", ["--out", str(out), "--duration", "0.2"], monkeypatch)
    lines = capsys.readouterr().out.splitlines()
    cases = [line for line in lines if "L_F2 =" in line]
    assert len(cases) == 6 and all(line.split()[0] in cs.wheel_model_names() for line in cases)
    assert (out / "summary.csv").is_file() and read_record(out)["given"]["set"] == ["time.duration=0.2"]


def test_example_receptance(quick_structures, monkeypatch, capsys):
    """examples/receptance.py on the quick study's wheel: the first peaks of every wheel model."""
    _run_example("receptance.py", ["--out", str(quick_structures), "--peaks", "3"], monkeypatch)
    text = capsys.readouterr().out
    assert all(f"{model} (spin" in text for model in cs.wheel_model_names())
    assert text.count("|H_yy|") == 3 * len(cs.wheel_model_names())


@pytest.mark.slow
@pytest.mark.parametrize("name", ["quick_study.py", "receptance.py"])
def test_example_runs_as_a_script(name, tmp_path):
    """Each example as a user runs it: its own process, its own temporary folder (about a minute each)."""
    import subprocess
    result = subprocess.run([sys.executable, str(EXAMPLES / name)], cwd=tmp_path, capture_output=True, text=True,
                            check=False, timeout=900)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip()
