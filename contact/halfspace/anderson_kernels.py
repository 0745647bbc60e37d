"""Type-II Anderson mixing of the Gauss-Seidel sweeps, compiled (lazily, cached on disk).

The memory (:class:`~contact.halfspace.bundles.AndersonHistory`: :func:`anderson_history`,
:func:`carried_anderson_history`, and :func:`continue_history`, which keeps or forgets it for the
next solution), the input of a sweep (:func:`anderson_input`) and the mix after it
(:func:`anderson_mix`, its least squares :func:`_anderson_coefficients`). The exact sweeps
(tangential_kernels.py), the local ones (local_sweep_kernels.py) and the steady ones (steady.py)
share it. Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from contact.halfspace.bundles import AndersonHistory
from contact.kernels_linalg import cholesky_solve, inner_product


@numba.njit(cache=True)
def continue_history(history, keep):
    """Prepare an Anderson memory for a new solution: keep its differences (``keep``) or forget them.

    The differences of sweep outputs and residuals that the mixing fits depend only on the
    sweep's linear part (the influence coefficients between the listed elements and their
    stick/slip pattern), not on the rigid slip and previous displacements that change from one
    step to the next; so while the contact list stays the same they stay useful, and the first
    sweeps of the next solution can already be mixed (the reuse of earlier time steps' secant
    information in interface quasi-Newton methods: Degroote, Bathe & Vierendeels 2009). The last
    sweep's output is not paired with the next solution's first (a different fixed-point map),
    and the restart test starts afresh. A memory whose ``counters[3]`` is 0 is always forgotten.
    """
    if not keep or history.counters[3] == 0:
        history.counters[0] = 0
        history.counters[1] = -1
    history.counters[2] = 0
    history.last_change[0] = np.inf


@numba.njit(cache=True)
def _anderson_coefficients(gram, df, f, count, newest, slots, length):
    """Least-squares coefficients of type-II Anderson mixing.

    ``df[j]`` (a ring buffer of ``slots`` rows, ``newest`` the latest) holds differences of
    consecutive residuals in its first ``length`` entries (the memory may be sized for longer
    lists) and ``gram`` their inner products. Solves
    ``min |f - sum_a gamma_a df[newest - a]|`` over the ``count`` latest differences by the
    normal equations (Cholesky), each difference scaled to unit norm and the scaled system
    regularised by 1e-10 on its diagonal. Returns gamma (count,), newest first, or an empty array
    when the system is singular.

    The scaling matters because the remembered differences span many decades (a transient step
    of the local sweeps takes its residual down by about 1e9 over the memory's rounds): a
    regularisation by a fraction of the trace, which the oldest and largest differences make,
    swamps the newest and smallest, and the mixing then hardly uses them (the iterations saved:
    docs/benchmarks.md, *Contact solvers against CONTACT*).
    """
    g = np.empty((count, count))
    rhs = np.empty(count)
    slot = np.empty(count, np.int64)  # slot of the a-th newest difference (one modulo each, not count²)
    for a in range(count):
        slot[a] = (newest - a) % slots
    trace = 0.0
    for a in range(count):
        ia = slot[a]
        for b in range(count):
            g[a, b] = gram[ia, slot[b]]
        trace += g[a, a]
        rhs[a] = inner_product(df[ia], f, length)
    if trace <= 0.0:
        return np.empty(0)
    scale = np.empty(count)
    for a in range(count):
        if g[a, a] <= 0.0:
            return np.empty(0)
        scale[a] = 1.0 / math.sqrt(g[a, a])
    for a in range(count):
        rhs[a] *= scale[a]
        for b in range(count):
            g[a, b] *= scale[a] * scale[b]
        g[a, a] += 1e-10
    if not cholesky_solve(g, rhs, count):
        return np.empty(0)
    for a in range(count):
        rhs[a] *= scale[a]
    return rhs


@numba.njit(cache=True)
def anderson_history(depth, n, m):
    """An empty :class:`~contact.halfspace.bundles.AndersonHistory` of ``depth`` sweeps (at least one slot).

    n tractions and m displacement points per direction.
    """
    slots = max(depth, 1)
    return AndersonHistory(np.zeros((slots, 2 * n)), np.zeros((slots, 2 * n)), np.zeros((slots, 2 * m)),
                           np.zeros((slots, slots)), np.zeros(2 * n), np.zeros(2 * n), np.zeros(2 * n),
                           np.zeros(2 * n), np.zeros(2 * m), np.array([0, -1, 0, 0], np.int64), np.array([np.inf]))


@numba.njit(cache=True)
def carried_anderson_history(depth, n, m):
    """An empty :func:`anderson_history` whose differences :func:`continue_history` carries to the next solution."""
    history = anderson_history(depth, n, m)
    history.counters[3] = 1
    return history


@numba.njit(cache=True)
def anderson_input(history, px, py):
    """Record the tractions (Pa) that enter a sweep (the input x of the fixed-point map)."""
    n = px.shape[0]
    for c in range(n):
        history.x[c] = px[c]
        history.x[n + c] = py[c]


@numba.njit(cache=True)
def anderson_mix(history, change, px, py, ux, uy, restart=True):
    """Type-II Anderson mixing after a sweep; returns whether the tractions were replaced by the mix.

    The sweep mapped ``history.x`` (:func:`anderson_input`) to ``(px, py)`` (Pa) with the
    displacements ``(ux, uy)`` (m) and largest traction change ``change`` (Pa). The mix is
    ``G(x_k) - sum_j gamma_j (G(x_j+1) - G(x_j))`` over the remembered sweeps, gamma the
    least-squares fit of the residuals ``G(x) - x`` (:func:`_anderson_coefficients`); the
    displacements, affine in the tractions, are mixed with the same coefficients, so they stay
    consistent. With ``restart``, a sweep whose change grew restarts the history (the mixing
    did not help).
    """
    dg = history.dg
    df = history.df
    du = history.du
    gram = history.gram
    x = history.x
    f_now = history.f_now
    g_prev = history.g_prev
    f_prev = history.f_prev
    u_prev = history.u_prev
    slots = dg.shape[0]
    n = px.shape[0]
    m = ux.shape[0]
    count = history.counters[0]
    newest = history.counters[1]
    have_prev = history.counters[2] == 1
    if restart and change > history.last_change[0]:
        count = 0
        have_prev = False
    history.last_change[0] = change
    for c in range(n):
        f_now[c] = px[c] - x[c]
        f_now[n + c] = py[c] - x[n + c]
    # the loops below run over 1-D rows of the memory (``dg[j]``): indexed as 2-D arrays they are
    # not vectorised (docs/benchmarks.md, *The half-space time loop*; the same operations in the same order)
    if have_prev:
        newest = (newest + 1) % slots
        dg_new = dg[newest]
        du_new = du[newest]
        df_new = df[newest]
        for i in range(n):
            dg_new[i] = px[i] - g_prev[i]
        for i in range(n):
            dg_new[n + i] = py[i] - g_prev[n + i]
        for i in range(m):
            du_new[i] = ux[i] - u_prev[i]
        for i in range(m):
            du_new[m + i] = uy[i] - u_prev[m + i]
        for i in range(2 * n):
            df_new[i] = f_now[i] - f_prev[i]
        count = min(count + 1, slots)
        for a in range(count):
            j = (newest - a) % slots
            acc = inner_product(df[newest], df[j], 2 * n)
            gram[newest, j] = acc
            gram[j, newest] = acc
    for i in range(n):
        g_prev[i] = px[i]
        g_prev[n + i] = py[i]
    for i in range(m):
        u_prev[i] = ux[i]
        u_prev[m + i] = uy[i]
    for i in range(2 * n):
        f_prev[i] = f_now[i]
    history.counters[0] = count
    history.counters[1] = newest
    history.counters[2] = 1
    if count == 0:
        return False
    gamma = _anderson_coefficients(gram, df, f_now, count, newest, slots, 2 * n)
    if gamma.shape[0] == 0:
        return False
    for a in range(count):
        j = (newest - a) % slots
        ga = gamma[a]
        dg_j = dg[j]
        du_j = du[j]
        for i in range(n):
            px[i] -= ga * dg_j[i]
        for i in range(n):
            py[i] -= ga * dg_j[n + i]
        for i in range(m):
            ux[i] -= ga * du_j[i]
        for i in range(m):
            uy[i] -= ga * du_j[m + i]
    return True
