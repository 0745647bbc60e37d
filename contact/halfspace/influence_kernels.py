"""Products of the half-space influence coefficients, compiled (lazily, cached on disk).

By FFT: :func:`list_product` (tangential, from one fixed list of grid elements to another, the
bundle :class:`~contact.halfspace.bundles.ListProduct`), :func:`grid_product` and
:func:`tangential_grid_product` (on the whole grid); the transforms are numpy.fft's through
rocket-fft. By dense rows among the elements of a contact list: the flat view of the
coefficients (:func:`flat_tangential`, :class:`~contact.halfspace.bundles.FlatTangential`),
the rows (:func:`dense_tangential`, kept per list in a
:class:`~contact.halfspace.bundles.DenseCache` by :func:`contact_rows`), their products
(:func:`add_dense_row`, :func:`dense_product`) and the rows of the elements upstream of a list's
leading edge (:func:`build_upstream_rows`). Nothing is compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np
import rocket_fft  # noqa: F401  (numpy.fft inside compiled kernels: list_product, grid_product)

from contact.halfspace.bundles import UPSTREAM_MAX_ROWS, DenseTangential, FlatTangential


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
        Kept buffer, positions and spectra (contact/halfspace/bundles.py); the buffer is
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
    from Python (docs/benchmarks.md, *Contact solvers against CONTACT*).
    """
    scatter_pair(plan.padded, plan.sources, px, py)
    spectrum = np.fft.rfft(plan.padded, axis=2)
    spectrum = np.fft.fft(spectrum, n=plan.lx, axis=1)
    multiply_tangential(spectrum, plan.s11, plan.s12, plan.s22)
    spectrum = np.fft.ifft(spectrum, axis=1)
    field = np.empty((2, plan.nx, plan.ly))  # given, so that its layout is known (C) to gather_pair
    np.fft.irfft(spectrum[:, :plan.nx], n=plan.ly, axis=2, out=field)
    gather_pair(field, plan.targets, ux, uy)


@numba.njit(cache=True)
def grid_product(spectrum, field):
    """``sum_j K[i - j] field[j]`` on an (nx, ny) grid by FFT on the grid doubled in each direction.

    ``spectrum`` is the real-FFT spectrum (2 nx, ny + 1) of the kernel wrapped on (2 nx, 2 ny)
    (:class:`~contact.halfspace.influence.ToeplitzOperator`); ``field`` (nx, ny). The
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
    there (:class:`~contact.halfspace.influence.ToeplitzOperator`). numpy.fft's transforms
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
def flat_tangential(influence):
    """The :class:`~contact.halfspace.bundles.FlatTangential` view of an ``Influence`` bundle."""
    K11 = influence.K11
    return FlatTangential(K11.ravel(), influence.K12.ravel(), influence.K22.ravel(), K11.shape[1],
                          (K11.shape[0] + 1) // 2 - 1, (K11.shape[1] + 1) // 2 - 1)


@numba.njit(cache=True)
def no_dense_rows():
    """An empty :class:`~contact.halfspace.bundles.DenseTangential` (the sweeps use the indexed products)."""
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


@numba.njit(cache=True)
def same_list(cache, cix, ciy):
    """Whether ``cache`` (:class:`~contact.halfspace.bundles.DenseCache`) holds the rows of this contact list."""
    nc = cix.shape[0]
    if cache.count[0] != nc:
        return False
    for c in range(nc):
        if cache.ix[c] != cix[c] or cache.iy[c] != ciy[c]:
            return False
    return True


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
    """Rows of :class:`~contact.halfspace.bundles.UpstreamRows` for a contact list, built in place.

    Parameters
    ----------
    operator : FlatTangential
    cix, ciy : (nc,) int64 ndarray
        Grid indices of the list (the one the :class:`~contact.halfspace.bundles.DenseCache`
        holds), none on the grid's edge.
    lookup : (nx ny,) int64 ndarray
        List position of grid element (ix, iy) at ``ix * ny + iy``, -1 outside the list.
    ny : int
        Grid elements along y.
    upstream : UpstreamRows
        Filled: a row per list element whose upstream neighbour (ix + 1, iy) is outside the list;
        none (``count`` -1) if the list is longer than the storage or needs more than
        :data:`~contact.halfspace.bundles.UPSTREAM_MAX_ROWS` rows.
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
