"""The steps every compiled time loop of the interaction shares (numba, compiled lazily, cached on disk).

A contact model's compiled loop (``contact/point/loop.py``, ``contact/halfspace/loop.py``) runs
the time stepping of interaction/simulate.py with the wheel as a pole-residue recursion and the
rail as a convolution, on the bundles of interaction/bundles.py. What does not depend on the
contact model lives here: the structures' displacement histories at a step
(:func:`structural_histories`), the commit of a step's force (:func:`commit_step`), the step's
outputs (:func:`store_step`), the sensitivity of the contact inputs to the force
(:func:`input_sensitivity`) with a 3 x 3 solve (:func:`solve3`), and the linear prediction of
the force that gives each step its first trial (:func:`fit_prediction`, :func:`predict_force`).
A loop returns ``state.failure`` codes :data:`RUNAWAY` or :data:`NOT_CONVERGED`. Nothing is
compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np

from contact.kernels_linalg import cholesky_solve, inner_product
from interaction.creepage import total_creepage

RUNAWAY = 4
"""``LoopState.failure``: the force is not finite or exceeds the runaway bound."""
NOT_CONVERGED = 5
"""``LoopState.failure``: the coupling iteration did not converge."""


@numba.njit(cache=True)
def structural_histories(structures, state, hist_w, hist_r, step):
    """Wheel and rail displacements (3,) at ``step`` due to all earlier forces (m), in place.

    The wheel's from its recursion states ``state.wheel`` (m, 3) and weights (m, 3, 3); the
    rail's from the force buffer ``state.rail``, which holds every force twice so that the
    last ``nk`` forces, newest first, are the contiguous slice ``rail[head:head + nk]``, plus
    the forces beyond the near kernel, ``state.far`` (summed per block by FFT; zero when the
    kernel has no far part).
    """
    weights = structures.wheel_weights
    rail_rows = structures.rail_rows
    h = state.wheel
    buffer = state.rail
    head = state.head[0]
    m = h.shape[0]
    nk = rail_rows.shape[1] // 3
    for i in range(3):
        acc = 0.0
        for r in range(m):
            for j in range(3):
                acc += 2.0 * (weights[r, i, j] * h[r, j]).real
        hist_w[i] = acc
    # the rail's sum: kernel row i against the last nk forces, both flat and contiguous
    forces = buffer.reshape(-1)[3 * head:3 * (head + nk)]  # forces[3 q + j] = buffer[head + q, j]
    for i in range(3):
        hist_r[i] = inner_product(rail_rows[i], forces, 3 * nk)
    k = step - state.far_start[0]
    if 0 <= k < state.far.shape[0]:
        for i in range(3):
            hist_r[i] += state.far[k, i]


@numba.njit(cache=True)
def commit_step(structures, state, df):
    """Advance the structures by one step with the force deviation ``df`` (3,).

    Wheel recursion ``h[n+1] = z (h[n] + dF[n])``; the rail buffer gets ``df`` as its newest force.
    """
    z = structures.wheel_z
    h = state.wheel
    buffer = state.rail
    for r in range(h.shape[0]):
        for j in range(3):
            h[r, j] = z[r] * (h[r, j] + df[j])
    nk = buffer.shape[0] // 2
    if nk == 0:
        return
    head = (state.head[0] - 1) % nk
    for j in range(3):
        buffer[head, j] = df[j]
        buffer[head + nk, j] = df[j]
    state.head[0] = head


@numba.njit(cache=True)
def store_step(n, f, hist_w, hist_r, structures, coupling, state, df, out):
    """Write step n's outputs for the converged force ``f`` and move the previous displacements on.

    ``df`` (out) receives the force deviation of the step.
    """
    k0_wheel = structures.wheel_k0
    k0_rail = structures.rail_k0
    uw_prev = state.wheel_previous
    ur_prev = state.rail_previous
    time_step = coupling.time_step
    speed = coupling.speed
    creepage = coupling.creepage
    force = out.force
    wheel_u = out.wheel_displacement
    rail_u = out.rail_displacement
    df[0] = f[0]
    df[1] = f[1]
    df[2] = f[2] - coupling.load
    for i in range(3):
        uw = hist_w[i] + k0_wheel[i, 0] * df[0] + k0_wheel[i, 1] * df[1] + k0_wheel[i, 2] * df[2]
        ur = -(hist_r[i] + k0_rail[i, 0] * df[0] + k0_rail[i, 1] * df[1] + k0_rail[i, 2] * df[2])
        force[n, i] = f[i]
        wheel_u[n, i] = uw
        rail_u[n, i] = ur
        out.wheel_velocity[n, i] = (uw - uw_prev[i]) / time_step
        out.rail_velocity[n, i] = (ur - ur_prev[i]) / time_step
    for i in range(2):
        out.creepage[n, i] = total_creepage(creepage[i], (wheel_u[n, i] - uw_prev[i]) - (rail_u[n, i] - ur_prev[i]),
                                            time_step, speed, True)
    out.creepage[n, 2] = creepage[2]
    for i in range(3):
        uw_prev[i] = wheel_u[n, i]
        ur_prev[i] = rail_u[n, i]




@numba.njit(cache=True)
def input_sensitivity(structures, coupling):
    """d(approach, ξ, η)/dF (3, 3) of the contact's inputs to the trial force (m/N, 1/N, 1/N).

    Through the instantaneous compliance ``C = k_w[0] + k_r[0]`` of the relative displacement:
    the approach falls by ``C[2] dF``, the creepages rise by ``C[0:2] dF / (Δt v)``.
    """
    out = np.empty((3, 3))
    scale = 1.0 / (coupling.time_step * coupling.speed)
    for j in range(3):
        c0 = structures.wheel_k0[0, j] + structures.rail_k0[0, j]
        c1 = structures.wheel_k0[1, j] + structures.rail_k0[1, j]
        c2 = structures.wheel_k0[2, j] + structures.rail_k0[2, j]
        out[0, j] = -c2
        out[1, j] = c0 * scale
        out[2, j] = c1 * scale
    return out


@numba.njit(cache=True)
def solve3(m, r, x):
    """``x = -m^-1 r`` for a 3 x 3 ``m`` by Cramer's rule, in place; False (x untouched) if singular."""
    c00 = m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]
    c01 = m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2]
    c02 = m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]
    det = m[0, 0] * c00 + m[0, 1] * c01 + m[0, 2] * c02
    if not (det != 0.0 and np.isfinite(det)):
        return False
    inv = -1.0 / det
    x0 = inv * (c00 * r[0] + (m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2]) * r[1]
                + (m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]) * r[2])
    x1 = inv * (c01 * r[0] + (m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0]) * r[1]
                + (m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]) * r[2])
    x2 = inv * (c02 * r[0] + (m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1]) * r[1]
                + (m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]) * r[2])
    if not (np.isfinite(x0) and np.isfinite(x1) and np.isfinite(x2)):
        return False
    x[0] = x0
    x[1] = x1
    x[2] = x2
    return True


