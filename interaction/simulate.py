r"""Time-domain wheel/rail interaction with implicit coupling of the contact forces.

Each step ``n`` (docs/design.md §4.6):

1. The wheel and rail displacements at the contact are a history term (earlier forces) plus the
   instantaneous compliance ``k[0]`` times the current force (interaction/structures.py). The
   rail receives ``-F``. All displacements are deviations from static equilibrium under the
   static normal force ``Q`` (the wheel load, over the cosine of the contact angle when the
   contact frame is inclined, interaction/frame.py); the force deviation is ``ΔF = F - (0, 0, Q)``.
   Everything is in the contact frame (z along the contact normal): the structures are turned
   into it before the loop.
2. The relative displacement ``Δu = u_wheel - u_rail`` sets the approach
   ``δ = δ_static - Δu_z (+ an optional excitation, m)`` and the structural creepages
   ``(Δu̇_x, Δu̇_y) / v`` added to the imposed ones (docs/design.md §4.5), with the backward-difference
   velocity ``Δu̇[n] = (Δu[n] - Δu[n-1]) / Δt`` (:func:`interaction.creepage.total_creepage`, the
   one function of the Python and the compiled loops).
3. The contact model returns the force for that approach and those creepages. Steps 1–3 are
   repeated until the force changes by less than ``tolerance × Q``; then the contact state and
   both structures are advanced.

How the implicit coupling is solved depends on the contact model:

* A model with ``accepts_compliance`` (the half-space model) takes the diagonal of the
  instantaneous compliance ``C = k_w[0] + k_r[0]`` into its own solution, as springs in series
  with the contact (a constant added to every influence coefficient; the structures'
  instantaneous response becomes part of the contact problem): one contact solution then satisfies the coupling exactly except for the
  small off-diagonal terms of ``C`` (vertical/lateral coupling of the wheel, ~1 % of the
  diagonal), which are iterated on from a linearly extrapolated force, each pass warm-started
  from the previous one. The iteration stops when those terms move the contact inputs by less
  than ``tolerance × Q`` divided by twice the contact's static normal stiffness. Typically 1–2
  passes per step instead of 15–25 fixed-point iterations (loop gain ≈ 0.4 for the default
  track).
* Other models (the point model) are iterated on the whole of ``C`` from the extrapolated force,
  by fixed point for :data:`NEWTON_AFTER` iterations (it contracts by the loop gain, ≈ 0.4),
  then by Newton steps with a forward-difference Jacobian. The compiled loop of
  contact/point/loop.py solves the same equations for the point contact by Newton's method
  from the first iteration, with the law's own Jacobian (one evaluation per iteration), from a
  linear prediction of the force.

In the compiled loops the rail's convolution is split: its first
:data:`~interaction.structures.RAIL_NEAR_STEPS` samples are summed each step, the rest once per
block of as many steps by FFT (:class:`~interaction.structures.RailFarField`), exact to round-off.

A contact model that offers a compiled time loop (``contact.compiled_path(static)``, see
contact/model.py) runs in it when the wheel is a recursion and the rail a
convolution; the loop runs in chunks of about half a second of wall time, between which a
KeyboardInterrupt gets through, the progress is reported and contact fields are snapshot.

The run starts from static equilibrium (``F = (0, 0, Q)``, zero tangential traction): the
lateral creepage is switched on at ``t = 0``. Lift-off (zero normal force) and full sliding are
ordinary contact states. A non-finite or runaway force raises :class:`SimulationDiverged` with
the step and the quantities at that step.
"""

from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from tqdm import tqdm

from interaction.bundles import Coupling, histories, loop_state
from interaction.creepage import total_creepage
from interaction.loop_steps import NOT_CONVERGED, RUNAWAY
from interaction.structures import RailFarField, compiled_structures
from squealcore.errors import InputError

logger = logging.getLogger(__name__)


