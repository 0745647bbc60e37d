"""The contact-geometry stage, its artefact and the ``geometry`` command."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import pipeline
from contact_geometry import ContactPoint, contact_table
from contact_geometry.artefact import read_pair, read_wheelset
from contact_geometry.plots import REPORT_FIGURES, plot_geometry_report
from contact_geometry.study import pair_from_study
from contact_geometry.wheelset import equivalent_conicity
from squealcore.artefacts import params_hash
from squealcore.errors import InputError
from squealcore.study import get_section
from stages import engine
from stages.config import load_study
from stages.geometry import read_operating_contact, read_operating_contacts, read_table

STAGE = engine.STAGE_BY_NAME["contact-geometry"]
#: Bad input: the parametric wheel narrowed to 90 mm does not reach the rail's crown contact when
#: it is moved 20 mm towards the field side.
NO_CONTACT = ["wheel.rim_width=0.09", "operating.lateral_displacement=-0.02"]


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """The default study's contact-geometry stage, built once."""
    out = tmp_path_factory.mktemp("geometry") / "out"
    study = load_study()
    assert engine.run(study, out, "contact-geometry", progress=False) == ["contact-geometry"]
    return study, out


def test_artefact_holds_the_in_memory_geometry(built):
    study, out = built
    path = out / STAGE.filename
    pair = pair_from_study(study)
    # the operating contact: recomputed here from the profiles (wheel centred, 50 kN)
    direct = ContactPoint.from_table(contact_table(pair, [0.0], wheel_load=50e3), 0, 0, pair)
    assert read_operating_contact(path) == direct
    assert len(read_operating_contacts(path)) == 1
    table = read_table(path)
    assert table.displacement.size == 201
    assert table.displacement[0] == pytest.approx(-0.010) and table.displacement[-1] == pytest.approx(0.010)
    again = contact_table(pair, table.displacement[::20], wheel_load=50e3)
    np.testing.assert_array_equal(table.rolling_radius[::20], again.rolling_radius)
    stored = read_pair(path)
    np.testing.assert_array_equal(stored.wheel.z, pair.wheel.z)
    assert (stored.flange_back, stored.rail_tilt) == (pair.flange_back, pair.rail_tilt)
    wheelset = read_wheelset(path)
    # the parametric tread is a 1:40 cone and the contact stays on it within +-3 mm
    assert wheelset["equivalent_conicity"] == pytest.approx(0.025, rel=1e-6)
    assert wheelset["equivalent_conicity"] == equivalent_conicity(pair, 0.003, wheel_load=50e3, two_point_tol=1e-5)
    on_tread = np.abs(wheelset["displacement"]) <= 0.005
    np.testing.assert_allclose(wheelset["rolling_radius_difference"][on_tread],
                               2 * 0.025 * wheelset["displacement"][on_tread], rtol=1e-6, atol=1e-12)


def test_report_figures(built, tmp_path):
    _, out = built
    written = plot_geometry_report(out / STAGE.filename, tmp_path / "figures", dpi=40)
    assert [p.name for p in written] == list(REPORT_FIGURES)
    assert all(p.stat().st_size > 0 for p in written)


def test_rerun_is_fresh_and_only_the_geometry_follows_the_displacement(built):
    study, out = built
    assert engine.run(study, out, "contact-geometry", progress=False) == []
    moved = load_study(assignments=["operating.lateral_displacement=0.002"])
    fresh, reason, _, _ = engine.inspect(STAGE, moved, out)
    assert not fresh and "param" in reason.lower()
    assert {name: f for name, f, _ in engine.status(study, out)}["contact-geometry"]
    assert not {name: f for name, f, _ in engine.status(moved, out)}["contact-geometry"]
    # stages that do not read [operating] keep their parameter hash (the Green's stages read the
    # speed from it, and will read the contact position from this stage)
    for stage in engine.STAGES:
        same = params_hash(engine.stage_params(stage, moved)) == params_hash(engine.stage_params(stage, study))
        assert same == ("operating" not in stage.sections), stage.name
    # keys the geometry does not read leave it fresh
    other = load_study(assignments=["contact.friction=0.5", "wheel.fe.f_max=5000.0", "track.loss_factor=0.02"])
    assert engine.inspect(STAGE, other, out)[0]


def test_displacement_change_rebuilds(tmp_path, built):
    study, out = built
    copy = tmp_path / "out"
    copy.mkdir()
    (copy / STAGE.filename).write_bytes((out / STAGE.filename).read_bytes())
    moved = load_study(assignments=["operating.lateral_displacement=0.002"])
    assert engine.run(moved, copy, "contact-geometry", progress=False) == ["contact-geometry"]
    contact = read_operating_contact(copy / STAGE.filename)
    assert contact.lateral_displacement == 0.002
    # on the 1:40 cone: the wheel contact moves 2 mm towards the flange, r grows by 2 mm / 40
    assert contact.wheel_lateral == pytest.approx(read_operating_contact(out / STAGE.filename).wheel_lateral - 0.002,
                                                  abs=1e-9)
    assert engine.run(moved, copy, "contact-geometry", progress=False) == []


