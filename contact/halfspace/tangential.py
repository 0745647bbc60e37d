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
element (Gauss-Seidel sweeps from the leading edge, tangential_kernels.py; Kalker's / Vollebregt's
ConvexGS idea); on large contact areas in partial slip, sweeps with local updates and one FFT
product per two sweeps (transient_fft.py) do most of the work and exact sweeps finish it.
Steady rolling is solved directly by Gauss-Seidel sweeps on the steady operator, line by line
along the rolling direction (steady.py, :func:`_solve_steady`).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from squealcore.errors import InputError

from contact.friction_law import CONSTANT_LAW
from contact.halfspace.bundles import FrictionCoefficients, Tractions
from contact.halfspace.influence import Kernels
from contact.halfspace.normal import NotConvergedError
from contact.params import Friction
from contact.halfspace.steady import steady_gauss_seidel, steady_points, steady_sweeps_fft
from contact.halfspace.tangential_kernels import (gather_pair_at, gather_tangential_problem, scatter_pair_at, scatter_solution,
                                 tangential_gauss_seidel)
from contact.halfspace.transient_fft import transient_sweeps_fft

log = logging.getLogger(__name__)

__all__ = ["TangentialSolution", "solve_tangential", "traction_scale", "MODES"]

MODES = ("steady", "transient", "shift")

EXTERIOR, STICK, SLIP = 0, 1, 2

ANDERSON_DEPTH = 8
"""Sweeps remembered by the Anderson mixing of the Gauss-Seidel sweeps (0: plain sweeps).
Over-relaxation of the stick updates was tried before and gave more sweeps, not fewer; Anderson
mixing over 8 sweeps gives far fewer on the interaction's contact problems (docs/benchmarks.md,
*The half-space time loop*)."""

STEADY_FFT_MIN_CONTACT = 2500
"""Steady problems with at least this many contact elements first try the sweeps with local
updates and one FFT product per sweep (steady.steady_sweeps_fft): faster on issue 16's large
steady cases, as fast as the exact updates at about 1000 elements (docs/benchmarks.md,
*Measurements behind the solvers' constants*)."""

TRANSIENT_FFT_MIN_CONTACT = 400
"""Transient and shift problems with at least this many contact elements run the sweeps with
local updates and one FFT product per :data:`transient_fft.SWEEPS_PER_PRODUCT` sweeps
(transient_fft.transient_sweeps_fft) to :data:`TRANSIENT_FFT_TOLERANCE` of the tolerance, then
the exact sweeps from their result (usually one sweep, which confirms the stopping test). If the
first product finds every element sliding (full slip), the exact sweeps take over at once: they
converge in a few there. The limit is the crossover of the two on issue 16's transient from
rest (docs/benchmarks.md, *Contact solvers against CONTACT*, after *The set-up of a stand-alone
step compiled*: the crossover to the exact sweeps)."""

TRANSIENT_EXACT_FIRST = 4
"""Exact sweeps tried first on those problems when the warm start slides everywhere (every
traction at least :data:`FULL_SLIP_WARM_START` of its kinetic bound), as long as they leave
every element sliding: a step in full slip converges in a few of them, where the local sweeps
would add work. Otherwise the local sweeps start at once: in partial slip an exact sweep, which
costs several local ones, does not bring the solution nearer than a local one
(docs/benchmarks.md, *Contact solvers against CONTACT*, *Fewer exact sweeps and a deeper mixing
in the local sweeps*)."""

FULL_SLIP_WARM_START = 0.99
"""A warm start counts as sliding everywhere (:data:`TRANSIENT_EXACT_FIRST`) if every traction is
at least this fraction of its kinetic bound."""

TRANSIENT_FFT_DEPTH = 48
"""Rounds (of two local sweeps and a product) remembered by the Anderson mixing of those local
sweeps (when the solver mixes at all): on issue 16's grids up to 88 x 72 every round of a
solution, with the mixing's differences scaled to unit norm
(anderson_kernels._anderson_coefficients). Deeper memories took fewer iterations up to this
depth on the larger grids and no more time on the smaller (docs/benchmarks.md, *Contact solvers
against CONTACT*, *Scaled Anderson mixing, a deeper memory*). The memory at 48 is about
2.4 MB at 1036 elements, 9.5 MB at 4144."""

TRANSIENT_FFT_TOLERANCE = 0.3
"""Tolerance of those sweeps relative to the solver's: the quickest step on the 44 x 36 transient
from rest; at 0.3 one exact sweep still finishes a step, above it more do (docs/benchmarks.md,
*Contact solvers against CONTACT*, *Fewer exact sweeps and a deeper mixing in the local
sweeps*)."""

STEADY_FFT_MAX_SWEEPS = 600
"""Sweep limit of that first try (well above what issue 16's cases took: docs/benchmarks.md,
*Measurements behind the solvers' constants*)."""


