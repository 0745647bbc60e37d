"""Solvers of the normal contact problem, compiled (lazily, cached on disk).

Polonsky-Keer constrained conjugate gradients (contact/halfspace/normal.py documents the
algorithm): :func:`normal_conjugate_gradient` with direct products of the influence matrix over
the candidate elements (:func:`_influence_add` on the flat view
:class:`~contact.halfspace.bundles.FlatNormal`; the problem a
:class:`~contact.halfspace.bundles.NormalProblem`), and :func:`normal_cg_fft` for a prescribed
force (:func:`normal_cg_fft_approach` for a prescribed approach) on the whole grid with FFT products. Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from contact.halfspace.bundles import FlatNormal
from contact.halfspace.influence_kernels import grid_product


@numba.njit(cache=True)
def normal_cg_fft(spectrum, own, gap, pressure, normal_force, area, tol, max_iter):
    """Polonsky-Keer constrained conjugate gradients for a prescribed normal force, products by FFT.

    The compiled solver's algorithm (:func:`normal_conjugate_gradient`) on the whole grid with
    one FFT product of the influence matrix per iteration (:func:`grid_product`) instead of
    direct sums: deformed gap r = h + u - its mean over the contact, search direction
    t = r + (G / G_old) t on the contact, step tau = <r, t> / <A t - mean, t>, projection on
    p >= 0, re-entry of overlapping elements with p = -tau r, or with the pressure that closes
    the element's own gap when the step is zero (the active set solved, elements outside it
    overlapping: as in the direct solver; without it such a start stalled), rescaling to the
    force. Converged when the relative pressure change is below tol and the gap residual
    (relative to the gap's range) below 10 tol, after a step without re-entries.

    Parameters
    ----------
    spectrum : (2 nx, ny + 1) complex ndarray
        Spectrum of K33 (m/Pa), as for :func:`grid_product`.
    own : float
        K33 at zero offset (an element's own compliance), m/Pa.
    gap : (nx, ny) ndarray
        Undeformed gap, m.
    pressure : (nx, ny) ndarray
        Start (Pa, positive somewhere, scaled to the force); the solution out (in place).
    normal_force, area : float
        N; element area, m^2.
    tol : float
    max_iter : int

    Returns
    -------
    iterations : int
    residual : float
        Relative pressure change of the last iteration.
    converged : bool
    displacement : (nx, ny) ndarray
        Normal displacement difference of the result, m.
    """
    nx, ny = gap.shape
    n = nx * ny
    h = gap.reshape(-1)
    p = pressure.reshape(-1)
    scale_h = max(h.max() - h.min(), 1e-300)
    t = np.zeros(n)
    r = np.empty(n)
    p_old = np.empty(n)
    g_old = 1.0
    conjugate = False
    residual = np.inf
    iterations = 0
    converged = False
    while iterations < max_iter:
        iterations += 1
        u = grid_product(spectrum, pressure).reshape(-1)
        count = 0
        mean = 0.0
        for i in range(n):
            if p[i] > 0.0:
                count += 1
                mean += h[i] + u[i]
        mean /= count
        g = 0.0
        for i in range(n):
            r[i] = h[i] + u[i] - mean
            if p[i] > 0.0:
                g += r[i] * r[i]
        ratio = g / g_old if conjugate else 0.0
        for i in range(n):
            t[i] = r[i] + ratio * t[i] if p[i] > 0.0 else 0.0
        g_old = g
        at = grid_product(spectrum, t.reshape(nx, ny)).reshape(-1)
        at_mean = 0.0
        for i in range(n):
            if p[i] > 0.0:
                at_mean += at[i]
        at_mean /= count
        den = 0.0
        num = 0.0
        for i in range(n):
            if p[i] > 0.0:
                den += (at[i] - at_mean) * t[i]
                num += r[i] * t[i]
        tau = num / den if den != 0.0 else 0.0
        for i in range(n):
            p_old[i] = p[i]
            if p[i] > 0.0:
                p[i] = max(p[i] - tau * t[i], 0.0)
        conjugate = True
        for i in range(n):
            if p[i] == 0.0 and r[i] < 0.0:
                # re-enter with the step length, or (when the active set is already solved and the
                # step is zero) with the pressure that closes the element's own gap
                conjugate = False
                p[i] = -tau * r[i] if tau > 0.0 else -r[i] / own
        total = 0.0
        for i in range(n):
            total += p[i]
        factor = normal_force / (total * area)
        change = 0.0
        total = 0.0
        for i in range(n):
            p[i] *= factor
            change += abs(p[i] - p_old[i])
            total += p[i]
        residual = change / total
        gap_residual = math.sqrt(g / max(count, 1)) / scale_h
        if residual < tol and gap_residual < 10.0 * tol and conjugate:
            converged = True
            break
    return iterations, residual, converged, grid_product(spectrum, pressure)


@numba.njit(cache=True)
def normal_cg_fft_approach(spectrum, own, gap, pressure, approach, tol, max_iter):
    """Polonsky-Keer constrained conjugate gradients for a prescribed approach, products by FFT.

    :func:`normal_cg_fft`'s iteration with the approach δ given instead of the force: the
    deformed gap is ``r = h + u - δ`` (no mean taken), the step ``tau = <r, t> / <A t, t>`` and no
    rescaling to a force. A warm start (positive somewhere) is first scaled so that its mean
    gap on its own area closes at δ (u is linear in p), as the direct solver does. Converged
    as :func:`normal_cg_fft`.

    Parameters
    ----------
    spectrum : (2 nx, ny + 1) complex ndarray
        Spectrum of K33 (m/Pa), as for :func:`grid_product`.
    own : float
        K33 at zero offset, m/Pa.
    gap : (nx, ny) ndarray
        Undeformed gap, m.
    pressure : (nx, ny) ndarray
        Start (Pa, positive somewhere); the solution out (in place).
    approach : float
        m, above the smallest gap.
    tol : float
    max_iter : int

    Returns
    -------
    iterations : int
    residual : float
        Relative pressure change of the last iteration.
    converged : bool
    displacement : (nx, ny) ndarray
        Normal displacement difference of the result, m.
    """
    nx, ny = gap.shape
    n = nx * ny
    h = gap.reshape(-1)
    p = pressure.reshape(-1)
    scale_h = max(h.max() - h.min(), 1e-300)
    u = grid_product(spectrum, pressure).reshape(-1)
    num = 0.0
    den = 0.0
    for i in range(n):
        if p[i] > 0.0:
            num += approach - h[i]
            den += u[i]
    if den > 0.0 and num > 0.0:
        for i in range(n):
            p[i] *= num / den
    t = np.zeros(n)
    r = np.empty(n)
    p_old = np.empty(n)
    g_old = 1.0
    conjugate = False
    residual = np.inf
    iterations = 0
    converged = False
    while iterations < max_iter:
        iterations += 1
        u = grid_product(spectrum, pressure).reshape(-1)
        count = 0
        g = 0.0
        for i in range(n):
            r[i] = h[i] + u[i] - approach
            if p[i] > 0.0:
                count += 1
                g += r[i] * r[i]
        ratio = g / g_old if conjugate else 0.0
        for i in range(n):
            t[i] = r[i] + ratio * t[i] if p[i] > 0.0 else 0.0
        g_old = g
        at = grid_product(spectrum, t.reshape(nx, ny)).reshape(-1)
        den = 0.0
        num = 0.0
        for i in range(n):
            if p[i] > 0.0:
                den += at[i] * t[i]
                num += r[i] * t[i]
        tau = num / den if den != 0.0 else 0.0
        for i in range(n):
            p_old[i] = p[i]
            if p[i] > 0.0:
                p[i] = max(p[i] - tau * t[i], 0.0)
        conjugate = True
        for i in range(n):
            if p[i] == 0.0 and r[i] < 0.0:
                conjugate = False
                p[i] = -tau * r[i] if tau > 0.0 else -r[i] / own
        change = 0.0
        total = 0.0
        for i in range(n):
            change += abs(p[i] - p_old[i])
            total += p[i]
        residual = change / total if total > 0.0 else 0.0
        gap_residual = math.sqrt(g / max(count, 1)) / scale_h
        if residual < tol and gap_residual < 10.0 * tol and conjugate:
            converged = True
            break
    return iterations, residual, converged, grid_product(spectrum, pressure)


@numba.njit(cache=True)
def _influence_add(matrix, x, columns, rows, out, scale):
    """``out[rows] += scale * A[rows, columns] x[columns]`` for the influence matrix A of ``matrix`` (FlatNormal).

    ``A[i, j] = f33[base[i] + offset[j]]``; zero entries of ``x`` are skipped.
    """
    f33 = matrix.f33
    base = matrix.base
    offset = matrix.offset
    for jj in range(columns.shape[0]):
        j = columns[jj]
        xj = x[j]
        if xj != 0.0:
            o = offset[j]
            c = scale * xj
            for r in range(rows.shape[0]):
                i = rows[r]
                out[i] += f33[base[i] + o] * c


@numba.njit(cache=True)
def normal_conjugate_gradient(K33, problem, full_displacement=True, u_warm=np.empty(0), u_threshold=np.inf):
    """Polonsky-Keer constrained conjugate gradients for the normal contact problem.

    The algorithm of contact/halfspace/normal.py (which documents it), with direct products of
    the influence matrix over the elements in contact, so that a small grid needs no FFT. Each
    iteration forms the product of the search direction once and updates the displacement from
    it (plus the few elements that the projection clips or lets re-enter). With a prescribed
    approach only candidate elements take part: those whose undeformed gap is below the
    contact's own approach (the approach minus the series springs' share, estimated from the
    warm start) plus a margin. Every influence coefficient is positive, so an element whose gap
    exceeds the final own approach keeps zero pressure; if an element outside the candidates
    fails that test, the candidates are widened and the solution continued.

    Parameters
    ----------
    K33 : ndarray (2 nx - 1, 2 ny - 1)
        Normal influence kernel (m/Pa) of the nx x ny grid.
    problem : NormalProblem
        Gap (m, flat in C order), pressure (Pa; initial guess in, solution out, in place),
        prescribed force (N) or approach (m), series compliance times element area (m/Pa; added
        to every influence coefficient, approach mode only), element area (m²), relative
        tolerance (pressure change and gap residual), iteration limit, and ``warm``: the
        pressure is a warm start, so exit at once if it already solves the problem and, with a
        prescribed approach, first rescale it to the approach (mean gap closed on its area)
        (contact/halfspace/bundles.py).
    full_displacement : bool
        Return the displacement on the whole grid (else on the candidates only, zero elsewhere).
    u_warm : ndarray (nx ny,) or empty
        ``A p`` of the warm start, if known (saves one product), at least where the undeformed
        gap is below ``u_threshold`` (m).
    u_threshold : float
        See ``u_warm``; ``inf`` when it is known on the whole grid.

    Returns
    -------
    iterations : int
    residual : float
        Final relative pressure change (-).
    converged : bool
    u : ndarray (nx ny,)
        Normal displacement difference ``A p`` of the contact alone, without the series term (m),
        on the candidates (the whole grid with ``full_displacement``).
    threshold : float
        The candidates' bound on the undeformed gap (m): ``u`` holds where the gap is below it.
    """
    h = problem.gap
    p = problem.pressure
    force_mode = problem.force_mode
    target = problem.target
    series = problem.series
    max_iter = problem.max_iter
    warm = problem.warm
    nx = (K33.shape[0] + 1) // 2
    ny = (K33.shape[1] + 1) // 2
    n = nx * ny
    my = K33.shape[1]
    ox = nx - 1
    oy = ny - 1
    base = np.empty(n, np.int64)
    offset = np.empty(n, np.int64)
    hmin = h[0]
    hmax = h[0]
    total = 0.0
    i = 0
    for ix in range(nx):  # i = ix * ny + iy, without a division per element
        for iy in range(ny):
            base[i] = ix * my + iy
            offset[i] = (ox - ix) * my + (oy - iy)
            i += 1
    for i in range(n):
        hmin = min(hmin, h[i])
        hmax = max(hmax, h[i])
        total += p[i]
    hscale = max(hmax - hmin, 1e-300)
    matrix = FlatNormal(K33.ravel(), base, offset)
    if force_mode:
        threshold = np.inf
    else:
        own = target - series * total if warm else target
        threshold = own + 0.25 * abs(own) if own > 0.0 else target
    u = np.zeros(n)
    known = u_warm.shape[0] == n and threshold <= u_threshold  # u_warm holds A p of the warm start there
    iterations = 0
    while True:
        nq = 0
        for i in range(n):
            if h[i] < threshold:
                nq += 1
        if nq == 0:  # the approach closes no gap: no contact
            for i in range(n):
                p[i] = 0.0
            return iterations, 0.0, True, u, threshold
        cand = np.empty(nq, np.int64)
        k = 0
        for i in range(n):
            if h[i] < threshold:
                cand[k] = i
                k += 1
            elif p[i] != 0.0:
                p[i] = 0.0
                known = False
        if known:
            for i in cand:
                u[i] = u_warm[i]
        it, residual, converged, total = _normal_cg(matrix, problem, cand, u, known, warm, max_iter - iterations,
                                                    hscale)
        known = False  # u is A p on these candidates only: a wider set needs it afresh
        iterations += it
        if force_mode or not converged or threshold >= target:
            break
        own = target - series * total
        outside = False  # an element outside the candidates that the final own approach reaches
        for i in range(n):
            if h[i] >= threshold and h[i] < own:
                outside = True
                break
        if not outside:
            break
        threshold = min(own + 0.25 * abs(own), target)
        warm = True
    if full_displacement:
        for i in range(n):
            u[i] = 0.0
        nq = 0
        for i in range(n):
            if p[i] > 0.0:
                nq += 1
        active = np.empty(nq, np.int64)
        k = 0
        for i in range(n):
            if p[i] > 0.0:
                active[k] = i
                k += 1
        _influence_add(matrix, p, active, np.arange(n), u, 1.0)
        threshold = np.inf
    return iterations, residual, converged, u, threshold


@numba.njit(cache=True)
def _normal_cg(matrix, problem, cand, u, known, warm, max_iter, hscale):
    """The iterations of :func:`normal_conjugate_gradient` on the candidate elements ``cand``.

    ``matrix`` (FlatNormal) is the influence matrix, ``problem`` (NormalProblem) the problem,
    whose pressure is zero outside the candidates; ``u`` (out) is ``A p`` on the candidates (in
    as well when ``known``). ``warm`` and ``max_iter`` replace the problem's (a continued
    solution is warm and has the remaining iterations); ``hscale`` is the gap's range (m).
    Returns ``(iterations, residual, converged, sum of p)``.
    """
    f33 = matrix.f33
    base = matrix.base
    offset = matrix.offset
    h = problem.gap
    p = problem.pressure
    force_mode = problem.force_mode
    target = problem.target
    series = problem.series
    area = problem.area
    tol = problem.tol
    n = h.shape[0]
    if not known:
        for i in cand:
            u[i] = 0.0
        _influence_add(matrix, p, cand, cand, u, 1.0)
    total = 0.0
    for i in cand:
        total += p[i]
    if warm and not force_mode:
        # rescale the warm start to the new approach: u is linear in p
        num = 0.0
        den = 0.0
        for i in cand:
            if p[i] > 0.0:
                num += target - h[i]
                den += u[i] + series * total
        if den > 0.0 and num > 0.0:
            factor = num / den
            if abs(factor - 1.0) > tol:
                for i in cand:
                    p[i] *= factor
                    u[i] *= factor
                total *= factor
    g = np.zeros(n)
    t = np.zeros(n)
    r = np.zeros(n)
    p_old = np.zeros(n)
    d = np.zeros(n)  # correction of the fixed elements
    fixed = np.empty(cand.shape[0], np.int64)  # elements clipped to zero or re-entered by the projection
    g_old = 1.0
    conjugate = False
    residual = np.inf
    converged = False
    it = 0
    for it in range(1, max_iter + 1):
        n_active = 0
        gsum = 0.0
        for i in cand:
            if p[i] > 0.0:
                n_active += 1
                gsum += h[i] + u[i]
        if n_active == 0:
            break
        gbar = gsum / n_active if force_mode else target - series * total
        G = 0.0
        ginactive = 0.0
        for i in cand:
            g[i] = h[i] + u[i] - gbar
            if p[i] > 0.0:
                G += g[i] * g[i]
            elif g[i] < ginactive:
                ginactive = g[i]
        gap_res = math.sqrt(G / n_active) / hscale
        if it == 1 and warm and gap_res < 10.0 * tol and ginactive > -tol * hscale:
            residual = 0.0
            converged = True
            break
        beta = G / g_old if conjugate else 0.0
        for i in cand:
            t[i] = g[i] + beta * t[i] if p[i] > 0.0 else 0.0
        g_old = G
        # r = A t on the candidates (only the active rows enter the step length)
        for i in cand:
            r[i] = 0.0
        _influence_add(matrix, t, cand, cand, r, 1.0)
        tsum = 0.0
        for i in cand:
            tsum += t[i]
        rbar = 0.0
        if force_mode:
            for i in cand:
                if p[i] > 0.0:
                    rbar += r[i]
            rbar /= n_active
        num = 0.0
        den = 0.0
        for i in cand:
            if p[i] > 0.0:
                ri = r[i] + series * tsum - rbar
                num += g[i] * t[i]
                den += ri * t[i]
        tau = num / den if den != 0.0 else 0.0
        overlap = False
        psum = 0.0
        nfixed = 0
        for i in cand:
            p_old[i] = p[i]
            q = p[i] - tau * t[i]
            if q < 0.0:
                q = 0.0
            if q == 0.0 and g[i] < 0.0:
                # re-enter with the step length, or (when the active set is already solved and the
                # step is zero) with the pressure that closes the element's own gap
                q = -tau * g[i] if tau > 0.0 else -g[i] / f33[base[i] + offset[i]]
                overlap = True
            if q != p[i] - tau * t[i]:
                fixed[nfixed] = i
                nfixed += 1
            p[i] = q
            psum += q
        # u(p) = u(p_old) - tau A t + A (p - p_old + tau t), the last term on the fixed elements only
        for i in cand:
            u[i] -= tau * r[i]
        for kk in range(nfixed):
            i = fixed[kk]
            d[i] = p[i] - p_old[i] + tau * t[i]
        _influence_add(matrix, d, fixed[:nfixed], cand, u, 1.0)
        conjugate = not overlap
        if force_mode and psum > 0.0:
            scale = target / (psum * area)
            for i in cand:
                p[i] *= scale
                u[i] *= scale
            psum *= scale
        total = psum
        change = 0.0
        for i in cand:
            change += abs(p[i] - p_old[i])
        residual = change / psum if psum > 0.0 else 0.0
        if residual < tol and gap_res < 10.0 * tol and not overlap:
            converged = True
            break
    return it, residual, converged, total