class SimulationDiverged(RuntimeError):
    """The time stepping produced a non-finite or runaway force, or the coupling did not converge.

    Attributes
    ----------
    step : int
        Time step at which it happened.
    details : dict
        Force, approach, creepages and iteration count at that step.
    """

    def __init__(self, step, message, details):
        self.step = step
        self.details = details
        text = ", ".join(f"{k}={v}" for k, v in details.items())
        super().__init__(f"step {step}: {message} ({text})")


@dataclass
class SimulationResult:
    """Histories of one simulation (SI units, contact frame).

    Attributes
    ----------
    time : (nt,) ndarray
        s.
    force : (nt, 3) ndarray
        Force of the rail on the wheel, N.
    creepage : (nt, 3) ndarray
        Total creepages (ξ, η, φ) including the structural ones; φ in 1/m.
    slip_fraction : (nt,) ndarray
        Share of the contact area in slip (point model: |F_t| / μF_n).
    wheel_displacement, rail_displacement : (nt, 3) ndarray
        Deviations from static equilibrium at the contact, m.
    wheel_velocity, rail_velocity : (nt, 3) ndarray
        Backward-difference velocities, m/s.
    iterations : (nt,) int ndarray
        Coupling iterations per step.
    static_approach : float
        Approach at static equilibrium, m.
    extra : dict
        ``"snapshots"``: {step: ContactFields} of the requested ``snapshot_steps`` (empty for a
        model without fields); compiled half-space loop: ``"normal_iterations"`` and
        ``"sweeps"`` (nt,) per step.
    """

    time: np.ndarray
    force: np.ndarray
    creepage: np.ndarray
    slip_fraction: np.ndarray
    wheel_displacement: np.ndarray
    rail_displacement: np.ndarray
    wheel_velocity: np.ndarray
    rail_velocity: np.ndarray
    iterations: np.ndarray
    static_approach: float
    extra: dict = field(default_factory=dict)


