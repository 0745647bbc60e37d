"""Typed bundles of the interaction's compiled time loops (numba-compatible named tuples).

The compiled loops (contact/*/loop.py, interaction/loop_steps.py) take a few bundles instead of dozens of
positional arguments (contact/halfspace/bundles.py explains the idea; the contact models
bring their own bundles): the structures (:class:`Structures`), the coupling settings
(:class:`Coupling`), the output histories (:class:`Histories`) and the state carried from one
step to the next (:class:`LoopState`). The loops run a range of steps ``[start, stop)`` and
leave every carried quantity in the :class:`LoopState`, so that a run can be split into chunks
without changing one bit of its result.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np

__all__ = ["Structures", "Coupling", "Histories", "LoopState", "histories", "loop_state"]


class Structures(NamedTuple):
    """Wheel (pole-residue recursion) and rail (convolution) at the contact point.

    Attributes
    ----------
    wheel_z : (m,) complex ndarray
        ``exp(p Δt)`` of the wheel's poles.
    wheel_weights : (m, 3, 3) complex ndarray
        Recursion weights of the wheel (fe.greens.recursion_coefficients), m/N.
    wheel_k0 : (3, 3) ndarray
        Instantaneous compliance of the wheel, m/N.
    rail_rows : (3, 3 nk) ndarray
        Rail kernel samples 1..nk (the near part of the kernel, nk at most
        ``interaction.structures.RAIL_NEAR_STEPS``; the far part is summed by FFT, block by block,
        into ``LoopState.far``), m/N, as one contiguous row per displacement direction:
        ``rail_rows[i, 3 q + j]`` is sample q + 1 of the displacement i due to the force j.
    rail_k0 : (3, 3) ndarray
        Instantaneous compliance of the rail, m/N.
    """

    wheel_z: np.ndarray
    wheel_weights: np.ndarray
    wheel_k0: np.ndarray
    rail_rows: np.ndarray
    rail_k0: np.ndarray


class Coupling(NamedTuple):
    """Settings of the implicit coupling of a run (interaction/simulate.py).

    Attributes
    ----------
    creepage : (3,) ndarray
        Imposed creepages (ξ, η, φ); φ in 1/m.
    speed : float
        Rolling speed, m/s.
    time_step : float
        s.
    load : float
        Static wheel load Q, N.
    static_approach : float
        Approach at static equilibrium, m.
    tolerance : float
        Convergence of the coupling relative to the load (-).
    max_iterations : int
        Coupling iterations per step before the run fails.
    runaway_factor : float
        A force larger than this times the load counts as divergence (-).
    """

    creepage: np.ndarray
    speed: float
    time_step: float
    load: float
    static_approach: float
    tolerance: float
    max_iterations: int
    runaway_factor: float


class Histories(NamedTuple):
    """Output arrays of a run (filled step by step).

    Attributes
    ----------
    force, creepage, wheel_displacement, rail_displacement, wheel_velocity, rail_velocity : (nt, 3) ndarray
        As in :class:`~interaction.simulate.SimulationResult`.
    slip_fraction : (nt,) ndarray
    iterations : (nt,) int64 ndarray
        Coupling iterations per step.
    work : (nt, 2) int64 ndarray
        Solver work per step (half-space model: normal-solver iterations and tangential sweeps).
    """

    force: np.ndarray
    creepage: np.ndarray
    slip_fraction: np.ndarray
    wheel_displacement: np.ndarray
    rail_displacement: np.ndarray
    wheel_velocity: np.ndarray
    rail_velocity: np.ndarray
    iterations: np.ndarray
    work: np.ndarray


def histories(n_steps) -> Histories:
    """Zeroed output arrays for ``n_steps`` steps."""
    def three():
        return np.zeros((n_steps, 3))

    return Histories(three(), three(), np.zeros(n_steps), three(), three(), three(), three(),
                     np.zeros(n_steps, np.int64), np.zeros((n_steps, 2), np.int64))


class LoopState(NamedTuple):
    """Everything a compiled loop carries from one step to the next (arrays, written in place).

    Attributes
    ----------
    wheel : (m, 3) complex ndarray
        Recursion states of the wheel.
    rail : (2 nk, 3) ndarray
        Force deviations of the rail's convolution, each held twice (newest first from ``head``).
    head : (1,) int64 ndarray
        Start of the newest force in ``rail``.
    wheel_previous, rail_previous : (3,) ndarray
        Displacements of the last step, m.
    force : (3,) ndarray
        Force of the last step (the first guess of the next), N.
    force_before : (3,) ndarray
        Force of the step before the last, N (linear extrapolation of the half-space loop).
    gamma : (1,) ndarray
        dFy/dFz of the last step (half-space loop).
    failure : (1,) int64 ndarray
        Reason of a failure (0 none; interaction/simulate.py lists the codes).
    contact : bundle
        The contact model's carried state (point model: (6,) relaxation states; half-space
        model: :class:`~contact.halfspace.bundles.ElementStates`).
    far : (nk, 3) ndarray
        The rail's displacement (m) due to the forces beyond its near kernel, for the steps
        ``far_start[0] + k``, k < nk (interaction.structures.RailFarField fills it per block).
    far_start : (1,) int64 ndarray
        First step of the block that ``far`` holds.
    """

    wheel: np.ndarray
    rail: np.ndarray
    head: np.ndarray
    wheel_previous: np.ndarray
    rail_previous: np.ndarray
    force: np.ndarray
    force_before: np.ndarray
    gamma: np.ndarray
    failure: np.ndarray
    contact: Any
    far: np.ndarray
    far_start: np.ndarray


def loop_state(structures: Structures, load, contact) -> LoopState:
    """The state at static equilibrium under ``load`` (N), structures at rest, with the contact's state."""
    f_static = np.array([0.0, 0.0, float(load)])
    near = structures.rail_rows.shape[1] // 3
    return LoopState(np.zeros((structures.wheel_z.shape[0], 3), np.complex128),
                     np.zeros((2 * near, 3)), np.zeros(1, np.int64), np.zeros(3),
                     np.zeros(3), f_static.copy(), f_static.copy(), np.zeros(1), np.zeros(1, np.int64), contact,
                     np.zeros((near, 3)), np.zeros(1, np.int64))
