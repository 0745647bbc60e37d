"""Hertz theory of an elliptic contact between quasi-identical bodies.

The undeformed gap is ``h(x, y) = A x^2 + B y^2`` (A, B in 1/m, the half sums of the principal
relative curvatures), x along rolling, y lateral. Semi-axes a (along x) and b (along y).
Formulas: Johnson, *Contact Mechanics* (1985), section 4.2, with the contact modulus
E* = G / (1 - nu) of two identical bodies. The complete elliptic integrals come from the
arithmetic-geometric mean (:func:`complete_elliptic_integrals`), exact to round-off in a few
iterations, instead of ``scipy.special``, whose import the contact command would otherwise pay
for these two numbers (docs/benchmarks.md, *Start-up*, *Lean start*).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from squealcore.errors import InputError, require_range

__all__ = ["HertzSolution", "hertz_from_curvatures", "hertz_from_semi_axes", "curvature_ratio",
           "hertz_pressure", "complete_elliptic_integrals", "axis_ratio_from_curvature_ratio"]

#: The arithmetic-geometric mean converges quadratically: the half gap c_{n+1} is about
#: c_n^2 / (4 a), so once c_n is below 1e-8 a the next is below 1e-17 a (round-off of a) and its
#: term 2^n c^2 of K - E below 1e-30: the iteration stops there. Waiting instead for a - b to
#: vanish can fail (a and b may stay one unit in the last place apart) and each further iteration
#: doubles the weight of that round-off.
_AGM_LAST_GAP = 1e-8
#: At most 12 iterations reach that gap for a complementary parameter down to 1e-300; the limit
#: only guards the loop.
_AGM_MAX_ITERATIONS = 64


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


def complete_elliptic_integrals(complementary_parameter):
    """Complete elliptic integrals K(m) and E(m) of the first and second kind, and K - E.

    Parameters
    ----------
    complementary_parameter : float
        ``m1 = 1 - m`` in (0, 1] (m = e^2, the parameter; for an elliptic contact m1 = (b/a)^2).
        Given as m1, not m, so that K stays accurate as m approaches 1 (a long, thin ellipse).

    Returns
    -------
    K, E, K_minus_E : float
        ``K(m)``, ``E(m)`` and ``K(m) - E(m)`` (dimensionless), the last without the cancellation
        of the difference for small m.

    Notes
    -----
    Gauss's arithmetic-geometric mean (Abramowitz & Stegun 17.6): a0 = 1, b0 = sqrt(m1),
    c0 = sqrt(m); a_{n+1} = (a_n + b_n)/2, b_{n+1} = sqrt(a_n b_n), c_{n+1} = (a_n - b_n)/2;
    K = pi / (2 a_N), K - E = K sum_{n>=0} 2^(n-1) c_n^2. Quadratic convergence: exact to
    round-off after at most 12 iterations down to m1 = 1e-300 (5 for m1 >= 0.01).
    """
    m1 = float(complementary_parameter)
    if not 0.0 < m1 <= 1.0:
        raise InputError("complementary_parameter", f"must lie in (0, 1], got {m1!r}")
    a, b = 1.0, math.sqrt(m1)
    weight = 0.5
    weighted_sum = weight * (1.0 - m1)  # n = 0: c0^2 = m
    for _ in range(_AGM_MAX_ITERATIONS):
        c = 0.5 * (a - b)
        a, b = 0.5 * (a + b), math.sqrt(a * b)
        weight *= 2.0
        weighted_sum += weight * c * c
        if c <= _AGM_LAST_GAP * a:  # the next gap, about c^2 / (4 a), is below round-off of a
            break
    K = math.pi / (2.0 * a)
    K_minus_E = K * weighted_sum
    return K, K - K_minus_E, K_minus_E


def _shape_integrals(g):
    """Return (K - E, (1/g^2) E - K, K) for ratio g = minor/major <= 1 (m = e^2 = 1 - g^2)."""
    K, E, K_minus_E = complete_elliptic_integrals(g * g)
    return K_minus_E, E / (g * g) - K, K


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


#: Bracket of :func:`axis_ratio_from_curvature_ratio`: curvature_ratio(1e-6) is about 7e10, above any
#: accepted ratio (<= 1e6), and curvature_ratio(1) = 1 below any ratio that is not taken as a circle.
_AXIS_RATIO_BRACKET = (1e-6, 1.0)
#: The bisection stops when the bracket is below 1e-14 + 1e-13 g (absolute and relative accuracy
#: of the semi-axis ratio g, about 45 halvings); the limit only guards the loop.
_AXIS_RATIO_XTOL, _AXIS_RATIO_RTOL, _BISECTION_MAX_ITERATIONS = 1e-14, 1e-13, 200


def axis_ratio_from_curvature_ratio(ratio: float) -> float:
    """Semi-axis ratio g = minor/major of the Hertz ellipse whose curvature ratio is ``ratio`` = B/A >= 1.

    Solves :func:`curvature_ratio` (g) = ``ratio`` by bisection on g in [1e-6, 1], where the
    ratio falls monotonically from about 7e10 to 1, to 1e-14 + 1e-13 g. Bisection rather than
    ``scipy.optimize.brentq``: the same root to that accuracy in about 45 evaluations, without
    importing scipy.optimize, a sizeable part of the contact command's start (docs/benchmarks.md,
    *Start-up*, *Lean start*).

    Parameters
    ----------
    ratio : float
        Larger over smaller gap curvature, in [1, 1e6].

    Returns
    -------
    float
        g in [1e-6, 1] (1 for ``ratio`` = 1).
    """
    if not 1.0 <= ratio <= 1e6:
        raise InputError("geometry.curvatures", f"ratio of curvatures must lie in [1, 1e6], got {ratio:g}")
    low, high = _AXIS_RATIO_BRACKET  # curvature_ratio(low) > ratio >= curvature_ratio(high)
    for _ in range(_BISECTION_MAX_ITERATIONS):
        if high - low <= _AXIS_RATIO_XTOL + _AXIS_RATIO_RTOL * low:
            break
        middle = 0.5 * (low + high)
        if curvature_ratio(middle) > ratio:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high) if ratio > 1.0 else 1.0


def hertz_from_curvatures(A: float, B: float, normal_force: float, contact_modulus: float) -> HertzSolution:
    """Hertz solution for gap curvatures A, B (1/m), load (N) and contact modulus E* (Pa).

    The semi-axis ratio follows from B/A (Johnson 4.39, solved by bisection:
    :func:`axis_ratio_from_curvature_ratio`), then the size from the load.
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
        g = axis_ratio_from_curvature_ratio(ratio)
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
