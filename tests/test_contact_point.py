"""Point-contact model: Kalker table, steady creep curves and transient response vs halfspace."""

import math

import numpy as np
import pytest

from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_curvatures
from contact.kalker import creep_coefficients, load_table
from contact.params import Friction, Material
from contact.point.fit_relaxation import fit_relaxation, halfspace_step_response, relaxation_step_response
from contact.point.model import PointContact, load_relaxation_table, relaxation_coefficients
from squealcore.errors import InputError

MAT = Material.from_young(210e9, 0.3)
FR = Friction(0.3)
HZ = hertz_from_curvatures(1 / (2 * 0.39), 1 / (2 * 0.3), 50e3, MAT.contact_modulus)  # default study
V = 50 / 3.6


def test_kalker_table_nodes_and_nu_interpolation():
    t = load_table()
    for ab, nu, c11, c22, c23 in zip(t["a_over_b"], t["nu"], t["C11"], t["C22"], t["C23"]):
        np.testing.assert_allclose(creep_coefficients(ab, nu), (c11, c22, c23), rtol=1e-12)
    # between nu nodes 1/C is quadratic in nu: check against an independent quadratic fit
    nus = np.array([0.0, 0.25, 0.5])
    inv = 1 / np.array([creep_coefficients(1.0, n)[0] for n in nus])
    quad = np.polyval(np.polyfit(nus, inv, 2), 0.3)
    assert creep_coefficients(1.0, 0.3)[0] == pytest.approx(1 / quad, rel=1e-12)


def _halfspace(kind, n=(24, 24)):
    g = Grid.covering(HZ.a, HZ.b, nx=n[0], ny=n[1])
    X, Y = np.meshgrid(g.x, g.y, indexing="ij")
    return HalfspaceContact(material=MAT, friction=FR, grid=g, gap=HZ.A * X ** 2 + HZ.B * Y ** 2,
                            kind=kind, speed=V)


def test_steady_creep_curve_matches_halfspace():
    hs = _halfspace("steady")
    pt = PointContact(material=MAT, friction=FR, hertz=HZ, kind="steady", speed=V, time_step=1e-5)
    for eta in (-5e-4, -1e-3, -2e-3, -4e-3, -8e-3):
        r = hs.solve(hs.initial_state(), normal_force=50e3, creepage=(0.0, eta, 0.0))
        q = pt.solve(pt.initial_state(), normal_force=50e3, creepage=(0.0, eta, 0.0))
        # measured: point below halfspace by 0.0-4.4 %: the 24 x 24 halfspace grid is ~4 %
        # too stiff in the linear range (see the creep-coefficient test) and the
        # Shen-Hedrick-Elkins law deviates from Kalker's exact theory by a few % mid-curve
        assert q.force[1] == pytest.approx(r.force[1], rel=0.05)
        assert q.force[1] > 0  # eta < 0 gives a positive lateral force on the wheel
    for xi in (-1e-3, 3e-3):
        r = hs.solve(hs.initial_state(), normal_force=50e3, creepage=(xi, 0.0, 0.0))
        q = pt.solve(pt.initial_state(), normal_force=50e3, creepage=(xi, 0.0, 0.0))
        assert q.force[0] == pytest.approx(r.force[0], rel=0.05)


def test_point_normal_spring_is_hertz():
    pt = PointContact(material=MAT, friction=FR, hertz=HZ, speed=V, time_step=1e-5)
    r = pt.solve(pt.initial_state(), approach=HZ.approach * 2 ** (2 / 3), creepage=(0, 0, 0))
    assert r.force[2] == pytest.approx(2 * 50e3, rel=1e-12)  # F ~ delta^(3/2)
    lift = pt.solve(pt.initial_state(), approach=-1e-6, creepage=(0, -0.01, 0))
    assert np.all(lift.force == 0)