#: Halvings of a Newton step of the point loop's coupling before it is taken as it is.


PREDICTION_ORDER = 30
"""Past forces that the linear prediction of the half-space loop's first coupling pass combines."""
PREDICTION_WINDOW = 300
"""Steps over which the prediction's coefficients are fitted (least squares)."""
PREDICTION_REFIT = 32
"""Steps between fits of the prediction: its coefficients at step n are fitted on the forces
before the last multiple of this at or below n (the same for any split of a run into chunks)."""


@numba.njit(cache=True)
def fit_prediction(force, end, coef, mean, use):
    """Fit the linear prediction of each force direction on the forces ``force[:end]`` (N).

    Per direction j, the model ``y[n] - c = sum_k a_k (y[n - k] - c)`` (k = 1 ..
    :data:`PREDICTION_ORDER`, c the mean of the forces used) is fitted by least squares (normal
    equations, Cholesky, regularised by 1e-12 of their trace) to the targets of the last
    :data:`PREDICTION_WINDOW` steps before ``end``. A constant plus h sinusoids obeys such a
    recursion exactly for an order of at least 2 h + 1, so a limit cycle of a few harmonics is predicted far
    better than by linear extrapolation ``2 y[n - 1] - y[n - 2]``. ``coef[j]`` receives a_k,
    ``mean[j]`` c, and ``use[j]`` 1 where the model's root-mean-square one-step error over the
    window is below the extrapolation's (0: extrapolate). Needs ``end >= window + order``.
    """
    order = coef.shape[1]
    window = PREDICTION_WINDOW
    gram = np.empty((order, order))
    rhs = np.empty(order)
    y = np.empty(window + order)  # y[k]: the force at step end - window - order + k, less the mean
    base = end - window - order
    for j in range(3):
        use[j] = 0
        c = 0.0
        for n in range(base, end):
            c += force[n, j]
        c /= window + order
        mean[j] = c
        for k in range(window + order):
            y[k] = force[base + k, j] - c
        # the targets are y[order:], lag a the same window shifted back by 1 + a: rhs and the first
        # column of the normal matrix are inner products of shifted windows, and each further entry
        # follows from its upper-left neighbour by one product in and one out (the window slides)
        target = y[order:]
        first = y[order - 1:order - 1 + window]
        for a in range(order):
            lagged = y[order - 1 - a:order - 1 - a + window]
            rhs[a] = inner_product(lagged, target, window)
            gram[a, 0] = inner_product(lagged, first, window)
        for b in range(order - 1):
            for a in range(b, order - 1):
                gram[a + 1, b + 1] = (gram[a, b] + y[order - 2 - a] * y[order - 2 - b]
                                      - y[order + window - 2 - a] * y[order + window - 2 - b])
        trace = 0.0
        for a in range(order):
            trace += gram[a, a]
        if not trace > 0.0:
            continue
        for a in range(order):  # regularised normal equations
            gram[a, a] += 1e-12 * trace
        if not cholesky_solve(gram, rhs, order):
            continue
        fit_error = 0.0
        extrapolation_error = 0.0
        for k in range(order, order + window):
            model = 0.0
            for a in range(order):
                model += rhs[a] * y[k - 1 - a]
            fit_error += (y[k] - model) ** 2
            extrapolation_error += (y[k] - 2.0 * y[k - 1] + y[k - 2]) ** 2
        for a in range(order):
            coef[j, a] = rhs[a]
        if fit_error < extrapolation_error:
            use[j] = 1


