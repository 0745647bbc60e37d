"""Kalker-type half-space contact model (``halfspace``): normal and tangential problems on a grid.

The grid of nx x ny elements (dx along rolling, dy lateral) is centred on the contact point.
A transient rolling step advances the contact by one element, so ``time_step = dx / speed``.
"""

from __future__ import annotations

import hashlib
import logging
import math
from collections import OrderedDict
from dataclasses import dataclass, replace
from typing import Optional

import numpy as np

from squealcore.errors import InputError, require_range

from contact.halfspace.loop import halfspace_contact_loop

from contact.halfspace.anderson_kernels import anderson_history, carried_anderson_history
from contact.halfspace.bundles import (COMMITTED, GAUSS_SEIDEL, FrictionCoefficients, GridGeometry, HalfspaceInputs, NormalTable,
                      SolverSettings, element_states)
from contact.halfspace.influence import rectangle_kernels
from contact.friction_law import scaled
from contact.model import CompiledPath, ContactFields, ContactResult, Diagnostics, freeze
from contact.halfspace.normal import NormalSolution, NotConvergedError, solve_normal
from contact.params import MAX_GRID_SIDE, Friction, Material, check_creepage
from contact.halfspace.rolling_kernels import normal_solution_table
from contact.halfspace.tangential import ANDERSON_DEPTH, MODES, SLIP, STICK, solve_tangential, traction_scale

LOOP_ANDERSON_DEPTH = 32
"""Sweeps remembered by the Anderson mixing in the interaction's compiled time loop, whose memory
is carried from one solution to the next while the contact list stays the same
(``anderson_kernels.continue_history``); a stand-alone solution starts with an empty memory of
``tangential.ANDERSON_DEPTH`` sweeps. A deeper carried memory takes fewer sweeps per step, down
to two (a mixed sweep and the confirming one) once the contact is steady, and less time per step
(docs/benchmarks.md, *The half-space time loop*, *Carried Anderson memory*)."""

LOOP_CARRY_MEMORY = True
"""Whether the time loop carries the Anderson memory from one solution to the next (False: each
solution starts with an empty memory of :data:`LOOP_ANDERSON_DEPTH` sweeps; for comparisons)."""

EXTRAPOLATED_WARM_START = True
"""Whether a stand-alone transient step starts its iterations from the last state extrapolated
linearly over one step (tractions and, consistently, displacements; :meth:`HalfspaceContact.solve`)
instead of the last state itself: fewer iterations in partial slip, a few more in full slip
while the stick area leaves the contact (docs/benchmarks.md, *Contact solvers against CONTACT*,
*A warm start extrapolated over one step*). The interaction's compiled time loop has its own
warm start and does not use this."""

STEADY_CHANGE = 100.0
"""A last traction change of at most this many tolerances (of the traction scale) counts as the
rounding of a steady state: the next warm start is not extrapolated from it
(:data:`EXTRAPOLATED_WARM_START`)."""

NORMAL_TABLES_KEPT = 2
"""Tables of normal solutions (:meth:`HalfspaceContact.normal_table`) kept in memory per process.

A table depends only on the influence coefficients (material, grid), the gap and the tolerance,
not on friction, creepage or the structures, so the cases of a study that share the contact
geometry share it: a process that runs several cases (the study's own process, or each Dask
worker) computes it once (1024 normal solutions; 17 MB per table on the default study's 1080
elements; its cost: docs/benchmarks.md, *The half-space time loop*, *The table of normal
solutions once per process*)."""

_normal_tables: OrderedDict = OrderedDict()

log = logging.getLogger(__name__)

__all__ = ["Grid", "HalfspaceState", "HalfspaceContact", "for_study", "for_command"]


