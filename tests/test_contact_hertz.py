"""Hertz formulas and the grid normal solver against Hertz theory."""

import math

import numpy as np
import pytest

from contact.halfspace.model import Grid
from contact.hertz import (axis_ratio_from_curvature_ratio, complete_elliptic_integrals, curvature_ratio,
                                      hertz_from_curvatures, hertz_from_semi_axes, hertz_pressure)
from contact.halfspace.influence import rectangle_kernels
from contact.halfspace.normal import solve_normal
from contact.params import Material
from squealcore.errors import InputError

MAT = Material.from_young(210e9, 0.3)
ES = MAT.contact_modulus


def test_complete_elliptic_integrals_equal_scipy_special():
    """The arithmetic-geometric mean against scipy.special (an independent algorithm, Cephes'
    polynomial approximations) over the complementary parameter m1 = (b/a)^2 from 1e-12 to 1.

    Tolerances: K and K - E to 2e-15 relative (a few round-offs of either method); E to 1e-14,
    which holds the cancellation of E = K - (K - E) for a thin ellipse (K eps, K = 15 at m1 = 1e-12).
    """
    from scipy.special import ellipe, ellipkm1

    for m1 in np.logspace(-12, 0, 400):
        K, E, K_minus_E = complete_elliptic_integrals(m1)
        assert K == pytest.approx(ellipkm1(m1), rel=2e-15)
        assert E == pytest.approx(ellipe(1.0 - m1), rel=1e-14)
        if m1 < 0.5:  # the reference difference itself cancels as m -> 0
            assert K_minus_E == pytest.approx(ellipkm1(m1) - ellipe(1.0 - m1), rel=2e-15)


def test_complete_elliptic_integrals_limits_and_input():
    """Circle (m = 0): K = E = pi/2 exactly; m -> 1: E -> 1 and K -> ln(4 / sqrt(m1)) (the
    asymptote's error is O(m1 ln m1), nothing at m1 = 1e-300); m1 outside (0, 1] is refused."""
    assert complete_elliptic_integrals(1.0) == (math.pi / 2, math.pi / 2, 0.0)
    K, E, _ = complete_elliptic_integrals(1e-300)
    assert K == pytest.approx(math.log(4.0) + 150.0 * math.log(10.0), rel=1e-15)
    assert E == pytest.approx(1.0, abs=1e-12)
    for bad in (0.0, -0.1, 1.5, float("nan")):
        with pytest.raises(InputError, match="complementary_parameter"):
            complete_elliptic_integrals(bad)


def test_axis_ratio_bisection_equals_brent():
    """The semi-axis ratio for a curvature ratio (bisection) against scipy.optimize.brentq on the same
    equation, ratios 1.001 .. 1e6: within the requested accuracy 1e-14 + 1e-13 g (twice, as both
    methods stop anywhere within it). Closer to 1 the equation itself is ill-conditioned (B/A - 1
    ~ 1.5 (1 - g)); there the two roots' residuals are compared instead."""
    from scipy.optimize import brentq

    for ratio in np.concatenate([np.geomspace(1.001, 1e6, 60), [2.0, 7.5]]):
        g = axis_ratio_from_curvature_ratio(ratio)
        reference = brentq(lambda t: curvature_ratio(t) - ratio, 1e-6, 1.0, xtol=1e-14, rtol=1e-13)
        assert abs(g - reference) <= 2 * (1e-14 + 1e-13 * reference)
    for ratio in (1.0 + 1e-8, 1.0 + 1e-6):
        g = axis_ratio_from_curvature_ratio(ratio)
        reference = brentq(lambda t: curvature_ratio(t) - ratio, 1e-6, 1.0, xtol=1e-14, rtol=1e-13)
        assert abs(curvature_ratio(g) - ratio) <= max(abs(curvature_ratio(reference) - ratio), 1e-8)
    assert axis_ratio_from_curvature_ratio(1.0) == 1.0
    with pytest.raises(InputError, match="geometry.curvatures"):
        axis_ratio_from_curvature_ratio(0.5)


