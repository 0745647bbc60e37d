"""Matrix-free influence products of the half-space contact model by FFT.

The influence matrices of a uniform nx x ny grid (:mod:`contact.halfspace.influence`) are
2-level Toeplitz: the coefficient between field element (i, j) and source element (k, l)
depends only on the offset (i - k, j - l) and is stored as a kernel ``K[i - k + nx - 1,
j - l + ny - 1]`` of shape (2 nx - 1, 2 ny - 1). Placing the kernel, offsets taken modulo
(Lx, Ly) with Lx >= 2 nx - 1 and Ly >= 2 ny - 1, on an Lx x Ly periodic grid embeds the
Toeplitz matrix into a 2-level circulant one without overlap, so the product with a field
zero-padded to Lx x Ly is a cyclic convolution, i.e. a pointwise product of 2-D DFTs whose
first nx x ny entries are the Toeplitz product (e.g. Golub & Van Loan, Matrix Computations,
sec. 4.8). Cost O(nx ny log(nx ny)) per product and memory O(nx ny), against O((nx ny)^2)
for a dense matrix.

Every kernel of two quasi-identical half-spaces has a parity that makes its spectrum real:
K11, K22 and K33 are even in both offsets, and K12 (from nu x y / r^3) is odd in each, hence
even under (x, y) -> (-x, -y). The same K12 couples u_x to p_y and u_y to p_x, so the
tangential block [[A11, A12], [A12, A22]] is symmetric. A real spectrum halves the memory
and the work of the pointwise product; a kernel without that parity keeps its complex
spectrum (detected, not assumed).

The products take and return grid fields of shape (nx, ny) in the grid's (x, y) index order,
tractions in Pa and displacement differences in m. The ``*_on`` variants form the product of
a field given on a subset of elements (e.g. the elements in contact; zero elsewhere) and
return it on a (possibly different) subset, the FFT replacement of the direct sums over the
contact set in :mod:`contact.halfspace.normal_kernels` and
:mod:`contact.halfspace.rolling_kernels`.
"""

from __future__ import annotations

import logging
from typing import NamedTuple, Optional

import numpy as np
import rocket_fft

from squealcore.errors import InputError

from contact.halfspace.bundles import ListProduct
from contact.halfspace.influence_kernels import list_product

__all__ = [
    "InfluenceSpectra",
    "influence_spectra",
    "spectra_from_kernels",
    "kernel_spectrum",
    "normal_product",
    "tangential_product",
    "normal_product_on",
    "tangential_product_on",
    "steady_tangential_product_on",
    "TangentialListProduct",
]

log = logging.getLogger(__name__)

# an imaginary part below this fraction of the kernel's l1 norm (which bounds every spectral
# value) is round-off of an exactly even/odd kernel: about log2(L) eps of the FFT plus the
# last-digit asymmetry of the closed-form coefficients
_REAL_SPECTRUM_TOLERANCE = 1e-12


class InfluenceSpectra(NamedTuple):
    """Precomputed spectra of the influence kernels of one grid (frozen; plain arrays and ints).

    Attributes
    ----------
    nx, ny : int
        Grid size (elements).
    shape : tuple of int
        (Lx, Ly), the size of the periodic embedding (Lx >= 2 nx - 1, Ly >= 2 ny - 1).
    s11, s12, s22, s33 : ndarray (Lx, Ly // 2 + 1) or None
        ``numpy.fft.rfft2`` of the wrapped kernels (m/Pa); real (float64) when the kernel has
        the half-space parity, else complex128; None when that kernel was not requested.
    """

    nx: int
    ny: int
    shape: tuple
    s11: Optional[np.ndarray]
    s12: Optional[np.ndarray]
    s22: Optional[np.ndarray]
    s33: Optional[np.ndarray]

    @property
    def nbytes(self) -> int:
        """Memory of the stored spectra (bytes)."""
        return sum(s.nbytes for s in (self.s11, self.s12, self.s22, self.s33) if s is not None)


def _embedding_shape(nx, ny):
    """Smallest fast FFT sizes that hold every offset -(n - 1) .. n - 1 without overlap."""
    return (rocket_fft.next_fast_len(2 * nx - 1, real=True), rocket_fft.next_fast_len(2 * ny - 1, real=True))


def _check_grid(nx, ny):
    for name, n in (("nx", nx), ("ny", ny)):
        if int(n) != n or n < 1:
            raise InputError(f"grid.{name}", f"must be an integer >= 1, got {n!r}")


