"""Local Gauss-Seidel sweeps between exact FFT products, with a coarse level, compiled (lazily, cached on disk).

The compiled loop of contact/halfspace/transient_fft.py (which documents the method):
:func:`local_sweeps_with_products` runs rounds of :func:`local_sweeps` (a traction change updates
only the neighbours of :func:`local_updates`), an exact FFT product over the contact list
(influence_kernels.py), a coarse correction on square blocks of the grid (:func:`coarse_level`,
:func:`coarse_correction`) and Anderson mixing (anderson_kernels.py). Nothing is compiled at
import time.
"""

from __future__ import annotations

import numba
import numpy as np

from contact.halfspace.anderson_kernels import anderson_input, anderson_mix
from contact.halfspace.bundles import CoarseLevel, LocalUpdates
from contact.halfspace.influence_kernels import list_product, no_dense_rows
from contact.kernels_linalg import inner_product
from contact.halfspace.tangential_kernels import sum_tractions, tangential_sweep


@numba.njit(cache=True)
def local_sweeps(operator, problem, flat, tractions, compliance, total, status, updates, rows, count):
    """``count`` sweeps of :func:`tangential_sweep` (every change applied).

    Returns the largest traction change (Pa) of the first sweep.
    """
    first = tangential_sweep(operator, problem, flat, tractions, compliance, total, 0.0, status, updates, rows)
    for _ in range(count - 1):
        tangential_sweep(operator, problem, flat, tractions, compliance, total, 0.0, status, updates, rows)
    return first


@numba.njit(cache=True)
def local_updates(operator, cix, ciy, nx, ny, reach):
    """The :class:`~contact.halfspace.bundles.LocalUpdates` of a contact list: neighbours within ``reach`` lines.

    ``cix, ciy`` are the grid indices of the list's elements on an nx x ny grid. The table and
    the stencil replace, in the sweeps' inner loop, a lookup of the grid position and a gather
    of the kernels per neighbour by one row of list positions and a few coefficients that stay
    in registers (the gain: docs/benchmarks.md, *Contact solvers against CONTACT*). The
    offsets run x outer, y inner, so the updates come in the same order as before: the same
    numbers.
    """
    nc = cix.shape[0]
    width = 2 * reach + 1
    lookup = np.full(nx * ny, -1, np.int64)
    for c in range(nc):
        lookup[cix[c] * ny + ciy[c]] = c
    neighbours = np.full((nc, width * width), -1, np.int64)
    for c in range(nc):
        q = 0
        for tx in range(cix[c] - reach, cix[c] + reach + 1):
            for ty in range(ciy[c] - reach, ciy[c] + reach + 1):
                if 0 <= tx < nx and 0 <= ty < ny:
                    neighbours[c, q] = lookup[tx * ny + ty]
                q += 1
    stencil = np.zeros((3, width * width))  # offsets beyond the grid have no neighbours: zero
    q = 0
    for di in range(-reach, reach + 1):
        for dj in range(-reach, reach + 1):
            if abs(di) < nx and abs(dj) < ny:
                k = (di + operator.ox) * operator.row + (dj + operator.oy)
                stencil[0, q] = operator.f11[k]
                stencil[1, q] = operator.f12[k]
                stencil[2, q] = operator.f22[k]
            q += 1
    return LocalUpdates(neighbours, stencil)


