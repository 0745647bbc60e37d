"""Numba kernels of the linear stability screen (stability/screen.py): the roots of the
closed loop's characteristic function of a rational (pole-residue) model, by the Aberth–Ehrlich
iteration (:func:`aberth_rational_roots`) from the first-order estimates of
:func:`first_order_roots`. Compiled lazily on first call, cached on disk; nothing is compiled at
import time.
"""

from __future__ import annotations

import numba
import numpy as np


@numba.njit(cache=True)
def _trace_of_solve(m, md, k):
    """``trace(M⁻¹ M')`` of two complex k×k matrices (overwritten): Gaussian elimination with
    partial pivoting on ``[M | M']``, then the diagonal of the back-substituted solution."""
    for c in range(k):
        piv = c
        for r in range(c + 1, k):
            if abs(m[r, c]) > abs(m[piv, c]):
                piv = r
        if piv != c:
            for j in range(k):
                m[c, j], m[piv, j] = m[piv, j], m[c, j]
                md[c, j], md[piv, j] = md[piv, j], md[c, j]
        if m[c, c] == 0:
            return complex(np.nan, np.nan)
        inv = 1.0 / m[c, c]
        for r in range(c + 1, k):
            f = m[r, c] * inv
            if f != 0:
                for j in range(c, k):
                    m[r, j] -= f * m[c, j]
                for j in range(k):
                    md[r, j] -= f * md[c, j]
    for r in range(k - 1, -1, -1):  # back substitution, column by column of M'
        for j in range(k):
            s = md[r, j]
            for c in range(r + 1, k):
                s -= m[r, c] * md[c, j]
            md[r, j] = s / m[r, r]
    t = 0j
    for r in range(k):
        t += md[r, r]
    return t


