"""Tangential contact problem: steady rolling, transient rolling and shift, Coulomb friction.

Discrete slip over one step of each contact element (m), in contact-fixed coordinates with
rolling in +x (material enters the contact at the leading edge, large x)::

    S_i = W_i + u_i - u'_i

* ``W`` the rigid slip over the step: rolling ``(xi - phi y, eta + phi x) dx``; shift: the
  given rigid shift.
* ``u`` the tangential displacement difference (m) of the current tractions.
* ``u'`` the previous displacement of the same particle: transient rolling, the previous
  step's field shifted by one element (``u'_i = u_prev[i + 1]``, step dx = V dt); shift,
  the previous field at the same element; steady rolling, the current field upstream
  (``u'_i = u[i + 1]``, i.e. the upwind difference of S = W - dx du/dx).

Friction: stick (S = 0) where |p_t| <= mu_s p_z, else p_t = -mu_k p_z S/|S| (traction on the
wheel opposes its slip). Transient and shift problems are convex and solved element by
element (Gauss-Seidel sweeps from the leading edge, kernels.py; Kalker's / Vollebregt's
ConvexGS idea). Steady rolling is solved directly with an active-set method on the dense
upwind matrix (see :func:`_solve_steady`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from squealcore.errors import InputError

from . import kernels as nb
from .bundles import TangentialProblem, Tractions
from .influence import Kernels
from .normal import NotConvergedError
from .params import Friction

log = logging.getLogger(__name__)

__all__ = ["TangentialSolution", "solve_tangential", "MODES"]

MODES = ("steady", "transient", "shift")

EXTERIOR, STICK, SLIP = 0, 1, 2

ANDERSON_DEPTH = 8
"""Sweeps remembered by the Anderson mixing of the Gauss-Seidel sweeps (0: plain sweeps).
Over-relaxation of the stick updates (1.3-1.7) was tried before and gave more sweeps, not fewer;
Anderson mixing over 8 sweeps gives 2-2.5 times fewer on the interaction's contact problems."""


@dataclass(frozen=True)
class TangentialSolution:
    """Tangential solution.

    Attributes
    ----------
    traction : ndarray (nx, ny, 2)
        Tangential traction on the wheel (Pa).
    displacement : ndarray (nx, ny, 2)
        Tangential displacement difference on the whole grid (m).
    status : int8 ndarray (nx, ny)
        0 exterior, 1 stick, 2 slip.
    sweeps : int
        Gauss-Seidel sweeps.
    residual : float
        Largest traction change in the last sweep relative to the traction scale (-).
    """

    traction: np.ndarray
    displacement: np.ndarray
    status: np.ndarray
    sweeps: int
    residual: float