def kernel_spectrum(kernel, nx, ny, shape=None):
    """Spectrum of one Toeplitz kernel in its periodic embedding.

    Parameters
    ----------
    kernel : ndarray (2 nx - 1, 2 ny - 1)
        Influence kernel indexed by offset, ``kernel[di + nx - 1, dj + ny - 1]`` (m/Pa).
    nx, ny : int
        Grid size.
    shape : tuple of int, optional
        Embedding size (Lx, Ly), each at least 2 n - 1; default the smallest fast sizes.

    Returns
    -------
    ndarray (Lx, Ly // 2 + 1)
        Real when the wrapped kernel is even (up to round-off), else complex (m/Pa).
    """
    _check_grid(nx, ny)
    kernel = np.asarray(kernel, float)
    if kernel.shape != (2 * nx - 1, 2 * ny - 1):
        raise InputError("kernel", f"shape must be (2 nx - 1, 2 ny - 1) = {(2 * nx - 1, 2 * ny - 1)}, "
                                   f"got {kernel.shape}")
    shape = _embedding_shape(nx, ny) if shape is None else tuple(int(s) for s in shape)
    if shape[0] < 2 * nx - 1 or shape[1] < 2 * ny - 1:
        raise InputError("shape", f"embedding must be at least (2 nx - 1, 2 ny - 1) = "
                                  f"{(2 * nx - 1, 2 * ny - 1)}, got {shape}")
    wrapped = np.zeros(shape)
    rows = np.arange(-(nx - 1), nx) % shape[0]
    cols = np.arange(-(ny - 1), ny) % shape[1]
    wrapped[np.ix_(rows, cols)] = kernel
    spectrum = np.fft.rfft2(wrapped)
    scale = np.abs(kernel).sum()
    if np.abs(spectrum.imag).max(initial=0.0) <= _REAL_SPECTRUM_TOLERANCE * scale:
        return np.ascontiguousarray(spectrum.real)
    return spectrum


def influence_spectra(nx, ny, K11=None, K12=None, K22=None, K33=None) -> InfluenceSpectra:
    """Precompute the spectra of the given kernels of an nx x ny grid.

    Parameters
    ----------
    nx, ny : int
        Grid size.
    K11, K12, K22, K33 : ndarray (2 nx - 1, 2 ny - 1), optional
        Influence kernels (m/Pa) as in :class:`contact.halfspace.influence.Kernels`. The
        tangential products need all of K11, K12, K22; the normal product needs K33.

    Returns
    -------
    InfluenceSpectra
    """
    _check_grid(nx, ny)
    shape = _embedding_shape(nx, ny)
    tangential = (K11, K12, K22)
    if any(k is not None for k in tangential) and any(k is None for k in tangential):
        raise InputError("kernels", "give all of K11, K12, K22 for the tangential products, or none")
    spectra = [None if k is None else kernel_spectrum(k, nx, ny, shape) for k in (*tangential, K33)]
    out = InfluenceSpectra(int(nx), int(ny), shape, *spectra)
    log.debug("influence spectra of a %d x %d grid: embedding %s, %.3g MB", nx, ny, shape, out.nbytes / 1e6)
    return out


def spectra_from_kernels(kernels, normal=True, tangential=True) -> InfluenceSpectra:
    """Spectra of a :class:`contact.halfspace.influence.Kernels` bundle.

    Parameters
    ----------
    kernels : Kernels
        Toeplitz kernels of the grid (anything with nx, ny, K11, K12, K22, K33).
    normal, tangential : bool
        Which spectra to compute (K33; K11, K12, K22).
    """
    t = (kernels.K11, kernels.K12, kernels.K22) if tangential else (None, None, None)
    return influence_spectra(kernels.nx, kernels.ny, *t, K33=kernels.K33 if normal else None)


def _field(value, spectra, name):
    a = np.asarray(value, float)
    if a.shape != (spectra.nx, spectra.ny):
        raise InputError(name, f"shape must be the grid's {(spectra.nx, spectra.ny)}, got {a.shape}")
    return a


def _require(spectrum, what):
    if spectrum is None:
        raise InputError("spectra", f"the {what} spectra were not computed (see influence_spectra)")


def normal_product(spectra: InfluenceSpectra, pressure):
    """Normal displacement difference ``u_z = A33 p`` on the whole grid.

    Parameters
    ----------
    spectra : InfluenceSpectra
        With ``s33``.
    pressure : ndarray (nx, ny)
        Pressure on each element (Pa).

    Returns
    -------
    ndarray (nx, ny)
        ``u[i, j] = sum_kl K33[i - k, j - l] p[k, l]`` (m).
    """
    _require(spectra.s33, "normal")
    p = _field(pressure, spectra, "pressure")
    f = np.fft.rfft2(p, s=spectra.shape)
    f *= spectra.s33
    return np.fft.irfft2(f, s=spectra.shape)[: spectra.nx, : spectra.ny]


