"""Steady curving of a two-axle bogie (issue 35, item 1) against closed forms (docs/verification.md).

(1) the pure-rolling offset of a free conical wheelset, y = r0 l0 / (λ R); (2) a rigid bogie in
flange contact: the friction-centre (Heumann) closed form of the flanging position when every
tread contact is saturated, and the diagonal position when both flanges touch; (3) the
equilibrium residuals recomputed from the returned per-wheel forces; (4) straight track and the
1/R limit; and the creep law at a curving operating point against the steady half-space solver.
"""

import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

from curving import ConicalGeometry, CurvingParams, profile_geometry, solve_bogie, solve_wheelset
from curving.creep import STEEL, CreepLaw
from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_curvatures
from contact.kalker import creep_coefficients
from contact.params import Friction
from squealcore.errors import InputError

SIDE = {"outer": 1, "inner": -1}


def _wheels(result, wheelset):
    return [w for w in result["wheels"] if w["wheelset"] == wheelset]


@pytest.mark.parametrize("radius", [1000.0, 3000.0])
def test_free_conical_wheelset_rolls_at_the_pure_rolling_offset(radius):
    g = ConicalGeometry(wheel_radius=0.45, contact_half_spacing=0.75, conicity=0.05, flangeway_clearance=0.01)
    r = solve_wheelset(CurvingParams(radius=radius, speed=10.0, geometry=g))
    ws = r["wheelsets"][0]
    # exact: the contacts stay on the rail crowns at ±l0 from the track centre line, so ω = 1
    assert ws["lateral_displacement"] == pytest.approx(0.45 * 0.75 / (0.05 * radius), rel=1e-9)
    assert ws["rotation"] == pytest.approx(1.0, abs=1e-12)
    for w in r["wheels"]:
        assert abs(w["creepage"][0]) < 1e-12
        assert w["flange_force"] == 0.0


def _friction_centre(radius, b, l0, fu2, c11, c22, mu_q):
    """Leading and trailing angles of attack of a rigid bogie whose leading outer flange (vertical,
    frictionless) touches, every tread contact saturated at μQ along the direction of Kalker's linear
    force (C11 ξ, C22 η): the bogie turns about a pole x_p on its axis (ψ_i = (x_i - x_p) / R, ξ = ±l0 / R);
    the flange force from the lateral balance, x_p from the yaw moment about the bogie centre."""
    def yaw(xp):
        total = 0.0
        for x in (b, -b):
            psi = (x - xp) / radius
            d = math.hypot(c11 * l0 / radius, c22 * psi)
            total += 2.0 * mu_q * (c11 * l0 ** 2 / radius + (x - b) * c22 * psi) / d
        return total - b * fu2
    xp = brentq(yaw, -20.0 * b, b)
    return (b - xp) / radius, (-b - xp) / radius


@pytest.mark.parametrize("speed", [1.0, 9.9])
def test_rigid_bogie_flanging_position_is_the_friction_centre_closed_form(speed):
    radius, mu = 200.0, 0.05
    g = ConicalGeometry(conicity=0.0, flangeway_clearance=0.012, flange_angle=math.pi / 2)
    p = CurvingParams(radius=radius, speed=speed, friction=mu, flange_friction=0.0, spin=False,
                      centre_of_gravity_height=0.0, geometry=g)
    r = solve_bogie(p)
    lead, trail = r["wheelsets"]
    assert lead["flange_contact"] == ["outer"] and trail["flange_contact"] == []
    assert all(c["friction_use"] == pytest.approx(1.0, abs=1e-9) for w in r["wheels"] for c in w["contacts"]
               if c["kind"] == "tread")  # every tread contact saturated, as the closed form assumes
    h = hertz_from_curvatures(1 / (2 * 0.45), 1 / (2 * 0.3), 50e3, STEEL.contact_modulus)
    c11, c22, _ = creep_coefficients(h.a / h.b, STEEL.poisson_ratio)
    q = r["loads"]["outer_wheel_load"]
    psi1, psi2 = _friction_centre(radius, 1.25, 0.75, 2 * r["loads"]["unbalanced_force"], c11, c22, mu * q)
    assert lead["angle_of_attack"] == pytest.approx(psi1, rel=1e-8)
    assert trail["angle_of_attack"] == pytest.approx(psi2, rel=1e-6, abs=1e-10)
    assert lead["angle_of_attack"] - trail["angle_of_attack"] == pytest.approx(2.5 / radius, rel=1e-12)
    # Heumann's friction centre with Coulomb's direction (force against the slip): within 2.5 %
    coulomb, _ = _friction_centre(radius, 1.25, 0.75, 2 * r["loads"]["unbalanced_force"], 1.0, 1.0, mu * q)
    assert lead["angle_of_attack"] == pytest.approx(coulomb, rel=0.025)
    if speed == 1.0:  # no cant deficiency: leading ≈ wheelbase / R (1.13 x), trailing near radial
        assert 1.0 < lead["angle_of_attack"] * radius / 2.5 < 1.2
        assert abs(trail["angle_of_attack"]) < 0.15 * 2.5 / radius