@numba.njit(cache=True)
def coarse_blocks(cix, ciy, block):
    """The blocks of a contact list: the grid's ``block`` x ``block`` squares (``ix // block``, ``iy // block``) that hold
    contact elements, numbered in the order the list first meets them.

    Returns
    -------
    group : (nc,) int64 ndarray
        The block of each contact element.
    size : (m,) ndarray
        Contact elements in each block.
    """
    nc = cix.shape[0]
    nbx = 0
    nby = 0
    for c in range(nc):
        nbx = max(nbx, cix[c] // block + 1)
        nby = max(nby, ciy[c] // block + 1)
    number = np.full(nbx * nby, -1, np.int64)
    group = np.empty(nc, np.int64)
    m = 0
    for c in range(nc):
        key = (cix[c] // block) * nby + ciy[c] // block
        if number[key] < 0:
            number[key] = m
            m += 1
        group[c] = number[key]
    size = np.zeros(m)
    for c in range(nc):
        size[group[c]] += 1.0
    return group, size


@numba.njit(cache=True)
def coarse_matrix(operator, cix, ciy, group, size, series_x, series_y):
    """The Galerkin coarse matrix ``P^T (A + S) P`` (m/Pa) of a contact list's blocks, x blocks first, then y.

    ``A`` the tangential influence coefficients among the contact elements, ``S`` the series
    compliances times the element area (every element's slip gains ``S * sum(p)``), ``P`` the
    indicator of the blocks ``group`` (:func:`coarse_blocks`). Exact: the sources of a block are
    split into runs of consecutive elements along y (at most one per line of the block), and the
    sum over a run is a difference of prefix sums of the kernels along y, so the cost is
    O(nc * runs) = O(nc^2 / block), not O(nc^2) (its time: docs/benchmarks.md, *The coarse level
    in the solver*).

    Parameters
    ----------
    operator : FlatTangential
    cix, ciy : (nc,) int64 ndarray
        Grid indices of the contact elements.
    group, size : ndarray
        The blocks (:func:`coarse_blocks`).
    series_x, series_y : float
        Series compliances times the element area (m/Pa).
    """
    nc = cix.shape[0]
    m = size.shape[0]
    # runs of sources: same block, same line x, consecutive y (the list sorted by block, x, y)
    span_x = cix.max() + 2
    span_y = ciy.max() + 2
    order = np.argsort((group * span_x + cix) * span_y + ciy)
    run_x = np.empty(nc, np.int64)
    run_lo = np.empty(nc, np.int64)
    run_hi = np.empty(nc, np.int64)
    run_block = np.empty(nc, np.int64)
    runs = 0
    for q in range(nc):
        c = order[q]
        if runs > 0 and run_block[runs - 1] == group[c] and run_x[runs - 1] == cix[c] \
                and run_hi[runs - 1] == ciy[c] - 1:
            run_hi[runs - 1] = ciy[c]
        else:
            run_x[runs] = cix[c]
            run_lo[runs] = ciy[c]
            run_hi[runs] = ciy[c]
            run_block[runs] = group[c]
            runs += 1
    # prefix sums of the kernels along y: prefix[kx, t] = sum of f[kx, :t]
    my = operator.row
    lines = operator.f11.shape[0] // my
    p11 = np.zeros((lines, my + 1))
    p12 = np.zeros((lines, my + 1))
    p22 = np.zeros((lines, my + 1))
    for kx in range(lines):
        for t in range(my):
            k = kx * my + t
            p11[kx, t + 1] = p11[kx, t] + operator.f11[k]
            p12[kx, t + 1] = p12[kx, t] + operator.f12[k]
            p22[kx, t + 1] = p22[kx, t] + operator.f22[k]
    ox = operator.ox
    oy = operator.oy
    matrix = np.zeros((2 * m, 2 * m))
    for i in range(nc):
        xx = matrix[group[i]]
        yy = matrix[m + group[i]]
        for r in range(runs):
            kx = cix[i] - run_x[r] + ox
            lo = ciy[i] - run_hi[r] + oy  # offsets along y of the run's sources, lo .. hi - 1
            hi = ciy[i] - run_lo[r] + oy + 1
            source = run_block[r]
            a12 = p12[kx, hi] - p12[kx, lo]
            xx[source] += p11[kx, hi] - p11[kx, lo]
            xx[m + source] += a12
            yy[source] += a12
            yy[m + source] += p22[kx, hi] - p22[kx, lo]
    for a in range(m):
        for b in range(m):
            matrix[a, b] += series_x * size[a] * size[b]
            matrix[m + a, m + b] += series_y * size[a] * size[b]
    return matrix


@numba.njit(cache=True)
def coarse_level(operator, cix, ciy, block, series_x, series_y):
    """The :class:`~contact.halfspace.bundles.CoarseLevel` of a contact list on square blocks of ``block`` grid lines.

    :func:`coarse_blocks`, and the inverse of their :func:`coarse_matrix` (the parameters there).
    """
    group, size = coarse_blocks(cix, ciy, block)
    return CoarseLevel(group, size, np.linalg.inv(coarse_matrix(operator, cix, ciy, group, size, series_x, series_y)))


@numba.njit(cache=True)
def no_coarse_level():
    """Empty :class:`~contact.halfspace.bundles.CoarseLevel`: no coarse correction."""
    return CoarseLevel(np.empty(0, np.int64), np.empty(0), np.empty((0, 0)))


@numba.njit(cache=True)
def coarse_correction(coarse, problem, tractions, compliance, total, status):
    """A coarse correction of the tractions (Pa) between two rounds of local sweeps; displacements (m) by block means.

    The slip of the sticking elements (as :func:`tangential_sweep` computes it), summed over
    each block, is cancelled by traction changes constant on each block (the coarse matrix's
    solution), applied to every contact element of the block; the sliding elements' slip is left
    out of the sums (their tractions sit on the friction bound, and the next sweep puts the
    changed ones back on it). The displacement of every element gains the mean over its block of
    the displacement the change causes, which the coarse matrix gives exactly (the smooth part of
    the change's effect); the next exact product replaces the rest.

    A fixed point of the sweeps has no slip at its sticking elements, so the correction is zero
    there: the solution is the same, it is reached in fewer rounds because the error's smooth part,
    which the sweeps (seeing the far coupling only through the last product) reduce slowly, is
    carried by the coarse level.

    Parameters
    ----------
    coarse : CoarseLevel
        The contact list's blocks (:func:`coarse_level`).
    problem : TangentialProblem
    tractions : Tractions
        Tractions (Pa) and their exact displacement differences (m), updated in place.
    compliance : SweepCompliance
    total : (2,) ndarray
        Summed tractions (Pa), updated in place.
    status : (nc,) int8 ndarray
        1 stick, 2 slip (of the last sweep).
    """
    group = coarse.group
    size = coarse.size
    inverse = coarse.inverse
    m = size.shape[0]
    nc = group.shape[0]
    wx = problem.slip_x
    wy = problem.slip_y
    upx = problem.previous_x
    upy = problem.previous_y
    px = tractions.px
    py = tractions.py
    ux = tractions.ux
    uy = tractions.uy
    spring_x = compliance.series_x * total[0]  # the series springs' displacement (m)
    spring_y = compliance.series_y * total[1]
    residual = np.zeros(2 * m)
    for c in range(nc):
        if status[c] == 1:
            b = group[c]
            residual[b] -= wx[c] + ux[c] - upx[c] + spring_x
            residual[m + b] -= wy[c] + uy[c] - upy[c] + spring_y
    change = np.empty(2 * m)
    for a in range(2 * m):
        change[a] = inner_product(inverse[a], residual, 2 * m)
    added_x = 0.0
    added_y = 0.0
    for b in range(m):
        added_x += size[b] * change[b]
        added_y += size[b] * change[m + b]
    # the block means of the change's displacement: the coarse matrix times the change (which is
    # the residual) per element of the block, less the series springs' part
    mean_effect = np.empty(2 * m)
    for b in range(m):
        mean_effect[b] = residual[b] / size[b] - compliance.series_x * added_x
        mean_effect[m + b] = residual[m + b] / size[b] - compliance.series_y * added_y
    for c in range(nc):
        b = group[c]
        px[c] += change[b]
        py[c] += change[m + b]
        ux[c] += mean_effect[b]
        uy[c] += mean_effect[m + b]
    total[0] += added_x
    total[1] += added_y


@numba.njit(cache=True)
def local_sweeps_with_products(operator, problem, flat, tractions, compliance, plan, updates, tol, max_sweeps,
                               per_product, history, depth, stop_in_full_slip, coarse):
    """Local Gauss-Seidel sweeps with an exact FFT product after every ``per_product``, a coarse level, Anderson mixing.

    The loop of :func:`contact.halfspace.transient_fft.transient_sweeps_fft` (see there): each
    round records the tractions for the mixing, runs ``per_product`` sweeps of
    :func:`tangential_sweep` with the local ``updates``, recomputes the
    displacements of all contact elements exactly (:func:`list_product`, targets = sources =
    the contact list), and mixes the map from one product to the next (no restarts).

    Parameters
    ----------
    operator : FlatTangential
    problem : TangentialProblem
    flat : (nc,) int64 ndarray
        ``problem.ix * operator.row + problem.iy``.
    tractions : Tractions
        Tractions (Pa) in and out; their displacements (m) in, the exact ones of the result out.
    compliance : SweepCompliance
    plan : ListProduct
        The product over the contact list (sources and targets in the list's order).
    updates : LocalUpdates
        The neighbours a traction change updates within a sweep (:func:`local_updates`).
    tol : float
        Stop when the first sweep after a product changes no traction by more than tol (Pa).
    max_sweeps, per_product : int
        Sweep limit; sweeps between two products.
    history : AndersonHistory
        Fresh memory of at least nc elements (used only with ``depth > 0``).
    depth : int
        0: no mixing.
    stop_in_full_slip : bool
        Return after the first product if every element slides.
    coarse : CoarseLevel
        A coarse level of the contact list (:func:`coarse_level`): every round after the first
        starts with :func:`coarse_correction` (part of the map the mixing accelerates), or
        :func:`no_coarse_level`.

    Returns
    -------
    sweeps : int
    change : float
        Largest traction change (Pa) of the first sweep of the last round, the one that started
        from the exact displacements of the product before it.
    status : (nc,) int8 ndarray
        1 stick, 2 slip after the last sweep.
    """
    px = tractions.px
    py = tractions.py
    ux = tractions.ux
    uy = tractions.uy
    nc = px.shape[0]
    status = np.ones(nc, np.int8)
    total = np.zeros(2)
    sum_tractions(px, py, total)
    rows = no_dense_rows()
    change = np.inf
    sweeps = 0
    while sweeps < max_sweeps:
        anderson_input(history, px, py)
        if sweeps > 0 and coarse.size.shape[0] > 0:
            coarse_correction(coarse, problem, tractions, compliance, total, status)
        now = min(per_product, max_sweeps - sweeps)
        change = local_sweeps(operator, problem, flat, tractions, compliance, total, status, updates, rows, now)
        sweeps += now
        list_product(plan, px, py, ux, uy)
        if change <= tol:
            break
        if stop_in_full_slip and sweeps == now and np.all(status == 2):
            break
        if depth > 0 and anderson_mix(history, change, px, py, ux, uy, False):
            sum_tractions(px, py, total)
    return sweeps, change, status