def simulate(wheel, rail, contact, *, speed, wheel_load, creepage, n_steps, excitation=None, tolerance=1e-9,
             max_iterations=50, runaway_factor=1e3, progress=False, compiled=True, snapshot_steps=(),
             chunk_seconds=0.5):
    """Run the interaction for ``n_steps`` steps.

    Parameters
    ----------
    wheel, rail : ModalStructure or ConvolutionStructure
        Structures at the contact point (interaction/structures.py), same time step.
    contact : ContactModel
        Contact model (contact/model.py) with the same time step.
    speed : float
        Rolling speed v, m/s.
    wheel_load : float
        Static normal force along the contact normal, N: the wheel load Q for an upright
        contact, ``Q / cos α`` in the contact frame inclined by the contact angle α
        (:func:`interaction.frame.static_normal_force`; the structures then come turned into
        that frame, :func:`interaction.frame.to_contact_frame`).
    creepage : (3,) sequence
        Imposed creepages (ξ, η, φ), switched on at t = 0; φ in 1/m.
    n_steps : int
        Number of time steps.
    excitation : (n_steps,) array_like, optional
        Extra approach per step (e.g. a roughness), m.
    tolerance : float
        Convergence of the coupling iteration, relative to Q.
    max_iterations : int
        Iterations per step before :class:`SimulationDiverged` is raised.
    runaway_factor : float
        A force larger than this times Q counts as divergence.
    progress : bool or callable
        True: show a progress bar (tqdm); a callable is called as ``progress(done, n_steps)``
        after each chunk of the compiled loop (each step of the Python loop).
    compiled : bool
        Use the compiled loop that the contact model offers (``contact.compiled_path``; point
        and transient half-space contact) when the wheel is a :class:`ModalStructure` and the
        rail a :class:`ConvolutionStructure`. Same algorithm; the Python loop below is the
        reference (tests compare them).
    snapshot_steps : sequence of int
        Steps (0 <= step < n_steps) after which the contact fields are kept:
        ``result.extra["snapshots"][step]`` is the :class:`ContactFields` of the committed
        contact state after that step (half-space model; none for the point model).
    chunk_seconds : float
        Wall time per chunk of the compiled loop, s (> 0); the result does not depend on it.

    Returns
    -------
    SimulationResult
    """
    dt = wheel.time_step
    if not np.isclose(rail.time_step, dt, rtol=1e-9) or not np.isclose(contact.time_step, dt, rtol=1e-9):
        raise ValueError(f"time steps differ: wheel {dt}, rail {rail.time_step}, contact {contact.time_step}")
    snapshot_steps = sorted({int(s) for s in snapshot_steps})
    if snapshot_steps and not 0 <= snapshot_steps[0] <= snapshot_steps[-1] < n_steps:
        raise InputError("snapshot_steps", f"must lie in [0, {n_steps - 1}], got {snapshot_steps}")
    if not chunk_seconds > 0.0:
        raise InputError("chunk_seconds", f"must be > 0 s, got {chunk_seconds!r}")
    q = float(wheel_load)
    xi, eta, phi = (float(c) for c in creepage)
    static = contact.solve(contact.initial_state(), normal_force=q, creepage=(0.0, 0.0, 0.0))
    delta_static = static.diagnostics.approach
    state = static.new_state
    f_static = np.array([0.0, 0.0, q])
    excitation = np.zeros(n_steps) if excitation is None else np.asarray(excitation, dtype=float)
    report = _progress_reporter(progress, n_steps)

    # a model without compiled_path (it is optional) runs in the Python loop
    structures = compiled_structures(wheel, rail) if compiled else None
    path = contact.compiled_path(static) if structures is not None and hasattr(contact, "compiled_path") else None
    if path is not None:
        coupling = Coupling(np.array([xi, eta, phi]), float(speed), float(dt), q, float(delta_static), float(tolerance),
                            int(max_iterations), float(runaway_factor))
        try:
            return _simulate_compiled(structures, RailFarField(rail.tail), path, coupling, n_steps,
                                      np.ascontiguousarray(excitation), snapshot_steps, chunk_seconds, report)
        finally:
            report(None)
    snapshots = {}
    snapshot_set = set(snapshot_steps)
    out = {name: np.zeros((n_steps, 3)) for name in
           ("force", "creepage", "wheel_displacement", "rail_displacement", "wheel_velocity", "rail_velocity")}
    slip = np.zeros(n_steps)
    iterations = np.zeros(n_steps, dtype=int)
    u_w_prev = np.zeros(3)
    u_r_prev = np.zeros(3)
    force = f_static.copy()
    force_before = f_static.copy()
    # Instantaneous compliance of the relative displacement: Δu = history + C ΔF. A contact model
    # that accepts series compliances takes the diagonal of C into its own solution (one solve
    # per pass); the off-diagonal rest is iterated on, as all of C is for other models.
    compliance = wheel.k0 + rail.k0
    series = np.diag(compliance).copy() if getattr(contact, "accepts_compliance", False) else np.zeros(3)
    rest = compliance - np.diag(series)
    # bound on the contact's stiffness (N/m): twice its static normal stiffness 3Q/(2δ)
    stiffness_bound = 3.0 * q / delta_static
    coupled = bool(series.any())

    for n in range(n_steps):
        hist_w = wheel.history()
        hist_r = rail.history()
        hist = hist_w + hist_r  # u_r = -(rail history + k0_r ΔF)
        rel_prev = u_w_prev - u_r_prev
        kwargs = {"compliance": series} if coupled else {}
        if n >= 2:
            force = 2.0 * force - force_before  # linear extrapolation: fewer passes
        def contact_at(trial):
            """The contact's solution for the inputs that the trial force gives (the map G)."""
            rel = hist + rest @ (trial - f_static)  # without the series part
            approach = delta_static - rel[2] + series[2] * q + excitation[n]
            imposed = (total_creepage(xi, rel[0] - rel_prev[0], dt, speed),
                       total_creepage(eta, rel[1] - rel_prev[1], dt, speed), phi)
            result = contact.solve(state, approach=approach, creepage=imposed, **kwargs)
            if not np.all(np.isfinite(result.force)) or np.max(np.abs(result.force)) > runaway_factor * q:
                raise SimulationDiverged(n, "force not finite or runaway",
                                         {"force": result.force.tolist(), "approach": approach, "creepage": imposed})
            return result

        for it in range(1, max_iterations + 1):
            result = contact_at(force)
            if coupled:
                kwargs["initial"] = result.new_state  # warm start of the next pass
            new_force = result.force
            change = np.max(np.abs(new_force - force))
            # with series compliances the force moves only through the rest of C
            input_change = np.max(np.abs(rest @ (new_force - force))) * stiffness_bound
            if change <= tolerance * q or (coupled and input_change <= tolerance * q):
                force = new_force
                break
            if not coupled and it >= NEWTON_AFTER:
                force = _newton_step(contact_at, force, new_force, q)
            else:
                force = new_force
        else:
            raise SimulationDiverged(n, "coupling iteration did not converge",
                                     {"force": force.tolist(), "change": change})
        dF = force - f_static
        u_w = wheel.displacement(hist_w, dF)
        u_r = -rail.displacement(hist_r, dF)
        out["force"][n] = force
        moved = (u_w - u_w_prev) - (u_r - u_r_prev)  # change of the relative displacement over the step
        out["creepage"][n] = (total_creepage(xi, moved[0], dt, speed), total_creepage(eta, moved[1], dt, speed), phi)
        out["wheel_displacement"][n] = u_w
        out["rail_displacement"][n] = u_r
        out["wheel_velocity"][n] = (u_w - u_w_prev) / dt
        out["rail_velocity"][n] = (u_r - u_r_prev) / dt
        slip[n] = result.diagnostics.slip_fraction
        iterations[n] = it
        state = result.new_state
        if n in snapshot_set and result.fields is not None:
            snapshots[n] = result.fields
        wheel.commit(dF)
        rail.commit(dF)
        u_w_prev, u_r_prev = u_w, u_r
        force_before = out["force"][n - 1] if n >= 1 else f_static
        report(n + 1)
    report(None)
    return SimulationResult(time=np.arange(n_steps) * dt, slip_fraction=slip, iterations=iterations,
                            static_approach=delta_static, extra={"snapshots": snapshots}, **out)