def test_rigid_bogie_in_the_diagonal_position():
    r = solve_bogie(CurvingParams(radius=100.0, speed=8.0))  # conical default, clearance 8 mm
    lead, trail = r["wheelsets"]
    assert lead["flange_contact"] == ["outer"] and trail["flange_contact"] == ["inner"]
    b, q = 1.25, 0.008
    assert lead["angle_of_attack"] == pytest.approx(b / 100.0 + q / b, rel=1e-12)
    assert trail["angle_of_attack"] == pytest.approx(-b / 100.0 + q / b, rel=1e-12)
    assert lead["flange_normal_force"]["outer"] > 0 and trail["flange_normal_force"]["inner"] > 0



@pytest.mark.parametrize("cant", [0.05, 0.15])
def test_rigid_bogie_pressed_against_the_outer_rail_by_a_large_cant_deficiency(cant):
    """R = 150 m at 30 m/s (lateral acceleration 5.3-4.1 m/s²): both wheelsets run at the outer
    flange, so the frame is not yawed and ψ_1 = b/R, ψ_2 = -b/R exactly. (The trailing wheelset,
    left past its flange while only the leading flange was in contact, once stopped the solver.)"""
    p = CurvingParams(radius=150.0, speed=30.0, cant=cant)  # conical default, clearance 8 mm
    r = solve_bogie(p)
    lead, trail = r["wheelsets"]
    assert lead["flange_contact"] == ["outer"] and trail["flange_contact"] == ["outer"]
    assert lead["lateral_displacement"] == pytest.approx(0.008, rel=1e-12)
    assert trail["lateral_displacement"] == pytest.approx(0.008, rel=1e-12)
    assert lead["angle_of_attack"] == pytest.approx(1.25 / 150.0, rel=1e-12)
    assert trail["angle_of_attack"] == pytest.approx(-1.25 / 150.0, rel=1e-12)
    assert lead["flange_normal_force"]["outer"] > 0 and trail["flange_normal_force"]["outer"] > 0
    forces, moments, torques = _recomputed_residuals(p, r)
    # the solver's tolerance: 1e-8 of the axle load (1 mN), 1e-8 of axle load x l0 for moments
    assert max(abs(f) for f in forces) < r["tolerance"]["force"]
    assert max(abs(m) for m in moments + torques) < r["tolerance"]["moment"]


def test_rigid_bogie_in_the_diagonal_position_on_the_profiles_under_a_cant_excess(profiles):
    """R = 150 m, 5 m/s, 100 mm cant (cant excess): leading wheelset on the outer flange, trailing on
    the inner one, ψ_1 = b/R + y_f/b with the profiles' flangeway clearance. (From the solution with
    the trailing wheelset off the table past its flange, its rotation there once stopped the solver.)"""
    p = CurvingParams(radius=150.0, speed=5.0, cant=0.1, geometry=profiles)
    r = solve_bogie(p)
    lead, trail = r["wheelsets"]
    assert lead["flange_contact"] == ["outer"] and trail["flange_contact"] == ["inner"]
    b, q = 1.25, profiles.flange_limit
    assert lead["angle_of_attack"] == pytest.approx(b / 150.0 + q / b, rel=1e-9)
    assert trail["angle_of_attack"] == pytest.approx(-b / 150.0 + q / b, rel=1e-9)
    assert lead["flange_normal_force"]["outer"] > 0 and trail["flange_normal_force"]["inner"] > 0

def _recomputed_residuals(p, r):
    """Lateral forces, yaw moments and axle torques (N, N m) recomputed from the returned wheels."""
    b = p.semi_wheelbase
    x = {"leading": b, "trailing": -b}
    lat, yaw, torque = {}, {}, {}
    for w in r["wheels"]:
        s = SIDE[w["side"]]
        k = w["wheelset"]
        lat[k] = lat.get(k, 0.0) + s * w["lateral_force"]
        for c in w["contacts"]:
            yaw[k] = yaw.get(k, 0.0) - s * c["lateral_arm"] * c["creep_force"][0]
            torque[k] = torque.get(k, 0.0) + c["creep_force"][0] * c["rolling_radius"]
    fu = r["loads"]["unbalanced_force"]
    if p.rigid:
        forces = [sum(lat.values()) + 2 * fu]
        moments = [sum(yaw[k] + x[k] * lat[k] for k in x)]
    else:
        ws = {w["position"]: w for w in r["wheelsets"]}
        yb, pb = r["bogie"]["lateral_displacement"], r["bogie"]["yaw"]
        ky, kpsi = 2 * p.lateral_stiffness, 2 * p.longitudinal_stiffness * p.axlebox_half_spacing ** 2
        fs = {k: -ky * (ws[k]["lateral_displacement"] - yb - x[k] * pb) for k in x}
        ms = {k: -kpsi * (ws[k]["angle_of_attack"] - pb - x[k] / p.radius) for k in x}
        forces = [lat[k] + fs[k] for k in x] + [2 * fu - sum(fs.values())]
        moments = [yaw[k] + ms[k] for k in x] + [-sum(ms[k] + x[k] * fs[k] for k in x)]
    return forces, moments, list(torque.values())


