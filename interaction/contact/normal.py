"""Normal contact problem on a grid: pressure p >= 0, deformed gap >= 0, complementarity.

Deformed gap ``e = h - delta + u_z`` with ``u_z = A33 p`` (FFT product), h the undeformed
gap (m) and delta the approach (m). Solved with the constrained conjugate-gradient method of
Polonsky & Keer (Wear 231, 1999), which is also the core of Vollebregt's NormCG, for a
prescribed normal force or a prescribed approach.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from squealcore.errors import InputError

from .influence import Kernels

log = logging.getLogger(__name__)

__all__ = ["NormalSolution", "NotConvergedError", "solve_normal"]


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
                 tol=1e-10, max_iter=1000) -> NormalSolution:
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

    Returns
    -------
    NormalSolution
    """
    if (normal_force is None) == (approach is None):
        raise InputError("load", "give exactly one of normal_force and approach")
    area = kernels.dx * kernels.dy
    op = kernels.operator("33")
    h = np.asarray(gap, float)
    zero = np.zeros_like(h)
    if (normal_force is not None and normal_force <= 0.0) or (approach is not None and approach <= 0.0):
        return NormalSolution(zero, zero.copy(), 0.0 if approach is None else float(approach), 0.0, 0, 0.0)
    force_mode = normal_force is not None
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
    elif warm:
        # rescale the warm start to the new approach (mean gap closed on its contact area);
        # if that leaves the previous solution unchanged the early exit below still applies
        u = op(p)
        m = p > 0
        factor = np.mean(approach - h[m]) / max(np.mean(u[m]), 1e-300)
        if factor > 0 and abs(factor - 1.0) > tol:
            p *= factor
    t = np.zeros_like(p)
    g_old = 1.0
    delta_flag = False
    hscale = max(np.ptp(h), 1e-300)
    residual = np.inf
    for it in range(1, max_iter + 1):
        u = op(p)
        g = h + u
        active = p > 0
        if force_mode:
            gbar = g[active].mean()
        else:
            gbar = approach
        g = g - gbar
        G = np.dot(g[active], g[active])
        if (it == 1 and warm and np.sqrt(G / active.sum()) / hscale < 10.0 * tol
                and g[~active].min(initial=0.0) > -tol * hscale):
            residual = 0.0
            break  # the warm start already solves the problem: u is up to date
        if delta_flag:
            t = np.where(active, g + (G / g_old) * t, 0.0)
        else:
            t = np.where(active, g, 0.0)
        g_old = G
        r = op(t)
        if force_mode:
            r = r - r[active].mean()
        denom = np.dot(r[active], t[active])
        tau = np.dot(g[active], t[active]) / denom if denom != 0 else 0.0
        p_old = p.copy()
        p = p - tau * t
        p[p < 0] = 0.0
        overlap = (p == 0) & (g < 0)
        if overlap.any():
            delta_flag = False
            p[overlap] -= tau * g[overlap]
        else:
            delta_flag = True
        if force_mode:
            p *= normal_force / (p.sum() * area)
        psum = p.sum()
        residual = np.abs(p - p_old).sum() / psum if psum > 0 else 0.0
        gap_res = np.sqrt(G / max(active.sum(), 1)) / hscale
        if residual < tol and gap_res < 10.0 * tol and not overlap.any():
            u = op(p)
            break
    else:
        raise NotConvergedError(
            f"normal contact: no convergence in {max_iter} iterations (residual {residual:.3g})")
    active = p > 0
    delta = float(np.mean(h[active] + u[active])) if force_mode else float(approach)
    log.debug("normal problem: %d iterations, residual %.3g, %d elements in contact", it, residual,
              int(active.sum()))
    return NormalSolution(p, u, delta, float(p.sum() * area), it, float(residual))