def tangential_product(spectra: InfluenceSpectra, traction_x, traction_y):
    """Tangential displacement differences ``(u_x, u_y) = [[A11, A12], [A12, A22]] (p_x, p_y)``.

    One batched forward and one batched inverse FFT for both components.

    Parameters
    ----------
    spectra : InfluenceSpectra
        With ``s11, s12, s22``.
    traction_x, traction_y : ndarray (nx, ny)
        Tangential tractions (Pa).

    Returns
    -------
    u_x, u_y : ndarray (nx, ny)
        Displacement differences (m).
    """
    _require(spectra.s11, "tangential")
    p = np.stack((_field(traction_x, spectra, "traction_x"), _field(traction_y, spectra, "traction_y")))
    f = np.fft.rfft2(p, s=spectra.shape)
    u = np.empty_like(f)
    np.multiply(spectra.s11, f[0], out=u[0])
    u[0] += spectra.s12 * f[1]
    np.multiply(spectra.s12, f[0], out=u[1])
    u[1] += spectra.s22 * f[1]
    u = np.fft.irfft2(u, s=spectra.shape)[:, : spectra.nx, : spectra.ny]
    return u[0], u[1]


def _source_values(spectra, values, sources, name):
    """``(values, sources)`` as arrays, checked: one value per source, flat indices within the grid."""
    sources = np.asarray(sources)
    values = np.asarray(values, float)
    if values.shape != sources.shape or sources.ndim != 1:
        raise InputError(name, f"needs one value per source element, got {values.shape} for {sources.shape}")
    n = spectra.nx * spectra.ny
    if sources.size and (sources.min() < 0 or sources.max() >= n):
        raise InputError("sources", f"flat element indices must lie in 0 .. {n - 1}")
    return values, sources


def _scatter(spectra, values, sources, name):
    """Zero-filled grid field with ``values`` at the flat (C-order) element indices ``sources``."""
    values, sources = _source_values(spectra, values, sources, name)
    grid = np.zeros(spectra.nx * spectra.ny)
    grid[sources] = values  # a repeated index keeps one value, as a set of elements should
    return grid.reshape(spectra.nx, spectra.ny)


def _targets(spectra, targets, sources):
    targets = np.asarray(sources if targets is None else targets)
    n = spectra.nx * spectra.ny
    if targets.size and (targets.min() < 0 or targets.max() >= n):
        raise InputError("targets", f"flat element indices must lie in 0 .. {n - 1}")
    return targets


def normal_product_on(spectra: InfluenceSpectra, pressure, sources, targets=None):
    """``A33[targets, sources] p`` for a pressure given on a subset of the elements.

    The FFT counterpart of the direct sums over the contact set of the compiled normal solver:
    the pressure is scattered onto a zero-filled grid, convolved, and read at ``targets``.

    Parameters
    ----------
    spectra : InfluenceSpectra
        With ``s33``.
    pressure : ndarray (ns,)
        Pressure (Pa) on the source elements.
    sources : int ndarray (ns,)
        Flat element indices ``ix * ny + iy`` of the sources (distinct).
    targets : int ndarray (nt,), optional
        Flat indices of the elements where the displacement is wanted; default ``sources``.

    Returns
    -------
    ndarray (nt,)
        Normal displacement difference (m) at the targets.
    """
    _require(spectra.s33, "normal")
    field = _scatter(spectra, pressure, sources, "pressure")
    targets = _targets(spectra, targets, sources)
    u = normal_product(spectra, field)
    return u.reshape(-1)[targets]


def tangential_product_on(spectra: InfluenceSpectra, traction_x, traction_y, sources, targets=None):
    """Tangential displacement differences at ``targets`` of tractions given on ``sources``.

    Parameters
    ----------
    spectra : InfluenceSpectra
        With ``s11, s12, s22``.
    traction_x, traction_y : ndarray (ns,)
        Tangential tractions (Pa) on the source elements.
    sources : int ndarray (ns,)
        Flat element indices ``ix * ny + iy`` of the sources (distinct).
    targets : int ndarray (nt,), optional
        Flat indices of the elements where the displacement is wanted; default ``sources``.

    Returns
    -------
    u_x, u_y : ndarray (nt,)
        Displacement differences (m) at the targets.
    """
    _require(spectra.s11, "tangential")
    traction_x, sources = _source_values(spectra, traction_x, sources, "traction_x")
    traction_y, sources = _source_values(spectra, traction_y, sources, "traction_y")
    targets = _targets(spectra, targets, sources)
    return TangentialListProduct(spectra, sources, targets)(traction_x, traction_y)