def _geometry_json(capsys, *argv):
    status = pipeline.main(["geometry", "--json", *argv])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    return json.loads(captured.out)


def test_cli_json(capsys):
    out = _geometry_json(capsys, "--set", "operating.lateral_displacement=0.001")
    assert out["lateral_displacement"] == 0.001
    [contact] = out["contacts"]
    reference = ContactPoint.from_table(contact_table(pair_from_study(load_study()), [0.001], wheel_load=50e3), 0, 0,
                                        pair_from_study(load_study()))
    assert contact["semi_axes"] == [reference.semi_axis_a, reference.semi_axis_b]
    for key in ("contact_angle", "rolling_radius", "wheel_lateral", "rail_lateral"):
        assert contact[key] == getattr(reference, key)
    # 1:40 cone: contact angle atan(1/40) in the track frame
    assert contact["contact_angle"] == pytest.approx(math.atan(0.025), rel=1e-6)
    assert out["main_contact"] == 0


def test_cli_flange_contact_and_human_output(capsys):
    flange = _geometry_json(capsys, "--set", "operating.lateral_displacement=0.012")
    assert math.degrees(flange["contacts"][0]["contact_angle"]) > 60.0
    assert pipeline.main(["geometry"]) == 0
    text = capsys.readouterr().out
    pair = pair_from_study(load_study())
    centred = ContactPoint.from_table(contact_table(pair, [0.0], wheel_load=50e3), 0, 0, pair)
    line = next(line for line in text.splitlines() if "rolling radius" in line)
    assert line.split()[-2:] == [f"{centred.rolling_radius * 1e3:.3f}", "mm"]
    assert "1 contact(s)" in text and "used by the interaction" in text


def test_cli_writes_only_with_out(tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _geometry_json(capsys)
    assert list(tmp_path.iterdir()) == []
    _geometry_json(capsys, "--out", str(tmp_path / "study"))
    assert [p.name for p in (tmp_path / "study").iterdir()] == [STAGE.filename]


def test_no_contact_is_bad_input(tmp_path, capsys):
    with pytest.raises(InputError, match="operating.lateral_displacement") as err:
        engine.run(load_study(assignments=NO_CONTACT), tmp_path / "direct", "contact-geometry", progress=False)
    assert "allowed range" in str(err.value) and "parametric wheel" in str(err.value)
    assert not (tmp_path / "direct" / STAGE.filename).exists()
    argv = ["geometry", "--out", str(tmp_path / "cli")]
    for assignment in NO_CONTACT:
        argv += ["--set", assignment]
    assert pipeline.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("error: operating.lateral_displacement:"), err
    assert not (tmp_path / "cli").exists()


def test_table_range_without_contact_names_the_key():
    study = load_study(assignments=["wheel.rim_width=0.09", "geometry.displacement_min=-0.02"])
    with pytest.raises(InputError, match=r"geometry.displacement_min.*allowed range for these profiles: \[-0.01"):
        engine.STAGE_BY_NAME["contact-geometry"].function()(_Context(study))


class _Context:
    """The part of a StageContext the stage body reads before it writes."""

    def __init__(self, study):
        self.study = study

    def config(self):
        return {name: get_section(self.study, name) for name in STAGE.sections}

    def writer(self):
        raise AssertionError("nothing may be written")


def test_two_point_contact_through_the_artefact(tmp_path, caplog):
    # 0.1 mm before the flange takes over, the flange gap of the parametric wheel is below 0.5 mm
    study = load_study(assignments=["operating.lateral_displacement=0.0095", "geometry.two_point_tolerance=5e-4"])
    engine.run(study, tmp_path, "contact-geometry", progress=False)
    path = tmp_path / STAGE.filename
    contacts = read_operating_contacts(path)
    assert [c.n_contacts for c in contacts] == [2, 2]
    pair = pair_from_study(study)
    table = contact_table(pair, [0.0095], wheel_load=50e3, two_point_tol=5e-4)
    assert contacts == [ContactPoint.from_table(table, 0, slot, pair) for slot in (0, 1)]
    # the second contact is the flange face (70 deg), no more than the tolerance higher up
    assert math.degrees(contacts[1].contact_angle) == pytest.approx(70.0, abs=0.5)
    assert 0.0 < table.separation[0, 1] <= 5e-4
    with caplog.at_level("WARNING", logger="contact_geometry.study"):
        main = read_operating_contact(path)
    assert main == contacts[0] and main.contact_angle < 0.05
    assert "flange contact" in caplog.text and "ignores" in caplog.text