def solve_tangential(kernels: Kernels, pressure, rigid_slip, *, mode, friction: Friction,
                     u_prev=None, p_init=None, u_init=None, tol=1e-9,
                     max_sweeps=5000, series_compliance=(0.0, 0.0), anderson_depth=None) -> TangentialSolution:
    """Solve the tangential problem for a given pressure.

    Parameters
    ----------
    kernels : Kernels
        Influence kernels of the grid.
    pressure : ndarray (nx, ny)
        Pressure (Pa); the contact area is where it is > 0.
    rigid_slip : ndarray (nx, ny, 2)
        Rigid slip W over the step (m).
    mode : {"steady", "transient", "shift"}
        Problem type (see module docstring). Transient and shift: Gauss-Seidel sweeps
        (kernels.py) from the leading edge; steady: a direct active-set method (dense),
        falling back to iterated rolling steps if it cycles.
    friction : Friction or FrictionCoefficients
        Static and kinetic coefficients (``friction.static``, ``friction.kinetic``).
    u_prev : ndarray (nx, ny, 2), optional
        Previous tangential displacement field (m) (transient, shift); zero if omitted.
    p_init : ndarray (nx, ny, 2), optional
        Warm start of the tractions (Pa).
    u_init : ndarray (nx, ny, 2), optional
        Displacement of ``p_init`` (m), if known (saves one FFT product).
    tol : float
        Convergence: largest traction change of a sweep below tol times the traction scale
        max(min(mu_s, 1) * max p_z) (-).
    max_sweeps : int
        Sweep limit; :class:`NotConvergedError` beyond.
    series_compliance : (c_x, c_y)
        Compliances (m/N) of springs in series with the contact along x and y (transient and
        shift only), e.g. the instantaneous compliance of the structures: their displacement
        ``c F`` over the step adds to the rigid slip of every element, with F the tangential
        force being solved for.
    anderson_depth : int, optional
        Sweeps remembered by the Anderson mixing (default :data:`ANDERSON_DEPTH`).

    Returns
    -------
    TangentialSolution
    """
    if mode not in MODES:
        raise InputError("kind", f"must be one of {MODES}, got {mode!r}")
    series_x, series_y = (float(c) * kernels.dx * kernels.dy for c in series_compliance)
    if mode == "steady" and (series_x or series_y):
        raise InputError("series_compliance", "applies to transient and shift problems only "
                         "(in steady rolling a series spring does not move)")
    if mode == "steady":
        return _solve_steady(kernels, pressure, rigid_slip, friction=friction, p_init=p_init,
                             tol=tol, max_sweeps=max_sweeps)
    nx, ny = kernels.nx, kernels.ny
    pz = np.asarray(pressure, float)
    contact = pz > 0
    cix, ciy = np.nonzero(contact)
    traction = np.zeros((nx, ny, 2))
    if cix.size == 0:
        return TangentialSolution(traction, np.zeros((nx, ny, 2)), np.zeros((nx, ny), np.int8), 0, 0.0)
    if mode != "shift" and cix.max() >= nx - 1:
        raise InputError("grid.nx", "the contact area reaches the leading edge of the grid; "
                         "enlarge the grid (nx or dx)")
    # sweep from the leading edge (large x) to the trailing edge
    order = np.lexsort((ciy, -cix))
    cix, ciy = cix[order].astype(np.int64), ciy[order].astype(np.int64)
    if u_prev is None:
        upx = upy = np.zeros(cix.size)
    else:
        src = cix + 1 if mode == "transient" else cix
        upx = np.ascontiguousarray(u_prev[src, ciy, 0], float)
        upy = np.ascontiguousarray(u_prev[src, ciy, 1], float)
    if p_init is not None:
        traction[cix, ciy] = p_init[cix, ciy]
    if u_init is not None and p_init is not None and np.array_equal(traction, p_init):
        u0 = u_init  # the displacement of the warm start is known
    else:
        u0 = kernels.tangential_displacement(traction)
    ux = np.ascontiguousarray(u0[cix, ciy, 0])
    uy = np.ascontiguousarray(u0[cix, ciy, 1])
    px = np.ascontiguousarray(traction[cix, ciy, 0])
    py = np.ascontiguousarray(traction[cix, ciy, 1])
    w = np.asarray(rigid_slip, float)
    wx = np.ascontiguousarray(w[cix, ciy, 0])
    wy = np.ascontiguousarray(w[cix, ciy, 1])
    gs = friction.static * pz[cix, ciy]
    gk = friction.kinetic * pz[cix, ciy]
    scale = pz.max() * min(max(friction.static, 1e-3), 1.0)
    sweeps, change, st = nb.tangential_gauss_seidel(
        kernels.bundle(), TangentialProblem(cix, ciy, wx, wy, upx, upy, gs, gk), Tractions(px, py, ux, uy),
        tol * scale, max_sweeps, (series_x, series_y), ANDERSON_DEPTH if anderson_depth is None else anderson_depth)
    residual = change / scale
    if change > tol * scale:
        raise NotConvergedError(f"tangential contact ({mode}): no convergence in {max_sweeps} sweeps "
                                f"(residual {residual:.3g})")
    traction[cix, ciy, 0] = px
    traction[cix, ciy, 1] = py
    status = np.zeros((nx, ny), np.int8)
    status[cix, ciy] = st
    displacement = kernels.tangential_displacement(traction)
    log.debug("tangential %s: %d sweeps, residual %.3g", mode, sweeps, residual)
    return TangentialSolution(traction, displacement, status, int(sweeps), float(residual))


