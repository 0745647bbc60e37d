r"""Time-domain wheel/rail interaction with implicit coupling of the contact forces.

Each step ``n`` (DESIGN §4.6):

1. The wheel and rail displacements at the contact are a history term (earlier forces) plus the
   instantaneous compliance ``k[0]`` times the current force (interaction/structures.py). The
   rail receives ``-F``. All displacements are deviations from static equilibrium under the
   wheel load ``Q``; the force deviation is ``ΔF = F - (0, 0, Q)``.
2. The relative displacement ``Δu = u_wheel - u_rail`` sets the approach
   ``δ = δ_static - Δu_z (+ an optional excitation, m)`` and the structural creepages
   ``(Δu̇_x, Δu̇_y) / v`` added to the imposed ones (DESIGN §4.5), with the backward-difference
   velocity ``Δu̇[n] = (Δu[n] - Δu[n-1]) / Δt``.
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
* Other models (the point model) are iterated on the whole of ``C`` by fixed point (it
  contracts by the loop gain, ≈ 0.4, so 15–25 iterations; cheap for the point model); the
  compiled loop of interaction/kernels.py does the same for point contact.

The run starts from static equilibrium (``F = (0, 0, Q)``, zero tangential traction): the
lateral creepage is switched on at ``t = 0``. Lift-off (zero normal force) and full sliding are
ordinary contact states. A non-finite or runaway force raises :class:`SimulationDiverged` with
the step and the quantities at that step.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from interaction.contact.tangential import ANDERSON_DEPTH

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
             max_iterations=50, runaway_factor=1e3, progress=False, compiled=True):
    """Run the interaction for ``n_steps`` steps.

    Parameters
    ----------
    wheel, rail : ModalStructure or ConvolutionStructure
        Structures at the contact point (interaction/structures.py), same time step.
    contact : ContactModel
        Contact model (interaction/contact/model.py) with the same time step.
    speed : float
        Rolling speed v, m/s.
    wheel_load : float
        Static wheel load Q, N.
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
    progress : bool
        Show a progress bar (Python loop; the compiled loops run a case in seconds to minutes
        and a sweep reports its cases).
    compiled : bool
        Use the compiled loop (interaction/kernels.py) when it covers the models: point or
        transient half-space contact, wheel by recursion, rail by convolution. Same algorithm;
        the Python loop below is the reference (tests compare them).

    Returns
    -------
    SimulationResult
    """
    dt = wheel.time_step
    if not np.isclose(rail.time_step, dt, rtol=1e-9) or not np.isclose(contact.time_step, dt, rtol=1e-9):
        raise ValueError(f"time steps differ: wheel {dt}, rail {rail.time_step}, contact {contact.time_step}")
    q = float(wheel_load)
    xi, eta, phi = (float(c) for c in creepage)
    static = contact.solve(contact.initial_state(), normal_force=q, creepage=(0.0, 0.0, 0.0))
    delta_static = static.diagnostics.approach
    state = static.new_state
    f_static = np.array([0.0, 0.0, q])
    excitation = np.zeros(n_steps) if excitation is None else np.asarray(excitation, dtype=float)

    from interaction.contact.halfspace import HalfspaceContact
    from interaction.contact.point import PointContact
    from interaction.structures import ConvolutionStructure, ModalStructure

    structures_compiled = type(wheel) is ModalStructure and type(rail) is ConvolutionStructure
    if compiled and structures_compiled and isinstance(contact, PointContact):
        return _simulate_compiled(wheel, rail, contact, speed, q, (xi, eta, phi), n_steps, excitation, tolerance,
                                  max_iterations, runaway_factor, delta_static)
    if compiled and structures_compiled and isinstance(contact, HalfspaceContact) and contact.kind == "transient":
        return _simulate_compiled_halfspace(wheel, rail, contact, speed, q, (xi, eta, phi), n_steps, excitation,
                                            tolerance, max_iterations, runaway_factor, delta_static,
                                            static.new_state.pressure)
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

    steps = range(n_steps)
    if progress:
        from tqdm import tqdm

        steps = tqdm(steps, desc="simulate", unit="step", mininterval=1.0)
    for n in steps:
        hist_w = wheel.history()
        hist_r = rail.history()
        hist = hist_w + hist_r  # u_r = -(rail history + k0_r ΔF)
        rel_prev = u_w_prev - u_r_prev
        kwargs = {"compliance": series} if coupled else {}
        if coupled and n >= 2:
            force = 2.0 * force - force_before  # linear extrapolation: fewer passes
        def contact_at(trial):
            """The contact's solution for the inputs that the trial force gives (the map G)."""
            rel = hist + rest @ (trial - f_static)  # without the series part
            approach = delta_static - rel[2] + series[2] * q + excitation[n]
            imposed = (xi + (rel[0] - rel_prev[0]) / (dt * speed), eta + (rel[1] - rel_prev[1]) / (dt * speed), phi)
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
        out["creepage"][n] = (xi + ((u_w - u_w_prev) - (u_r - u_r_prev))[0] / (dt * speed),
                              eta + ((u_w - u_w_prev) - (u_r - u_r_prev))[1] / (dt * speed), phi)
        out["wheel_displacement"][n] = u_w
        out["rail_displacement"][n] = u_r
        out["wheel_velocity"][n] = (u_w - u_w_prev) / dt
        out["rail_velocity"][n] = (u_r - u_r_prev) / dt
        slip[n] = result.diagnostics.slip_fraction
        iterations[n] = it
        state = result.new_state
        wheel.commit(dF)
        rail.commit(dF)
        u_w_prev, u_r_prev = u_w, u_r
        force_before = out["force"][n - 1] if n >= 1 else f_static
    return SimulationResult(time=np.arange(n_steps) * dt, slip_fraction=slip, iterations=iterations,
                            static_approach=delta_static, **out)