@pytest.fixture(scope="module")
def profiles():
    from stages.config import load_study
    return profile_geometry(load_study())


@pytest.mark.parametrize("case", ["rigid-cone", "suspended-cone", "rigid-profiles", "suspended-profiles"])
def test_equilibrium_residuals_of_the_returned_forces(case, profiles):
    geometry = profiles if "profiles" in case else ConicalGeometry()
    stiff = dict(longitudinal_stiffness=5e6, lateral_stiffness=3e6) if "suspended" in case else {}
    p = CurvingParams(radius=250.0, speed=14.0, cant=0.05, geometry=geometry, **stiff)
    r = solve_bogie(p)
    forces, moments, torques = _recomputed_residuals(p, r)
    # tolerance: 1e-8 of the axle load (1 mN), 1e-8 of axle load x l0 for moments
    assert max(abs(f) for f in forces) < r["tolerance"]["force"]
    assert max(abs(m) for m in moments + torques) < r["tolerance"]["moment"]
    assert r["wheelsets"][0]["flange_contact"] == ["outer"]
    assert json.loads(json.dumps(r)) == r  # JSON-ready


def test_straight_track_and_the_large_radius_limit():
    r = solve_bogie(CurvingParams(radius=math.inf, speed=20.0))
    for ws in r["wheelsets"]:
        assert ws["lateral_displacement"] == 0.0 and ws["angle_of_attack"] == 0.0 and ws["rotation"] == 1.0
    for w in r["wheels"]:
        assert w["creepage"][:2] == [0.0, 0.0] and w["flange_force"] == 0.0
        assert w["contacts"][0]["creep_force"][0] == 0.0
    # the conical tread's spin leaves equal and opposite lateral forces on the two wheels
    lateral = {(w["wheelset"], w["side"]): w["lateral_force"] for w in r["wheels"]}
    assert lateral["leading", "outer"] == pytest.approx(lateral["leading", "inner"], rel=1e-12)
    # large radii: everything scales as 1 / R
    a, b = (solve_bogie(CurvingParams(radius=R, speed=5.0)) for R in (2e4, 4e4))
    for wa, wb in zip(a["wheelsets"], b["wheelsets"]):
        assert wa["lateral_displacement"] == pytest.approx(2 * wb["lateral_displacement"], rel=0.01)
        assert wa["angle_of_attack"] == pytest.approx(2 * wb["angle_of_attack"], rel=0.01)


def test_creep_law_at_a_curving_point_against_the_steady_halfspace():
    r = solve_bogie(CurvingParams(radius=600.0, speed=15.0, friction=0.4))
    wheel = _wheels(r, "leading")[1]  # leading inner wheel, partial slip
    c = wheel["contacts"][0]
    xi, eta, phi = c["creepage"]
    n = c["normal_force"]
    assert 0.3 < c["friction_use"] < 0.95
    g = ConicalGeometry()
    tread = g.tread(0.0)[0][1]
    a_c, b_c = tread.hertz_curvatures()
    hz = hertz_from_curvatures(a_c, b_c, n, STEEL.contact_modulus)
    grid = Grid.covering(hz.a, hz.b, nx=24, ny=24)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    hs = HalfspaceContact(material=STEEL, friction=Friction(0.4), grid=grid, gap=hz.A * x ** 2 + hz.B * y ** 2,
                          kind="steady", speed=15.0)
    ref = hs.solve(hs.initial_state(), normal_force=n, creepage=(xi, eta, phi)).force
    point = CreepLaw().force(tread, 0.4, n, (xi, eta, phi))
    np.testing.assert_allclose(point, c["creep_force"], rtol=1e-12)
    # measured: within 4 % of μN (the Shen-Hedrick-Elkins law against the exact theory, 24 x 24 grid)
    assert np.hypot(*(point - ref[:2])) < 0.05 * 0.4 * n


def test_inputs_are_checked():
    with pytest.raises(InputError, match="curving.radius"):
        CurvingParams(radius=5.0, speed=10.0)
    with pytest.raises(InputError, match="curving.longitudinal_stiffness"):
        CurvingParams(radius=300.0, speed=10.0, longitudinal_stiffness=1e6)
    with pytest.raises(InputError, match="curving.geometry.conicity"):
        ConicalGeometry(conicity=-0.1)
    with pytest.raises(InputError, match="curving.friction"):
        CurvingParams(radius=300.0, speed=10.0, friction=0.0)
