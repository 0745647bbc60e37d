"""Sweeps: case ids that cannot collide, duplicate values refused, what a case reports back."""

import dataclasses
import hashlib
import json
import math
import os
import subprocess
import sys
import wave
from pathlib import Path

import h5py
import pytest

import interaction.metrics
import pipeline
from stages import engine
from squealcore.artefacts import params_hash
from squealcore.errors import InputError
from squealcore.study import get_section
from stages.cases import CASE_SECTIONS, execute_case, expand_sweep, make_case_id
from stages.config import load_study

ROOT = Path(__file__).resolve().parent.parent


def _sweep_study(tmp_path, body):
    config = tmp_path / "sweep.toml"
    config.write_text("[sweep]\n" + body)
    study = load_study(config, quick=True)
    expand_sweep(study)  # the sweep is checked when the cases are planned
    return study


def test_values_alike_in_the_label_get_distinct_ids(tmp_path):
    study = _sweep_study(tmp_path, '"contact.friction" = [0.3, 0.3000001]\n')
    (first, _), (second, _) = expand_sweep(study)
    assert first.startswith("friction=0.3-") and second.startswith("friction=0.3-")  # same readable label
    assert first != second
    assert len({c.case_id for c in engine.plan_cases(study, tmp_path / "o")}) == 2


def test_case_id_follows_its_documented_rule():
    # label, "-", first 8 hex digits of the SHA-256 of the canonical JSON of the exact values
    # (computed here from the rule, independently of the implementation)
    overrides = {"contact.friction": 0.3, "contact.lateral_creepage": -0.01, "simulation.wheel_model": "stationary"}
    text = json.dumps(overrides, sort_keys=True, separators=(",", ":"))
    expected = ("friction=0.3_lateral_creepage=-0.01_wheel_model=stationary-"
                + hashlib.sha256(text.encode()).hexdigest()[:8])
    assert make_case_id(overrides) == expected
    assert make_case_id(dict(reversed(list(overrides.items())))) == expected  # order of the keys does not matter
    assert make_case_id({"contact.friction": 1}) == make_case_id({"contact.friction": 1.0})  # one value, one id
    assert make_case_id({}).startswith("base-")


def test_case_ids_are_stable_across_processes(tmp_path):
    study = load_study(quick=True)
    here = [cid for cid, _ in expand_sweep(study)]
    code = ("from stages.cases import expand_sweep\nfrom stages.config import load_study\n"
            "print('\\n'.join(c for c, _ in expand_sweep(load_study(quick=True))))")
    ids = set()
    for seed in ("1", "2"):
        completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path,
                                   check=True, env={**os.environ, "PYTHONPATH": str(ROOT), "PYTHONHASHSEED": seed})
        ids.add(tuple(completed.stdout.split()))
    assert ids == {tuple(here)}


def test_long_labels_are_cut_but_stay_distinct():
    long_a = {f"wheel.key_{i}": "x" * 40 for i in range(10)}
    long_b = dict(long_a, **{"wheel.key_9": "y" * 40})
    assert make_case_id(long_a) != make_case_id(long_b)
    assert len(make_case_id(long_a).encode()) < 200  # file names of cases/<id>.h5 and their temporaries fit


@pytest.mark.parametrize("values, shown", [("[0.3, 0.6, 0.3]", "0.3"), ("[1, 1.0]", "1.0"), ("[-0.0, 0.0]", "0.0")])
def test_duplicate_numbers_are_refused(tmp_path, values, shown):
    with pytest.raises(InputError) as err:
        _sweep_study(tmp_path, f'"contact.friction" = {values}\n')
    assert err.value.field == "sweep.contact.friction"
    assert "twice" in err.value.message and shown in err.value.message


def test_duplicate_words_are_refused_and_a_bad_sweep_exits_2(tmp_path, capsys):
    with pytest.raises(InputError) as err:
        _sweep_study(tmp_path, '"simulation.wheel_model" = ["stationary", "eulerian", "stationary"]\n')
    assert err.value.field == "sweep.simulation.wheel_model"
    assert "items 1 and 3" in err.value.message
    config = tmp_path / "dup.toml"
    config.write_text('[sweep]\n"contact.lateral_creepage" = [-0.01, -0.01]\n')
    out = tmp_path / "never"
    assert pipeline.main(["run", "--quick", "--quiet", "--config", str(config), "--out", str(out)]) == 2
    assert "sweep.contact.lateral_creepage" in capsys.readouterr().err
    assert not out.exists()