@dataclass(frozen=True)
class Grid:
    """Uniform grid of the potential contact area, centred at the origin.

    Parameters
    ----------
    nx, ny : int
        Elements along x (rolling) and y (lateral), >= 3.
    dx, dy : float
        Element sizes (m).
    """

    nx: int
    ny: int
    dx: float
    dy: float

    def __post_init__(self):
        for name in ("nx", "ny"):
            v = getattr(self, name)
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 3 <= v <= MAX_GRID_SIDE:
                raise InputError(f"grid.{name}", f"must be an integer in [3, {MAX_GRID_SIDE}], got {v!r}")
        require_range("grid.dx", self.dx, 0.0, None, low_open=True, unit="m")
        require_range("grid.dy", self.dy, 0.0, None, low_open=True, unit="m")

    @property
    def x(self) -> np.ndarray:
        """Element centres along x (m), shape (nx,)."""
        return (np.arange(self.nx) - 0.5 * (self.nx - 1)) * self.dx

    @property
    def y(self) -> np.ndarray:
        """Element centres along y (m), shape (ny,)."""
        return (np.arange(self.ny) - 0.5 * (self.ny - 1)) * self.dy

    @classmethod
    def covering(cls, a, b, nx=None, ny=None, dx=None, dy=None, margin=0.1) -> "Grid":
        """Grid covering the Hertz patch 2a x 2b (m) plus ``margin`` (default 10 %).

        Give the number of elements (nx, ny) or the sizes (dx, dy) per direction; the
        default is 40 elements. With a size alone, the grid gets one more element on each side,
        so that even a coarse grid keeps the contact off its border elements.
        """
        def one(n, d, half, name):
            if d is not None:
                d = require_range(f"grid.d{name}", d, 0.0, None, low_open=True, unit="m")
                if n is None:
                    n = int(np.ceil(2.0 * (1.0 + margin) * half / d)) + 2
                return n, d
            n = 40 if n is None else n
            if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 3:
                raise InputError(f"grid.n{name}", f"must be an integer >= 3, got {n!r}")
            return n, 2.0 * (1.0 + margin) * half / n

        nx, dx = one(nx, dx, a, "x")
        ny, dy = one(ny, dy, b, "y")
        return cls(int(nx), int(ny), float(dx), float(dy))


@dataclass(frozen=True)
class HalfspaceState:
    """State of the half-space model between steps (immutable; arrays read-only).

    Attributes
    ----------
    pressure : ndarray (nx, ny)
        Pressure (Pa).
    traction : ndarray (nx, ny, 2)
        Tangential traction on the wheel (Pa).
    displacement : ndarray (nx, ny, 2)
        Tangential displacement difference (m).
    step : int
        Steps committed so far.
    traction_change, displacement_change : ndarray (nx, ny, 2) or None
        Change of the traction (Pa) and of the displacement (m) over the transient step that
        made this state, None where there was none (the initial state, after lift-off, other
        kinds): the transient solver's warm start of the next step extrapolates with them
        (:meth:`HalfspaceContact.solve`).
    normal : (tuple, NormalSolution) or None
        The normal problem that ``pressure`` solves: its key (the model's
        :attr:`HalfspaceContact.normal_problem_key`, the load of the step that made this state:
        normal force in N or None, approach in m or None, series compliance c_z in m/N) and
        that step's normal solution (its pressure is ``pressure``). A next step of the same
        problem (the same influence coefficients, gap, grid, tolerance and load) starts from it
        and does not solve the normal problem again. None for the initial state and after
        lift-off.
    """

    pressure: np.ndarray
    traction: np.ndarray
    displacement: np.ndarray
    step: int = 0
    traction_change: Optional[np.ndarray] = None
    displacement_change: Optional[np.ndarray] = None
    normal: Optional[tuple] = None