class TangentialListProduct:
    """The tangential product from one fixed list of elements to another, its buffers kept for repeated use.

    ``product(px, py)`` returns ``(u_x, u_y)`` at the targets of the tractions on the sources
    (as :func:`tangential_product_on`, which validates its input and uses this). The tractions
    are written into a field of the grid's nx rows, zero-padded to Ly columns and kept between
    calls (the same positions every call, so the padding stays zero). The transform is pruned:
    along y only the grid's nx rows are transformed (the other Lx - nx rows of the embedding
    are zero), then along x with zero padding to Lx; after the pointwise product by the spectra
    the inverse transforms along x, and along y only the nx rows of the grid. The same numbers
    as the full 2-D transforms of :func:`tangential_product`. The whole product runs compiled
    (:func:`~contact.halfspace.influence_kernels.list_product`, with the bundle :attr:`plan`), so a
    compiled iteration can form it too, e.g. the local sweeps of transient_fft. For an iteration
    that forms the product of the same contact list many times.

    Parameters
    ----------
    spectra : InfluenceSpectra
        With ``s11, s12, s22``.
    sources, targets : int ndarray
        Flat element indices ``ix * ny + iy`` (valid; not checked here).
    """

    def __init__(self, spectra: InfluenceSpectra, sources, targets=None):
        _require(spectra.s11, "tangential")
        lx, ly = spectra.shape

        def padded_positions(flat):
            ix, iy = np.divmod(np.asarray(flat, np.int64), spectra.ny)
            return np.ascontiguousarray(ix * ly + iy)

        source_positions = padded_positions(sources)
        target_positions = source_positions if targets is None else padded_positions(targets)
        #: the compiled product's bundle (influence_kernels.list_product), e.g. for a compiled iteration
        self.plan = ListProduct(np.zeros((2, spectra.nx, ly)), source_positions, target_positions,
                                spectra.s11, spectra.s12, spectra.s22, int(spectra.nx), int(lx), int(ly))

    def __call__(self, traction_x, traction_y):
        """Displacement differences ``(u_x, u_y)`` (m) at the targets of the tractions (Pa) on the sources."""
        n = self.plan.targets.size
        ux = np.empty(n)
        uy = np.empty(n)
        list_product(self.plan, np.ascontiguousarray(traction_x, float), np.ascontiguousarray(traction_y, float),
                        ux, uy)
        return ux, uy


def steady_tangential_product_on(spectra: InfluenceSpectra, traction_x, traction_y, sources, targets=None):
    """Rows of the steady-rolling matrix ``B = (I - S) A``: ``u(i, j) - u(i + 1, j)`` at the targets.

    ``S`` shifts by one element along x (the rolling direction), so ``B p`` is the change of
    the tangential displacement difference over one element upstream, the term of the steady
    slip; this is the matrix-free form of the dense ``B`` of the steady solver.

    Parameters
    ----------
    spectra : InfluenceSpectra
        With ``s11, s12, s22``.
    traction_x, traction_y : ndarray (ns,)
        Tangential tractions (Pa) on the source elements.
    sources : int ndarray (ns,)
        Flat element indices ``ix * ny + iy`` of the sources (distinct).
    targets : int ndarray (nt,), optional
        Flat indices of the rows wanted, all with ``ix < nx - 1``; default ``sources``.

    Returns
    -------
    b_x, b_y : ndarray (nt,)
        ``u_k(ix, iy) - u_k(ix + 1, iy)`` (m) at the targets.
    """
    _require(spectra.s11, "tangential")
    fx = _scatter(spectra, traction_x, sources, "traction_x")
    fy = _scatter(spectra, traction_y, sources, "traction_y")
    ti, tj = np.divmod(_targets(spectra, targets, sources), spectra.ny)
    if ti.size and ti.max() >= spectra.nx - 1:
        raise InputError("targets", f"rows need an element downstream: ix must be below nx - 1 = {spectra.nx - 1}")
    ux, uy = tangential_product(spectra, fx, fy)
    return ux[ti, tj] - ux[ti + 1, tj], uy[ti, tj] - uy[ti + 1, tj]
