"""The friction law of one contact element, compiled (lazily, cached on disk).

:func:`element_law` is the Gauss-Seidel update of one element with the other elements'
tractions held fixed: stick if the traction that cancels its slip lies within the static bound,
else the sliding traction on the kinetic bound (:func:`_local_slip`, Newton's method). The
transient sweeps (tangential_kernels.py) and the steady ones (steady.py) use it. With a friction
characteristic of the sliding speed (contact/friction_law.py), :func:`element_law_characteristic`
evaluates the kinetic bound at the element's own slip over the step (:func:`sliding_factor`).
Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba

from contact.friction_law import EXPONENTIAL, LINEAR


SLIP_NEWTON_STEP = 1e-8
"""A Newton step of :func:`_local_slip` below this fraction of its slip scale is the last one
(quadratic convergence: the error after it is below 1e-15 of the scale). The test used to wait
for a step of 1e-14, one more iteration for almost every sliding element (its cost:
docs/benchmarks.md, *Contact solvers against CONTACT*)."""


@numba.njit(cache=True)
def _local_slip(cx, cy, dxx, dyy, g):
    """Traction of one slipping element.

    Solve s = c + D p with p = -g s/|s| (D = diag(dxx, dyy) > 0). With sigma = |s|:
    s_k = c_k sigma / (sigma + g d_k), and sigma solves sum c_k^2/(sigma + g d_k)^2 = 1
    (monotone and convex: Newton from the equal-diagonal solution converges quadratically).
    Newton stops after a step below :data:`SLIP_NEWTON_STEP` of ``|c| + g (dxx + dyy) / 2``:
    the error left after it is of the order of the step squared over sigma + g d (< |c|), i.e.
    below 1e-15 of |c|. Both reciprocals of an iteration come from one division.
    """
    cn2 = cx * cx + cy * cy
    cn = math.sqrt(cn2)
    if g <= 0.0 or cn == 0.0:
        return 0.0, 0.0
    dm = 0.5 * (dxx + dyy)
    # start from the exact solution for a compliance equal in both directions, weighted by the
    # slip's direction (first order in the difference of dxx and dyy): one Newton step then lands
    # at round-off where the plain mean dm needs two or three
    sig = max(cn - g * (cx * cx * dxx + cy * cy * dyy) / cn2, 0.0)
    small_step = SLIP_NEWTON_STEP * (cn + g * dm)
    for _ in range(30):
        ax = sig + g * dxx
        ay = sig + g * dyy
        r = 1.0 / (ax * ay)
        rx = ay * r
        ry = ax * r
        tx = cx * cx * rx * rx
        ty = cy * cy * ry * ry
        f = tx + ty - 1.0
        df = -2.0 * (tx * rx + ty * ry)
        step = f / df
        new = sig - step
        if new < 0.0:
            new = 0.5 * sig
        if abs(new - sig) <= small_step:
            sig = new
            break
        sig = new
    return -g * cx / (sig + g * dxx), -g * cy / (sig + g * dyy)


@numba.njit(cache=True)
def element_law(sx, sy, px, py, dxx, dyy, static_bound, kinetic_bound):
    """The Gauss-Seidel update of one contact element: its traction with the others' held fixed.

    ``(sx, sy)`` is the element's slip (m) with its current traction ``(px, py)`` (Pa) in it,
    ``dxx, dyy`` its own compliances (m/Pa). Stick if the traction that cancels the slip lies
    within the static bound (Pa), else the sliding traction on the kinetic bound
    (:func:`_local_slip`). Returns ``(qx, qy, sliding)``.
    """
    cx = sx - dxx * px
    cy = sy - dyy * py
    qx = -cx / dxx
    qy = -cy / dyy
    if qx * qx + qy * qy <= static_bound * static_bound:
        return qx, qy, False
    qx, qy = _local_slip(cx, cy, dxx, dyy, kinetic_bound)
    return qx, qy, True


#: Most safeguarded Newton iterations of :func:`element_law_characteristic`.
CHARACTERISTIC_ITERATIONS = 100


@numba.njit(cache=True)
def sliding_factor(law, x):
    """``φ(x)`` of a :class:`~contact.friction_law.FrictionLaw` at a sliding measure ``x >= 0``
    (speed, m/s, or slip over a step, m, as the law's rate is given): the sliding coefficient is
    the base coefficient times it (contact/friction_law.py)."""
    if law.kind == EXPONENTIAL:
        return 1.0 + law.amplitude * math.exp(-law.rate * x)
    if law.kind == LINEAR:
        return max(1.0 + law.rate * x, 0.0)
    return 1.0


@numba.njit(cache=True)
def sliding_factor_slope(law, x):
    """``dφ/dx`` at ``x >= 0`` (s/m or 1/m; 0 where the linear law is clipped at zero)."""
    if law.kind == EXPONENTIAL:
        return -law.amplitude * law.rate * math.exp(-law.rate * x)
    if law.kind == LINEAR:
        return law.rate if 1.0 + law.rate * x > 0.0 else 0.0
    return 0.0


@numba.njit(cache=True)
def element_law_characteristic(sx, sy, px, py, dxx, dyy, static_bound, kinetic_bound, law):
    """:func:`element_law` with the kinetic bound a function of the element's slip.

    The sliding traction's size is ``g(σ) = kinetic_bound * φ(σ)`` with ``σ`` the element's slip
    over the step (m) once it slides, ``law``'s rate per metre of slip (the sliding speed is
    ``σ / Δt``). As in :func:`_local_slip`, ``s = c + D p`` with ``p = -g(σ) s/σ`` gives
    ``s_k = c_k σ / (σ + g(σ) d_k)``, and ``σ`` solves
    ``F(σ) = Σ c_k² / (σ + g(σ) d_k)² - 1 = 0``. ``F(0) > 0`` where the element slides (its stick
    traction exceeds the bound at rest) and ``F(|c|) <= 0``, so a root lies in ``(0, |c|]``: it is
    found by Newton steps kept inside the bracket (bisection where a step would leave it), which
    converge for any characteristic, however steep (a steeply falling one may have several
    roots; one of them is taken). Stick as in :func:`element_law`. Returns ``(qx, qy, sliding)``.
    """
    cx = sx - dxx * px
    cy = sy - dyy * py
    qx = -cx / dxx
    qy = -cy / dyy
    if qx * qx + qy * qy <= static_bound * static_bound:
        return qx, qy, False
    cx2 = cx * cx
    cy2 = cy * cy
    cn = math.sqrt(cx2 + cy2)
    if cn == 0.0:
        return 0.0, 0.0, True
    lo = 0.0
    hi = cn
    # start from the slip of the bound at rest (Coulomb's solution at g(0), direction-weighted)
    g0 = kinetic_bound * sliding_factor(law, 0.0)
    sig = min(max(cn - g0 * (cx2 * dxx + cy2 * dyy) / (cn * cn), 0.0), cn)
    small_step = SLIP_NEWTON_STEP * (cn + g0 * 0.5 * (dxx + dyy))
    for _ in range(CHARACTERISTIC_ITERATIONS):
        g = kinetic_bound * sliding_factor(law, sig)
        dg = kinetic_bound * sliding_factor_slope(law, sig)
        ax = sig + g * dxx
        ay = sig + g * dyy
        if ax <= 0.0 or ay <= 0.0:  # only at sig = 0 with g = 0: no traction
            return 0.0, 0.0, True
        tx = cx2 / (ax * ax)
        ty = cy2 / (ay * ay)
        f = tx + ty - 1.0
        if f > 0.0:
            lo = sig
        else:
            hi = sig
        df = -2.0 * (tx * (1.0 + dg * dxx) / ax + ty * (1.0 + dg * dyy) / ay)
        new = sig - f / df if df != 0.0 else -1.0
        if not (lo < new < hi):
            new = 0.5 * (lo + hi)
        if abs(new - sig) <= small_step:
            sig = new
            break
        sig = new
    g = kinetic_bound * sliding_factor(law, sig)
    return -g * cx / (sig + g * dxx), -g * cy / (sig + g * dyy), True
