"""From a curve to the squeal cases (issue 35, item 2): each wheel's operating point, its sign
convention, the ``curve`` command and a study that names a curve.

The sign convention is checked against a second computation, independent of
``curving.kinematics``: the rigid-body velocity of the wheel's material at the contact (the
wheelset carried round the curve's centre, yawed by ψ, spinning about its axle), projected on the
wheel's own contact frame of the squeal study (x rolling, y towards the wheel's field side, z the
contact normal; docs/conventions.md).
"""

import json
import math

import numpy as np
import pytest

from curving import (WHEEL_LABELS, ConicalGeometry, CurvingParams, WheelOperatingPoint, solve_bogie, solve_wheelset,
                     wheel_operating_points)
from squealcore.errors import InputError

SIDE = {"outer": 1, "inner": -1}


def _rigid_body_creepages(radius, y, psi, rotation, side, arm, rolling_radius, contact_angle, r0):
    """(ξ, η, φ) of the wheel's material at its contact from the wheelset's rigid-body motion.

    Track frame X along the track, Y towards the outer rail, Z up (right-handed), so the curve's
    centre is at (0, -R, 0) and the track turns at -V/R about Z; V = 1. The wheelset's centre is at
    (0, y, 0), its axle along a = (-sin ψ, cos ψ, 0) (heading turned towards the outer rail for
    ψ > 0), spinning at Ω = ω / r0 about a; the contact lies at ``side * arm`` along the axle and
    ``rolling_radius`` below it. The rail is at rest, so the slip is the material's velocity. The
    wheel's frame has y = side * Y tilted by the contact angle towards the gauge side; it is
    right-handed for the outer wheel and mirrored for the inner one, so the spin (an axial vector)
    takes the factor ``side``.
    """
    w_track = np.array([0.0, 0.0, -1.0 / radius])
    axle = np.array([-math.sin(psi), math.cos(psi), 0.0])
    w_axle = rotation / r0 * axle
    centre = np.array([0.0, y, 0.0])
    contact = centre + side * arm * axle - np.array([0.0, 0.0, rolling_radius])
    curve_centre = np.array([0.0, -radius, 0.0])
    velocity = np.cross(w_track, centre - curve_centre) + np.cross(w_track + w_axle, contact - centre)
    e_x = np.array([1.0, 0.0, 0.0])
    e_y = np.array([0.0, side * math.cos(contact_angle), math.sin(contact_angle)])
    normal = np.array([0.0, -side * math.sin(contact_angle), math.cos(contact_angle)])
    return velocity @ e_x, velocity @ e_y, side * ((w_track + w_axle) @ normal)


def _geometry_of(result, label):
    wheel = next(w for w in result["wheels"] if f"{w['wheelset']}_{w['side']}" == label)
    main = max((c for c in wheel["contacts"] if c["kind"] == "tread"), key=lambda c: c["load_share"])
    return main["lateral_arm"], main["rolling_radius"], main["contact_angle"]


