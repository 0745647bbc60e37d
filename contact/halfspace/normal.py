"""Normal contact problem on a grid: pressure p >= 0, deformed gap >= 0, complementarity.

Deformed gap ``e = h - delta + u_z`` with ``u_z = A33 p`` (FFT product), h the undeformed
gap (m) and delta the approach (m). Solved with the constrained conjugate-gradient method of
Polonsky & Keer (Wear 231, 1999), which is also the core of Vollebregt's NormCG, for a
prescribed normal force or a prescribed approach. Each iteration: the deformed gap g on the
contact area (minus its mean for a prescribed force), a conjugate direction t, the step
tau = <g, t> / <A t, t>, p <- max(p - tau t, 0), and elements outside the contact with
negative gap re-enter with p = -tau g (then the conjugation restarts). The iterations run
compiled (normal_kernels.normal_conjugate_gradient) with direct products of the influence matrix
over the elements in contact.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from squealcore.errors import InputError

from contact.halfspace.bundles import NormalProblem
from contact.halfspace.influence import Kernels
from contact.halfspace.normal_kernels import normal_cg_fft, normal_cg_fft_approach, normal_conjugate_gradient

log = logging.getLogger(__name__)

__all__ = ["NormalSolution", "NotConvergedError", "solve_normal", "FFT_MIN_ELEMENTS"]

FFT_MIN_ELEMENTS = 144
"""Grids of at least this many elements solve a prescribed-force normal problem with FFT
products (:func:`_conjugate_gradient_fft`), smaller ones with the compiled direct products:
the crossover of the two compiled iterations (docs/benchmarks.md, the row *normal problem,
prescribed force, FFT vs direct products*; docs/design.md, "Contact solvers"). It was 625 while
the FFT iteration ran in Python."""


_NO_WARM_DISPLACEMENT = np.empty(0)
"""``u_warm`` of :func:`~contact.halfspace.normal_kernels.normal_conjugate_gradient` when not known."""


class NotConvergedError(RuntimeError):
    """An iterative contact solver did not reach its tolerance."""


@dataclass(frozen=True)
class NormalSolution:
    """Solution of the normal problem.

    Attributes
    ----------
    pressure : ndarray (nx, ny)
        Pressure (Pa), >= 0.
    displacement : ndarray (nx, ny)
        Normal displacement difference u_z (m).
    approach : float
        Approach delta (m).
    normal_force : float
        Total normal force (N).
    iterations : int
        CG iterations.
    residual : float
        Final relative change of the pressure (-).
    """

    pressure: np.ndarray
    displacement: np.ndarray
    approach: float
    normal_force: float
    iterations: int
    residual: float


def solve_normal(kernels: Kernels, gap, *, normal_force=None, approach=None, p_init=None,
                 tol=1e-10, max_iter=1000, compliance=0.0, full_displacement=True, fft=False) -> NormalSolution:
    """Solve the normal problem for a prescribed normal force (N) or approach (m).

    Parameters
    ----------
    kernels : Kernels
        Influence kernels of the grid.
    gap : ndarray (nx, ny)
        Undeformed gap h at the element centres (m).
    normal_force, approach : float
        Exactly one must be given. A non-positive approach or force gives zero pressure.
    p_init : ndarray (nx, ny), optional
        Warm start (Pa).
    tol : float
        Tolerance on the relative pressure change per iteration and on the gap/force
        residual.
    max_iter : int
        Iteration limit; :class:`NotConvergedError` beyond.
    compliance : float
        Compliance c (m/N) of a spring in series with the contact, e.g. the instantaneous
        compliance of the structures: with a prescribed ``approach`` (then the approach of the
        spring and contact together) the contact's own approach is ``approach - c Fn``. This
        adds the constant ``c dx dy`` to every influence coefficient (a rank-one term, still
        symmetric positive definite), so the coupled problem is solved in one go. Ignored for a
        prescribed normal force.
    full_displacement : bool
        Compute the displacement on the whole grid (else only where the contact's own approach
        could reach, zero elsewhere: one product fewer).
    fft : bool
        A prescribed approach without series compliance on a grid of at least
        :data:`FFT_MIN_ELEMENTS` is solved with FFT products too
        (:func:`~contact.halfspace.normal_kernels.normal_cg_fft_approach`; the same solution to
        ``tol``, faster on large contacts: docs/benchmarks.md, *Half-space screen and curve map*); default the
        direct products.

    Returns
    -------
    NormalSolution
    """
    if (normal_force is None) == (approach is None):
        raise InputError("load", "give exactly one of normal_force and approach")
    area = kernels.dx * kernels.dy
    h = np.asarray(gap, float)
    zero = np.zeros_like(h)
    # every influence coefficient is positive, so an approach below the smallest gap touches nowhere
    if (normal_force is not None and normal_force <= 0.0) or (approach is not None and approach <= max(h.min(), 0.0)):
        return NormalSolution(zero, zero.copy(), 0.0 if approach is None else float(approach), 0.0, 0, 0.0)
    force_mode = normal_force is not None
    series = 0.0 if force_mode else float(compliance) * area  # m/Pa, added to every coefficient
    contact_op = kernels.operator("33")
    op = contact_op if series == 0.0 else (lambda q: contact_op(q) + series * q.sum())
    warm = p_init is not None and np.any(p_init > 0)
    if warm:
        p = np.array(p_init, float)
    else:
        if force_mode:
            dguess = np.quantile(h, 0.1)
        else:
            dguess = approach
        p = np.where(h < dguess, 1.0, 0.0)
        if not p.any():
            p[np.unravel_index(np.argmin(h), h.shape)] = 1.0
        p *= (normal_force if force_mode else 1.0) / (p.sum() * area)
        if not force_mode:
            # scale to the approach in the mean over the guessed contact
            u = op(p)
            m = p > 0
            p *= max(np.mean(approach - h[m]) / max(np.mean(u[m]), 1e-300), 0.0)
    if force_mode:
        p *= normal_force / (p.sum() * area)
    p = np.ascontiguousarray(p)
    if force_mode and h.size >= FFT_MIN_ELEMENTS:
        # large grid, prescribed force: every element is a candidate, so the products are over
        # the whole grid and the FFT ones win (FFT_MIN_ELEMENTS)
        return _conjugate_gradient_fft(kernels, h, p, float(normal_force), area, tol, max_iter)
    if fft and not force_mode and series == 0.0 and h.size >= FFT_MIN_ELEMENTS:
        return _approach_fft(kernels, h, p, float(approach), area, tol, max_iter)
    # the iterations run compiled (normal_kernels.py); with a prescribed approach a warm start is first
    # rescaled to the new approach, and it ends at once if it already solves the problem
    problem = NormalProblem(np.ascontiguousarray(h).ravel(), p.reshape(-1), force_mode,
                            float(normal_force if force_mode else approach), series, area, tol, max_iter, warm)
    # every argument given: an omitted array default makes numba's cache key differ in every
    # process (it recompiled on every run)
    iterations, residual, converged, u, _ = normal_conjugate_gradient(kernels.K33, problem, bool(full_displacement),
                                                                         _NO_WARM_DISPLACEMENT, np.inf)
    if not converged:
        raise NotConvergedError(
            f"normal contact: no convergence in {max_iter} iterations (residual {residual:.3g})")
    u = u.reshape(h.shape)  # the contact's own displacement (without the series term)
    it = iterations
    active = p > 0
    delta = float(np.mean(h[active] + u[active])) if force_mode else float(approach) - series * p.sum()
    log.debug("normal problem: %d iterations, residual %.3g, %d elements in contact", it, residual,
              int(active.sum()))
    return NormalSolution(p, u, delta, float(p.sum() * area), it, float(residual))


def _conjugate_gradient_fft(kernels, h, p, normal_force, area, tol, max_iter):
    """Polonsky-Keer constrained conjugate gradients for a prescribed force, products by FFT.

    The algorithm of the module docstring on the whole grid, compiled with one FFT product of
    the influence matrix per iteration instead of direct sums
    (:func:`~contact.halfspace.normal_kernels.normal_cg_fft`). Memory O(nx ny); the displacement is
    returned on the whole grid.
    """
    own = float(kernels.K33[kernels.nx - 1, kernels.ny - 1])
    spectrum = kernels.operator("33").spectrum
    it, residual, converged, u = normal_cg_fft(spectrum, own, np.ascontiguousarray(h, float), p, float(normal_force),
                                                  float(area), float(tol), int(max_iter))
    if not converged:
        raise NotConvergedError(
            f"normal contact: no convergence in {max_iter} iterations (residual {residual:.3g})")
    active = p > 0
    delta = float(np.mean(h[active] + u[active]))
    log.debug("normal problem (FFT): %d iterations, residual %.3g, %d elements in contact", it, residual,
              int(active.sum()))
    return NormalSolution(p, u, delta, float(p.sum() * area), it, residual)


def _approach_fft(kernels, h, p, approach, area, tol, max_iter):
    """Polonsky-Keer for a prescribed approach on the whole grid, products by FFT
    (:func:`~contact.halfspace.normal_kernels.normal_cg_fft_approach`)."""
    own = float(kernels.K33[kernels.nx - 1, kernels.ny - 1])
    spectrum = kernels.operator("33").spectrum
    it, residual, converged, u = normal_cg_fft_approach(spectrum, own, np.ascontiguousarray(h, float), p,
                                                        float(approach), float(tol), int(max_iter))
    if not converged:
        raise NotConvergedError(
            f"normal contact: no convergence in {max_iter} iterations (residual {residual:.3g})")
    log.debug("normal problem (FFT, approach): %d iterations, residual %.3g, %d elements in contact", it, residual,
              int((p > 0).sum()))
    return NormalSolution(p, u, approach, float(p.sum() * area), it, residual)
