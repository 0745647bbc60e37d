"""Influence coefficients of uniform tractions on rectangles of an elastic half-space.

Two quasi-identical half-spaces (combined shear modulus G, Poisson ratio nu). A traction
``p`` acts on body 1 and ``-p`` on body 2; the coefficients give the displacement
difference ``u = u(1) - u(2)`` (m) per unit traction (Pa) on one grid element, for field
points at element centres. The point-load kernels (Kalker 1990, sec. 1.5) are

* normal (Boussinesq):  A33 = (1 - nu) / (pi G r)
* tangential (Cerruti): A11 = [(1 - nu)/r + nu x^2/r^3] / (pi G),
  A22 = [(1 - nu)/r + nu y^2/r^3] / (pi G),  A12 = nu x y / (pi G r^3)

and the normal/tangential coupling vanishes for identical materials. Integrated over a
rectangle in closed form (Love 1929) with the antiderivatives

* int int 1/r      = x asinh(y/|x|) + y asinh(x/|y|)   (+ terms that cancel)
* int int y^2/r^3  = x asinh(y/|x|)
* int int x^2/r^3  = y asinh(x/|y|)
* int int x y/r^3  = -r

A 2D (plane-strain) variant serves Carter's line-contact problem.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from contact.halfspace.bundles import DENSE_MAX_CONTACT, Influence, dense_cache, no_spectra
from contact.halfspace.fft_products import kernel_spectrum
from contact.halfspace.influence_kernels import contact_rows, flat_tangential, grid_product, no_dense_rows, tangential_grid_product

__all__ = ["Kernels", "rectangle_kernels", "plane_strain_kernels", "ToeplitzOperator"]


def _xasinh(x, y):
    """x asinh(y/|x|), with its limit 0 at x = 0."""
    ax = np.abs(x)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = x * np.arcsinh(y / np.where(ax > 0, ax, 1.0))
    return np.where(ax > 0, out, 0.0)


def _double_difference(f, x, y, hx, hy):
    """int_{x-hx}^{x+hx} int_{y-hy}^{y+hy} g = F(x+hx, y+hy) - F(x+hx, y-hy) - F(x-hx, y+hy) + F(x-hx, y-hy)."""
    return f(x + hx, y + hy) - f(x + hx, y - hy) - f(x - hx, y + hy) + f(x - hx, y - hy)


def _int_inv_r(x, y):
    return _xasinh(x, y) + _xasinh(y, x)


def _int_x2(x, y):
    return _xasinh(y, x)


def _int_y2(x, y):
    return _xasinh(x, y)


def _int_xy(x, y):
    return -np.hypot(x, y)


def rectangle_influence(x, y, hx, hy, shear_modulus, poisson_ratio):
    """Displacement difference at (x, y) (m) due to unit uniform traction on |x'|<=hx, |y'|<=hy.

    Parameters
    ----------
    x, y : array_like
        Field points relative to the rectangle centre (m).
    hx, hy : float
        Half sides of the rectangle (m).
    shear_modulus : float
        Combined shear modulus G (Pa).
    poisson_ratio : float
        Poisson ratio nu (-).

    Returns
    -------
    dict of ndarray
        ``"11", "12", "22", "33"``: influence coefficients (m/Pa), shape of ``x``.
    """
    x = np.asarray(x, float)
    y = np.asarray(y, float)
    nu = poisson_ratio
    c = 1.0 / (math.pi * shear_modulus)
    i_r = _double_difference(_int_inv_r, x, y, hx, hy)
    i_x2 = _double_difference(_int_x2, x, y, hx, hy)
    i_y2 = _double_difference(_int_y2, x, y, hx, hy)
    i_xy = _double_difference(_int_xy, x, y, hx, hy)
    return {
        "11": c * ((1.0 - nu) * i_r + nu * i_x2),
        "22": c * ((1.0 - nu) * i_r + nu * i_y2),
        "12": c * nu * i_xy,
        "33": c * (1.0 - nu) * i_r,
    }


@dataclass(frozen=True)
class Kernels:
    """Toeplitz influence kernels of a uniform nx x ny grid.

    ``K[c][i + nx - 1, j + ny - 1]`` (m/Pa) is the displacement difference at element
    (k + i, l + j) due to unit traction on element (k, l), component pair ``c`` in
    ``"11", "12", "22", "33"``; each array has shape (2 nx - 1, 2 ny - 1).
    """

    nx: int
    ny: int
    dx: float
    dy: float
    K11: np.ndarray
    K12: np.ndarray
    K22: np.ndarray
    K33: np.ndarray
    _ops: dict = field(default_factory=dict, repr=False, compare=False)

    def bundle(self) -> Influence:
        """The coefficients as the :class:`~contact.halfspace.bundles.Influence` bundle of the compiled solvers (cached: always the same object)."""
        if "bundle" not in self._ops:
            self._ops["bundle"] = Influence(self.K11, self.K12, self.K22, self.K33, no_spectra())
        return self._ops["bundle"]

    def dense_rows(self, cix, ciy):
        """Dense influence rows between the contact elements ``cix``, ``ciy`` (int64, sweep order) for the exact sweeps.

        Kept in a cache of this grid's size and rebuilt only when the contact list changes (a
        transient run at constant load keeps it), see
        :class:`~contact.halfspace.bundles.DenseTangential`; an empty bundle for lists longer
        than :data:`~contact.halfspace.bundles.DENSE_MAX_CONTACT`.
        """
        if cix.size > DENSE_MAX_CONTACT:
            return no_dense_rows()
        if "rows" not in self._ops:
            self._ops["rows"] = dense_cache(self.nx * self.ny)
        return contact_rows(flat_tangential(self.bundle()), cix, ciy, self._ops["rows"])

    def operator(self, name: str) -> "ToeplitzOperator":
        """FFT matrix-vector product for kernel ``name`` in ``"11", "12", "22", "33"`` (cached)."""
        if name not in self._ops:
            self._ops[name] = ToeplitzOperator(getattr(self, "K" + name), self.nx, self.ny)
        return self._ops[name]

    def tangential_displacement(self, traction):
        """Tangential displacement difference (m), shape (nx, ny, 2), from traction (nx, ny, 2) (Pa).

        FFT convolutions on the grid doubled in each direction, compiled
        (:func:`~contact.halfspace.influence_kernels.tangential_grid_product`).
        """
        if "t" not in self._ops:
            self._ops["t"] = tuple(self.operator(n).spectrum for n in ("11", "12", "22"))
        h11, h12, h22 = self._ops["t"]
        return tangential_grid_product(h11, h12, h22, np.asarray(traction, float))


def rectangle_kernels(nx, ny, dx, dy, shear_modulus, poisson_ratio) -> Kernels:
    """Kernels of an nx x ny grid of dx x dy (m) elements on two identical half-spaces."""
    ix = np.arange(-(nx - 1), nx) * dx
    iy = np.arange(-(ny - 1), ny) * dy
    X, Y = np.meshgrid(ix, iy, indexing="ij")
    k = rectangle_influence(X, Y, 0.5 * dx, 0.5 * dy, shear_modulus, poisson_ratio)
    return Kernels(nx, ny, dx, dy, k["11"], k["12"], k["22"], k["33"])


def plane_strain_kernels(nx, dx, shear_modulus, poisson_ratio) -> Kernels:
    """Kernels of a line of nx strips of width dx (m) in plane strain (2D, ny = 1).

    Two identical bodies: u_x(x) = -(2 (1 - nu) / (pi G)) int q(s) ln|x - s| ds + const (and
    the same for u_z under pressure). The constant is undetermined in 2D; only differences
    of u enter the rolling problem. The lateral (anti-plane) coefficient is
    -(2 / (pi G)) ln|x - s| (two bodies, each 1/(pi G)).
    """
    x = np.arange(-(nx - 1), nx) * dx
    h = 0.5 * dx

    def F(t):  # int ln|t| dt = t ln|t| - t
        at = np.abs(t)
        with np.errstate(divide="ignore", invalid="ignore"):
            v = t * np.log(np.where(at > 0, at, 1.0))
        return v - t

    i_ln = F(x + h) - F(x - h)
    c = -2.0 / (math.pi * shear_modulus)
    k11 = (c * (1.0 - poisson_ratio) * i_ln)[:, None]
    return Kernels(nx, 1, dx, 1.0, k11, np.zeros_like(k11), (c * i_ln)[:, None], k11.copy())


class ToeplitzOperator:
    """Product of a block-Toeplitz influence matrix with a grid field by FFT convolution.

    Parameters
    ----------
    kernel : ndarray, shape (2 nx - 1, 2 ny - 1)
        Kernel indexed by offset (see :class:`Kernels`).
    nx, ny : int
        Grid size.
    """

    def __init__(self, kernel, nx, ny):
        self.nx, self.ny = nx, ny
        self.shape = (2 * nx, 2 * ny)
        #: real-FFT spectrum of the kernel wrapped on the doubled grid (the circulant embedding:
        #: one implementation, in fft_products), m/Pa
        self.spectrum = kernel_spectrum(kernel, nx, ny, shape=self.shape)

    def __call__(self, field):
        """Return sum_j K[i - j] field[j], shape (nx, ny) (compiled, :func:`influence_kernels.grid_product`)."""
        return grid_product(self.spectrum, np.ascontiguousarray(field, float))