@numba.njit(cache=True)
def predicted(force, step, j, coef, mean):
    """Force of direction ``j`` at ``step`` (N) predicted from ``force[:step]`` (:func:`fit_prediction`)."""
    acc = mean[j]
    for a in range(coef.shape[1]):
        acc += coef[j, a] * (force[step - 1 - a, j] - mean[j])
    return acc


@numba.njit(cache=True)
def predict_force(force, step, f, coef, mean, use, fitted_at):
    """The trial force ``f`` (3,) of ``step``'s first coupling pass from the linear prediction, in place.

    Refits the prediction (:func:`fit_prediction`) on the forces before the last multiple of
    :data:`PREDICTION_REFIT` at or below ``step`` when that differs from ``fitted_at`` and enough
    steps exist; then replaces ``f[j]`` by the prediction in the directions where it is in use
    (elsewhere ``f`` keeps the caller's linear extrapolation). Returns the step the coefficients
    were fitted at (-1: not yet).
    """
    fit_end = step - step % PREDICTION_REFIT
    if fit_end < PREDICTION_WINDOW + PREDICTION_ORDER:
        return fitted_at
    if fitted_at != fit_end:
        fit_prediction(force, fit_end, coef, mean, use)
        fitted_at = fit_end
    for i in range(3):
        if use[i]:
            f[i] = predicted(force, step, i, coef, mean)
    return fitted_at
