"""The one schema: declarations, generated validation/messages/defaults/documentation, default study."""

import logging
import math
import os
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from contact.config import parse_case
from contact.params import CASE_SECTIONS, ContactParams, FrictionTable
from squealcore.artefacts import canonical_json
from squealcore.errors import InputError
from squealcore.schema import REQUIRED, param, section, spec_of
from squealcore.study import load_toml
from stages.config import STUDY_SECTIONS, default_study, load_study, main, parameters_markdown, schema_defaults

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).resolve().parent / "data"


@section("demo")
@dataclass(frozen=True)
class Demo:
    """A section declared only for these tests."""

    name: str = param(REQUIRED, kind="string", doc="required")
    length: float = param(1.0, unit="m", low=0.0, high=2.0, low_open=True, doc="open below, closed above")
    ratio: float = param(0.1, low=0.0, high=0.5, high_open=True, doc="closed below, open above")
    count: int = param(3, low=1, high=10, doc="an integer")
    flag: bool = param(True, doc="a boolean")
    mode: str = param("a", choices=("a", "b"), doc="a choice")
    pair: list = param([1.0, 2.0], unit="m", low=0.0, doc="two numbers")


def _field_error(cls, mapping):
    with pytest.raises(InputError) as err:
        cls.from_mapping(mapping)
    return err.value


def test_bounds_open_and_closed_as_declared():
    ok = Demo.from_mapping({"name": "x", "length": 2.0, "ratio": 0.0, "count": 10})
    assert (ok.length, ok.ratio, ok.count) == (2.0, 0.0, 10)
    for key, value, allowed in (("length", 0.0, "(0, 2] m"), ("length", 2.0000001, "(0, 2] m"),
                                ("ratio", 0.5, "[0, 0.5)"), ("ratio", -1e-9, "[0, 0.5)"), ("count", 0, "[1, 10]")):
        err = _field_error(Demo, {"name": "x", key: value})
        assert err.field == f"demo.{key}" and allowed in err.message, err


@pytest.mark.parametrize("mapping, field, words", [
    ({"name": "x", "count": 3.5}, "demo.count", "integer"),
    ({"name": "x", "count": True}, "demo.count", "integer"),
    ({"name": "x", "flag": 1}, "demo.flag", "true or false"),
    ({"name": "x", "mode": "c"}, "demo.mode", "'a' | 'b'"),
    ({"name": "x", "pair": [1.0]}, "demo.pair", "list of 2"),
    ({"name": "x", "pair": [1.0, -1.0]}, "demo.pair", "[0, inf)"),
    ({"name": "x", "length": "long"}, "demo.length", "number"),
    ({"name": "x", "colour": "red"}, "demo.colour", "unknown key"),
    ({}, "demo.name", "missing"),
    ({"name": "x", "length": math.inf}, "demo.length", "finite"),
    ({"name": "x", "length": math.nan}, "demo.length", "finite"),
    ({"name": "x", "pair": [1.0, math.inf]}, "demo.pair", "finite"),
])
def test_messages_name_the_field_and_what_is_allowed(mapping, field, words):
    err = _field_error(Demo, mapping)
    assert err.field == field and words in err.message and "must" in err.message


def test_defaults_and_normalisation():
    demo = Demo.from_mapping({"name": "x", "length": 1, "pair": [0, 1]})
    assert demo == Demo("x", 1.0, 0.1, 3, True, "a", [0.0, 1.0])
    assert isinstance(demo.length, float) and all(isinstance(v, float) for v in demo.pair)


def _numeric_params():
    for cls in STUDY_SECTIONS + CASE_SECTIONS:
        for name, p in spec_of(cls).items():
            if p.kind in ("number", "integer", "numbers"):
                yield cls, name, p


@pytest.mark.parametrize("bad", [math.inf, -math.inf, math.nan])
def test_every_numeric_parameter_refuses_non_finite_values(bad):
    checked = 0
    for cls, name, p in _numeric_params():
        value = [bad] * p.length if p.kind == "numbers" else bad
        mapping = {"model": "point"} if cls.SECTION == "" else {}
        with pytest.raises(InputError) as err:
            cls.from_mapping({**mapping, name: value})
        assert err.value.field == (f"{cls.SECTION}.{name}" if cls.SECTION else name)
        checked += 1
    assert checked > 80


def test_every_parameter_is_documented_and_its_default_passes_its_check():
    for cls in STUDY_SECTIONS + CASE_SECTIONS:
        assert cls.SECTION_DOC
        for name, p in spec_of(cls).items():
            assert p.doc, f"{cls.SECTION}.{name} has no doc"
            if not p.required and p.default is not None:
                assert p.check(name, p.default) == p.default