def traction_scale(pressure, static_friction):
    """The traction scale (Pa) that the tangential tolerances are relative to.

    ``max(pressure) * min(max(mu_s, 1e-3), 1)``: the largest static bound, kept away from zero
    for (nearly) frictionless problems and from the pressure's own scale above mu_s = 1.
    """
    return float(np.max(pressure, initial=0.0)) * min(max(static_friction, 1e-3), 1.0)


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


def _slip_law(friction):
    """The :class:`~contact.friction_law.FrictionLaw` (per metre of slip) of ``friction``."""
    if isinstance(friction, FrictionCoefficients):
        return friction.law
    if friction.characteristic != "constant":
        raise ValueError("a friction characteristic of the sliding speed needs the model's FrictionCoefficients "
                         "(its law per metre of slip over the time step)")
    return CONSTANT_LAW


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
        (tangential_kernels.py) from the leading edge; steady: Gauss-Seidel sweeps on the steady
        operator (steady.py), falling back to iterated rolling steps (WARNING) if they do
        not converge.
    friction : Friction or FrictionCoefficients
        Static and kinetic coefficients (``friction.static``, ``friction.kinetic``); a friction
        characteristic of the sliding speed (transient and shift problems) as the
        :class:`FrictionCoefficients` of the model, whose law is per metre of slip over the step
        (:class:`~contact.halfspace.model.HalfspaceContact` builds it from the time step).
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
                             tol=tol, max_sweeps=max_sweeps, anderson_depth=anderson_depth)
    nx, ny = kernels.nx, kernels.ny
    nothing = np.empty((0, 0, 2))

    def field(name, value, shape, optional=True):
        """``value`` as a contiguous float array of the grid's ``shape`` (the compiled gather does not check)."""
        if value is None and optional:
            return nothing
        a = np.ascontiguousarray(value, float)
        if a.shape != shape:
            raise InputError(name, f"must have the grid's shape {shape}, got {a.shape}")
        return a

    pz = field("pressure", pressure, (nx, ny), optional=False)
    # the contact elements in sweep order (from the leading edge, large x, to the trailing edge),
    # their rigid slip, previous displacements, bounds and warm start, gathered in one compiled call
    problem, start, gathered = gather_tangential_problem(
        pz, field("rigid_slip", rigid_slip, (nx, ny, 2), optional=False), field("u_prev", u_prev, (nx, ny, 2)),
        1 if mode == "transient" else 0, field("p_init", p_init, (nx, ny, 2)),
        field("u_init", u_init, (nx, ny, 2)) if p_init is not None else nothing,
        float(friction.static), float(friction.kinetic), _slip_law(friction))
    if gathered == 1:
        raise InputError("grid.nx", "the contact area reaches the leading edge of the grid; "
                         "enlarge the grid (nx or dx)")
    cix, ciy = problem.ix, problem.iy
    traction = np.zeros((nx, ny, 2))
    if cix.size == 0:
        return TangentialSolution(traction, np.zeros((nx, ny, 2)), np.zeros((nx, ny), np.int8), 0, 0.0)
    px, py, ux, uy = start
    if gathered == 2 and p_init is not None:  # the displacement of the warm start is not known: one product
        scatter_pair_at(traction, cix, ciy, px, py)
        gather_pair_at(kernels.tangential_displacement(traction), cix, ciy, ux, uy)
    scale = traction_scale(pz, friction.static)
    depth = ANDERSON_DEPTH if anderson_depth is None else anderson_depth
    gk = problem.kinetic_bound
    rows = kernels.dense_rows(cix, ciy)

    def exact_sweeps(limit):
        """Up to ``limit`` exact sweeps from the present tractions and displacements: (sweeps, change, status)."""
        return tangential_gauss_seidel(kernels.bundle(), problem, Tractions(px, py, ux, uy), tol * scale, limit,
                                          (series_x, series_y), depth, rows)

    sweeps = 0
    change = np.inf
    if cix.size >= TRANSIENT_FFT_MIN_CONTACT:
        if np.all(np.hypot(px, py) >= FULL_SLIP_WARM_START * gk):
            # the warm start slides everywhere: the exact sweeps first (in full slip they converge
            # in a few), while they leave every element sliding
            sweeps, change, st = exact_sweeps(1)
            if change > tol * scale and np.all(st == SLIP):
                more, change, st = exact_sweeps(TRANSIENT_EXACT_FIRST - 1)
                sweeps += more
        if change > tol * scale:
            # the local sweeps, unless their first product finds every element sliding
            local_depth = max(depth, TRANSIENT_FFT_DEPTH) if depth > 0 else 0
            local, _, ux, uy, _ = transient_sweeps_fft(kernels, problem, Tractions(px, py, ux, uy),
                                                       (series_x, series_y), TRANSIENT_FFT_TOLERANCE * tol * scale,
                                                       max_sweeps, local_depth, stop_in_full_slip=True)
            sweeps += local
    if change > tol * scale:  # the exact sweeps: all of them, or the finish after the local ones
        more, change, st = exact_sweeps(max_sweeps)
        sweeps += more
    residual = change / scale
    if change > tol * scale:
        raise NotConvergedError(f"tangential contact ({mode}): no convergence in {max_sweeps} sweeps "
                                f"(residual {residual:.3g})")
    status = np.zeros((nx, ny), np.int8)
    scatter_solution(cix, ciy, px, py, st, traction, status)
    displacement = kernels.tangential_displacement(traction)
    log.debug("tangential %s: %d sweeps, residual %.3g", mode, sweeps, residual)
    return TangentialSolution(traction, displacement, status, int(sweeps), float(residual))