def test_relaxation_table_nodes_and_interpolation():
    t = load_relaxation_table()
    cols = [f"{n}_{d}" for d in "xy" for n in ("beta", "alpha1", "alpha2")]
    for k, (ab, nu) in enumerate(zip(t["a_over_b"], t["nu"])):
        np.testing.assert_allclose(relaxation_coefficients(ab, nu).ravel(), [t[c][k] for c in cols], rtol=1e-12)
    # between nodes: linear in ln(a/b) and in nu (independent evaluation from the raw table)
    def node(ab, nu):
        m = np.isclose(t["a_over_b"], ab) & np.isclose(t["nu"], nu)
        return np.array([t[c][m][0] for c in cols])
    hi = t["a_over_b"][np.argmin(abs(t["a_over_b"] - 1 / 0.7))]  # the node as printed in the table
    w = math.log(1.2) / math.log(hi)
    expect = 0.5 * ((1 - w) * node(1.0, 0.25) + w * node(hi, 0.25)) \
        + 0.5 * ((1 - w) * node(1.0, 0.3) + w * node(hi, 0.3))
    np.testing.assert_allclose(relaxation_coefficients(1.2, 0.275).ravel(), expect, rtol=1e-12)


def test_relaxation_table_edges_and_bad_input(caplog):
    # outside the table: its edge, with a warning; a/b <= 0 is bad input
    with caplog.at_level("WARNING", logger="contact.point.model"):
        np.testing.assert_allclose(relaxation_coefficients(5.0, 0.3), relaxation_coefficients(1 / 0.3, 0.3),
                                   rtol=1e-5)  # the table prints 1/0.3 with 6 digits
    assert "outside the fitted relaxation table" in caplog.text
    with pytest.raises(InputError, match="geometry.a_over_b"):
        relaxation_coefficients(-1.0, 0.3)


def test_fit_recovers_known_law_and_reproduces_table():
    # (1) the fit applied to the law's own step response (scipy.signal, 20 a long) returns its
    # constants (to 1e-4: optimiser tolerance)
    x = np.arange(1, 241) / 12
    fit = fit_relaxation(x, relaxation_step_response(x, 0.56, 1.78, 0.93))
    np.testing.assert_allclose((fit.beta, fit.alpha1, fit.alpha2), (0.56, 1.78, 0.93), rtol=1e-4)
    # (2) a refit from a coarser halfspace grid (8 instead of 12 elements per semi-axis) lands
    # within 3 % of the table (measured: beta -1.2 %, alpha1 -0.1 %, alpha2 -0.6 %: the grid
    # dependence of the reference)
    x, resp = halfspace_step_response(1.0, 0.3, 1, per_a=8)
    fit = fit_relaxation(x, resp)
    np.testing.assert_allclose((fit.beta, fit.alpha1, fit.alpha2), relaxation_coefficients(1.0, 0.3)[1], rtol=0.03)
    assert fit.max_log_error < 0.1  # the second-order law's own misfit over the band, measured 0.077


def _second_order_step(x, b, a1, a2):
    """Closed-form unit-step response of a2 y'' + a1 y' + y = u + b u' (complex poles)."""
    sigma = a1 / (2 * a2)
    wd = math.sqrt(1 / a2 - sigma ** 2)
    return 1 - np.exp(-sigma * x) * (np.cos(wd * x) + (sigma - b / a2) / wd * np.sin(wd * x))


@pytest.mark.parametrize("component, fn", [(1, 50e3), (0, 50e3), (1, 110e3)])
def test_point_step_response_is_second_order_relaxation(component, fn):
    # a creepage step: F_n = F_ss y(n V dt), y the closed-form step response of the relaxation ODE
    # with the tabulated constants and lengths scaled with the semi-axis a ~ Fn^(1/3); the
    # discretisation is exact for piecewise-constant creepage
    dt = 3.6e-5
    pt = PointContact(material=MAT, friction=FR, hertz=HZ, speed=V, time_step=dt, tangential="relaxation")
    s = (fn / 50e3) ** (1 / 3)
    a = HZ.a * s
    beta, alpha1, alpha2 = pt.relaxation[component]
    assert alpha1 ** 2 < 4 * alpha2  # complex poles: the closed form below applies
    st = pt.initial_state()
    u = -1e-5
    c = (pt.c11, pt.c22)[component]
    fss = -MAT.shear_modulus * HZ.a * HZ.b * s * s * c * u
    creep = [0.0, 0.0, 0.0]
    creep[component] = u
    for n in range(1, 80):
        r = pt.solve(st, normal_force=fn, creepage=tuple(creep))
        st = r.new_state
        flin = fss * _second_order_step(n * V * dt, beta * a, alpha1 * a, alpha2 * a * a)
        b = abs(flin) / (0.3 * fn)
        # composed with the Shen-Hedrick-Elkins factor 1 - beta/3 + beta^2/27 (beta ~ 5e-3);
        # exact up to round-off
        assert r.force[component] == pytest.approx(flin * (1 - b / 3 + b ** 2 / 27), rel=1e-10)
        assert r.force[1 - component] == 0.0


