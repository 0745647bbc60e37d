"""Steady curving on the standard profiles: S1002 wheels on 60E1 rails inclined 1:40 (issue 35 item 1).

The default rigid bogie (wheelbase 2b = 2.5 m, axle load 100 kN, h_cg = 1.2 m) in 150 m and 300 m
curves on level track, on the contact geometry of :func:`curving.profile_geometry` (the project's
contact search on the two profiles, every 0.05 mm). Not closed forms; what is checked and why:

* **the flange**: S1002's flange flank is a 70° line (EN 13715), so the flange contact's angle is
  70° (60–70° for worn flanges); the contact jumps to the flange root (17–36°) from 5.25 mm and
  onto the flank at 6.65 mm, the flangeway clearance. (The flange was once taken at the first
  contact steeper than 0.6 rad, the root's 36° contact at 6.6 mm, and the bogie held there found
  no equilibrium at 150 m: the flange threshold is now 1.0 rad, between root and flank.)
* **the angles of attack**: a rigid bogie has ψ_1 - ψ_2 = 2b/R exactly; flanging, it turns about
  a pole on its axis near the trailing axle (Heumann's friction centre), ψ_i = (x_i - x_P)/R, so
  the trailing wheelset runs near radial and the leading one near 2b/R, the finding of
  docs/user-guide.md (8.1 mrad against 8.3 at 300 m on the default profiles). Bound: the pole
  within b/2 of the trailing axle, |ψ_2| < 0.25 × 2b/R. Measured: ψ_1 = 0.79–0.80 × 2b/R at
  150 m, 0.90 at 300 m; ψ_2 negative, the trailing wheelset (4–6 mm towards the inner rail, where
  S1002's rolling-radius difference is large) steering a little past radial.
* **the leading inner wheel** is on its tread (contact angle 0.5°) and its lateral creepage is
  η = +ψ_1 cos δ in its own frame (y towards its field side), i.e. -ψ_1 cos δ towards the outer
  rail: the yawed wheelset's material slips inwards at -V ψ (curving/kinematics.py).
* **plausibility**: the leading outer wheel's derailment quotient Y/Q below Nadal's limit
  (tan δ - μ)/(1 + μ tan δ) of the 70° flank (1.34 at μ = 0.3, 1.12 at 0.4; measured 0.44–0.52);
  the flange force positive; the residuals, recomputed from the returned per-wheel forces, below
  the solver's tolerance (1e-8 of the axle load, N, and of axle load × l0, N m).
"""

import math

import pytest

from curving import CurvingParams, profile_geometry, solve_bogie

S1002_60E1 = ('wheel.tread_profile="S1002"', 'rail.profile="60E1"', "rail.inclination=40")
B = 1.25
SIDE = {"outer": 1, "inner": -1}


@pytest.fixture(scope="module")
def s1002():
    from stages.config import load_study  # lazy: the study loader is only needed to build the fixture
    return profile_geometry(load_study(assignments=S1002_60E1))


def _wheel(result, wheelset, side):
    return next(w for w in result["wheels"] if w["wheelset"] == wheelset and w["side"] == side)


def _rigid_residuals(result):
    """Bogie lateral force, yaw moment and the axle torques (N, N m) from the returned wheels."""
    x = {"leading": B, "trailing": -B}
    lat, yaw, torque = {k: 0.0 for k in x}, {k: 0.0 for k in x}, {k: 0.0 for k in x}
    for w in result["wheels"]:
        k, s = w["wheelset"], SIDE[w["side"]]
        lat[k] += s * w["lateral_force"]
        for c in w["contacts"]:
            yaw[k] -= s * c["lateral_arm"] * c["creep_force"][0]
            torque[k] += c["creep_force"][0] * c["rolling_radius"]
    force = sum(lat.values()) + 2.0 * result["loads"]["unbalanced_force"]
    moment = sum(yaw[k] + x[k] * lat[k] for k in x)
    return force, [moment, *torque.values()]