def _solve_steady(kernels, pressure, rigid_slip, *, friction, p_init, tol, max_sweeps, anderson_depth=None):
    """Steady rolling solved directly by Gauss-Seidel sweeps on the steady operator (steady.py).

    The contact elements are visited line by line along the rolling direction (lines of
    constant y), each from the leading edge to the trailing edge, so that an element's
    upstream neighbour, whose displacement enters its slip with the same weight as its own, is
    always already updated in the sweep. Falls back (WARNING) to the fixed point of transient
    steps if the sweeps do not converge within ``max_sweeps``.
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
    order = np.lexsort((-cix, ciy))  # lines of constant y, each from the leading edge
    cix, ciy = cix[order].astype(np.int64), ciy[order].astype(np.int64)
    points = steady_points(cix, ciy, nx, ny)
    if p_init is not None:
        traction[cix, ciy] = np.asarray(p_init, float)[cix, ciy]
    u0 = kernels.tangential_displacement(traction)
    ux = np.ascontiguousarray(u0[points.ix, points.iy, 0])
    uy = np.ascontiguousarray(u0[points.ix, points.iy, 1])
    px = np.ascontiguousarray(traction[cix, ciy, 0])
    py = np.ascontiguousarray(traction[cix, ciy, 1])
    w = np.asarray(rigid_slip, float)
    wx = np.ascontiguousarray(w[cix, ciy, 0])
    wy = np.ascontiguousarray(w[cix, ciy, 1])
    gs = friction.static * pz[cix, ciy]
    gk = friction.kinetic * pz[cix, ciy]
    scale = traction_scale(pz, friction.static)
    ox, oy = nx - 1, ny - 1
    depth = ANDERSON_DEPTH if anderson_depth is None else anderson_depth
    change = np.inf
    if nc >= STEADY_FFT_MIN_CONTACT:
        fx, fy, fs = px.copy(), py.copy(), gs.copy()
        sweeps, change, st = steady_sweeps_fft(kernels, points, wx, wy, fs, gk, fx, fy, tol * scale,
                                               min(max_sweeps, STEADY_FFT_MAX_SWEEPS), depth)
        if change <= tol * scale:
            px, py = fx, fy
        else:
            log.info("steady sweeps with FFT products: no convergence in %d sweeps (residual %.3g); "
                     "continuing with exact updates", sweeps, change / scale)
    if change > tol * scale:
        sweeps, change, st = steady_gauss_seidel(
            kernels.K11, kernels.K12, kernels.K22, points.ix, points.iy, points.upstream, wx, wy, gs, gk,
            px, py, ux, uy, float(kernels.K11[ox, oy]), float(kernels.K22[ox, oy]), tol * scale, max_sweeps, depth)
    residual = change / scale
    traction[cix, ciy, 0] = px
    traction[cix, ciy, 1] = py
    if change > tol * scale:
        log.warning("steady Gauss-Seidel: no convergence in %d sweeps (residual %.3g); "
                    "continuing with transient-step iteration", sweeps, residual)
        return _solve_steady_by_rolling(kernels, pz, rigid_slip, friction=friction,
                                        p_init=traction, tol=tol, max_sweeps=max_sweeps)
    status[cix, ciy] = st
    displacement = kernels.tangential_displacement(traction)
    log.debug("tangential steady: %d sweeps, %d slip of %d", sweeps, int((st == SLIP).sum()), nc)
    return TangentialSolution(traction, displacement, status, int(sweeps), float(residual))


def _solve_steady_by_rolling(kernels, pz, rigid_slip, *, friction, p_init, tol, max_sweeps,
                             max_outer=20000):
    """Steady rolling as the fixed point of transient steps (u' = current u shifted).

    Robust but slow: information travels one element per step. Converged when a step
    changes the tractions by less than tol times the traction scale.
    """
    scale = traction_scale(pz, friction.static)
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
