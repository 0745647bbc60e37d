"""Transient and shift tangential problems on large contact areas: local sweeps plus one FFT product per sweep.

The exact Gauss-Seidel sweeps (:func:`~interaction.contact.kernels.tangential_gauss_seidel`)
update the displacement of every contact element after every traction change, so a sweep costs
O(n_contact^2): at 44 x 36 elements (1036 in contact) about 1.3 ms, and a transient step in
partial slip needs about 33 sweeps at tolerance 1e-9. Here a sweep updates the displacement
only at the contact elements within ``reach`` grid lines of the changed one
(:func:`~interaction.contact.kernels.tangential_sweep` with ``reach``, O(n_contact (2 reach + 1)^2)), and
after the sweep the displacement of all contact elements is recomputed exactly by one FFT
product (:func:`~interaction.contact.fft_products.tangential_product_on`, O(nx ny log(nx ny))). The deferred coupling makes the sweeps converge more slowly (measured on a step
of the 44 x 36 transient from rest: 50-55 sweeps with Anderson mixing against 33 exact ones),
but each costs a fraction of an exact one. Anderson mixing is done without restarts (restarts
stall these sweeps, as in steady.steady_sweeps_fft). A fixed point of these sweeps is one of the
exact sweeps; the caller finishes with exact sweeps, so the result passes the very same
stopping test as the exact solver.
"""

from __future__ import annotations

import numpy as np

from . import kernels as nb
from .bundles import SweepCompliance, TangentialProblem, Tractions
from .fft_products import InfluenceSpectra, spectra_from_kernels, tangential_product_on
from .influence import Kernels

__all__ = ["transient_sweeps_fft"]


def tangential_spectra(kernels: Kernels) -> InfluenceSpectra:
    """The tangential FFT spectra of ``kernels``, computed once per Kernels object (kept in its cache of operators)."""
    if "tangential_spectra" not in kernels._ops:
        kernels._ops["tangential_spectra"] = spectra_from_kernels(kernels, normal=False)
    return kernels._ops["tangential_spectra"]


def transient_sweeps_fft(kernels: Kernels, problem: TangentialProblem, px, py, series, tol, max_sweeps, depth,
                         reach=1):
    """Local Gauss-Seidel sweeps with an exact FFT product after each, Anderson-accelerated.

    Parameters
    ----------
    kernels : Kernels
        Influence kernels of the grid.
    problem : TangentialProblem
        Contact elements in sweep order (leading edge first), rigid slip (m), previous
        displacement (m) and traction bounds (Pa); the static bound is lowered to the kinetic
        one in place where an element slides (as in the exact sweeps).
    px, py : (nc,) ndarray
        Tractions (Pa): initial guess in, result out (updated in place).
    series : (float, float)
        Series compliances times the element area, m/Pa (as for the exact sweeps).
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps : int
        Sweep limit.
    depth : int
        Sweeps remembered by the Anderson mixing (0: plain sweeps).
    reach : int
        Grid lines on each side, along x and y, whose displacement a traction change updates
        within a sweep.

    Returns
    -------
    sweeps : int
    change : float
        Largest traction change of the last sweep, Pa.
    ux, uy : (nc,) ndarray
        Displacement differences (m) of the result at the contact elements (exact product).
    """
    nx, ny = kernels.nx, kernels.ny
    cix, ciy = problem.ix, problem.iy
    nc = cix.size
    lookup = -np.ones(nx * ny, np.int64)
    lookup[cix * ny + ciy] = np.arange(nc)
    operator = nb.flat_tangential(kernels.bundle())
    flat_kernel = cix * operator.row + ciy
    series_x, series_y = series
    ox, oy = nx - 1, ny - 1
    compliance = SweepCompliance(float(kernels.K11[ox, oy]) + series_x, float(kernels.K22[ox, oy]) + series_y,
                                 series_x, series_y)
    spectra = tangential_spectra(kernels)
    flat = cix * ny + ciy

    def displacement():
        return tangential_product_on(spectra, px, py, flat)

    ux, uy = displacement()
    total = np.array([px.sum(), py.sum()])
    history = nb.anderson_history(depth, nc, nc)
    status = np.ones(nc, np.int8)
    change = np.inf
    sweeps = 0
    for sweeps in range(1, max_sweeps + 1):
        nb.anderson_input(history, px, py)
        change = nb.tangential_sweep(operator, problem, flat_kernel, Tractions(px, py, ux, uy), compliance, total, 0.0,
                                     status, lookup, ny, reach, nb.no_dense_rows())
        ux, uy = displacement()
        if change <= tol:
            break
        if depth > 0 and nb.anderson_mix(history, change, px, py, ux, uy, False):
            total[:] = px.sum(), py.sum()
    return sweeps, change, ux, uy