def test_point_high_frequency_stiffness_near_mindlin():
    # the law's high-frequency limit is a tangential contact stiffness; for a/b ~ 1.2 it must be
    # close to Mindlin's no-slip stiffness of a circular contact of radius sqrt(ab),
    # 4 G sqrt(ab) / (2 - nu) (measured: 0.955 and 0.963; the halfspace's own first-step
    # stiffness on the default grid is 1.008 of it). 10 %: the ellipse is not a circle.
    pt = PointContact(material=MAT, friction=FR, hertz=HZ, speed=V, time_step=1e-5, tangential="relaxation")
    mindlin = 4 * MAT.shear_modulus * math.sqrt(HZ.a * HZ.b) / (2 - MAT.poisson_ratio)
    for k in pt.contact_stiffness(50e3):
        assert k == pytest.approx(mindlin, rel=0.10)
    # and it scales as a ~ Fn^(1/3) (Mindlin: k ~ contact radius)
    assert pt.contact_stiffness(400e3)[1] == pytest.approx(2 * pt.contact_stiffness(50e3)[1], rel=1e-12)


def _harmonic(model, f, eta0, dt, fn=50e3):
    nper = max(int(round(1 / (f * dt))), 1)
    n = int(math.ceil(max(3 / f, 3 * 0.02 / V) / dt)) + 3 * nper
    t = np.arange(1, n + 1) * dt
    st = model.initial_state()
    force = []
    for e in eta0 * np.sin(2 * np.pi * f * t):
        r = model.solve(st, normal_force=fn, creepage=(0.0, e, 0.0))
        st = r.new_state
        force.append(r.force[1])
    k = n // 2  # after the start-up transient
    M = np.stack([np.sin(2 * np.pi * f * t[k:]), np.cos(2 * np.pi * f * t[k:]), np.ones(n - k)], 1)
    c = np.linalg.lstsq(M, np.array(force)[k:], rcond=None)[0]
    return math.hypot(c[0], c[1]), math.degrees(math.atan2(c[1], c[0]))


def _halfspace_on_default_grid(hz, friction=FR):
    """Transient halfspace on the default study grid, dx = dy = 0.5 mm."""
    g = Grid.covering(hz.a, hz.b, dx=0.5e-3, dy=0.5e-3)
    X, Y = np.meshgrid(g.x, g.y, indexing="ij")
    return HalfspaceContact(material=MAT, friction=friction, grid=g, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                            kind="transient", speed=V)


def _compare(f, hz=HZ):
    hs = _halfspace_on_default_grid(hz)
    pt = PointContact(material=MAT, friction=FR, hertz=hz, speed=V, time_step=hs.time_step, tangential="relaxation")
    # eta0 = 1e-4 for the default contact: the linear force is 5 % of mu Fn (nearly linear, a
    # little slip at the trailing edge); the same fraction for other contacts
    eta0 = 0.05 * FR.kinetic * hz.normal_force / (MAT.shear_modulus * hz.a * hz.b * pt.c22)
    eta0 = 1e-4 if hz is HZ else eta0
    fn = hz.normal_force
    return _harmonic(hs, f, eta0, hs.time_step, fn), _harmonic(pt, f, eta0, hs.time_step, fn)


BAND = [100.0, 200.0, 500.0, 1000.0, 2000.0, 5000.0]
FAST = [500.0, 1000.0, 2000.0, 5000.0]
# other contacts (wheel radius 0.39 m): rail head radius 0.8 m at 80 kN (a/b = 0.62, a = 5.2 mm,
# b = 8.4 mm) and 0.12 m at 40 kN (a/b = 2.18, a = 5.6 mm, b = 2.5 mm)
HZ_B = hertz_from_curvatures(1 / (2 * 0.39), 1 / (2 * 0.8), 80e3, MAT.contact_modulus)
HZ_C = hertz_from_curvatures(1 / (2 * 0.39), 1 / (2 * 0.12), 40e3, MAT.contact_modulus)


