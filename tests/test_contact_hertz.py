"""Hertz formulas and the grid normal solver against Hertz theory."""

import math

import numpy as np
import pytest

from interaction.contact.halfspace import Grid
from interaction.contact.hertz import hertz_from_curvatures, hertz_from_semi_axes, hertz_pressure
from interaction.contact.influence import rectangle_kernels
from interaction.contact.normal import solve_normal
from interaction.contact.params import Material

MAT = Material.from_young(210e9, 0.3)
ES = MAT.contact_modulus


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