NEWTON_AFTER = 3
"""Coupling iterations by plain fixed point before :func:`_newton_step` takes over (models without
series compliance): the fixed point contracts by the loop gain (about 0.4-0.6 in a limit cycle),
which stick phases of a stick/slip cycle can push above 1. Python loop only: the compiled point
loop takes Newton's steps with the law's own Jacobian from the first iteration."""


def _newton_step(contact_at, force, image, load, relative_step=1e-6, halvings=12):
    """One Newton step on the coupling residual ``R(F) = G(F) - F`` from ``force`` (N).

    ``G = contact_at(F).force`` is the contact's force for the inputs of the trial force F and
    ``image = G(force)``; the Jacobian of R is taken by forward differences of
    ``relative_step * load`` (N), and the step is halved until the largest residual component
    drops. Returns the new trial force (N).
    """
    residual = image - force
    h = relative_step * load
    jacobian = -np.eye(3)
    for k in range(3):
        trial = force.copy()
        trial[k] += h
        jacobian[:, k] += (contact_at(trial).force - image) / h
    try:
        step = np.linalg.solve(jacobian, -residual)
    except np.linalg.LinAlgError:
        return image
    size = np.max(np.abs(residual))
    for _ in range(halvings):
        trial = force + step
        if np.max(np.abs(contact_at(trial).force - trial)) < size:
            return trial
        step = 0.5 * step
    return image