NEWTON_AFTER = 20
"""Coupling iterations by plain fixed point before :func:`_newton_step` takes over (models without
series compliance): the fixed point contracts by the loop gain, which stick phases of a
stick/slip cycle can push above 1."""


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


def _outputs(n_steps):
    """Output arrays of the compiled loops."""
    names = ("force", "creepage", "wheel_displacement", "rail_displacement", "wheel_velocity", "rail_velocity")
    return {name: np.zeros((n_steps, 3)) for name in names}, np.zeros(n_steps), np.zeros(n_steps, dtype=np.int64)


def _simulate_compiled_halfspace(wheel, rail, contact, speed, load, creepage, n_steps, excitation, tolerance,
                                 max_iterations, runaway_factor, delta_static, static_pressure):
    """:func:`simulate` for transient half-space contact with the compiled loop of interaction/kernels.py."""
    from interaction.kernels import halfspace_contact_loop
    from squealcore.errors import InputError

    if np.any(wheel.state != 0) or np.any(rail.buffer != 0):
        raise ValueError("the compiled loop starts from rest: structures must be fresh")
    dt = wheel.time_step
    out, slip, iterations = _outputs(n_steps)
    failure = np.zeros(1, dtype=np.int64)
    work = np.zeros((n_steps, 2), dtype=np.int64)
    k, g = contact.kernels, contact.grid
    table_approach, table_force, table_pressure, table_displacement = contact.normal_table()
    failed = halfspace_contact_loop(
        np.ascontiguousarray(wheel.z), np.ascontiguousarray(wheel.weights), np.ascontiguousarray(wheel.k0),
        np.ascontiguousarray(rail.tail), np.ascontiguousarray(rail.k0), k.K11, k.K12, k.K22, k.K33, g.nx, g.ny,
        np.ascontiguousarray(contact.gap).ravel(), g.x, g.y, g.dx, g.dx * g.dy, float(contact.friction.static),
        float(contact.friction.kinetic), float(contact.tol), int(contact.max_sweeps), ANDERSON_DEPTH,
        table_approach, table_force, table_pressure, table_displacement, np.ascontiguousarray(static_pressure).ravel(), np.asarray(creepage, dtype=float), float(speed), float(dt),
        float(load), float(delta_static), np.ascontiguousarray(excitation, dtype=float), float(tolerance),
        int(max_iterations), float(runaway_factor), out["force"], out["creepage"], slip, out["wheel_displacement"],
        out["rail_displacement"], out["wheel_velocity"], out["rail_velocity"], iterations, work, failure)
    if failed >= 0:
        step = int(failed)
        details = {"iterations": int(iterations[step]), "force": out["force"][max(step - 1, 0)].tolist()}
        reason = int(failure[0])
        if reason == 3:
            raise InputError("contact.grid", f"step {step}: the contact area reaches the grid edge (normal force "
                             f"{out['force'][max(step - 1, 0), 2]:.0f} N before it); enlarge the grid")
        messages = {1: "normal contact problem did not converge", 2: "tangential contact problem did not converge",
                    4: "force not finite or runaway", 5: "coupling iteration did not converge"}
        raise SimulationDiverged(step, messages.get(reason, "failed"), details)
    return SimulationResult(time=np.arange(n_steps) * dt, slip_fraction=slip, iterations=iterations,
                            static_approach=delta_static, extra={"normal_iterations": work[:, 0], "sweeps": work[:, 1]},
                            **out)


def _simulate_compiled(wheel, rail, contact, speed, load, creepage, n_steps, excitation, tolerance, max_iterations,
                       runaway_factor, delta_static):
    """:func:`simulate` for point contact with the compiled loop of interaction/kernels.py."""
    from interaction.kernels import point_contact_loop

    if np.any(wheel.state != 0) or np.any(rail.buffer != 0):
        raise ValueError("the compiled loop starts from rest: structures must be fresh")
    dt = wheel.time_step
    out, slip, iterations = _outputs(n_steps)
    failed = point_contact_loop(
        np.ascontiguousarray(wheel.z), np.ascontiguousarray(wheel.weights), np.ascontiguousarray(wheel.k0),
        np.ascontiguousarray(rail.tail), np.ascontiguousarray(rail.k0), contact.kernel_constants(),
        np.asarray(creepage, dtype=float), float(speed), float(dt), float(load), float(delta_static),
        np.ascontiguousarray(excitation, dtype=float), float(tolerance), int(max_iterations), float(runaway_factor),
        NEWTON_AFTER, out["force"], out["creepage"], slip, out["wheel_displacement"], out["rail_displacement"],
        out["wheel_velocity"], out["rail_velocity"], iterations)
    if failed >= 0:
        raise SimulationDiverged(int(failed), "force not finite, runaway or coupling not converged",
                                 {"iterations": int(iterations[failed])})
    return SimulationResult(time=np.arange(n_steps) * dt, slip_fraction=slip, iterations=iterations,
                            static_approach=delta_static, **out)