def test_friction_coefficient_is_declared_once_and_must_be_positive():
    assert spec_of(ContactParams)["friction"] == spec_of(FrictionTable)["coefficient"]
    with pytest.raises(InputError) as err:
        load_study(assignments=["contact.friction=0"])
    assert err.value.field == "contact.friction" and "(0, 5]" in err.value.message
    with pytest.raises(InputError) as err:
        parse_case({"model": "point", "friction": {"coefficient": 0.0}})
    assert err.value.field == "friction.coefficient" and "(0, 5]" in err.value.message
    with pytest.raises(InputError) as err:
        parse_case({"model": "point", "friction": {"coefficient": 0.3, "kinetic": 0.4}})
    assert err.value.field == "friction.kinetic"
    case = parse_case({"model": "point", "friction": {"coefficient": 0.4, "kinetic": 0.3}})
    assert (case.model.friction.static, case.model.friction.kinetic) == (0.4, 0.3)


@pytest.mark.parametrize("assignment, field, words", [
    ("operating.speed=-1", "operating.speed", "(0, 150] m/s"),
    ("time.duration=inf", "time.duration", "finite"),
    ("wheel.fe.f_max=nan", "wheel.fe.f_max", "finite"),
    ("track.damping_low_frequency=30000.0", "track.damping_low_frequency", "below damping_high_frequency"),
    ("report.receptance_f_max=40.0", "report.receptance_f_max", "larger than receptance_f_min"),
    ("contact.wheel_transverse_curvature=-4.0", "contact.wheel_transverse_curvature", "hollow tread"),
    ("simulation.wheel_model=rigid", "simulation.wheel_model", "'stationary'"),
    ("report.dpi=99.5", "report.dpi", "integer"),
])
def test_study_errors(assignment, field, words):
    with pytest.raises(InputError) as err:
        load_study(assignments=[assignment])
    assert err.value.field == field and words in err.value.message


def _same(a, b, where=""):
    """Equal keys, equal values and equal types (so that canonical JSON and the stage hashes agree)."""
    assert set(a) == set(b), (where, set(a) ^ set(b))
    for key in a:
        if isinstance(a[key], dict):
            _same(a[key], b[key], f"{where}{key}.")
        else:
            assert a[key] == b[key] and type(a[key]) is type(b[key]), f"{where}{key}: {a[key]!r} != {b[key]!r}"


def test_resolved_default_study_equals_the_original_paper_file():
    # tests/data/paper_v1.toml is the complete default study before the schema (every key written
    # out); the default study is now schema defaults + the shorter paper.toml, value for value the same
    reference = load_toml(DATA / "paper_v1.toml")
    _same(default_study(), reference)
    _same(load_study(), reference)
    assert canonical_json(default_study()) == canonical_json(reference)


def test_paper_file_keeps_fewer_keys_than_the_study_has():
    paper = load_toml(ROOT / "studies" / "paper.toml")
    full = schema_defaults()
    assert "report" not in paper and "section_element_size" not in paper["wheel"]
    assert sum(len(t) for t in paper.values()) < sum(len(t) for t in full.values())


def test_set_on_a_swept_key_replaces_the_sweep(caplog):
    with caplog.at_level(logging.INFO, logger="stages.config"):
        study = load_study(assignments=["contact.friction=0.6"])
    assert study["contact"]["friction"] == 0.6
    assert "contact.friction" not in study["sweep"]
    assert study["sweep"]["contact.lateral_creepage"] == [-0.003, -0.005, -0.01, -0.015]
    assert "replaces the sweep" in caplog.text
    assert "contact.friction" in load_study()["sweep"]


def test_study_config_does_not_import_the_cases():
    code = "import sys, stages.config; print('stages.cases' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         env={**os.environ, "PYTHONPATH": str(ROOT)}).stdout
    assert out.strip() == "False"


def test_load_toml_refuses_directories_binary_and_unreadable_files(tmp_path):
    binary = tmp_path / "binary.toml"
    binary.write_bytes(bytes(range(256)))
    for path in (tmp_path, binary, tmp_path / "missing.toml"):
        with pytest.raises(InputError) as err:
            load_toml(path)
        assert err.value.field == str(path)
    locked = tmp_path / "locked.toml"
    locked.write_text("a = 1\n")
    locked.chmod(0)
    if not os.access(locked, os.R_OK):  # root reads anything: nothing to test then
        with pytest.raises(InputError) as err:
            load_toml(locked)
        assert err.value.field == str(locked) and "permission" in err.value.message


def test_parameters_doc_is_up_to_date():
    # regenerate with: python -m stages.config
    assert (ROOT / "docs" / "parameters.md").read_text(encoding="utf-8") == parameters_markdown()


def test_doc_generator_check_mode(tmp_path):
    target = tmp_path / "parameters.md"
    target.write_text("old\n")
    assert main(["--check", "--out", str(target)]) == 1
    assert main(["--out", str(target)]) == 0
    assert main(["--check", "--out", str(target)]) == 0
    assert "`contact.friction`" in target.read_text() and "`friction.coefficient`" in target.read_text()
