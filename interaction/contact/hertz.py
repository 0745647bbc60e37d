"""Hertz theory of an elliptic contact between quasi-identical bodies.

The undeformed gap is ``h(x, y) = A x^2 + B y^2`` (A, B in 1/m, the half sums of the principal
relative curvatures), x along rolling, y lateral. Semi-axes a (along x) and b (along y).
Formulas: Johnson, *Contact Mechanics* (1985), section 4.2, with the contact modulus
E* = G / (1 - nu) of two identical bodies.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.special import ellipe, ellipkm1

from squealcore.errors import InputError, require_range

__all__ = ["HertzSolution", "hertz_from_curvatures", "hertz_from_semi_axes", "curvature_ratio",
           "hertz_pressure"]


@dataclass(frozen=True)
class HertzSolution:
    """Hertz solution (SI units).

    Attributes
    ----------
    a, b : float
        Semi-axes along x (rolling) and y (lateral) (m).
    A, B : float
        Gap curvatures, h = A x^2 + B y^2 (1/m).
    normal_force : float
        Normal load (N).
    approach : float
        Mutual approach of distant points delta (m).
    p0 : float
        Maximum pressure (Pa), p = p0 sqrt(1 - x^2/a^2 - y^2/b^2).
    """

    a: float
    b: float
    A: float
    B: float
    normal_force: float
    approach: float
    p0: float

    def scaled(self, normal_force: float) -> "HertzSolution":
        """The same geometry at another load: a, b ~ F^(1/3), delta ~ F^(2/3), p0 ~ F^(1/3)."""
        s = (normal_force / self.normal_force) ** (1.0 / 3.0)
        return HertzSolution(self.a * s, self.b * s, self.A, self.B, normal_force,
                             self.approach * s * s, self.p0 * s)


def _shape_integrals(g):
    """Return (K - E, (1/g^2) E - K, K) for ratio g = minor/major <= 1 (m = e^2 = 1 - g^2)."""
    m = 1.0 - g * g
    K = ellipkm1(g * g)  # accurate K(m) near m = 1
    E = ellipe(m)
    return K - E, E / (g * g) - K, K


def curvature_ratio(g: float) -> float:
    """Ratio of the larger to the smaller gap curvature for a semi-axis ratio g = minor/major.

    Johnson (4.39): B/A = [(a/b)^2 E(e) - K(e)] / [K(e) - E(e)], e^2 = 1 - g^2.
    """
    if g >= 1.0:
        return 1.0
    kme, num, _ = _shape_integrals(g)
    return num / kme


def hertz_from_semi_axes(a: float, b: float, normal_force: float, contact_modulus: float) -> HertzSolution:
    """Hertz solution for given semi-axes a, b (m), load (N) and contact modulus E* (Pa)."""
    a = require_range("geometry.semi_axes.a", a, 0.0, None, low_open=True, unit="m")
    b = require_range("geometry.semi_axes.b", b, 0.0, None, low_open=True, unit="m")
    normal_force = require_range("load.normal_force", normal_force, 0.0, None, low_open=True, unit="N")
    major, minor = max(a, b), min(a, b)
    g = minor / major
    p0 = 3.0 * normal_force / (2.0 * math.pi * a * b)
    if g >= 1.0 - 1e-9:
        curv_small = math.pi * p0 / (4.0 * contact_modulus * major)  # circle: A = pi p0 / (4 E* a)
        curv_large = curv_small
        approach = math.pi * p0 * major / (2.0 * contact_modulus)
    else:
        e2 = 1.0 - g * g
        kme, num, K = _shape_integrals(g)
        curv_small = p0 * minor / (contact_modulus * e2 * major ** 2) * kme
        curv_large = p0 * minor / (contact_modulus * e2 * major ** 2) * num
        approach = p0 * minor * K / contact_modulus
    A, B = (curv_small, curv_large) if a >= b else (curv_large, curv_small)
    return HertzSolution(float(a), float(b), float(A), float(B), float(normal_force), float(approach),
                         float(p0))


def hertz_from_curvatures(A: float, B: float, normal_force: float, contact_modulus: float) -> HertzSolution:
    """Hertz solution for gap curvatures A, B (1/m), load (N) and contact modulus E* (Pa).

    The semi-axis ratio follows from B/A (Johnson 4.39, solved with Brent's method), then the
    size from the load.
    """
    A = require_range("geometry.curvatures.A", A, 0.0, None, low_open=True, unit="1/m")
    B = require_range("geometry.curvatures.B", B, 0.0, None, low_open=True, unit="1/m")
    normal_force = require_range("load.normal_force", normal_force, 0.0, None, low_open=True, unit="N")
    ratio = max(A, B) / min(A, B)
    if ratio > 1e6:
        raise InputError("geometry.curvatures", f"ratio of curvatures must be <= 1e6, got {ratio:g}")
    if ratio - 1.0 < 1e-10:
        g = 1.0
    else:
        from scipy.optimize import brentq  # lazy: scipy.optimize, 0.18 s of start-up (measured)
        g = brentq(lambda t: curvature_ratio(t) - ratio, 1e-6, 1.0 - 1e-9, xtol=1e-14, rtol=1e-13)
    # size from the smaller curvature: c_small = 3 F (K - E) / (2 pi E* major^3 e^2)
    if g >= 1.0:
        major = (3.0 * normal_force / (8.0 * contact_modulus * min(A, B))) ** (1.0 / 3.0)
    else:
        kme, _, _ = _shape_integrals(g)
        e2 = 1.0 - g * g
        major = (3.0 * normal_force * kme / (2.0 * math.pi * contact_modulus * min(A, B) * e2)) ** (1.0 / 3.0)
    minor = g * major
    a, b = (major, minor) if A <= B else (minor, major)
    return hertz_from_semi_axes(a, b, normal_force, contact_modulus)


def hertz_pressure(x, y, sol: HertzSolution):
    """Hertz pressure p0 sqrt(1 - x^2/a^2 - y^2/b^2) (Pa) at points x, y (m), zero outside."""
    r2 = 1.0 - (np.asarray(x) / sol.a) ** 2 - (np.asarray(y) / sol.b) ** 2
    return sol.p0 * np.sqrt(np.clip(r2, 0.0, None))
