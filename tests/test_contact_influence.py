"""Half-space influence coefficients against independent integrals and point-load solutions."""

import math

import numpy as np
import pytest
from scipy.integrate import dblquad, quad

from contact.halfspace.influence import plane_strain_kernels, rectangle_influence, rectangle_kernels

G, NU = 80e9, 0.28

# scipy's quad warns about round-off near its 1e-11 target; the assertions check 1e-9
pytestmark = pytest.mark.filterwarnings("ignore::scipy.integrate.IntegrationWarning")


def polar_integral(weight, hx, hy, x0, y0):
    """int over the rectangle |x|<=hx, |y|<=hy of weight(theta)/r about an inner/edge point (x0, y0):
    = int_0^2pi weight(theta) R(theta) dtheta, R the distance to the boundary (1-D quadrature)."""
    def R(t):
        c, s = math.cos(t), math.sin(t)
        cand = []
        if c > 1e-15:
            cand.append((hx - x0) / c)
        if c < -1e-15:
            cand.append((-hx - x0) / c)
        if s > 1e-15:
            cand.append((hy - y0) / s)
        if s < -1e-15:
            cand.append((-hy - y0) / s)
        return max(min(cand), 0.0)

    pts = [math.atan2(sy * hy - y0, sx * hx - x0) % (2 * math.pi) for sx in (-1, 1) for sy in (-1, 1)]
    edges = sorted(set([0.0, 2 * math.pi] + pts))
    return sum(quad(lambda t: weight(t) * R(t), lo, hi, epsabs=0, epsrel=1e-11)[0]
               for lo, hi in zip(edges[:-1], edges[1:]))


@pytest.mark.parametrize("hx,hy", [(1e-3, 1e-3), (1e-3, 0.4e-3), (0.3e-3, 1e-3)])
@pytest.mark.parametrize("where", ["centre", "corner", "inside"])
def test_uniform_rectangle_matches_polar_quadrature(hx, hy, where):
    x0, y0 = {"centre": (0.0, 0.0), "corner": (hx, hy), "inside": (0.3 * hx, -0.6 * hy)}[where]
    k = rectangle_influence(x0, y0, hx, hy, G, NU)
    c = 1.0 / (math.pi * G)
    ref33 = c * (1 - NU) * polar_integral(lambda t: 1.0, hx, hy, x0, y0)
    ref11 = c * polar_integral(lambda t: (1 - NU) + NU * math.cos(t) ** 2, hx, hy, x0, y0)
    ref22 = c * polar_integral(lambda t: (1 - NU) + NU * math.sin(t) ** 2, hx, hy, x0, y0)
    ref12 = c * NU * polar_integral(lambda t: math.cos(t) * math.sin(t), hx, hy, x0, y0)
    # closed form vs adaptive 1-D quadrature of an independent formulation: 1e-9 is the
    # quadrature accuracy, far above round-off of the closed form
    assert k["33"] == pytest.approx(ref33, rel=1e-9)
    assert k["11"] == pytest.approx(ref11, rel=1e-9)
    assert k["22"] == pytest.approx(ref22, rel=1e-9)
    assert k["12"] == pytest.approx(ref12, rel=1e-9, abs=1e-9 * ref11)


def test_square_centre_and_corner_classical_constants():
    # Love (1929) / Timoshenko & Goodier: square of side B under p, one body,
    # w_centre = 1.1222 p B (1-nu^2)/E, w_corner = 0.5611 p B (1-nu^2)/E (4 ln(1+sqrt2)/pi = 1.12219).
    # Two identical bodies double it; (1-nu^2)/E = (1-nu)/(2G).
    B = 2e-3
    one_body = (1 - NU) / (2 * G) * B
    centre = rectangle_influence(0.0, 0.0, B / 2, B / 2, G, NU)["33"] / 2
    corner = rectangle_influence(B / 2, B / 2, B / 2, B / 2, G, NU)["33"] / 2
    assert centre / one_body == pytest.approx(4 * math.log(1 + math.sqrt(2)) / math.pi, rel=1e-12)
    assert centre / one_body == pytest.approx(1.1222, abs=5e-5)  # published to 4 decimals
    assert corner / one_body == pytest.approx(0.5611, abs=5e-5)


