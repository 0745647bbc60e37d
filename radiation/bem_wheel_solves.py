r"""The BEM solves of the default wheel's axial modes that the fast model is fitted to and checked on.

Each row is one boundary-element solve (radiation/bem_compare.py, bempp-cl) of an axial mode with
n nodal diameters and no nodal circle of the default geometry's wheel, on the surface of the quick
study's mesh (3264 flat triangles, 24 elements around; ``pipeline.py run --quick --until
wheel-modes``), driven at its own frequency (``factor`` 1) or at half of it (0.5), with the mode's
surface integrals (radiation/surface.py) so that the fast model can be evaluated again without the
BEM. The efficiency is ``σ_BEM = W / (ρ c ½ (I_ax + I_rad))`` for a unit modal velocity amplitude.

The fast model's axial laws of n = 0…3 (radiation/efficiency.py) are the one-parameter fits
(:func:`fit_axial_corner`, minimax in dB) to these rows; n ≥ 4 keep the rim's corners k a = n + 1
and are only checked. The tests (tests/test_radiation.py) re-evaluate the fast model on these rows
without bempp-cl; tests/test_radiation_bem.py (slow) solves them again.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import minimize_scalar

from radiation.acoustics import SOUND_SPEED
from radiation.efficiency import wheel_axial_efficiency, wheel_radial_efficiency

#: Outer (tread) radius a and rim width b of the quick study's wheel mesh, m.
RADIUS = 0.418
RIM_WIDTH = 0.127

#: ``(n, factor, frequency Hz, σ_BEM, I_ax, I_rad)`` (I in m⁴/kg). n = 0, 1: σ to the three digits
#: recorded when their corners were fitted; n = 2, 3 to five digits from the solves of their fit
#: (their cost: docs/benchmarks.md, *Radiation*).
AXIAL_SOLVES = (
    (0, 1.0, 204.54, 0.333, 3.8221e-3, 2.1705e-4),
    (0, 0.5, 102.27, 0.0151, 3.8221e-3, 2.1705e-4),
    (1, 1.0, 137.90, 0.00172, 3.4609e-3, 3.2991e-4),
    (1, 0.5, 68.95, 0.000154, 3.4609e-3, 3.2991e-4),
    (2, 1.0, 396.351, 0.055665, 2.87502e-3, 6.50119e-4),
    (2, 0.5, 198.176, 0.00081183, 2.87502e-3, 6.50119e-4),
    (3, 1.0, 1114.99, 0.35419, 2.47833e-3, 9.99540e-4),
    (3, 0.5, 557.497, 0.066373, 2.47833e-3, 9.99540e-4),
)


def solves(n=None):
    """The stored solves as dicts (``n``, ``factor``, ``frequency``, ``ka``, ``sigma_bem``,
    ``axial_integral``, ``radial_integral``), all or those with n nodal diameters."""
    rows = [{"n": row[0], "factor": row[1], "frequency": row[2], "ka": 2 * np.pi * row[2] * RADIUS / SOUND_SPEED,
             "sigma_bem": row[3], "axial_integral": row[4], "radial_integral": row[5]} for row in AXIAL_SOLVES]
    return [row for row in rows if n is None or row["n"] == n]


def fast_efficiency(row, axial=None):
    """The fast model's efficiency of a stored mode, ``(σ_ax I_ax + σ_rad I_rad) / (I_ax + I_rad)``.

    ``axial``: σ_ax (-) to use instead of :func:`radiation.efficiency.wheel_axial_efficiency`.
    """
    f, n = row["frequency"], row["n"]
    sigma_ax = wheel_axial_efficiency(f, n, RADIUS) if axial is None else axial
    sigma_rad = wheel_radial_efficiency(f, n, RADIUS, RIM_WIDTH)
    total = row["axial_integral"] + row["radial_integral"]
    return float((sigma_ax * row["axial_integral"] + sigma_rad * row["radial_integral"]) / total)


def difference_db(row, axial=None):
    """Fast model minus BEM, dB."""
    return 10.0 * np.log10(fast_efficiency(row, axial) / row["sigma_bem"])


def fit_axial_corner(n, exponent):
    """k a of the corner of ``σ_ax = 1 / (1 + (κ/ka)^exponent)`` that minimises the largest |fast - BEM|
    in dB over the stored solves of n (the radial law as it is), and that largest difference.

    Returns
    -------
    (float, float)
        κ (-) and the residual (dB).
    """
    rows = solves(n)

    def worst(kappa):
        return max(abs(difference_db(row, 1.0 / (1.0 + (kappa / row["ka"]) ** exponent))) for row in rows)

    result = minimize_scalar(worst, bounds=(0.5, 30.0), method="bounded", options={"xatol": 1e-6})
    return float(result.x), float(result.fun)
