"""Numba kernels of the contact solvers (compiled lazily on first call, cached on disk).

:func:`tangential_gauss_seidel` is the element-by-element (Gauss-Seidel) solution of the
tangential problem with Coulomb friction, in the spirit of Kalker's ConvexGS, accelerated by
Anderson mixing (:func:`gauss_seidel_with_memory` the same with a given mixing memory, which the
time loop carries from step to step, :func:`continue_history`; the products read dense rows of
the influence coefficients, :func:`contact_rows`, for contact lists of up to
``bundles.DENSE_MAX_CONTACT`` elements); :func:`normal_conjugate_gradient` solves the normal problem;
:func:`transient_rolling_step` the half-space model's transient step of that loop. The kernels
of the models take the bundles of interaction/contact/bundles.py, and so do the solvers'
inner kernels (a :class:`~interaction.contact.bundles.NormalProblem`, the flat influence views
:class:`~interaction.contact.bundles.FlatNormal` and
:class:`~interaction.contact.bundles.FlatTangential`). Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba
import numpy as np
import rocket_fft  # noqa: F401  (numpy.fft inside compiled kernels: list_product, grid_product)

from .bundles import (UPSTREAM_MAX_ROWS, AndersonHistory, CoarseLevel, DenseTangential, FlatNormal, FlatTangential,
                      LocalUpdates, NormalProblem, SweepCompliance, TangentialProblem, Tractions)


def compiled_entry(kernel, *example):
    """The compiled function of ``kernel`` for the argument types of ``example``, without numba's dispatch.

    Calls ``kernel(*example)`` once (compiling it, or loading it from the cache) and returns the
    compiled entry point of that signature. A call through it skips the typing of the arguments
    that the dispatcher does on every call (about 6 us for a named-tuple argument, more than the
    point-contact law itself); it must be called with arguments of the same types.
    """
    kernel(*example)
    return kernel.get_overload(tuple(numba.typeof(a) for a in example))


@numba.njit(cache=True, fastmath={"reassoc"})
def inner_product(a, b, length):
    """Inner product of the first ``length`` entries of ``a`` and ``b``.

    Compiled with reassociation allowed (numba ``fastmath={"reassoc"}``, nothing else relaxed), so
    that the sum runs in vector registers: a strict left-to-right sum waits on every addition and
    is about three times slower for the few hundred to tens of thousands of entries of the
    Anderson mixing's inner products and the rail's convolution. The order of the additions is
    then the compiler's, for the machine's vector width: results agree with the strict sum to
    round-off, and may differ between machines by round-off.
    """
    total = 0.0
    for i in range(length):
        total += a[i] * b[i]
    return total


@numba.njit(cache=True)
def scatter_pair(padded, positions, a, b):
    """Write ``a`` and ``b`` into the two layers of ``padded`` (2, Lx, Ly) at the flat ``positions`` of a layer."""
    first = padded[0].reshape(-1)
    second = padded[1].reshape(-1)
    for c in range(positions.shape[0]):
        first[positions[c]] = a[c]
        second[positions[c]] = b[c]


@numba.njit(cache=True)
def gather_pair(padded, positions, a, b):
    """Read ``a`` and ``b`` from the two layers of ``padded`` (2, Lx, Ly) at the flat ``positions`` of a layer."""
    first = padded[0].reshape(-1)
    second = padded[1].reshape(-1)
    for c in range(positions.shape[0]):
        a[c] = first[positions[c]]
        b[c] = second[positions[c]]


@numba.njit(cache=True)
def multiply_tangential(spectrum, s11, s12, s22):
    """``spectrum <- [[s11, s12], [s12, s22]] spectrum`` pointwise, in place (``spectrum`` (2, Lx, Ly // 2 + 1))."""
    for i in range(spectrum.shape[1]):
        for j in range(spectrum.shape[2]):
            fx = spectrum[0, i, j]
            fy = spectrum[1, i, j]
            spectrum[0, i, j] = s11[i, j] * fx + s12[i, j] * fy
            spectrum[1, i, j] = s12[i, j] * fx + s22[i, j] * fy


@numba.njit(cache=True)
def list_product(plan, px, py, ux, uy):
    """Tangential displacement differences at ``plan``'s targets of tractions on its sources (FFT product).

    Parameters
    ----------
    plan : ListProduct
        Kept buffer, positions and spectra (interaction/contact/bundles.py); the buffer is
        written at the source positions only, so its padding stays zero between calls.
    px, py : (ns,) ndarray
        Tractions on the source elements, Pa.
    ux, uy : (nt,) ndarray
        Out: displacement differences at the target elements, m.

    Notes
    -----
    The transforms are ``numpy.fft``'s interface on DUCC0 (the C++ library of scipy.fft),
    called from compiled code through rocket-fft, one thread: along y over the grid's nx rows
    only (the other rows of the embedding are zero), along x with zero padding to ``plan.lx``,
    and back over the nx rows the targets lie in. The compiled calls save the overhead of calls
    from Python (about 48 against 83 us a product at 44 x 36).
    """
    scatter_pair(plan.padded, plan.sources, px, py)
    spectrum = np.fft.rfft(plan.padded, axis=2)
    spectrum = np.fft.fft(spectrum, n=plan.lx, axis=1)
    multiply_tangential(spectrum, plan.s11, plan.s12, plan.s22)
    spectrum = np.fft.ifft(spectrum, axis=1)
    field = np.empty((2, plan.nx, plan.ly))  # given, so that its layout is known (C) to gather_pair
    np.fft.irfft(spectrum[:, :plan.nx], n=plan.ly, axis=2, out=field)
    gather_pair(field, plan.targets, ux, uy)


SLIP_NEWTON_STEP = 1e-8
"""A Newton step of :func:`_local_slip` below this fraction of its slip scale is the last one
(quadratic convergence: the error after it is below 1e-15 of the scale). The test used to wait
for a step of 1e-14, one more iteration for almost every sliding element (about 15 % of a local
sweep, measured at 44 x 36; docs/benchmarks.md)."""


@numba.njit(cache=True)
def grid_product(spectrum, field):
    """``sum_j K[i - j] field[j]`` on an (nx, ny) grid by FFT on the grid doubled in each direction.

    ``spectrum`` is the real-FFT spectrum (2 nx, ny + 1) of the kernel wrapped on (2 nx, 2 ny)
    (:class:`~interaction.contact.influence.ToeplitzOperator`); ``field`` (nx, ny). The
    transforms are numpy.fft's through rocket-fft (DUCC0), one thread.
    """
    nx, ny = field.shape
    shape = (2 * nx, 2 * ny)
    transformed = np.fft.rfft2(field, s=shape)
    return np.ascontiguousarray(np.fft.irfft2(transformed * spectrum, s=shape)[:nx, :ny])


@numba.njit(cache=True)
def tangential_grid_product(s11, s12, s22, traction):
    """Tangential displacement differences (m), (nx, ny, 2), of tractions (Pa), (nx, ny, 2), on the whole grid.

    ``u_x = K11 * p_x + K12 * p_y``, ``u_y = K12 * p_x + K22 * p_y`` (discrete convolutions) by FFT
    on the grid doubled in each direction; ``s11, s12, s22`` the real-FFT spectra of the kernels
    there (:class:`~interaction.contact.influence.ToeplitzOperator`). numpy.fft's transforms
    through rocket-fft (DUCC0), one thread.
    """
    nx = traction.shape[0]
    ny = traction.shape[1]
    shape = (2 * nx, 2 * ny)
    fx = np.fft.rfft2(np.ascontiguousarray(traction[:, :, 0]), s=shape)
    fy = np.fft.rfft2(np.ascontiguousarray(traction[:, :, 1]), s=shape)
    ux = np.fft.irfft2(s11 * fx + s12 * fy, s=shape)
    uy = np.fft.irfft2(s12 * fx + s22 * fy, s=shape)
    out = np.empty((nx, ny, 2))
    for i in range(nx):
        for j in range(ny):
            out[i, j, 0] = ux[i, j]
            out[i, j, 1] = uy[i, j]
    return out


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


@numba.njit(cache=True)
def flat_tangential(influence):
    """The :class:`~interaction.contact.bundles.FlatTangential` view of an ``Influence`` bundle."""
    K11 = influence.K11
    return FlatTangential(K11.ravel(), influence.K12.ravel(), influence.K22.ravel(), K11.shape[1],
                          (K11.shape[0] + 1) // 2 - 1, (K11.shape[1] + 1) // 2 - 1)


@numba.njit(cache=True)
def no_dense_rows():
    """An empty :class:`~interaction.contact.bundles.DenseTangential` (the sweeps use the indexed products)."""
    empty = np.empty(0)
    return DenseTangential(empty, empty, empty, 0)


@numba.njit(cache=True)
def dense_tangential(operator, flat, m11, m12, m22):
    """Dense rows of the tangential influence coefficients between the elements of a contact list.

    Parameters
    ----------
    operator : FlatTangential
        The flat influence coefficients, m/Pa.
    flat : (nc,) int64 ndarray
        ``ix * operator.row + iy`` of the list's elements.
    m11, m12, m22 : (capacity,) ndarray
        Out: ``m[c * nc + t]`` the coefficient between a traction on element c and the
        displacement difference at element t (capacity >= nc²).

    Returns
    -------
    DenseTangential
    """
    nc = flat.shape[0]
    f11 = operator.f11
    f12 = operator.f12
    f22 = operator.f22
    for c in range(nc):
        off = np.uint64(operator.ox * operator.row + operator.oy - flat[c])
        base = c * nc
        for t in range(nc):
            k = np.uint64(flat[t]) + off
            m11[base + t] = f11[k]
            m12[base + t] = f12[k]
            m22[base + t] = f22[k]
    return DenseTangential(m11, m12, m22, nc)


SWEEP_SKIP = 0.1
"""A Gauss-Seidel sweep of :func:`gauss_seidel_with_memory` leaves an element's traction as it is
when its update would change it by at most this many tolerances (so its O(n) update of the
other elements' displacements is saved). The stopping test is unchanged: a sweep whose applied
changes are all within the tolerance ends the iteration, and a skipped update is smaller still,
so the solution satisfies the friction law to the tolerance either way. It matters in the sweep
that confirms a mixed one, whose updates are mostly a small fraction of the tolerance: on the
default study's quiet case (mu = 0.3, eta = -0.3 %, first 1 s) 0.001 and 0.01 tolerances (skip
almost nothing) cost 213 us per step, 0.1 178 us (docs/benchmarks.md)."""

CARRY_LIMIT = 1e4
"""A memory carried into a solution (:func:`continue_history`) is dropped if the first sweep
changes a traction by more than this many tolerances: the carried differences were taken near
the last solution and extrapolate a much larger residual badly (from a zero start, a carried
memory stopped 60-1000 tolerances from the solution, against one for a fresh memory)."""


@numba.njit(cache=True)
def same_list(cache, cix, ciy):
    """Whether ``cache`` (:class:`~interaction.contact.bundles.DenseCache`) holds the rows of this contact list."""
    nc = cix.shape[0]
    if cache.count[0] != nc:
        return False
    for c in range(nc):
        if cache.ix[c] != cix[c] or cache.iy[c] != ciy[c]:
            return False
    return True


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
def contact_rows(operator, cix, ciy, cache):
    """The dense rows of a contact list, from ``cache`` if it holds this list, else built into it.

    Parameters
    ----------
    operator : FlatTangential
    cix, ciy : (nc,) int64 ndarray
        Grid indices of the list, in sweep order.
    cache : DenseCache
        Row storage; rebuilt in place when the list differs from the one it holds.

    Returns
    -------
    DenseTangential
        The rows, or :func:`no_dense_rows` if the list is longer than the cache's capacity (the
        cache is then emptied: it holds the rows of the last list seen, or none).
    """
    nc = cix.shape[0]
    if nc > cache.ix.shape[0]:
        cache.count[0] = -1  # the cache no longer describes the last list (continue_history relies on it)
        return no_dense_rows()
    if not same_list(cache, cix, ciy):
        dense_tangential(operator, cix * operator.row + ciy, cache.m11, cache.m12, cache.m22)
        for c in range(nc):
            cache.ix[c] = cix[c]
            cache.iy[c] = ciy[c]
        cache.count[0] = nc
    return DenseTangential(cache.m11, cache.m12, cache.m22, nc)


@numba.njit(cache=True, inline="always")
def add_dense_row(rows, c, tx, ty, ux, uy):
    """Add to ``ux, uy`` (m) the displacement differences of tractions ``(tx, ty)`` (Pa) on list element ``c``.

    ``rows`` (DenseTangential) holds the list; the update reads its three contiguous rows of
    element c (vectorised): a Gauss-Seidel sweep's update and one term of :func:`dense_product`.
    """
    nc = rows.count
    base = c * nc
    r11 = rows.m11[base:base + nc]
    r12 = rows.m12[base:base + nc]
    r22 = rows.m22[base:base + nc]
    for t in range(nc):
        k12 = r12[t]
        ux[t] += r11[t] * tx + k12 * ty
        uy[t] += k12 * tx + r22[t] * ty


@numba.njit(cache=True)
def dense_product(rows, px, py, ux, uy):
    """Displacement differences (m) of the list's tractions ``(px, py)`` (Pa) from its dense rows, into ``ux, uy``.

    ``rows`` (DenseTangential) must hold the list (``rows.count`` elements).
    """
    nc = rows.count
    for t in range(nc):
        ux[t] = 0.0
        uy[t] = 0.0
    for c in range(nc):
        add_dense_row(rows, c, px[c], py[c], ux, uy)


@numba.njit(cache=True)
def build_upstream_rows(operator, cix, ciy, lookup, ny, upstream):
    """Rows of :class:`~interaction.contact.bundles.UpstreamRows` for a contact list, built in place.

    Parameters
    ----------
    operator : FlatTangential
    cix, ciy : (nc,) int64 ndarray
        Grid indices of the list (the one the :class:`~interaction.contact.bundles.DenseCache`
        holds), none on the grid's edge.
    lookup : (nx ny,) int64 ndarray
        List position of grid element (ix, iy) at ``ix * ny + iy``, -1 outside the list.
    ny : int
        Grid elements along y.
    upstream : UpstreamRows
        Filled: a row per list element whose upstream neighbour (ix + 1, iy) is outside the list;
        none (``count`` -1) if the list is longer than the storage or needs more than
        :data:`~interaction.contact.bundles.UPSTREAM_MAX_ROWS` rows.
    """
    f11 = operator.f11
    f12 = operator.f12
    f22 = operator.f22
    my = operator.row
    ox = operator.ox
    oy = operator.oy
    nc = cix.shape[0]
    upstream.count[0] = -1
    if nc > upstream.position.shape[0]:
        return
    rows = 0
    for c in range(nc):
        upstream.position[c] = -1
    for c in range(nc):
        ix = cix[c] + 1
        iy = ciy[c]
        if lookup[ix * ny + iy] >= 0:
            continue
        if rows == UPSTREAM_MAX_ROWS:
            return
        base = rows * nc
        for k in range(nc):
            kk = (ix - cix[k] + ox) * my + (iy - ciy[k] + oy)
            upstream.m11[base + k] = f11[kk]
            upstream.m12[base + k] = f12[kk]
            upstream.m22[base + k] = f22[kk]
        upstream.position[c] = rows
        rows += 1
    upstream.count[0] = rows


@numba.njit(cache=True)
def tangential_sweep(operator, problem, flat, tractions, compliance, total, skip, status, updates, rows):
    """One Gauss-Seidel sweep over the contact elements (see :func:`tangential_gauss_seidel`).

    Parameters
    ----------
    operator : FlatTangential
        The tangential influence coefficients (m/Pa).
    problem : TangentialProblem
        The contact elements; ``static_bound`` is lowered in place where an element slides.
    flat : (nc,) int64 ndarray
        ``problem.ix * operator.row + problem.iy``.
    tractions : Tractions
        Tractions (Pa) and displacement differences (m), updated in place.
    compliance : SweepCompliance
        Own and series compliances, m/Pa.
    total : (2,) ndarray
        Summed tractions (Pa), updated in place.
    skip : float
        Traction changes up to this (Pa) are not applied.
    status : (nc,) int8 ndarray
        Out: 1 stick, 2 slip.
    updates : LocalUpdates
        Empty (:func:`no_local_updates`): after a traction change the displacement of every
        contact element is updated (the exact sweep). Else (:func:`local_updates`) only at the
        contact elements within a few grid lines of the changed one, the rest of the coupling
        being left to an exact product after the sweep (interaction/contact/transient_fft.py);
        the series springs' term is global and stays exact.
    rows : DenseTangential
        With exact updates and ``rows.count == nc``: the exact updates read these dense rows
        (the same coefficients as ``operator``; bit-identical results, faster). Else
        :func:`no_dense_rows`.

    Returns
    -------
    float
        The largest traction change of the sweep, Pa.
    """
    f11 = operator.f11
    f12 = operator.f12
    f22 = operator.f22
    my = operator.row
    ox = operator.ox
    oy = operator.oy
    cix = problem.ix
    wx = problem.slip_x
    wy = problem.slip_y
    upx = problem.previous_x
    upy = problem.previous_y
    gs = problem.static_bound
    gk = problem.kinetic_bound
    px = tractions.px
    py = tractions.py
    ux = tractions.ux
    uy = tractions.uy
    dxx = compliance.dxx
    dyy = compliance.dyy
    series_x = compliance.series_x
    series_y = compliance.series_y
    nc = cix.shape[0]
    neighbours = updates.neighbours
    exact = neighbours.shape[0] == 0
    s11 = updates.stencil[0]
    s12 = updates.stencil[1]
    s22 = updates.stencil[2]
    change = 0.0
    total_x = total[0]
    total_y = total[1]
    for c in range(nc):
        sx = wx[c] + ux[c] - upx[c] + series_x * total_x
        sy = wy[c] + uy[c] - upy[c] + series_y * total_y
        qx, qy, sliding = element_law(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c])
        status[c] = 2 if sliding else 1
        if sliding:
            gs[c] = gk[c]  # once sliding, kinetic friction bounds a return to stick
        dpx = qx - px[c]
        dpy = qy - py[c]
        if abs(dpx) > skip or abs(dpy) > skip:
            px[c] = qx
            py[c] = qy
            total_x += dpx
            total_y += dpy
            if exact and rows.count == nc:
                add_dense_row(rows, c, dpx, dpy, ux, uy)
            elif exact:
                off = np.uint64(ox * my + oy - flat[c])  # unsigned indices: no wraparound test, the loop vectorises
                for t in range(nc):
                    k = np.uint64(flat[t]) + off
                    k12 = f12[k]
                    ux[t] += f11[k] * dpx + k12 * dpy
                    uy[t] += k12 * dpx + f22[k] * dpy
            else:
                near = neighbours[c]
                for q in range(near.shape[0]):
                    t = near[q]
                    if t >= 0:
                        ux[t] += s11[q] * dpx + s12[q] * dpy
                        uy[t] += s12[q] * dpx + s22[q] * dpy
            m = max(abs(dpx), abs(dpy))
            if m > change:
                change = m
    total[0] = total_x
    total[1] = total_y
    return change


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
    """The :class:`~interaction.contact.bundles.LocalUpdates` of a contact list: neighbours within ``reach`` lines.

    ``cix, ciy`` are the grid indices of the list's elements on an nx x ny grid. The table and
    the stencil replace, in the sweeps' inner loop, a lookup of the grid position and a gather
    of the kernels per neighbour by one row of list positions and a few coefficients that stay
    in registers (two local sweeps 77 against 96 us at 44 x 36; docs/benchmarks.md). The
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
def no_local_updates():
    """Empty :class:`~interaction.contact.bundles.LocalUpdates`: the sweep updates every contact element (exact)."""
    return LocalUpdates(np.empty((0, 0), np.int64), np.empty((3, 0)))


@numba.njit(cache=True)
def gather_tangential_problem(pressure, rigid_slip, previous, upstream, warm, warm_displacement, static, kinetic):
    """A transient or shift tangential problem gathered from grid fields, its contact elements in sweep order.

    The sweep order is the exact sweeps': lines of constant x from the leading edge (large x)
    to the trailing edge, each along increasing y.

    Parameters
    ----------
    pressure : (nx, ny) ndarray
        Pressure (Pa); the contact is where it is > 0.
    rigid_slip : (nx, ny, 2) ndarray
        Rigid slip over the step (m).
    previous : (nx, ny, 2) ndarray
        Previous displacement field (m); an empty (0, 0, 2) array for zero.
    upstream : int
        1 (transient rolling): an element's previous displacement is that of the element
        upstream (``ix + 1``); 0 (shift): its own.
    warm, warm_displacement : (nx, ny, 2) ndarray
        Warm-start tractions (Pa) and their displacement (m); empty (0, 0, 2) arrays for none.
    static, kinetic : float
        Friction coefficients.

    Returns
    -------
    problem : TangentialProblem
        Empty lists with ``status`` 1 if the contact reaches the grid's leading line in
        transient rolling (no element upstream there).
    tractions : Tractions
        The warm start at the contact elements; its displacements are ``warm_displacement``'s,
        valid only if ``status`` is 0 (given, and the warm tractions are zero outside the
        contact, so they are those of the contact's tractions).
    status : int
        0 the warm displacements hold, 2 they must be computed from the tractions, 1 as above.
    """
    nx, ny = pressure.shape
    count = 0
    for ix in range(nx):
        for iy in range(ny):
            if pressure[ix, iy] > 0.0:
                count += 1
                if upstream == 1 and ix == nx - 1:
                    empty = np.empty(0)
                    index = np.empty(0, np.int64)
                    return (TangentialProblem(index, index, empty, empty, empty, empty, empty, empty),
                            Tractions(empty, empty, empty, empty), 1)
    cix = np.empty(count, np.int64)
    ciy = np.empty(count, np.int64)
    wx = np.empty(count)
    wy = np.empty(count)
    upx = np.zeros(count)
    upy = np.zeros(count)
    gs = np.empty(count)
    gk = np.empty(count)
    px = np.zeros(count)
    py = np.zeros(count)
    ux = np.zeros(count)
    uy = np.zeros(count)
    have_previous = previous.shape[0] > 0
    have_warm = warm.shape[0] > 0
    c = 0
    for ix in range(nx - 1, -1, -1):
        for iy in range(ny):
            pz = pressure[ix, iy]
            if pz > 0.0:
                cix[c] = ix
                ciy[c] = iy
                wx[c] = rigid_slip[ix, iy, 0]
                wy[c] = rigid_slip[ix, iy, 1]
                if have_previous:
                    upx[c] = previous[ix + upstream, iy, 0]
                    upy[c] = previous[ix + upstream, iy, 1]
                gs[c] = static * pz
                gk[c] = kinetic * pz
                if have_warm:
                    px[c] = warm[ix, iy, 0]
                    py[c] = warm[ix, iy, 1]
                c += 1
    status = 2
    if have_warm and warm_displacement.shape[0] > 0:
        status = 0
        for ix in range(nx):
            for iy in range(ny):
                if pressure[ix, iy] <= 0.0 and (warm[ix, iy, 0] != 0.0 or warm[ix, iy, 1] != 0.0):
                    status = 2
        if status == 0:
            for c in range(count):
                ux[c] = warm_displacement[cix[c], ciy[c], 0]
                uy[c] = warm_displacement[cix[c], ciy[c], 1]
    return TangentialProblem(cix, ciy, wx, wy, upx, upy, gs, gk), Tractions(px, py, ux, uy), status


@numba.njit(cache=True)
def gather_pair_at(field, cix, ciy, a, b):
    """``a, b <- field[cix, ciy, 0], field[cix, ciy, 1]`` for a (nx, ny, 2) field."""
    for c in range(cix.shape[0]):
        a[c] = field[cix[c], ciy[c], 0]
        b[c] = field[cix[c], ciy[c], 1]


@numba.njit(cache=True)
def scatter_pair_at(field, cix, ciy, a, b):
    """``field[cix, ciy, 0], field[cix, ciy, 1] <- a, b`` for a (nx, ny, 2) field (the rest left as it is)."""
    for c in range(cix.shape[0]):
        field[cix[c], ciy[c], 0] = a[c]
        field[cix[c], ciy[c], 1] = b[c]


@numba.njit(cache=True)
def scatter_solution(cix, ciy, px, py, status, traction, grid_status):
    """``traction[cix, ciy] <- (px, py)`` and ``grid_status[cix, ciy] <- status`` (the rest left as it is)."""
    scatter_pair_at(traction, cix, ciy, px, py)
    for c in range(cix.shape[0]):
        grid_status[cix[c], ciy[c]] = status[c]


@numba.njit(cache=True)
def sum_tractions(px, py, total):
    """``total <- (sum px, sum py)`` (Pa): the summed tractions that the series springs see."""
    total[0] = 0.0
    total[1] = 0.0
    for c in range(px.shape[0]):
        total[0] += px[c]
        total[1] += py[c]


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
    O(nc * runs) = O(nc^2 / block), not O(nc^2) (10 ms at 88 x 72, 4144 elements in contact,
    blocks of 8 lines).

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
    """The :class:`~interaction.contact.bundles.CoarseLevel` of a contact list on square blocks of ``block`` grid lines.

    :func:`coarse_blocks`, and the inverse of their :func:`coarse_matrix` (the parameters there).
    """
    group, size = coarse_blocks(cix, ciy, block)
    return CoarseLevel(group, size, np.linalg.inv(coarse_matrix(operator, cix, ciy, group, size, series_x, series_y)))


@numba.njit(cache=True)
def no_coarse_level():
    """Empty :class:`~interaction.contact.bundles.CoarseLevel`: no coarse correction."""
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

    The loop of :func:`interaction.contact.transient_fft.transient_sweeps_fft` (see there): each
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


@numba.njit(cache=True)
def cholesky_solve(g, rhs, count):
    """Solve ``G x = rhs`` in place for a symmetric positive definite ``G`` (its lower triangle).

    The leading ``count`` × ``count`` block of ``g`` is overwritten by its Cholesky factor L
    (lower triangle, row by row) and ``rhs[:count]`` by the solution (forward, then backward
    substitution). Returns False, with ``g`` and ``rhs`` partly overwritten, if a pivot is not
    positive (G not positive definite to round-off). Shared by the Anderson mixing of the contact
    solvers and the force predictor of the interaction's half-space loop.
    """
    for a in range(count):
        for b in range(a + 1):
            acc = g[a, b]
            for c in range(b):
                acc -= g[a, c] * g[b, c]
            if a == b:
                if acc <= 0.0:
                    return False
                g[a, a] = math.sqrt(acc)
            else:
                g[a, b] = acc / g[b, b]
    for a in range(count):
        acc = rhs[a]
        for c in range(a):
            acc -= g[a, c] * rhs[c]
        rhs[a] = acc / g[a, a]
    for a in range(count - 1, -1, -1):
        acc = rhs[a]
        for c in range(a + 1, count):
            acc -= g[c, a] * rhs[c]
        rhs[a] = acc / g[a, a]
    return True


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
    swamps the newest and smallest, and the mixing then hardly uses them. Measured on the
    44 x 36 transient from rest (eta = -0.3 %, first 100 steps): 5628 against 5891 iterations
    with the same memory of 16 (docs/benchmarks.md).
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
    """An empty :class:`~interaction.contact.bundles.AndersonHistory` of ``depth`` sweeps (at least one slot).

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
    # not vectorised (about three times slower; the same operations in the same order)
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


@numba.njit(cache=True)
def tangential_gauss_seidel(influence, problem, tractions, tol, max_sweeps, series, depth, rows):
    """Gauss-Seidel sweeps, Anderson-accelerated, for the tangential tractions of the contact elements.

    :func:`gauss_seidel_with_memory` with a fresh Anderson memory (its documentation holds the
    parameters and returns).
    """
    nc = problem.ix.shape[0]
    return gauss_seidel_with_memory(influence, problem, tractions, tol, max_sweeps, series, rows,
                                    anderson_history(depth, nc, nc), depth)


@numba.njit(cache=True)
def gauss_seidel_with_memory(influence, problem, tractions, tol, max_sweeps, series, rows, history, depth):
    """Gauss-Seidel sweeps, Anderson-accelerated, for the tangential tractions of the contact elements.

    Each sweep visits the contact elements in order and solves each one's local problem with the
    others fixed: stick if the traction that cancels its slip is within the static bound, else
    the slip traction on the kinetic bound (Kalker's / Vollebregt's ConvexGS idea). The sweep is
    a fixed-point map ``x -> G(x)`` of the tractions; type-II Anderson mixing over the last
    ``depth`` sweeps (``x <- G(x_k) - sum_j gamma_j (G(x_j+1) - G(x_j))``, gamma the least-squares
    fit of the residuals ``G(x) - x``) cuts the sweeps 2-2.5 fold. The displacements are affine in
    the tractions, so they are mixed with the same coefficients and stay consistent. The result
    is always the output of a plain sweep, so it satisfies the friction bounds, and convergence
    is judged on that sweep's change. A mixing step that makes the next change grow restarts
    the history.

    Parameters
    ----------
    influence : Influence
        Influence coefficients of the grid (interaction/contact/bundles.py); K11, K12, K22
        (2 nx - 1, 2 ny - 1), m/Pa.
    problem : TangentialProblem
        The contact elements in sweep order (leading edge first), their rigid slip, previous
        displacements and traction bounds. The static bound is lowered to the kinetic one in
        place where an element slides (hysteresis: this keeps the iteration monotone, and
        convergent, when mu_s > mu_k).
    tractions : Tractions
        Tractions (Pa), initial guess in, solution out, and the displacement differences (m) of
        the contact elements, consistent with the tractions on entry; updated in place.
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps : int
        Limit of sweeps.
    series : (float, float)
        Compliances of springs in series with the contact along x and y (e.g. the structures'
        instantaneous compliance) times the element area (m/Pa): every element's slip gains
        ``series * sum(p)``, the displacement of the springs under the total force. Zero for the
        contact alone.
    rows : DenseTangential
        The influence coefficients between the contact elements as dense rows
        (:func:`contact_rows`; the same numbers, faster), or :func:`no_dense_rows`: the sweeps
        then index the kernels directly.
    history : AndersonHistory
        The mixing's memory (:func:`anderson_history` for at least nc elements), empty or carried
        from an earlier solution of the same contact list (:func:`carried_anderson_history`,
        :func:`continue_history`); updated in place. A carried memory is dropped if the first
        sweep changes a traction by more than :data:`CARRY_LIMIT` tolerances.
    depth : int
        0: plain Gauss-Seidel sweeps, no mixing; else the memory's ring holds its own number of
        sweeps.

    Returns
    -------
    sweeps : int
        Sweeps done.
    change : float
        Largest traction change (Pa) in the last sweep.
    status : int8 ndarray (nc,)
        1 stick, 2 slip.
    """
    K11 = influence.K11
    K22 = influence.K22
    cix = problem.ix
    ciy = problem.iy
    px = tractions.px
    py = tractions.py
    ux = tractions.ux
    uy = tractions.uy
    series_x, series_y = series
    nc = cix.shape[0]
    status = np.ones(nc, np.int8)
    operator = flat_tangential(influence)
    ox = operator.ox
    oy = operator.oy
    my = operator.row
    compliance = SweepCompliance(K11[ox, oy] + series_x, K22[ox, oy] + series_y, series_x, series_y)
    total = np.zeros(2)  # sum of the tractions (Pa): the series springs' displacement is series * total
    sum_tractions(px, py, total)
    skip = SWEEP_SKIP * tol  # changes this small are not applied (below the tolerance)
    flat = cix * my + ciy
    exact = no_local_updates()
    change = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        anderson_input(history, px, py)
        change = tangential_sweep(operator, problem, flat, tractions, compliance, total, skip, status, exact, rows)
        sweeps = sweep + 1
        if change <= tol:
            break
        if depth == 0:
            continue
        if sweep == 0 and change > CARRY_LIMIT * tol:
            # far from the solution: the carried differences (taken near the last one) would
            # extrapolate the much larger residual, so they are dropped
            history.counters[0] = 0
            history.counters[1] = -1
        if anderson_mix(history, change, px, py, ux, uy):
            sum_tractions(px, py, total)
    return sweeps, change, status


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

    The algorithm of interaction/contact/normal.py (which documents it), with direct products of
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
        (interaction/contact/bundles.py).
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


@numba.njit(cache=True)
def normal_solution_table(influence, grid, gap, approaches, tol):
    """Normal solutions of the contact alone at the given approaches (m), each warm-started from the last.

    The normal problem of quasi-identical bodies depends on the approach alone, so these
    solutions give any later solution a warm start with nearly the right contact area
    (:func:`transient_rolling_step`).

    Parameters
    ----------
    influence : Influence
        Influence coefficients of the grid (K33 is used), m/Pa.
    grid : GridGeometry
        The grid (nx, ny and the element area are used).
    gap : ndarray (nx ny,)
        Undeformed gap, m, flat in C order.
    approaches : ndarray (m,)
        Ascending approaches, m.
    tol : float
        Relative tolerance of the solutions (-).

    Returns
    -------
    pressure : ndarray (len(approaches), nx ny)
        Pa.
    displacement : ndarray (len(approaches), nx ny)
        Normal displacement difference ``A p`` on the whole grid, m.
    force : ndarray (len(approaches),)
        Normal forces, N.
    ok : bool
        Every solution converged.
    """
    area = grid.area
    n = grid.nx * grid.ny
    m = approaches.shape[0]
    pressure = np.zeros((m, n))
    displacement = np.zeros((m, n))
    force = np.zeros(m)
    p = np.zeros(n)
    ok = True
    for k in range(m):
        warm = False
        for i in range(n):
            if p[i] > 0.0:
                warm = True
                break
        if not warm:
            for i in range(n):
                if gap[i] < approaches[k]:
                    p[i] = 1.0
                    warm = True
        if warm:
            _, _, converged, u, _ = normal_conjugate_gradient(
                influence.K33, NormalProblem(gap, p, False, approaches[k], 0.0, area, tol, 1000, True), True)
            ok = ok and converged
            for i in range(n):
                displacement[k, i] = u[i]
        total = 0.0
        for i in range(n):
            pressure[k, i] = p[i]
            total += p[i]
        force[k] = total * area
    return pressure, displacement, force, ok


@numba.njit(cache=True)
def _table_warm_start(table, approach, series, out, out_displacement):
    """Warm start of the normal problem for a total ``approach`` (m) with series compliance ``series`` (m/N).

    Interpolates the tabulated solutions of the contact alone, pressure (Pa) into ``out`` and
    displacement (m) into ``out_displacement``, at the own approach d that solves
    ``d + series F(d) = approach`` (increasing in d; F interpolated linearly), from the
    :class:`~interaction.contact.bundles.NormalTable` ``table``.
    """
    table_approach = table.approach
    table_force = table.force
    table_pressure = table.pressure
    table_displacement = table.displacement
    m = table_approach.shape[0]
    lo = 0
    hi = m - 1
    if table_approach[hi] + series * table_force[hi] <= approach:
        lo = hi - 1
    else:
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if table_approach[mid] + series * table_force[mid] <= approach:
                lo = mid
            else:
                hi = mid
    g_lo = table_approach[lo] + series * table_force[lo] - approach
    g_hi = table_approach[lo + 1] + series * table_force[lo + 1] - approach
    theta = g_lo / (g_lo - g_hi) if g_hi != g_lo else 0.0
    theta = min(max(theta, 0.0), 1.0)
    for i in range(out.shape[0]):
        out[i] = (1.0 - theta) * table_pressure[lo, i] + theta * table_pressure[lo + 1, i]
        out_displacement[i] = (1.0 - theta) * table_displacement[lo, i] + theta * table_displacement[lo + 1, i]


@numba.njit(cache=True)
def _tangential_displacement_at(operator, ix, iy, src_ix, src_iy, src_tx, src_ty, sources):
    """Tangential displacement difference (m) at element (ix, iy) of the source tractions listed in ``sources``.

    ``operator`` (FlatTangential) holds the influence coefficients; the sources are the elements
    ``(src_ix[j], src_iy[j])`` with tractions ``(src_tx[j], src_ty[j])`` (Pa) for j in ``sources``.
    """
    f11 = operator.f11
    f12 = operator.f12
    f22 = operator.f22
    my = operator.row
    ox = operator.ox
    oy = operator.oy
    ux = 0.0
    uy = 0.0
    for jj in range(sources.shape[0]):
        j = sources[jj]
        k = (ix - src_ix[j] + ox) * my + (iy - src_iy[j] + oy)
        k12 = f12[k]
        ux += f11[k] * src_tx[j] + k12 * src_ty[j]
        uy += k12 * src_tx[j] + f22[k] * src_ty[j]
    return ux, uy


@numba.njit(cache=True)
def transient_rolling_step(inputs, step, states, committed, warm, out):
    """One transient rolling step of the half-space model, all compiled (the interaction's time loop).

    The same problem as :meth:`HalfspaceContact.solve` with ``kind="transient"``, a prescribed
    approach and series compliances (interaction/contact/halfspace.py documents it), with the
    states held as lists of the elements in contact instead of full-grid fields: for each, the
    tractions and the tangential displacement difference at those elements. The displacement
    of a state at other elements (the particles entering the contact, elements that join it) is
    summed directly from its tractions.

    Parameters
    ----------
    inputs : HalfspaceInputs
        The model (influence coefficients, grid, gap, friction, solver settings, table of normal
        solutions; interaction/contact/bundles.py).
    step : RollingInputs
        Approach, creepages and series compliances of this solution.
    states : ElementStates
        Contact states; slot ``committed`` holds the committed state of the previous step,
        slot ``warm`` the warm start (the committed state or an earlier solution of this step),
        slot ``out`` receives the result (all but its ``count`` and ``threshold``, which the
        caller stores from the returned values once the solution is accepted).
    committed, warm, out : int
        Slots of ``states``.

    Returns
    -------
    (status, count, fx, fy, fz, n_slip, normal_iterations, sweeps, threshold) : tuple
        ``status`` 0 converged, 1 normal problem not converged, 2 tangential problem not
        converged, 3 the contact area reaches the grid edge; ``count`` elements in contact (the
        result's list length), forces on the wheel (N), elements in slip, the normal solver's
        iterations, the tangential sweeps, and the gap bound (m) below which the result's
        ``normal_u`` holds.
    """
    K33 = inputs.influence.K33
    nx = inputs.grid.nx
    ny = inputs.grid.ny
    x = inputs.grid.x
    y = inputs.grid.y
    dx = inputs.grid.dx
    area = inputs.grid.area
    gap = inputs.gap
    mu_static = inputs.friction.static
    mu_kinetic = inputs.friction.kinetic
    tol = inputs.solver.tol
    max_sweeps = inputs.solver.max_sweeps
    depth = inputs.solver.anderson_depth
    approach = step.approach
    creepage = step.creepage
    creepage_per_force = step.creepage_per_force
    force_reference = step.force_reference
    series = step.series
    use_table = step.use_table
    s_count = states.count[committed]
    s_ix = states.ix[committed]
    s_iy = states.iy[committed]
    s_tx = states.tx[committed]
    s_ty = states.ty[committed]
    s_ux = states.ux[committed]
    s_uy = states.uy[committed]
    s_lookup = states.lookup[committed]
    w_pressure = states.pressure[warm]
    w_normal_u = states.normal_u[warm]
    w_threshold = states.threshold[warm]
    w_count = states.count[warm]
    w_ix = states.ix[warm]
    w_iy = states.iy[warm]
    w_tx = states.tx[warm]
    w_ty = states.ty[warm]
    w_ux = states.ux[warm]
    w_uy = states.uy[warm]
    w_lookup = states.lookup[warm]
    r_pressure = states.pressure[out]
    r_normal_u = states.normal_u[out]
    r_ix = states.ix[out]
    r_iy = states.iy[out]
    r_tx = states.tx[out]
    r_ty = states.ty[out]
    r_ux = states.ux[out]
    r_uy = states.uy[out]
    r_status = states.status[out]
    r_lookup = states.lookup[out]
    n = nx * ny
    operator = flat_tangential(inputs.influence)
    u_warm = w_normal_u
    u_threshold = w_threshold
    if use_table and approach > 0.0:
        u_warm = np.empty(n)
        u_threshold = np.inf
        _table_warm_start(inputs.table, approach, series[2], r_pressure, u_warm)
    else:
        for i in range(n):
            r_pressure[i] = w_pressure[i]
    for i in range(n):
        r_lookup[i] = -1
    warm = False
    for i in range(n):
        if r_pressure[i] > 0.0:
            warm = True
            break
    if not warm and approach > 0.0:
        # cold start (after lift-off): unit pressure where the approach closes the gap, which the
        # solver first rescales to the approach
        for i in range(n):
            if gap[i] < approach:
                r_pressure[i] = 1.0
                warm = True
    iterations = 0
    threshold = np.inf  # r_normal_u is A p where the gap is below it
    if warm and approach > 0.0:
        if u_warm.shape[0] == n and not use_table:
            for i in range(n):
                if r_pressure[i] != w_pressure[i]:  # the cold start replaced the warm state
                    u_warm = np.empty(0)
                    break
        iterations, _, converged, u, threshold = normal_conjugate_gradient(
            K33, NormalProblem(gap, r_pressure, False, approach, series[2] * area, area, tol, 1000, warm), False,
            u_warm, u_threshold)
        if not converged:
            return 1, 0, 0.0, 0.0, 0.0, 0, iterations, 0, threshold
        for i in range(n):
            r_normal_u[i] = u[i]
    else:
        for i in range(n):
            r_pressure[i] = 0.0
            r_normal_u[i] = 0.0
    # elements in contact, in sweep order: leading edge (large x) first
    count = 0
    pmax = 0.0
    fz = 0.0
    for ix in range(nx - 1, -1, -1):
        for iy in range(ny):
            i = ix * ny + iy
            pz = r_pressure[i]
            if pz > 0.0:
                if ix == 0 or ix == nx - 1 or iy == 0 or iy == ny - 1:
                    return 3, 0, 0.0, 0.0, 0.0, 0, iterations, 0, threshold
                r_ix[count] = ix
                r_iy[count] = iy
                r_lookup[i] = count
                count += 1
                pmax = max(pmax, pz)
                fz += pz
    fz *= area
    if count == 0:
        return 0, 0, 0.0, 0.0, 0.0, 0, iterations, 0, threshold
    cix = r_ix[:count]
    ciy = r_iy[:count]
    wx = np.empty(count)
    wy = np.empty(count)
    upx = np.empty(count)
    upy = np.empty(count)
    gs = np.empty(count)
    gk = np.empty(count)
    every_s = np.arange(s_count)
    # warm-start elements out of contact now, and those still in contact
    n_dropped = 0
    for j in range(w_count):
        if r_lookup[w_ix[j] * ny + w_iy[j]] < 0:
            n_dropped += 1
    dropped = np.empty(n_dropped, np.int64)
    kept = np.empty(w_count - n_dropped, np.int64)
    a = 0
    b = 0
    for j in range(w_count):
        if r_lookup[w_ix[j] * ny + w_iy[j]] < 0:
            dropped[a] = j
            a += 1
        else:
            kept[b] = j
            b += 1
    # the last step's displacement upstream of the leading edge from rows, while its list is the cached one
    upstream = states.upstream
    rows_upstream = upstream.count[0] >= 0 and same_list(states.rows, s_ix[:s_count], s_iy[:s_count])
    xi = creepage[0] + creepage_per_force[0] * (fz - force_reference)
    eta = creepage[1] + creepage_per_force[1] * (fz - force_reference)
    phi = creepage[2]
    for c in range(count):
        ix = cix[c]
        iy = ciy[c]
        pz = r_pressure[ix * ny + iy]
        gs[c] = mu_static * pz
        gk[c] = mu_kinetic * pz
        wx[c] = (xi - phi * y[iy]) * dx
        wy[c] = (eta + phi * x[ix]) * dx
        # u': the previous displacement of the particle now here, one element upstream
        j = s_lookup[(ix + 1) * ny + iy]
        if j >= 0:
            upx[c] = s_ux[j]
            upy[c] = s_uy[j]
        else:
            row = -1
            if rows_upstream:
                j = s_lookup[ix * ny + iy]
                if j >= 0:
                    row = upstream.position[j]
            if row >= 0:
                base = row * s_count
                r11 = upstream.m11[base:base + s_count]
                r12 = upstream.m12[base:base + s_count]
                r22 = upstream.m22[base:base + s_count]
                upx[c] = inner_product(r11, s_tx, s_count) + inner_product(r12, s_ty, s_count)
                upy[c] = inner_product(r12, s_tx, s_count) + inner_product(r22, s_ty, s_count)
            else:
                upx[c], upy[c] = _tangential_displacement_at(operator, ix + 1, iy, s_ix, s_iy, s_tx, s_ty,
                                                             every_s)
        # warm start: the warm state's tractions where still in contact, with their displacement
        j = w_lookup[ix * ny + iy]
        if j >= 0:
            r_tx[c] = w_tx[j]
            r_ty[c] = w_ty[j]
            r_ux[c] = w_ux[j]
            r_uy[c] = w_uy[j]
            if n_dropped > 0:
                ax, ay = _tangential_displacement_at(operator, ix, iy, w_ix, w_iy, w_tx, w_ty, dropped)
                r_ux[c] -= ax
                r_uy[c] -= ay
        else:
            r_tx[c] = 0.0
            r_ty[c] = 0.0
            r_ux[c], r_uy[c] = _tangential_displacement_at(operator, ix, iy, w_ix, w_iy, w_tx, w_ty, kept)
    scale = pmax * min(max(mu_static, 1e-3), 1.0)
    px = r_tx[:count]
    py = r_ty[:count]
    ux = r_ux[:count]
    uy = r_uy[:count]
    # the mixing's memory and the dense rows belong to the last contact list: kept while it stays
    same = same_list(states.rows, cix, ciy)
    continue_history(states.mixing, same)
    rows = contact_rows(operator, cix, ciy, states.rows)
    if not same:
        if rows.count == count:
            build_upstream_rows(operator, cix, ciy, r_lookup, ny, upstream)
        else:
            upstream.count[0] = -1
    sweeps, change, status = gauss_seidel_with_memory(
        inputs.influence, TangentialProblem(cix, ciy, wx, wy, upx, upy, gs, gk), Tractions(px, py, ux, uy), tol * scale,
        max_sweeps, (series[0] * area, series[1] * area), rows, states.mixing, depth)
    if change > tol * scale:
        return 2, count, 0.0, 0.0, 0.0, 0, iterations, sweeps, threshold
    fx = 0.0
    fy = 0.0
    n_slip = 0
    for c in range(count):
        fx += px[c]
        fy += py[c]
        r_status[c] = status[c]
        if status[c] == 2:
            n_slip += 1
    return 0, count, fx * area, fy * area, fz, n_slip, iterations, sweeps, threshold