def _local_slip_vec(cx, cy, dxx, dyy, g, iterations=40):
    """Vectorised local slip problem (see kernels._local_slip): traction (px, py) (Pa)."""
    cn = np.hypot(cx, cy)
    sig = np.maximum(cn - g * 0.5 * (dxx + dyy), 0.0)
    for _ in range(iterations):
        ax = sig + g * dxx
        ay = sig + g * dyy
        f = cx * cx / ax ** 2 + cy * cy / ay ** 2 - 1.0
        df = -2.0 * (cx * cx / ax ** 3 + cy * cy / ay ** 3)
        with np.errstate(divide="ignore", invalid="ignore"):
            new = np.where(df < 0, sig - f / df, sig)
        sig = np.where(new < 0, 0.5 * sig, new)
    return -g * cx / (sig + g * dxx), -g * cy / (sig + g * dyy)


def _steady_matrix(kernels, cix, ciy):
    """Dense steady-rolling matrix B = (I - S) A on the contact elements, shape (2 nc, 2 nc).

    Row block k of ``B @ [px; py]`` is u_k(i) - u_k(i + 1) at contact element i (m/Pa).
    """
    ox, oy = kernels.nx - 1, kernels.ny - 1
    di = cix[:, None] - cix[None, :] + ox
    dj = ciy[:, None] - ciy[None, :] + oy
    blocks = {}
    for name in ("11", "12", "22"):
        K = getattr(kernels, "K" + name)
        Kp = np.zeros((K.shape[0] + 1, K.shape[1]))
        Kp[: K.shape[0]] = K  # offset +1 beyond the table: never reached when contact < grid
        blocks[name] = K[di, dj] - Kp[di + 1, dj]
    return np.block([[blocks["11"], blocks["12"]], [blocks["12"], blocks["22"]]])