class HalfspaceContact:
    """Non-steady rolling contact of two quasi-identical elastic half-spaces.

    Parameters
    ----------
    material : Material
        Combined elastic constants.
    friction : Friction
        Static and kinetic friction coefficients and the characteristic of the sliding speed.
    grid : Grid
        Potential contact area.
    gap : ndarray (nx, ny)
        Undeformed gap at the element centres (m), e.g. ``A x^2 + B y^2``.
    kind : {"steady", "transient", "shift"}
        Tangential problem solved by :meth:`solve`.
    speed : float
        Rolling speed V (m/s), > 0; sets ``time_step = dx / V``.
    tol : float
        Relative tolerance of the normal and tangential solvers (-).
    max_sweeps : int
        Gauss-Seidel sweep limit of one tangential solution.

    Attributes
    ----------
    influence : Influence
        Influence coefficients (bundle, contact/halfspace/bundles.py).
    geometry : GridGeometry
        The grid as numbers.
    coefficients : FrictionCoefficients
        Static and kinetic friction, with the characteristic's law per metre of an element's slip
        over a time step ``dx / V`` (its sliding speed is the slip over the step); steady rolling
        takes mu at the contact's sliding speed instead (:meth:`_tangential_friction`).
    settings : SolverSettings
        Tolerance, sweep limit, Anderson depth and tangential solver. :meth:`solve` and the
        compiled time loop (:meth:`compiled_path`) use these same bundles.
    """

    accepts_compliance = True
    """:meth:`solve` takes series compliances (the time-domain interaction uses them)."""

    def __init__(self, *, material: Material, friction: Friction, grid: Grid, gap, kind="transient",
                 speed=30.0, tol=1e-9, max_sweeps=5000):
        if kind not in MODES:
            raise InputError("kind", f"must be one of {MODES}, got {kind!r}")
        self.material = material
        self.friction = friction
        self.grid = grid
        self.kind = kind
        self.speed = require_range("rolling.speed", speed, 0.0, None, low_open=True, unit="m/s")
        self.settings = SolverSettings(float(tol), int(max_sweeps), ANDERSON_DEPTH, GAUSS_SEIDEL)
        # the characteristic's rate per metre of slip over a step: v = slip / dt, dt = dx / V
        self.coefficients = FrictionCoefficients(float(friction.static), float(friction.kinetic),
                                                 scaled(friction.law(), self.speed / float(grid.dx)))
        gap = np.asarray(gap, float)
        if gap.shape != (grid.nx, grid.ny):
            raise InputError("geometry.gap", f"must have shape {(grid.nx, grid.ny)}, got {gap.shape}")
        self.gap = freeze(gap)
        self.kernels = rectangle_kernels(grid.nx, grid.ny, grid.dx, grid.dy,
                                         material.shear_modulus, material.poisson_ratio)
        self.influence = self.kernels.bundle()
        self.geometry = GridGeometry(int(grid.nx), int(grid.ny), grid.x, grid.y, float(grid.dx), float(grid.dy),
                                     float(grid.dx * grid.dy))
        self._X, self._Y = np.meshgrid(grid.x, grid.y, indexing="ij")
        self._upstream = None  # kernels of the grid plus one line upstream, when needed
        self._last_slip = None  # (creepage or shift, rigid slip field) of the last solution
        self._normal_problem_key = None  # normal_problem_key, once computed

    def with_friction(self, friction: Friction) -> "HalfspaceContact":
        """The same model (grid, gap, kind, speed, solver settings) with another :class:`~contact.params.Friction`."""
        return HalfspaceContact(material=self.material, friction=friction, grid=self.grid, gap=self.gap, kind=self.kind,
                                speed=self.speed, tol=self.tol, max_sweeps=self.max_sweeps)

    @property
    def tol(self) -> float:
        """Relative tolerance of the normal and tangential solvers (-)."""
        return self.settings.tol

    @property
    def max_sweeps(self) -> int:
        """Gauss-Seidel sweep limit of one tangential solution."""
        return self.settings.max_sweeps

    @property
    def normal_problem_key(self) -> str:
        """Digest of what the normal problem's solution depends on besides the load: the normal
        influence coefficients, the gap, the grid and the tolerance (computed once per model)."""
        if self._normal_problem_key is None:
            g = self.geometry
            digest = hashlib.sha256(np.ascontiguousarray(self.influence.K33, dtype=float).tobytes())
            digest.update(np.ascontiguousarray(self.gap, dtype=float).tobytes())
            digest.update(repr((g.nx, g.ny, g.dx, g.dy, g.area, float(self.tol))).encode())
            self._normal_problem_key = digest.hexdigest()
        return self._normal_problem_key

    def normal_table(self, entries=1024) -> NormalTable:
        """Normal solutions of the contact alone from zero approach to the grid's capacity.

        The approaches are spaced evenly up to the smallest undeformed gap on the grid's border
        (where the contact would reach the edge). The compiled time loop starts each step's
        normal problem from them (interpolated at the step's approach). The table of the same
        contact alone (coefficients, gap, tolerance, entries) is computed once per process and
        then reused (:data:`NORMAL_TABLES_KEPT`); its arrays are shared, to be read only.

        Returns
        -------
        NormalTable
            Approaches (entries,) m, forces N, pressures (entries, nx ny) Pa and normal
            displacement differences (entries, nx ny) m, flat in C order.
        """
        gap = np.ascontiguousarray(self.gap, dtype=float).ravel()
        g = self.geometry
        key = (self.normal_problem_key, int(entries))
        if key in _normal_tables:  # the same contact alone: the same table (NORMAL_TABLES_KEPT)
            _normal_tables.move_to_end(key)
            log.debug("table of normal solutions reused")
            return _normal_tables[key]
        border = np.concatenate([self.gap[0], self.gap[-1], self.gap[:, 0], self.gap[:, -1]]).min()
        approaches = np.linspace(0.0, border, entries + 1)[1:]
        pressure, displacement, force, ok = normal_solution_table(self.influence, g, gap, approaches, self.tol)
        if not ok:
            raise NotConvergedError("normal contact: a solution of the approach table did not converge")
        table = NormalTable(approaches, force, pressure, displacement)
        _normal_tables[key] = table
        while len(_normal_tables) > NORMAL_TABLES_KEPT:
            _normal_tables.popitem(last=False)
        return table

    def inputs(self) -> HalfspaceInputs:
        """The bundle of the compiled transient step (with the table of normal solutions, computed the first time)."""
        return HalfspaceInputs(self.influence, self.geometry, np.ascontiguousarray(self.gap).ravel(), self.coefficients,
                               self.settings, self.normal_table())

    def compiled_path(self, static: ContactResult) -> CompiledPath | None:
        """The compiled time loop of the interaction with this model's :class:`HalfspaceInputs`.

        Transient rolling only (None for the other kinds). The loop starts from the pressure of
        ``static`` (the solution at static equilibrium), without tractions.
        """
        if self.kind != "transient":
            return None
        g = self.geometry
        memory = carried_anderson_history if LOOP_CARRY_MEMORY else anderson_history
        mixing = memory(LOOP_ANDERSON_DEPTH, g.nx * g.ny, g.nx * g.ny)
        return CompiledPath(
            loop=halfspace_contact_loop, contact=self.inputs(),
            state=element_states(g.nx * g.ny, static.new_state.pressure, mixing),
            snapshot=self.element_fields,
            failures={1: "normal contact problem did not converge", 2: "tangential contact problem did not converge",
                      3: "the contact area reaches the grid edge (normal force {force:.0f} N before it); "
                         "enlarge the grid"},
            input_failures={3: "contact.grid"}, work=("normal_iterations", "sweeps"))

    def element_fields(self, states) -> ContactFields:
        """The contact fields of the committed slot of the compiled loop's element states.

        Parameters
        ----------
        states : ElementStates
            Element states of the compiled loop (contact/halfspace/bundles.py).

        Returns
        -------
        ContactFields
            Pressure (nx, ny) Pa, traction (nx, ny, 2) Pa and status (nx, ny) (0 exterior,
            1 stick, 2 slip) of the committed state; new arrays.
        """
        g = self.geometry
        c = int(states.count[COMMITTED])
        ix, iy = states.ix[COMMITTED, :c], states.iy[COMMITTED, :c]
        traction = np.zeros((g.nx, g.ny, 2))
        traction[ix, iy, 0] = states.tx[COMMITTED, :c]
        traction[ix, iy, 1] = states.ty[COMMITTED, :c]
        status = np.zeros((g.nx, g.ny), np.int8)
        status[ix, iy] = states.status[COMMITTED, :c]
        pressure = states.pressure[COMMITTED].reshape(g.nx, g.ny).copy()
        return ContactFields(g.x.copy(), g.y.copy(), pressure, traction, status)

    @property
    def time_step(self) -> float:
        """Time step of a transient rolling step, dx / V (s)."""
        return self.grid.dx / self.speed

    def initial_state(self) -> HalfspaceState:
        """Unloaded state: zero pressure, traction and displacement."""
        g = self.grid
        return HalfspaceState(freeze(np.zeros((g.nx, g.ny))), freeze(np.zeros((g.nx, g.ny, 2))),
                              freeze(np.zeros((g.nx, g.ny, 2))), 0)

    def _rigid_slip(self, creepage, shift):
        """The rigid slip W over the step (m) on the grid, (nx, ny, 2); not to be modified.

        The last one is kept: a run of steps at one creepage (or shift) asks for the same field
        every step.
        """
        if self.kind == "shift":
            if shift is None:
                shift = (0.0, 0.0, 0.0)
            key = ("shift", *(require_range(f"shift.{n}", v, -1.0, 1.0) for n, v in zip("xyr", shift)))
        else:
            key = ("creepage", *check_creepage(creepage))
        if self._last_slip is not None and self._last_slip[0] == key:
            return self._last_slip[1]
        X, Y = self._X, self._Y
        if self.kind == "shift":
            _, sx, sy, rot = key
            w = np.stack([sx - rot * Y, sy + rot * X], axis=-1)
        else:
            _, xi, eta, phi = key
            w = np.stack([xi - phi * Y, eta + phi * X], axis=-1) * self.grid.dx
        self._last_slip = (key, w)
        return w

    def solve(self, state: HalfspaceState, *, approach=None, normal_force=None,
              creepage=(0.0, 0.0, 0.0), shift=None, compliance=None, initial=None) -> ContactResult:
        """Solve one step from ``state``.

        Parameters
        ----------
        state : HalfspaceState
            Previous state (not modified).
        approach : float, optional
            Approach delta (m); <= 0 means lift-off.
        normal_force : float, optional
            Normal force (N); exactly one of approach and normal_force.
        creepage : (xi, eta, phi)
            Creepages of the wheel relative to the rail: xi, eta (-), spin phi (1/m).
        shift : (sx, sy, rot), optional
            Rigid shift over the step (m, m, rad) for ``kind="shift"``.
        compliance : (c_x, c_y, c_z), optional
            Compliances (m/N) of springs in series with the contact (transient and shift), e.g.
            the structures' instantaneous compliance in a time-domain interaction. ``approach``
            is then that of springs and contact together (the contact's own approach is
            ``approach - c_z Fz``, reported in the diagnostics), and the springs' tangential
            displacement ``c_x Fx``, ``c_y Fy`` over the step adds to the rigid slip. The
            coupled problem is solved at once: every influence coefficient gains ``c dx dy``.
        initial : HalfspaceState, optional
            Warm start of the iterative solvers, e.g. an earlier solution of the same step. It
            changes nothing but the iteration count. Default: ``state``; for transient rolling
            ``state`` extrapolated linearly over one step (``traction + traction_change``, the
            same for the displacement, consistent with it), which in partial slip saves about
            a tenth of the sweeps (:data:`EXTRAPOLATED_WARM_START`).

        Returns
        -------
        ContactResult
        """
        if (approach is None) == (normal_force is None):
            raise InputError("load", "give exactly one of normal_force and approach")
        g = self.grid
        area = self.geometry.area
        w = self._rigid_slip(creepage, shift)
        start = state if initial is None else initial
        if compliance is None:
            compliance = (0.0, 0.0, 0.0)
        compliance = tuple(require_range(f"compliance[{i}]", c, 0.0, None, unit="m/N")
                           for i, c in enumerate(compliance))
        load = (self.normal_problem_key, normal_force, approach, compliance[2])
        nsol = self._normal_solution(load, start)
        p = nsol.pressure
        if not np.any(p > 0):
            zeros = self.initial_state()
            new = HalfspaceState(zeros.pressure, zeros.traction, zeros.displacement, state.step + 1)
            diag = Diagnostics(0, 0, 0, 0.0, nsol.iterations, 0.0, 0.0, float(nsol.approach))
            fields = ContactFields(g.x, g.y, new.pressure, new.traction, np.zeros((g.nx, g.ny), np.int8))
            return ContactResult(np.zeros(3), 0.0, new, diag, fields)
        self._warn_if_at_edge(p)
        if self.kind != "shift" and (p[-1, :] > 0).any():
            tsol = self._solve_tangential_extended(p, w, state, start, compliance, self._tangential_friction(creepage))
        else:
            p_init, u_init = start.traction, start.displacement
            if initial is None:
                p_init, u_init = self._extrapolated_warm_start(state)
            tsol = solve_tangential(self.kernels, p, w, mode=self.kind, friction=self._tangential_friction(creepage),
                                    u_prev=state.displacement, p_init=p_init,
                                    u_init=u_init, tol=self.settings.tol,
                                    max_sweeps=self.settings.max_sweeps, series_compliance=compliance[:2],
                                    anderson_depth=self.settings.anderson_depth)
        pt = tsol.traction
        fx, fy = pt[..., 0].sum() * area, pt[..., 1].sum() * area
        fz = p.sum() * area
        mz = float(((self._X * pt[..., 1] - self._Y * pt[..., 0]).sum()) * area)
        n_contact = int((p > 0).sum())
        n_stick = int((tsol.status == STICK).sum())
        n_slip = int((tsol.status == SLIP).sum())
        diag = Diagnostics(n_contact, n_stick, n_slip, n_slip / n_contact,
                           nsol.iterations + tsol.sweeps, max(nsol.residual, tsol.residual),
                           float(p.max()), float(nsol.approach))
        changes = (None, None)
        if self.kind == "transient":  # what the next step's warm start extrapolates with
            changes = (freeze(pt - state.traction), freeze(tsol.displacement - state.displacement))
        pressure = freeze(p)
        new = HalfspaceState(pressure, freeze(pt), freeze(tsol.displacement), state.step + 1, *changes,
                             normal=(load, replace(nsol, pressure=pressure)))
        fields = ContactFields(g.x, g.y, new.pressure, new.traction, tsol.status)
        return ContactResult(np.array([fx, fy, fz]), mz, new, diag, fields)

    def _normal_solution(self, load, start) -> NormalSolution:
        """The normal problem ``load`` (problem key, force, approach, c_z), started from ``start``'s pressure.

        If ``start`` records that its pressure solves this same normal problem
        (:attr:`HalfspaceState.normal`: the same model key and the same force or approach and
        series compliance, exactly), that solution is returned with 0 iterations instead of
        solving again: it already meets the tolerance, and solving again
        only rounds it anew (one conjugate-gradient iteration that moves the pressure by about
        5e-10 of its peak), a noticeable part of a small transient step (docs/benchmarks.md,
        *Contact solvers against CONTACT*, *The normal problem solved once for a constant load*). The result depends on ``start`` and ``load`` only.
        """
        if start.normal is not None and start.normal[0] == load:
            return replace(start.normal[1], iterations=0)
        _, normal_force, approach, compliance_z = load
        return solve_normal(self.kernels, self.gap, normal_force=normal_force, approach=approach,
                            p_init=start.pressure, tol=self.tol, compliance=compliance_z, full_displacement=False)

    def _extrapolated_warm_start(self, state):
        """The tangential warm start of a transient step: ``state`` extrapolated over one step.

        ``(traction, displacement)`` of ``state`` plus their changes over the step that made it
        (:data:`EXTRAPOLATED_WARM_START`); the displacement stays that of the tractions (both
        are extrapolated alike, and the displacement is linear in the tractions). Without a
        change on record, or for the other kinds: ``state``'s own; also when the last change is
        within :data:`STEADY_CHANGE` tolerances of the traction scale, i.e. the rounding of two
        converged solutions of a steady state, which extrapolated would only double (in full
        slip the sweeps would then apply every element's change instead of skipping them).
        """
        if not (EXTRAPOLATED_WARM_START and self.kind == "transient" and state.traction_change is not None):
            return state.traction, state.displacement
        scale = traction_scale(state.pressure, self.coefficients.static)
        if np.abs(state.traction_change).max(initial=0.0) <= STEADY_CHANGE * self.settings.tol * scale:
            return state.traction, state.displacement
        return state.traction + state.traction_change, state.displacement + state.displacement_change

    def _warn_if_at_edge(self, pressure):
        """Log a WARNING with the numbers when the contact area reaches the grid's border elements.

        The grid is the potential contact area (as in CONTACT): the solution is that of a
        contact confined to it, which differs from the unbounded one if the pressure is not
        negligible there.
        """
        g = self.grid
        edges = {"x = x_min (trailing)": pressure[0, :], "x = x_max (leading)": pressure[-1, :],
                 "y = y_min": pressure[:, 0], "y = y_max": pressure[:, -1]}
        touched = [f"{name}: {int((row > 0).sum())} elements, max pressure {row.max() / pressure.max():.2%} of p_max"
                   for name, row in edges.items() if (row > 0).any()]
        if touched:
            log.warning("the contact area reaches the edge of the %d x %d grid (%.4g x %.4g m): %s; "
                        "the contact is confined to the grid", g.nx, g.ny, g.nx * g.dx, g.ny * g.dy,
                        "; ".join(touched))

    def _extended_kernels(self):
        """Kernels of the grid extended by one line upstream (nx + 1 lines; cached)."""
        if self._upstream is None:
            g = self.grid
            self._upstream = rectangle_kernels(g.nx + 1, g.ny, g.dx, g.dy, self.material.shear_modulus,
                                               self.material.poisson_ratio)
        return self._upstream

    def _tangential_friction(self, creepage) -> FrictionCoefficients:
        """The friction of a tangential solution: :attr:`coefficients`, but in steady rolling with
        a friction characteristic of the sliding speed, Coulomb friction at mu of the contact's
        sliding speed ``V |(xi, eta)|`` (the steady sweeps bound every element by one coefficient)."""
        if self.kind != "steady" or self.friction.characteristic == "constant":
            return self.coefficients
        mu = float(self.friction.coefficient(self.speed * math.hypot(float(creepage[0]), float(creepage[1]))))
        return FrictionCoefficients(mu, mu)

    def _solve_tangential_extended(self, p, w, state, start, compliance, friction):
        """The tangential problem when the contact reaches the leading edge: on the grid plus one line upstream.

        The particles entering the contact come from outside the grid, so their previous
        displacement (transient) or the upstream displacement (steady) is needed one element
        beyond it: the problem is solved on the grid extended by one exterior line (zero
        pressure, so never in contact) and the result cut back to the grid.
        """
        k = self._extended_kernels()

        def pad(a):
            return np.concatenate([np.asarray(a, float), np.zeros((1,) + np.shape(a)[1:])], axis=0)

        sol = solve_tangential(k, pad(p), pad(w), mode=self.kind, friction=friction,
                               u_prev=k.tangential_displacement(pad(state.traction)), p_init=pad(start.traction),
                               tol=self.settings.tol, max_sweeps=self.settings.max_sweeps,
                               series_compliance=compliance[:2], anderson_depth=self.settings.anderson_depth)
        return type(sol)(sol.traction[:-1], sol.displacement[:-1], sol.status[:-1], sol.sweeps, sol.residual)