@pytest.mark.parametrize("f", [pytest.param(f, marks=pytest.mark.slow) if f not in FAST else f for f in BAND])
def test_harmonic_lateral_creepage_matches_halfspace(f):
    # Issue 5: imposed eta = 1e-4 sin(2 pi f t), force amplitude within 10 % and phase within
    # 10 deg of the transient halfspace (default grid). 100 and 200 Hz need ~70 s of halfspace
    # steps: marked slow (the linear transfer-function test below covers them in the default run).
    # Measured: 100 Hz -2.6 % / +0.1 deg, 200 Hz -1.8 % / -0.4 deg, 500 Hz -6.0 % / -1.9 deg,
    # 1 kHz -4.1 % / +3.4 deg, 2 kHz -5.8 % / -2.4 deg, 5 kHz -5.4 % / -0.5 deg; about -3 % of
    # it is the default grid's steady stiffness error (halfspace C22 3.3 % above Kalker's).
    (ah, ph), (ap, pp) = _compare(f)
    assert ap == pytest.approx(ah, rel=0.10)
    assert abs((pp - ph + 180) % 360 - 180) < 10.0


@pytest.mark.parametrize("hz, f", [pytest.param(HZ_C, f, marks=pytest.mark.slow) if f not in BAND[1:] else (HZ_C, f)
                                   for f in BAND] + [pytest.param(HZ_B, f, marks=pytest.mark.slow) for f in BAND],
                         ids=[f"ab2.18_40kN-{f:g}" for f in BAND] + [f"ab0.62_80kN-{f:g}" for f in BAND])
def test_harmonic_lateral_creepage_other_contacts(hz, f):
    # As above (linear force 5 % of mu Fn, default grid) for other a/b and loads; slow: 100 Hz
    # (10 s) and the a/b = 0.62 contact (23 x 37 elements, minutes). Measured:
    # a/b = 2.18, 40 kN: -6.7 ... -1.8 %, -2.0 ... +4.3 deg (100 Hz -2.7 %, 500 Hz -6.7 %,
    # 1 kHz +4.3 deg); a/b = 0.62, 80 kN: -5.9 ... -2.6 %, -2.0 ... +2.9 deg.
    (ah, ph), (ap, pp) = _compare(f, hz)
    assert ap == pytest.approx(ah, rel=0.10)
    assert abs((pp - ph + 180) % 360 - 180) < 10.0


def _step_transfer(model, fn, steps, freqs, dt):
    """Force per unit lateral creepage of a linear model at ``freqs`` (Hz), from its step response."""
    st = model.initial_state()
    force = np.empty(steps)
    for n in range(steps):
        r = model.solve(st, normal_force=fn, creepage=(0.0, -1e-5, 0.0))
        st = r.new_state
        force[n] = r.force[1] / -1e-5
    h = np.diff(np.concatenate(([0.0], force)))  # impulse response; settled: h = 0 afterwards
    return np.exp(-2j * np.pi * np.outer(freqs, np.arange(steps)) * dt) @ h


@pytest.mark.parametrize("hz", [HZ, HZ_C], ids=["default", "ab2.18_40kN"])
def test_linear_transfer_function_matches_halfspace(hz):
    # Linear (no slip: mu = 1e3) force per unit lateral creepage over the band 100 Hz - 5 kHz,
    # from step responses (the DTFT of the impulse response): point against the transient
    # halfspace on the default grid dx = dy = 0.5 mm. The halfspace runs 8 a of rolling (its
    # force has settled to 1e-3); the point model 40 a.
    # Measured, default: amplitude -5.6 ... -1.7 %, phase -2.4 ... +3.4 deg; a/b = 2.18, 40 kN:
    # -6.4 ... -1.5 %, -2.0 ... +4.3 deg (a/b = 0.62, 80 kN, not run: -5.8 ... -2.6 %,
    # -1.8 ... +3.0 deg). The steady -2.6 % is the halfspace grid's stiffness error.
    # Tolerance 10 % / 10 deg (issue 5).
    big = Friction(1e3)
    hs = _halfspace_on_default_grid(hz, big)
    pt = PointContact(material=MAT, friction=big, hertz=hz, speed=V, time_step=hs.time_step, tangential="relaxation")
    fn = hz.normal_force
    freqs = np.array(BAND)
    ref = _step_transfer(hs, fn, int(math.ceil(8 * hz.a / hs.grid.dx)), freqs, hs.time_step)
    got = _step_transfer(pt, fn, int(math.ceil(40 * hz.a / hs.grid.dx)), freqs, hs.time_step)
    ratio = got / ref
    np.testing.assert_array_less(abs(abs(ratio) - 1), 0.10)
    np.testing.assert_array_less(abs(np.degrees(np.angle(ratio))), 10.0)
