"""Squeal risk over a curve (issue 35 item 3): the curve map on the session's quick structures.

(1) The map's stored screen of a configuration equals a direct :func:`stages.screen.screen_study`
of the same operating point (the wheel's curving creepages, normal force and contact angle set
on the study and its contact by hand); (2) in a tight curve the leading inner wheel has the
largest |lateral creepage| (the leading wheelset's angle of attack, about the wheelbase over R,
against the trailing one's); (3) at a friction coefficient of 0.1 no wheel model grows on any
wheel (the curving finds no equilibrium in a 50 m curve at 0.02–0.1); (4) the grid's bad values are
refused naming the axis.
"""

import dataclasses

import numpy as np
import pytest

from curving import profile_geometry, solve_bogie
from curving.operating import WHEEL_LABELS, wheel_operating_points
from squealcore.errors import InputError
from squealcore.study import get_section
from stages.cases import case_study
from stages.config import load_study
import pipeline
from stages.curve_map import curve_map, curving_params, read_curve_map
from stages.screen import WheelModels, screen_study, structures, wheel_point
from stages.wheel import read_mesh, read_modes

RADII, SPEEDS, FRICTIONS = (100.0,), (10.0,), (0.1, 0.3)


@pytest.fixture(scope="module")
def small_map(copy_quick_structures, tmp_path_factory):
    """A 1 x 1 x 2 curve map of the quick study, in a copy of the session's structures."""
    out = copy_quick_structures(tmp_path_factory.mktemp("curve_map"))
    study = load_study(quick=True)
    result = curve_map(study, out, RADII, SPEEDS, FRICTIONS, progress=False)
    return study, out, result, read_curve_map(result["path"])


def test_map_writes_its_artefact_figure_and_summary(small_map):
    _, out, result, data = small_map
    assert result["computed"] and result["configurations"] == 2 and result["wheel_screens"] == 8
    assert (out / "figures" / "curve_map.png").stat().st_size > 0
    assert "leading inner" in (out / "curve_map.md").read_text()
    np.testing.assert_array_equal(data["radius"], RADII)
    assert data["wheels"] == list(WHEEL_LABELS)
    assert (data["solved"] == 1).all() and (data["screened"] == 1).all()
    # a rerun finds it fresh
    again = curve_map(load_study(quick=True), out, RADII, SPEEDS, FRICTIONS, progress=False)
    assert not again["computed"]


def test_map_screen_equals_a_direct_screen_of_the_same_operating_point(small_map):
    study, out, _, data = small_map
    i, k, w = 0, 1, WHEEL_LABELS.index("leading_inner")  # R = 100 m, mu = 0.3
    radius, speed, mu = RADII[i], SPEEDS[0], FRICTIONS[k]
    op = wheel_operating_points(solve_bogie(curving_params(study, radius, speed, mu, profile_geometry(study))))[
        WHEEL_LABELS[w]]
    assert data["lateral_creepage"][i, 0, k, w] == op.lateral_creepage
    _, rail, point = structures(study, out)
    config = case_study(study, {"operating.speed": speed, "contact.friction": mu, "contact.model": "halfspace",
                                "contact.lateral_creepage": op.lateral_creepage,
                                "contact.longitudinal_creepage": op.longitudinal_creepage})
    # the wheel's contact: the study's position and curvatures, the curving's normal force, angle and
    # spin (a computed contact's spin is read as -point.spin)
    at = dataclasses.replace(point, normal_force=op.normal_force, contact_angle=op.contact_angle,
                             rail_section_angle=point.rail_section_angle + op.contact_angle - point.contact_angle,
                             spin=-op.spin)
    wheel = WheelModels(read_modes(out / "wheel_modes.h5", with_shapes=True), read_mesh(out / "wheel_mesh.h5"),
                        get_section(study, "wheel.rotation"))
    direct = screen_study(config, wheel.at(speed, wheel_point(study, point)), rail, point=at, pole_modes=False)
    for name, result in direct.items():
        assert data[f"{name}/margin"][i, 0, k, w] == pytest.approx(result["margin"], rel=1e-12, abs=1e-12)
        assert data[f"{name}/frequency"][i, 0, k, w] == pytest.approx(result["margin_frequency"], rel=1e-12)
        assert data[f"{name}/n_growing"][i, 0, k, w] == len(result["poles"])


def test_leading_inner_wheel_has_the_largest_lateral_creepage_in_a_tight_curve(small_map):
    _, _, _, data = small_map
    eta = np.abs(data["lateral_creepage"][0, 0, 1])  # R = 100 m, mu = 0.3
    lead = WHEEL_LABELS.index("leading_inner")
    assert eta[lead] >= eta.max() * (1 - 1e-12)
    trailing = [WHEEL_LABELS.index(label) for label in ("trailing_inner", "trailing_outer")]
    assert eta[lead] > 1.5 * eta[trailing].max()
    # the leading wheelset's angle of attack of a rigid bogie in flange contact: about half the
    # wheelbase over R (2.5 m wheelbase) or more, and its creepage is psi cos(delta)
    assert eta[lead] > 0.5 * 2.5 / RADII[0]


def test_no_wheel_grows_at_low_friction(small_map):
    _, _, _, data = small_map
    small = FRICTIONS.index(0.1)
    for name in data["models"]:
        assert (data[f"{name}/margin"][:, :, small] < 0).all(), name


@pytest.mark.parametrize("axis, values, field", [("radii", [10.0], "curve_map.radii"),
                                                 ("speeds", [0.0], "curve_map.speeds"),
                                                 ("frictions", [1.5], "curve_map.frictions"),
                                                 ("frictions", [], "curve_map.frictions")])
def test_bad_grid_is_refused_naming_the_axis(axis, values, field, tmp_path):
    grid = {"radii": [100.0], "speeds": [10.0], "frictions": [0.3], axis: values}
    with pytest.raises(InputError) as err:
        curve_map(load_study(quick=True), tmp_path, progress=False, **grid)
    assert err.value.field == field
    assert not any(tmp_path.iterdir())  # refused before anything is built


def test_command_line_refuses_bad_input_with_exit_status_2(tmp_path, capsys):
    assert pipeline.main(["curve-map", "--quick", "--out", str(tmp_path), "--radii", "10", "--quiet"]) == 2
    assert "error: curve_map.radii:" in capsys.readouterr().err