@pytest.mark.parametrize("radius", [150.0, 300.0])  # diagonal position; flanging on the outer rail only
def test_leading_inner_wheel_slides_towards_its_field_side(radius):
    """A rigid bogie flanging on the outer rail: the leading wheelset's angle of attack is about the
    wheelbase over R, and every wheel's creepages equal the rigid-body slip of its material. The
    leading inner wheel gets η = +ψ cos δ > 0 (its material slips inwards, towards its field
    side), the leading outer wheel η = -ψ cos δ < 0."""
    params = CurvingParams(radius=radius, speed=10.0)
    result = solve_bogie(params)
    points = wheel_operating_points(result)
    assert tuple(points) == WHEEL_LABELS
    r0 = params.geometry.nominal_radius
    wheelsets = {w["position"]: w for w in result["wheelsets"]}
    psi = wheelsets["leading"]["angle_of_attack"]
    b, y_f = 0.5 * params.wheelbase, params.geometry.flange_limit
    if wheelsets["trailing"]["flange_contact"]:
        # the diagonal position (both flanges touch, y = ±y_f): ψ_1 = b / R + y_f / b exactly
        assert psi == pytest.approx(b / radius + y_f / b, rel=1e-9)
    else:
        # flanging on the outer rail, trailing wheelset nearly radial: ψ_1 about the wheelbase over R
        # (user guide: 8.1 mrad at 300 m against 2b / R = 8.3 mrad)
        assert psi == pytest.approx(2.0 * b / radius, rel=0.05)
    for label, point in points.items():
        ws = wheelsets[point.wheelset]
        side = SIDE[point.side]
        arm, rolling_radius, angle = _geometry_of(result, label)
        xi, eta, phi = _rigid_body_creepages(radius, ws["lateral_displacement"], ws["angle_of_attack"],
                                             ws["rotation"], side, arm, rolling_radius, angle, r0)
        # the curving kinematics drop the terms of second order in ψ and the product ψ ξ (exact:
        # η = s cos δ sin ψ (s l / R - ω r / r0) = -s ψ cos δ (1 - ξ + y / R) + O(ψ³))
        a = abs(ws["angle_of_attack"])
        assert point.lateral_creepage == pytest.approx(eta, abs=a * (abs(xi) + abs(ws["lateral_displacement"]) / radius)
                                                       + a ** 3 + 1e-12)
        assert point.longitudinal_creepage == pytest.approx(xi, abs=a * a + 1e-12)
        assert point.spin == pytest.approx(phi, abs=a * a / r0 + 1e-12)
        assert point.wheel_displacement == pytest.approx(side * ws["lateral_displacement"], abs=0.0)
    inner, outer = points["leading_inner"], points["leading_outer"]
    assert inner.lateral_creepage > 0.0 > outer.lateral_creepage
    assert inner.lateral_creepage == pytest.approx(psi * math.cos(inner.contact_angle), rel=1e-12)
    assert outer.lateral_creepage == pytest.approx(-psi * math.cos(outer.contact_angle), rel=1e-12)
    assert outer.flange_contact and outer.flange_force > 0.0 and not inner.flange_contact
    # the leading inner wheel sits away from its flange: its displacement towards the flange is -y
    assert inner.wheel_displacement == pytest.approx(-params.geometry.flange_limit, rel=1e-9)
    # the normal forces and loads: the tread's vertical part plus the flange's equal the wheel load
    wheel = next(w for w in result["wheels"] if w["wheelset"] == "leading" and w["side"] == "outer")
    assert outer.tread_load == pytest.approx(outer.normal_force * math.cos(outer.contact_angle), rel=1e-12)
    assert outer.wheel_load == pytest.approx(wheel["vertical_force"], rel=1e-9)
    # without a flange the tread carries the wheel load: N cos δ + Fy sin δ = Q (the inner wheel's
    # creep force points towards its flange, Fy < 0, so N cos δ exceeds Q)
    tread = [c for c in next(w for w in result["wheels"] if w["wheelset"] == "leading"
                             and w["side"] == "inner")["contacts"]]
    fy_sin = sum(c["creep_force"][1] * math.sin(c["contact_angle"]) for c in tread)
    assert fy_sin < 0.0
    assert inner.tread_load + fy_sin == pytest.approx(inner.wheel_load, rel=1e-9)


def test_free_conical_wheelset_with_a_cant_deficiency():
    """A free conical wheelset under an unbalanced force yaws until its lateral creep forces carry
    it; whatever the angle, each wheel's η is the rigid-body slip of its material (-s ψ cos δ)."""
    geometry = ConicalGeometry(conicity=0.15, flangeway_clearance=0.02)
    params = CurvingParams(radius=600.0, speed=20.0, geometry=geometry)
    result = solve_wheelset(params)
    points = wheel_operating_points(result)
    assert tuple(points) == ("single_inner", "single_outer")
    ws = result["wheelsets"][0]
    psi = ws["angle_of_attack"]
    assert abs(psi) > 1e-5  # the unbalanced force 100 kN x 0.068 is carried by creep, not by a flange
    assert not any(p.flange_contact for p in points.values())
    for label, point in points.items():
        side = SIDE[point.side]
        arm, rolling_radius, angle = _geometry_of(result, label)
        xi, eta, phi = _rigid_body_creepages(600.0, ws["lateral_displacement"], psi, ws["rotation"], side, arm,
                                             rolling_radius, angle, geometry.wheel_radius)
        assert point.lateral_creepage == pytest.approx(eta, abs=abs(psi) * (abs(xi) + 0.02 / 600.0) + 1e-12)
        assert math.copysign(1.0, point.lateral_creepage) == -side * math.copysign(1.0, psi)
        assert math.isnan(point.wheel_lateral) and point.to_dict()["wheel_lateral"] is None