@numba.njit(cache=True)
def aberth_rational_roots(poles, gains, row_lo, row_hi, width, basis, orders, z, paired, size, active, tolerance,
                          max_sweeps, newton, evaluations):
    r"""All roots of ``q(s) = Π_g (s - μ_g)^{ρ_g} det(I - Q Σ_g G_g / (s - μ_g))`` by the
    Aberth–Ehrlich simultaneous iteration (Gauss–Seidel form: each root moves with the others'
    newest values).

    With ``H = Σ G_g/(s - μ_g)`` (r×k) and ``det(I_k - Q H) = det(I_r - H Q)``:
    ``q'/q = Σ_g ρ_g/(s - μ_g) + trace(M⁻¹ M')``, ``M = I_r - H Q``, ``M' = Σ G_g Q/(s - μ_g)²``;
    each root moves by ``1 / (q'/q(z_i) - Σ_{j≠i} 1/(z_i - z_j))`` (the sum over every root, the
    conjugates of the ``paired`` ones included) until that step is at most ``tolerance |z_i|``
    (or at most ``1e4 tolerance |z_i|`` and no smaller than the step before: the round-off floor
    of a small root among large poles), then stays. An iterate within ``1e3 tolerance |z_i|`` of another (two at
    one root) is moved away by ``1e-3 |z_i|`` to converge elsewhere (at most N such moves). An
    iterate at which M is singular to working precision is a root (q'/q infinite): it stays, with
    a zero Newton step.

    Parameters
    ----------
    poles : (ng,) complex ndarray
        μ_g, 1/s (distinct).
    gains : (ng, r, k) complex ndarray
        G_g, non-zero only in rows ``row_lo[g]:row_hi[g]`` and columns ``:width[g]`` (the rest is skipped).
    row_lo, row_hi, width : (ng,) int ndarray
    basis : (k, r) complex ndarray
        Q.
    orders : (ng,) float ndarray
        ρ_g, the order of μ_g's pole in det M.
    z : (N,) complex ndarray
        Starting points ``z[:size[0]]``, overwritten with the roots ``z[:size[0]]`` (N: room for
        a root per pair more).
    paired : (N,) bool ndarray
        True: the root's conjugate is a root too (not listed; q is then real). A pair's iterate
        that comes within 5 % of its modulus to the real axis (where the pair may part as two
        real roots) is split: its conjugate is listed as a root of its own from there.
    size : (1,) int ndarray
        In and out: how many roots are listed.
    active : (N,) bool ndarray
        In and out: the roots still moving (those given False stay where they are unless
        another root joins them).
    tolerance : float
        Relative step at which a root stops, -.
    max_sweeps : int
    newton : (N,) float ndarray
        Out: ``|q/q'|`` at each root's last evaluation (its Newton step), 1/s.
    evaluations : (N,) int ndarray
        Out: evaluations of q'/q per root (added to).

    Returns
    -------
    int
        Sweeps taken; -1 when some root had not stopped after ``max_sweeps``, -2 when an
        evaluation hit a pole or two roots coincided (the roots are then not valid).
    """
    ng, r, k = gains.shape[0], gains.shape[1], gains.shape[2]
    n = size[0]
    h = np.empty((r, k), np.complex128)
    hd = np.empty((r, k), np.complex128)
    m = np.empty((r, r), np.complex128)
    md = np.empty((r, r), np.complex128)
    last_step = np.full(z.size, np.inf)
    separation = 1e3 * tolerance  # iterates closer than this (relative) count as one
    separation_kick = 1e-3
    kicks = 0
    for sweep in range(max_sweeps):
        moving = False
        for i in range(n):
            if not active[i]:
                continue
            zi = z[i]
            evaluations[i] += 1
            h[:, :] = 0.0
            hd[:, :] = 0.0
            log_der = 0j
            for g in range(ng):
                if zi == poles[g]:
                    return -2
                d = zi - poles[g]
                w = d.conjugate() / (d.real * d.real + d.imag * d.imag)  # 1/d without complex division
                w2 = w * w
                log_der += orders[g] * w
                for a in range(row_lo[g], row_hi[g]):
                    for b in range(width[g]):
                        gab = gains[g, a, b]
                        h[a, b] += w * gab
                        hd[a, b] += w2 * gab
            for a in range(r):
                for b in range(r):
                    s = 0j
                    sd = 0j
                    for c in range(k):
                        s += h[a, c] * basis[c, b]
                        sd += hd[a, c] * basis[c, b]
                    m[a, b] = -s
                    md[a, b] = sd
                m[a, a] += 1.0
            trace = _trace_of_solve(m, md, r)
            if not (np.isfinite(trace.real) and np.isfinite(trace.imag)):
                # M is singular to working precision at z_i (a zero pivot, or one whose inverse
                # overflows): z_i is a root, q'/q is infinite there and the step zero. Which
                # iterate lands exactly on a root depends on the last bits of the arithmetic
                # (seen on one machine and not on another)
                newton[i] = 0.0
                last_step[i] = 0.0
                active[i] = False
                continue
            log_der += trace
            repulsion = 0j
            nearest = np.inf
            for j in range(n):
                if j != i:
                    if zi == z[j]:
                        return -2
                    d = zi - z[j]
                    d2 = d.real * d.real + d.imag * d.imag
                    repulsion += d.conjugate() / d2
                    nearest = min(nearest, d2)
                if paired[j]:
                    zc = z[j].conjugate()
                    if zi == zc:
                        return -2
                    d = zi - zc
                    d2 = d.real * d.real + d.imag * d.imag
                    repulsion += d.conjugate() / d2
                    nearest = min(nearest, d2)
            if log_der == repulsion or log_der == 0:
                return -2
            step = 1.0 / (log_der - repulsion)
            newton[i] = abs(1.0 / log_der)
            if nearest <= (separation * abs(zi)) ** 2:  # nearest: the squared distance
                # two iterates at one root: their steps are as small as their distance, and they
                # would part only slowly; this one is sent off to find another root
                step = -separation_kick * abs(zi) * np.exp(2j * np.pi * 0.6180339887 * (i + sweep))
                kicks += 1
                if kicks > z.size:
                    return -1
            z[i] = zi - step
            if paired[i] and abs(z[i].imag) < 0.05 * abs(z[i]) and n < z.size:
                paired[i] = False  # its mirror image becomes a root of its own
                z[n] = z[i].conjugate() if z[i].imag != 0 else z[i] * (1.0 + 1e-3j)
                paired[n] = False
                active[n] = True
                n += 1
                size[0] = n
            if abs(step) <= tolerance * abs(zi) or (abs(step) <= 1e4 * tolerance * abs(zi)
                                                    and abs(step) >= last_step[i]):
                active[i] = False  # converged, or at the round-off floor of its evaluation
            else:
                moving = True
            last_step[i] = abs(step)
        if not moving:
            # a root that stopped early may have been joined by another since: two at one root
            # (or at the mirror image of a pair's root) are told apart, the later one sent off
            for i in range(n):
                for j in range(n):
                    if j < i and abs(z[i] - z[j]) <= separation * abs(z[i]) or (
                            paired[j] and abs(z[i] - z[j].conjugate()) <= separation * abs(z[i])):
                        z[i] += separation_kick * abs(z[i]) * np.exp(2j * np.pi * 0.6180339887 * (i + sweep))
                        active[i] = True
                        moving = True
                        kicks += 1
                        break
            if kicks > z.size:
                return -1
            if not moving:
                return sweep + 1
    return -1