def _progress_reporter(progress, n_steps) -> Callable:
    """``report(done)`` for the ``progress`` argument of :func:`simulate`; ``report(None)`` ends it."""
    if callable(progress):
        return lambda done: None if done is None else progress(done, n_steps)
    if not progress:
        return lambda done: None
    bar = tqdm(total=n_steps, desc="simulate", unit="step", mininterval=1.0)

    def report(done):
        if done is None:
            bar.close()
        else:
            bar.update(done - bar.n)
    return report


def _chunks(n_steps, snapshot_steps, chunk_seconds, block=0):
    """Generator of the chunks ``(start, stop)`` of a compiled run; send it each chunk's wall time (s).

    A chunk ends after every snapshot step and, with ``block > 0``, at every multiple of
    ``block`` (the rail's far field is filled per block); its length follows the measured speed
    so that a chunk takes about ``chunk_seconds`` (the first one 64 steps).
    """
    ends = [s + 1 for s in snapshot_steps] + [n_steps]
    start = 0
    size = 64
    while start < n_steps:
        stop = min(start + size, next(e for e in ends if e > start))
        if block > 0:
            stop = min(stop, (start // block + 1) * block)
        elapsed = yield start, stop
        rate = (stop - start) / max(elapsed, 1e-6)  # steps per second
        size = int(min(max(rate * chunk_seconds, 1), 8 * size, 100_000))
        start = stop


def _simulate_compiled(structures, far, path, coupling, n_steps, excitation, snapshot_steps, chunk_seconds, report):
    """:func:`simulate` in the contact model's compiled loop (the loop.py of its folder in contact/), chunk by chunk.

    ``far`` (:class:`~interaction.structures.RailFarField`) fills the rail's far field at the
    start of each of its blocks; chunks do not cross a block's end.
    """
    out = histories(n_steps)
    state = loop_state(structures, coupling.load, path.state)
    snapshots = {}
    wanted = set(snapshot_steps)
    block = far.near if far.active else 0
    chunks = _chunks(n_steps, snapshot_steps, chunk_seconds, block)
    elapsed = None
    while True:
        try:
            start, stop = chunks.send(elapsed)
        except StopIteration:
            break
        t0 = time.perf_counter()
        if block and start % block == 0:
            far.fill(out.force, coupling.load, start, state)
        failed = path.loop(structures, path.contact, coupling, excitation, state, out, start, stop)
        elapsed = time.perf_counter() - t0
        if failed >= 0:
            _raise_failure(path, int(failed), int(state.failure[0]), out)
        if stop - 1 in wanted:
            fields = path.snapshot(state.contact)
            if fields is not None:
                snapshots[stop - 1] = fields
        report(stop)
    extra = {"snapshots": snapshots}
    extra.update({name: out.work[:, k] for k, name in enumerate(path.work)})
    return SimulationResult(time=np.arange(n_steps) * coupling.time_step, force=out.force, creepage=out.creepage,
                            slip_fraction=out.slip_fraction, wheel_displacement=out.wheel_displacement,
                            rail_displacement=out.rail_displacement, wheel_velocity=out.wheel_velocity,
                            rail_velocity=out.rail_velocity, iterations=out.iterations,
                            static_approach=coupling.static_approach, extra=extra)


FAILURES = {RUNAWAY: "force not finite or runaway", NOT_CONVERGED: "coupling iteration did not converge"}
"""Messages of the compiled loops' own failure codes (the contact models add theirs)."""


def _raise_failure(path, step, code, out):
    """Raise the error of a compiled loop that failed at ``step`` with the failure ``code``."""
    before = out.force[max(step - 1, 0)]
    message = path.failures.get(code, FAILURES.get(code, "failed")).format(force=before[2])
    if code in path.input_failures:
        raise InputError(path.input_failures[code], f"step {step}: {message}")
    raise SimulationDiverged(step, message, {"iterations": int(out.iterations[step]), "force": before.tolist()})