@pytest.mark.parametrize("xy", [(15, 0), (0, 15), (10, 12), (-14, 7)])
def test_far_field_is_boussinesq_cerruti_point_load(xy):
    # a unit traction on a 1 mm^2 element seen from 10-15 element sizes acts like a point
    # load P = dx dy; the relative error of that approximation is O((h/r)^2) ~ 1e-3
    h = 1e-3
    x, y = xy[0] * h, xy[1] * h
    r = math.hypot(x, y)
    k = rectangle_influence(x, y, h / 2, h / 2, G, NU)
    P = h * h
    c = P / (math.pi * G)
    assert k["33"] == pytest.approx(c * (1 - NU) / r, rel=2e-3)
    assert k["11"] == pytest.approx(c * ((1 - NU) / r + NU * x * x / r ** 3), rel=2e-3)
    assert k["22"] == pytest.approx(c * ((1 - NU) / r + NU * y * y / r ** 3), rel=2e-3)
    assert k["12"] == pytest.approx(c * NU * x * y / r ** 3, rel=5e-3, abs=2e-3 * c / r)


def test_neighbour_element_against_dblquad():
    # adjacent and diagonal elements: 2-D adaptive quadrature of the point kernels (smooth there)
    h = 1e-3
    for x, y in [(h, 0.0), (h, h), (2 * h, -h)]:
        k = rectangle_influence(x, y, h / 2, h / 2, G, NU)
        f = lambda yy, xx: 1.0 / math.hypot(x - xx, y - yy)
        g = lambda yy, xx: (x - xx) * (y - yy) / math.hypot(x - xx, y - yy) ** 3
        i1 = dblquad(f, -h / 2, h / 2, -h / 2, h / 2, epsabs=0, epsrel=1e-9)[0]
        i2 = dblquad(g, -h / 2, h / 2, -h / 2, h / 2, epsabs=0, epsrel=1e-9)[0]
        assert k["33"] == pytest.approx((1 - NU) / (math.pi * G) * i1, rel=1e-7)  # quadrature accuracy (epsrel 1e-9)
        assert k["12"] == pytest.approx(NU / (math.pi * G) * i2, rel=1e-7, abs=1e-12 * k["33"])


def test_toeplitz_fft_product_equals_dense_sum():
    rng = np.random.default_rng(1)
    k = rectangle_kernels(7, 5, 1e-3, 0.6e-3, G, NU)
    p = rng.random((7, 5, 2))
    u = k.tangential_displacement(p)
    dense = np.zeros((7, 5, 2))
    for i in range(7):
        for j in range(5):
            a = i - np.arange(7)[:, None] + 6
            b = j - np.arange(5)[None, :] + 4
            dense[i, j, 0] = (k.K11[a, b] * p[..., 0] + k.K12[a, b] * p[..., 1]).sum()
            dense[i, j, 1] = (k.K12[a, b] * p[..., 0] + k.K22[a, b] * p[..., 1]).sum()
    # FFT vs direct summation: round-off only
    assert np.abs(u - dense).max() <= 1e-12 * np.abs(dense).max()


def test_plane_strain_kernel_gradient_matches_hilbert_transform():
    # 2-D: d u_x/dx = -(2(1-nu)/(pi G)) int q(s)/(x-s) ds; for q = sqrt(1-s^2/a^2) the integral
    # is pi x / a (Johnson 1985, eq. 2.41 family). Discrete strips of width a/200: the
    # central-difference gradient matches to 1 % away from the edges.
    a, n = 1e-2, 400
    dx = 2.4 * a / n
    k = plane_strain_kernels(n, dx, G, NU)
    x = (np.arange(n) - (n - 1) / 2) * dx
    q = np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))
    u = k.operator("11")(q[:, None])[:, 0]
    grad = np.gradient(u, dx)
    ref = -(2 * (1 - NU) / (math.pi * G)) * math.pi * x / a
    inner = np.abs(x) < 0.8 * a
    assert np.abs(grad[inner] - ref[inner]).max() <= 0.01 * np.abs(ref[inner]).max()