@numba.njit(cache=True)
def first_order_roots(poles, gains, row_lo, row_hi, width, basis, orders, group, z):
    r"""Starting points for :func:`aberth_rational_roots` by first-order perturbation of each pole.

    Near μ_g, ``M(s) ≈ M_g - C_g / (s - μ_g)`` with ``M_g`` the rest of M at μ_g and
    ``C_g = G_g Q``, so the roots that leave μ_g are ``μ_g + ε`` with ε the non-zero eigenvalues
    of ``M_g⁻¹ C_g`` (for ρ_g = 1 its trace). ``z[i]`` (one root per entry, of group
    ``group[i]``; the ρ_g roots of a group are consecutive) is overwritten where the estimates
    are finite and move the root by less than half the distance to the nearest other pole;
    elsewhere the given start stays. Arguments as :func:`aberth_rational_roots`.
    """
    ng, r, k = gains.shape[0], gains.shape[1], gains.shape[2]
    h = np.empty((r, k), np.complex128)
    m = np.empty((r, r), np.complex128)
    c = np.empty((r, r), np.complex128)
    i = 0
    n = z.size
    while i < n:
        g = group[i]
        count = int(orders[g])
        mu = poles[g]
        h[:, :] = 0.0
        gap = np.inf
        for q in range(ng):
            if q == g:
                continue
            d = mu - poles[q]
            d2 = d.real * d.real + d.imag * d.imag
            gap = min(gap, d2)
            w = d.conjugate() / d2
            for a in range(row_lo[q], row_hi[q]):
                for b in range(width[q]):
                    h[a, b] += w * gains[q, a, b]
        for a in range(r):
            for b in range(r):
                s = 0j
                sc = 0j
                for e in range(k):
                    s += h[a, e] * basis[e, b]
                    sc += gains[g, a, e] * basis[e, b]
                m[a, b] = -s
                c[a, b] = sc
            m[a, a] += 1.0
        limit = 0.25 * gap  # (half the gap)²
        # where no estimate is taken: the group's roots spread on a circle of half the gap
        for j in range(count):
            z[i + j] = mu + 0.5 * np.sqrt(gap) * np.exp(1j * (2.0 * np.pi * (j + 0.25) / count + 0.3))
        if count == 1:
            eps = _trace_of_solve(m, c, r)
            if np.isfinite(eps.real) and np.isfinite(eps.imag) and (eps.real ** 2 + eps.imag ** 2) < limit:
                z[i] = mu + eps
        elif count > 1:
            shifts = np.linalg.eigvals(np.linalg.solve(m, c))
            order = np.argsort(-np.abs(shifts))
            ok = True
            for j in range(count):
                e = shifts[order[j]]
                if not (np.isfinite(e.real) and np.isfinite(e.imag) and abs(e) ** 2 < limit and abs(e) > 0):
                    ok = False
            if ok:
                for j in range(count):
                    z[i + j] = mu + shifts[order[j]]
        i += max(count, 1)