def _solve_steady(kernels, pressure, rigid_slip, *, friction, p_init, tol, max_sweeps):
    """Steady rolling solved directly: active sets and slip directions (Kalker's scheme).

    With B = (I - S) A on the contact elements (dense; a direct Gauss-Seidel sweep on this
    non-symmetric system does not converge because the upstream coupling is as large as the
    diagonal): the stick tractions solve B p = -W with the slip tractions
    p = mu_k p_z e fixed, e the unit traction direction. Then stick elements over the
    static bound turn to slip (e along their traction), slip elements take e = -S/|S| from
    their new slip, and slip elements whose slip turns against e go back to stick.
    Repeated until the sets are unchanged and e changes by less than tol.
    """
    pz = np.asarray(pressure, float)
    nx, ny = kernels.nx, kernels.ny
    cix, ciy = np.nonzero(pz > 0)
    nc = cix.size
    traction = np.zeros((nx, ny, 2))
    status = np.zeros((nx, ny), np.int8)
    if nc == 0:
        return TangentialSolution(traction, np.zeros((nx, ny, 2)), status, 0, 0.0)
    if cix.max() >= nx - 1:
        raise InputError("grid.nx", "the contact area reaches the leading edge of the grid; "
                         "enlarge the grid (nx or dx)")
    B = _steady_matrix(kernels, cix, ciy)
    dg = np.stack([np.diag(B)[:nc], np.diag(B)[nc:]], axis=1)  # local diagonal (m/Pa)
    w = np.asarray(rigid_slip, float)[cix, ciy].T.ravel()  # [wx..., wy...]
    gs = friction.static * pz[cix, ciy]
    gk = friction.kinetic * pz[cix, ciy]
    slip = np.zeros(nc, bool)
    e = np.zeros((nc, 2))
    if p_init is not None:
        p0 = np.asarray(p_init, float)[cix, ciy]
        mag = np.hypot(p0[:, 0], p0[:, 1])
        slip = mag >= gk * (1 - 1e-9)
        slip &= mag > 0
        e[slip] = p0[slip] / mag[slip, None]
    max_iter = 200
    change = np.inf
    for it in range(1, max_iter + 1):
        stick = ~slip
        p = np.zeros((nc, 2))
        p[slip] = gk[slip, None] * e[slip]
        pv = p.T.ravel()
        st2 = np.concatenate([stick, stick])
        if st2.any():
            rhs = -w[st2] - B[np.ix_(st2, ~st2)] @ pv[~st2]
            pv[st2] = np.linalg.solve(B[np.ix_(st2, st2)], rhs)
        p = pv.reshape(2, nc).T
        sv = (w + B @ pv).reshape(2, nc).T
        smag = np.hypot(sv[:, 0], sv[:, 1])
        pmag = np.hypot(p[:, 0], p[:, 1])
        new_slip = slip.copy()
        new_e = e.copy()
        over = stick & (pmag > gs * (1 + 1e-12))
        new_slip[over] = True
        new_e[over] = p[over] / pmag[over, None]
        # slip elements: local (element-wise) problem with the others fixed, as one
        # Gauss-Seidel update would do: back to stick if the stick traction is admissible,
        # else the direction of the local slip solution
        if slip.any():
            cx = sv[slip, 0] - dg[slip, 0] * p[slip, 0]
            cy = sv[slip, 1] - dg[slip, 1] * p[slip, 1]
            qx, qy = -cx / dg[slip, 0], -cy / dg[slip, 1]
            ok = qx * qx + qy * qy <= gs[slip] ** 2
            lx, ly = _local_slip_vec(cx, cy, dg[slip, 0], dg[slip, 1], gk[slip])
            ln = np.hypot(lx, ly)
            idx = np.nonzero(slip)[0]
            back = np.zeros(nc, bool)
            back[idx[ok]] = True
            good = ~ok & (ln > 0)
            new_e[idx[good]] = np.stack([lx[good], ly[good]], axis=1) / ln[good, None]
            new_slip[back] = False
        change = float(np.abs(new_e - e)[slip & new_slip].max(initial=0.0))
        sets_same = np.array_equal(new_slip, slip)
        slip, e = new_slip, new_e
        if sets_same and change <= tol:
            break
    else:
        # the direction iteration can cycle (strong spin, elements flipping between stick
        # and slip): finish with the robust fixed point of transient steps
        log.info("steady active-set iteration cycles (direction change %.3g); "
                 "continuing with transient-step iteration", change)
        traction[cix, ciy] = p
        return _solve_steady_by_rolling(kernels, pz, rigid_slip, friction=friction,
                                        p_init=traction, tol=tol, max_sweeps=max_sweeps)
    traction[cix, ciy] = p
    status[cix, ciy] = np.where(slip, SLIP, STICK)
    displacement = kernels.tangential_displacement(traction)
    log.debug("tangential steady: %d active-set iterations, %d slip of %d", it, slip.sum(), nc)
    return TangentialSolution(traction, displacement, status, it, change)


def _solve_steady_by_rolling(kernels, pz, rigid_slip, *, friction, p_init, tol, max_sweeps,
                             max_outer=20000):
    """Steady rolling as the fixed point of transient steps (u' = current u shifted).

    Robust but slow: information travels one element per step. Converged when a step
    changes the tractions by less than tol times the traction scale.
    """
    scale = pz.max() * min(max(friction.static, 1e-3), 1.0)
    traction = np.array(p_init, float)
    u = kernels.tangential_displacement(traction)
    total = 0
    change = np.inf
    for outer in range(1, max_outer + 1):
        sol = solve_tangential(kernels, pz, rigid_slip, mode="transient", friction=friction,
                               u_prev=u, p_init=traction, u_init=u, tol=tol, max_sweeps=max_sweeps)
        total += sol.sweeps
        change = np.abs(sol.traction - traction).max() / scale
        traction, u = sol.traction, sol.displacement
        if change <= 10.0 * tol:  # the inner solves are accurate to tol
            break
    else:
        raise NotConvergedError(f"tangential contact (steady): no convergence in {max_outer} "
                                f"rolling steps (residual {change:.3g})")
    log.debug("tangential steady by rolling: %d steps, %d sweeps", outer, total)
    return TangentialSolution(traction, u, sol.status, total, float(change))