# --------------------------------------------------------------------------- registry hooks
# (contact/registry.py: how a study and the contact command build this model)

def for_study(setup) -> HalfspaceContact:
    """The transient half-space model of a case (:class:`~contact.registry.ContactSetup`).

    Its grid covers the Hertz patch at ``setup.grid_load_factor`` times the static normal force
    plus 10 %, with ``dx`` the rolled distance per time step and ``dy`` the study's
    ``contact.grid_dy``; the gap is Hertz's quadratic one.
    """
    hertz = setup.hertz
    peak = hertz.scaled(setup.grid_load_factor * hertz.normal_force)
    grid = Grid.covering(peak.a, peak.b, dx=setup.speed * setup.time_step, dy=setup.options.grid_dy, margin=0.1)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    gap = hertz.A * x**2 + hertz.B * y**2
    return HalfspaceContact(material=setup.material, friction=setup.friction, grid=grid, gap=gap, kind="transient",
                            speed=setup.speed, tol=setup.tolerance)


def for_command(setup, grid, gap, kind) -> HalfspaceContact:
    """The contact command's half-space model on the case file's ``grid`` and ``gap`` (m)."""
    return HalfspaceContact(material=setup.material, friction=setup.friction, grid=grid, gap=gap, kind=kind,
                            speed=setup.speed)