def test_operating_point_is_frozen_and_refuses_other_input():
    point = next(iter(wheel_operating_points(solve_bogie(CurvingParams(radius=500.0, speed=10.0))).values()))
    assert isinstance(point, WheelOperatingPoint)
    with pytest.raises(AttributeError):
        point.lateral_creepage = 0.0
    assert point.creepage == (point.longitudinal_creepage, point.lateral_creepage, point.spin)
    with pytest.raises(InputError, match="curving"):
        wheel_operating_points({"wheels": []})


# ---- the curve command -------------------------------------------------------------------------

def test_curve_command_prints_every_wheel_and_the_json_matches_the_solution(capsys):
    import pipeline
    from stages.config import load_study
    from stages.curve import study_curve

    assert pipeline.main(["curve", "--radius", "150", "--speed", "30", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert (out["radius"], out["speed"], out["cant"], out["feeds"]) == (150.0, 30.0, 0.0, "leading_inner")
    assert set(out["wheels"]) == set(WHEEL_LABELS)
    # the same numbers as the library's solution of the same study
    _, points = study_curve(load_study(assignments=["curve.radius=150.0", "curve.speed=30.0"]))
    for label, point in points.items():
        assert out["wheels"][label] == json.loads(json.dumps(point.to_dict()))
    inner = out["wheels"]["leading_inner"]
    assert inner["lateral_creepage"] > 0.0 and not inner["flange_contact"]
    assert out["wheels"]["leading_outer"]["flange_contact"]
    assert max(out["residuals"].values()) < 1.0  # N and N m, of a 100 kN axle
    assert pipeline.main(["curve", "--radius", "300", "--speed", "20", "--cant", "0.1"]) == 0
    table = capsys.readouterr().out
    for label in WHEEL_LABELS:
        assert label in table
    assert "cant 100 mm" in table and "lateral creepage eta (%)" in table


@pytest.mark.parametrize("argv, field", [
    (["--radius", "5"], "curve.radius"),
    (["--radius", "150", "--speed", "120"], "curve.speed"),
    (["--radius", "150", "--cant", "-0.01"], "curve.cant"),
    (["--radius", "many"], "--radius"),
    (["--radius", "150", "--set", "curve.wheel=front"], "curve.wheel"),
])
def test_curve_command_refuses_bad_values_with_exit_2(argv, field, capsys):
    import pipeline

    assert pipeline.main(["curve", *argv]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(f"error: {field}:"), err


# ---- a study that names a curve -----------------------------------------------------------------

CURVE = ["curve.enabled=true", "curve.radius=150.0"]


@pytest.mark.parametrize("extra, field", [
    (["contact.lateral_creepage=-0.005"], "contact.lateral_creepage"),
    (["operating.wheel_load=60000.0"], "operating.wheel_load"),
    (["operating.lateral_displacement=0.002"], "operating.lateral_displacement"),
    (["curve.speed=20.0", "operating.speed=10.0"], "operating.speed"),
    (['sweep."contact.lateral_creepage"=[-0.003, -0.01]'], "sweep.contact.lateral_creepage"),
    (['contact.geometry="manual"'], "curve.enabled"),
])
def test_a_curve_and_a_hand_set_value_are_refused_naming_both(extra, field):
    from stages.config import load_study

    with pytest.raises(InputError) as err:
        load_study(quick=True, assignments=[*CURVE, *extra])
    assert err.value.field == field
    assert "curve" in err.value.message or "curve" in field


def test_a_sweep_over_a_value_the_curve_sets_is_refused_in_the_cases():
    from stages.cases import case_study
    from stages.config import load_study

    study = load_study(quick=True, assignments=["curve.radius=300.0"])  # no curve yet: the sweep is the user's
    with pytest.raises(InputError) as err:
        case_study(study, {"curve.enabled": True, "contact.lateral_creepage": -0.01})
    assert err.value.field == "sweep.contact.lateral_creepage" and "curve" in err.value.message


def test_the_study_takes_the_wheel_it_names_and_a_curve_sweep_solves_each_curve_once(tmp_path):
    from stages import curve as study_curve_module
    from stages.cases import is_structural
    from stages.config import load_study
    from stages.engine import plan_cases

    study = load_study(quick=True, assignments=CURVE)
    # the quick preset's creepage sweep is dropped: friction x wheel model
    assert "contact.lateral_creepage" not in study["sweep"]
    _, points = study_curve_module.study_curve(study)
    inner = points["leading_inner"]
    assert study["contact"]["lateral_creepage"] == inner.lateral_creepage > 0.0
    assert study["contact"]["longitudinal_creepage"] == inner.longitudinal_creepage
    assert study["contact"]["spin"] == inner.spin
    assert study["operating"]["lateral_displacement"] == inner.wheel_displacement < 0.0
    assert study["operating"]["wheel_load"] == inner.tread_load
    outer = load_study(quick=True, assignments=[*CURVE, 'curve.wheel="leading_outer"'])
    assert outer["contact"]["lateral_creepage"] == points["leading_outer"].lateral_creepage < 0.0
    assert outer["operating"]["lateral_displacement"] == points["leading_outer"].wheel_displacement > 0.0

    assert is_structural("curve.radius")
    swept = load_study(quick=True, assignments=[*CURVE, 'sweep."curve.radius"=[150.0, 300.0]',
                                                'sweep."contact.friction"=[0.3, 0.6]'])
    before = study_curve_module._solve.cache_info()
    cases = plan_cases(swept, tmp_path)
    after = study_curve_module._solve.cache_info()
    assert len(cases) == 2 * 2 * 3
    assert after.misses - before.misses <= 1  # R = 150 m was solved above; 300 m once for its six cases
    creepages = {c.overrides["curve.radius"]: c.study["contact"]["lateral_creepage"] for c in cases}
    assert creepages[150.0] == inner.lateral_creepage and creepages[300.0] < creepages[150.0]
    # each radius its own structures (the contact moves), with distinct folders
    assert len({c.variant_dir for c in cases}) == 2


def test_a_curve_study_runs_end_to_end_on_the_quick_structures(copy_quick_structures, tmp_path):
    """The quick study in a 150 m curve, one short case: the case runs at the leading inner wheel's
    operating point of the curving solution (its attributes), the wheel and rail meshes and the
    wheel's modes are the session's (only the stages at the contact, which the curve moves, rerun),
    and a changed radius makes the structures at the contact and the case stale."""
    import h5py

    from stages import engine
    from stages.config import load_study
    from stages.curve import study_curve

    out = copy_quick_structures(tmp_path / "curve")
    assignments = [*CURVE, "time.duration=0.02", 'sweep."simulation.wheel_model"=["stationary"]']
    study = load_study(quick=True, assignments=assignments)
    rebuilt = engine.run(study, out, until="simulate", progress=False)
    assert not {"wheel-mesh", "wheel-modes", "rail-mesh"} & set(rebuilt)
    assert {"contact-geometry", "wheel-greens", "rail-greens"} <= set(rebuilt)
    (case_file,) = sorted((out / "cases").glob("*.h5"))
    point = study_curve(study)[1]["leading_inner"]
    with h5py.File(case_file, "r") as f:
        attrs = dict(f.attrs)
    assert attrs["lateral_creepage"] == point.lateral_creepage
    assert attrs["spin"] == point.spin  # the curving's spin, with the yaw rate, not the profile's alone
    # the contact-geometry stage finds the contact at the curve's wheel displacement; the curving's
    # tread contact is the nearest row of its table (0.05 mm apart): positions within half a row
    assert attrs["wheel_lateral"] == pytest.approx(point.wheel_lateral, abs=2.5e-5 + 1e-9)
    assert attrs["rail_lateral"] == pytest.approx(point.rail_lateral, abs=2.5e-5 + 1e-9)
    assert attrs["contact_angle"] == pytest.approx(point.contact_angle, abs=1e-3)
    assert attrs["normal_force"] == pytest.approx(point.normal_force, rel=1e-6)
    assert json.loads(attrs["curve"])["radius"] == 150.0
    # fresh as it is; a changed radius reruns the structures at the contact and the case
    assert engine.run(study, out, until="simulate", progress=False) == []
    moved = load_study(quick=True, assignments=[*assignments, "curve.radius=600.0"])
    stale = {name for name, fresh, _ in engine.status(moved, out) if not fresh}
    assert {"contact-geometry", "wheel-greens", "rail-greens"} <= stale
    assert any(name.startswith("simulate:") for name in stale)
    assert not {"wheel-mesh", "wheel-modes", "rail-mesh"} & stale


def test_a_study_recorded_before_the_curve_section_still_validates():
    from stages.config import load_study, validate

    study = load_study(quick=True)
    del study["curve"]  # a folder's record written before [curve] existed
    assert validate(study)["curve"].enabled is False
