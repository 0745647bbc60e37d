"""Point-contact model: Kalker table, steady creep curves and transient response vs halfspace."""

import math

import numpy as np
import pytest

from interaction.contact.halfspace import Grid, HalfspaceContact
from interaction.contact.hertz import hertz_from_curvatures
from interaction.contact.kalker import creep_coefficients, load_table
from interaction.contact.params import Friction, Material
from interaction.contact.point import PointContact

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


def test_point_step_response_is_first_order_relaxation():
    # a creepage step: F_n = F_ss (1 - exp(-n V dt / L)) in the linear range (closed form of
    # the relaxation ODE; the discretisation is exact for piecewise-constant creepage)
    dt = 3.6e-5
    pt = PointContact(material=MAT, friction=FR, hertz=HZ, speed=V, time_step=dt)
    _, ly = pt.relaxation_lengths(50e3)
    st = pt.initial_state()
    eta = -1e-5
    fss = -MAT.shear_modulus * HZ.a * HZ.b * pt.c22 * eta
    for n in range(1, 30):
        r = pt.solve(st, normal_force=50e3, creepage=(0, eta, 0))
        st = r.new_state
        flin = fss * (1 - math.exp(-n * V * dt / ly))
        beta = abs(flin) / (0.3 * 50e3)
        # composed with the Shen-Hedrick-Elkins factor 1 - beta/3 + beta^2/27 (beta ~ 5e-3);
        # exact up to round-off
        assert r.force[1] == pytest.approx(flin * (1 - beta / 3 + beta ** 2 / 27), rel=1e-10)


def _harmonic(model, f, eta0, dt):
    nper = max(int(round(1 / (f * dt))), 1)
    n = int(math.ceil(max(3 / f, 3 * 0.02 / V) / dt)) + 3 * nper
    t = np.arange(1, n + 1) * dt
    st = model.initial_state()
    force = []
    for e in eta0 * np.sin(2 * np.pi * f * t):
        r = model.solve(st, normal_force=50e3, creepage=(0.0, e, 0.0))
        st = r.new_state
        force.append(r.force[1])
    k = n // 2  # after the start-up transient
    M = np.stack([np.sin(2 * np.pi * f * t[k:]), np.cos(2 * np.pi * f * t[k:]), np.ones(n - k)], 1)
    c = np.linalg.lstsq(M, np.array(force)[k:], rcond=None)[0]
    return math.hypot(c[0], c[1]), math.degrees(math.atan2(c[1], c[0]))


def _default_halfspace():
    """Transient halfspace on the default study grid, dx = dy = 0.5 mm."""
    g = Grid.covering(HZ.a, HZ.b, dx=0.5e-3, dy=0.5e-3)
    X, Y = np.meshgrid(g.x, g.y, indexing="ij")
    return HalfspaceContact(material=MAT, friction=FR, grid=g, gap=HZ.A * X ** 2 + HZ.B * Y ** 2,
                            kind="transient", speed=V)


def _compare(f):
    hs = _default_halfspace()
    pt = PointContact(material=MAT, friction=FR, hertz=HZ, speed=V, time_step=hs.time_step)
    eta0 = 1e-4  # ~ 1/6 of the saturation creepage: nearly linear, little slip
    return _harmonic(hs, f, eta0, hs.time_step), _harmonic(pt, f, eta0, hs.time_step)


@pytest.mark.parametrize("f", [100.0, 2000.0, 5000.0])
def test_harmonic_lateral_creepage_matches_halfspace(f):
    (ah, ph), (ap, pp) = _compare(f)
    # measured: 100 Hz -6.2 % / -4.2 deg, 2 kHz -6.3 % / +2.8 deg, 5 kHz -2.5 % / +1.6 deg
    assert ap == pytest.approx(ah, rel=0.10)
    assert abs((pp - ph + 180) % 360 - 180) < 10.0


@pytest.mark.parametrize("f", [500.0, 1000.0])
@pytest.mark.xfail(strict=True, reason="known limitation: the first-order relaxation of the point "
                   "model misses the half-space response where the creepage wavelength V/f is "
                   "comparable to the contact length (measured 500 Hz: -22 %; 1 kHz: -12 %, +10.3 deg)")
def test_harmonic_mid_band_known_deviation(f):
    (ah, ph), (ap, pp) = _compare(f)
    assert ap == pytest.approx(ah, rel=0.10)
    assert abs((pp - ph + 180) % 360 - 180) < 10.0