def test_circular_limit_closed_form():
    # sphere on plane, Johnson (4.22)-(4.24): a^3 = 3 P R / (4 E*), delta = a^2 / R, p0 = 3P/(2 pi a^2)
    R, P = 0.25, 30e3
    h = hertz_from_curvatures(1 / (2 * R), 1 / (2 * R), P, ES)
    a = (3 * P * R / (4 * ES)) ** (1 / 3)
    assert h.a == pytest.approx(a, rel=1e-12) and h.b == pytest.approx(a, rel=1e-12)
    assert h.approach == pytest.approx(a * a / R, rel=1e-12)
    assert h.p0 == pytest.approx(3 * P / (2 * math.pi * a * a), rel=1e-12)


def test_nearly_circular_is_continuous():
    # curvature ratio 1 + 1e-6 goes through the elliptic-integral branch: must meet the circle
    c = hertz_from_curvatures(1.0, 1.0, 1e4, ES)
    e = hertz_from_curvatures(1.0, 1.0 + 1e-6, 1e4, ES)
    assert e.a == pytest.approx(c.a, rel=1e-6) and e.approach == pytest.approx(c.approach, rel=1e-6)


@pytest.mark.parametrize("ratio", [1.5, 3.0, 10.0])
def test_elliptic_against_brewe_hamrock(ratio):
    # Brewe & Hamrock (1977) curve fit k = a/b = 1.0339 (B/A)^0.636 (claimed within 3 %),
    # an independent approximation of the elliptic-integral solution.
    h = hertz_from_curvatures(1.0, ratio, 1e4, ES)
    assert h.a / h.b == pytest.approx(1.0339 * ratio ** 0.636, rel=0.03)
    assert 2 * math.pi * h.a * h.b * h.p0 / 3 == pytest.approx(1e4, rel=1e-12)


@pytest.mark.parametrize("a,b", [(6e-3, 3e-3), (2e-3, 5e-3)])
def test_curvatures_and_semi_axes_are_inverse(a, b):
    # the two entry points solve Johnson (4.39) in opposite directions (Brent root vs direct)
    h = hertz_from_semi_axes(a, b, 2e4, ES)
    g = hertz_from_curvatures(h.A, h.B, 2e4, ES)
    assert (g.a, g.b) == pytest.approx((a, b), rel=1e-9)
    assert g.approach == pytest.approx(h.approach, rel=1e-9)


@pytest.mark.parametrize("a_over_b", [0.5, 1.0, 2.0])
def test_grid_normal_solution_matches_hertz(a_over_b):
    b = 4e-3
    a = a_over_b * b
    F = 40e3
    hz = hertz_from_semi_axes(a, b, F, ES)
    grid = Grid.covering(a, b, nx=60, ny=60, margin=0.15)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    k = rectangle_kernels(grid.nx, grid.ny, grid.dx, grid.dy, MAT.shear_modulus, MAT.poisson_ratio)
    gap = hz.A * X ** 2 + hz.B * Y ** 2
    byforce = solve_normal(k, gap, normal_force=F)
    byapproach = solve_normal(k, gap, approach=hz.approach)
    p = byforce.pressure
    area = grid.dx * grid.dy
    # 60 x 60 elements over 2.3 a x 2.3 b: discretisation error of force/approach/p0 ~ 0.1-0.4 %;
    # 1 % is the requirement
    assert byapproach.normal_force == pytest.approx(F, rel=0.01)
    assert byforce.approach == pytest.approx(hz.approach, rel=0.01)
    assert p.max() == pytest.approx(hz.p0, rel=0.01)
    # semi-axes from the second moments of the contact area: int x^2 dA = pi a^3 b / 4
    c = p > 0
    Ac = c.sum() * area
    a_num = math.sqrt(4 * (X[c] ** 2).sum() * area / Ac)
    b_num = math.sqrt(4 * (Y[c] ** 2).sum() * area / Ac)
    assert Ac == pytest.approx(math.pi * a * b, rel=0.02)  # staircase boundary: ~1 element row
    assert a_num == pytest.approx(a, rel=0.01)
    assert b_num == pytest.approx(b, rel=0.01)
    # pressure shape: rms deviation from the ellipsoid below 1 % of p0
    ref = hertz_pressure(X, Y, hz)
    assert np.sqrt(np.mean((p - ref)[c | (ref > 0)] ** 2)) < 0.01 * hz.p0
    # complementarity: gap closed where p > 0, open elsewhere (tolerance of the CG solver)
    e = gap - byforce.approach + byforce.displacement
    assert np.abs(e[c]).max() < 1e-6 * hz.approach
    assert e[~c].min() > -1e-6 * hz.approach