def test_s1002_geometry_flange_on_the_flank(s1002):
    assert s1002.flange_limit == pytest.approx(6.65e-3, abs=1e-4)
    assert math.degrees(s1002.flange().contact_angle) == pytest.approx(70.0, abs=0.5)
    # the last tread row is the flange root's contact, steeper than 0.6 rad but not the flank
    assert 30.0 < math.degrees(s1002.rows[-1].contact_angle) < 40.0
    assert math.degrees(s1002.tread(0.0)[0][1].contact_angle) < 3.0


@pytest.mark.parametrize("radius, speed, mu", [
    (150.0, 10.0, 0.3),
    (150.0, 10.0, 0.35),
    (300.0, 15.0, 0.4),
    pytest.param(150.0, 10.0, 0.4, marks=pytest.mark.slow),  # 7 s: the solver continues over the curvature
])
def test_rigid_bogie_flanging_on_s1002(s1002, radius, speed, mu):
    p = CurvingParams(radius=radius, speed=speed, friction=mu, geometry=s1002)
    r = solve_bogie(p)
    lead, trail = r["wheelsets"]
    two_b_over_r = 2.0 * B / radius
    # the leading outer flange on the rail, on the 70° flank; no other flange
    assert lead["flange_contact"] == ["outer"] and trail["flange_contact"] == []
    assert lead["lateral_displacement"] == pytest.approx(s1002.flange_limit, rel=1e-9)
    outer = _wheel(r, "leading", "outer")
    flange = next(c for c in outer["contacts"] if c["kind"] == "flange")
    assert 60.0 <= math.degrees(flange["contact_angle"]) <= 70.5
    assert lead["flange_normal_force"]["outer"] > 0.0 and outer["flange_force"] > 0.0
    # the leading inner wheel on its tread, η = +ψ_1 cos δ in its frame (-ψ_1 towards the outer rail)
    inner = _wheel(r, "leading", "inner")
    assert all(c["kind"] == "tread" for c in inner["contacts"])
    assert math.degrees(inner["contact_angle"]) < 3.0
    psi1, psi2 = lead["angle_of_attack"], trail["angle_of_attack"]
    assert inner["creepage"][1] == pytest.approx(psi1 * math.cos(inner["contact_angle"]), rel=1e-12)
    assert inner["creepage"][1] == pytest.approx(psi1, rel=2e-3)  # cos δ > 0.998 on the tread
    # rigid bogie: ψ_1 - ψ_2 = 2b/R; the pole near the trailing axle: leading near 2b/R, trailing near radial
    assert psi1 - psi2 == pytest.approx(two_b_over_r, rel=1e-12)
    assert abs(psi2) < 0.25 * two_b_over_r
    assert 0.75 * two_b_over_r < psi1 < 1.25 * two_b_over_r
    # Y/Q of the leading outer wheel below Nadal's limit of its flank
    tan_f = math.tan(flange["contact_angle"])
    assert 0.0 < outer["derailment_quotient"] < (tan_f - mu) / (1.0 + mu * tan_f)
    # equilibrium of the returned forces
    force, moments = _rigid_residuals(r)
    assert abs(force) < r["tolerance"]["force"]
    assert max(abs(m) for m in moments) < r["tolerance"]["moment"]
    assert r["residuals"]["lateral_force"] < r["tolerance"]["force"]


def test_at_300_m_and_low_friction_the_flange_root_guides(s1002):
    """μ = 0.3 at 300 m: the leading outer wheel's lateral force is carried by its contact on the
    flange root (30–36°, the last rows below the flangeway clearance), so the flank does not touch;
    the angles are those of the flanging bogie (ψ_1 = 0.90 × 2b/R)."""
    r = solve_bogie(CurvingParams(radius=300.0, speed=15.0, friction=0.3, geometry=s1002))
    lead, trail = r["wheelsets"]
    assert lead["flange_contact"] == [] and trail["flange_contact"] == []
    outer = _wheel(r, "leading", "outer")
    assert 28.0 < math.degrees(outer["contact_angle"]) < 37.0
    assert s1002.flange_limit - 1e-4 < lead["lateral_displacement"] <= s1002.flange_limit
    assert abs(trail["angle_of_attack"]) < 0.25 * 2.0 * B / 300.0
    force, moments = _rigid_residuals(r)
    assert abs(force) < r["tolerance"]["force"]
    assert max(abs(m) for m in moments) < r["tolerance"]["moment"]