# --- one real case --------------------------------------------------------------------------


@pytest.fixture(scope="module")
def structures(copy_quick_structures, tmp_path_factory):
    """The structural artefacts of the quick study (no cases): a copy of the session's."""
    out = copy_quick_structures(tmp_path_factory.mktemp("structures"))
    assert engine.run_structural(load_study(quick=True), out, engine.STAGES, progress=False) == []
    return out


def _payload(out, study=None):
    case = engine.plan_cases(study or load_study(quick=True), out)[0]
    return case, engine.case_payload(case, out, False)


def test_outcome_reports_the_case_metrics(structures, tmp_path):
    out = tmp_path / "o"
    case, payload = _payload(structures)
    payload["out_dir"] = str(out)
    outcome = execute_case(payload)
    assert outcome["ok"], outcome["error"]
    assert set(outcome) == {"case_id", "ok", "seconds", "error", "L_F2", "squeal", "squeal_frequency", "oscillation",
                            "regime", "wav"}
    with h5py.File(out / "cases" / f"{case.case_id}.h5", "r") as f:
        attrs = dict(f.attrs)
    assert outcome["L_F2"] == attrs["L_F2"] and outcome["squeal"] == bool(attrs["squeal"])
    assert outcome["squeal_frequency"] == attrs["squeal_frequency"]
    assert outcome["regime"] == attrs["regime"] in ("bouncing", "contact")
    assert outcome["oscillation"] == attrs["oscillation"] in ("squeal", "low-frequency oscillation", "none")
    assert (outcome["wav"] != "") == outcome["squeal"]
    assert all(type(outcome[k]) is t for k, t in (("L_F2", float), ("squeal", bool), ("wav", str)))
    # the case artefact records the sections it read, and they hash to its parameter hash
    config = json.loads(attrs["config"])
    assert config == {s: get_section(case.study, s) for s in CASE_SECTIONS}
    assert params_hash(config) == attrs["params_sha256"] == engine.case_check(case, out)[2]
    assert engine.case_check(case, out)[:2] == (True, "")


def test_outcome_names_the_sound_of_a_squealing_case(structures, tmp_path, monkeypatch):
    # The quick study does not squeal; declare every case squealing to follow the sound file.
    real = interaction.metrics.squeal_metrics
    monkeypatch.setattr(interaction.metrics, "squeal_metrics",
                        lambda *args, **kwargs: dataclasses.replace(real(*args, **kwargs), squeal=True))
    case, payload = _payload(structures)
    payload["out_dir"] = str(tmp_path)
    outcome = execute_case(payload)
    assert outcome["ok"] and outcome["squeal"], outcome["error"]
    assert outcome["wav"] == str(tmp_path / "sounds" / f"{case.case_id}.wav")
    with wave.open(outcome["wav"], "rb") as sound:
        assert sound.getframerate() == 44100 and sound.getnframes() > 0


def test_time_step_mismatch_names_the_artefact(structures, tmp_path):
    study = load_study(quick=True, assignments=["time.time_step=2e-5"])
    _, payload = _payload(structures, study)
    payload["out_dir"] = str(tmp_path)
    outcome = execute_case(payload)
    assert not outcome["ok"] and outcome["error"].startswith("ArtefactError: ")
    assert str(structures / "wheel_greens.h5") in outcome["error"] and "time step" in outcome["error"]
    assert math.isnan(outcome["L_F2"]) and outcome["wav"] == "" and outcome["squeal"] is False


def test_overwritten_residues_name_file_and_dataset(structures, tmp_path):
    variant = tmp_path / "variant"
    variant.mkdir()
    for name in ("wheel_greens.h5", "rail_greens.h5"):
        (variant / name).write_bytes((structures / name).read_bytes())
    with h5py.File(variant / "wheel_greens.h5", "r+") as f:
        f["stationary/residues"][0] *= 1e6
    # the case reads the root models (those of the contact the artefact holds, the study's)
    _, payload = _payload(structures)
    payload.update(variant_dir=str(variant), out_dir=str(tmp_path))
    outcome = execute_case(payload)
    assert not outcome["ok"] and outcome["error"].startswith("ArtefactError: ")
    assert f"{variant / 'wheel_greens.h5'}:/stationary/residues: checksum mismatch" in outcome["error"]
