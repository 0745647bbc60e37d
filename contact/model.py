"""The common interface of the contact models, called once (or several times) per time step.

A model is a solver object; its state is an explicit immutable value. ``solve`` is pure with
respect to the state: calling it twice from the same state with the same input returns the
same result, so a time-domain interaction can iterate on the structural coupling within a
step and then commit by keeping ``result.new_state``::

    model = create_model("halfspace", ...)      # or "point" (contact/factory.py)
    state = model.initial_state()
    for n in range(nt):
        for it in range(k):                      # coupling iterations
            res = model.solve(state, approach=d, creepage=(xi, eta, phi))
        state = res.new_state                    # commit

Forces are those of the rail on the wheel in the contact frame (x rolling, y lateral,
z up), ``force[2] > 0`` in compression. Lift-off (approach <= 0 or normal force <= 0)
returns zero force.

A model may also hand the interaction a compiled time loop with its bundle
(:meth:`ContactModel.compiled_path`, :class:`CompiledPath`); the Python ``solve`` and the
compiled loop use the same bundles, so the contact law lives in one place per path.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any, NamedTuple, Protocol

import numpy as np

__all__ = ["Diagnostics", "ContactFields", "ContactResult", "ContactModel", "CompiledPath", "freeze"]


def freeze(array) -> np.ndarray:
    """Return a read-only float copy of ``array`` (state arrays are immutable)."""
    out = np.array(array, dtype=float, copy=True)
    out.setflags(write=False)
    return out


class Diagnostics(NamedTuple):
    """Solver diagnostics of one contact solution (an immutable named tuple).

    Attributes
    ----------
    n_contact, n_stick, n_slip : int
        Elements in contact, in stick and in slip (point model: 1 element; stick if the
        force is below the friction bound).
    slip_fraction : float
        n_slip / n_contact (point model: ratio |F_t| / (mu Fn)) (-).
    iterations : int
        Normal iterations plus tangential sweeps.
    residual : float
        Final relative residual of the iterative solvers (-).
    pmax : float
        Maximum pressure (Pa).
    approach : float
        Approach of the bodies (m).
    """

    n_contact: int
    n_stick: int
    n_slip: int
    slip_fraction: float
    iterations: int
    residual: float
    pmax: float
    approach: float


@dataclass(frozen=True)
class ContactFields:
    """Traction fields on the grid of the half-space model.

    Attributes
    ----------
    x, y : ndarray (nx,), (ny,)
        Element centres (m).
    pressure : ndarray (nx, ny)
        Pressure (Pa).
    traction : ndarray (nx, ny, 2)
        Tangential traction on the wheel (Pa).
    status : int8 ndarray (nx, ny)
        0 exterior, 1 stick, 2 slip.
    """

    x: np.ndarray
    y: np.ndarray
    pressure: np.ndarray
    traction: np.ndarray
    status: np.ndarray


class ContactResult(NamedTuple):
    """Result of one contact solution (an immutable named tuple).

    Attributes
    ----------
    force : ndarray (3,)
        Force of the rail on the wheel in the contact frame (N).
    spin_moment : float
        Moment about z of the tangential tractions (N m).
    new_state : Any
        Model state after this step (commit it to advance).
    diagnostics : Diagnostics
    fields : ContactFields or None
        Traction fields (half-space model only).
    """

    force: np.ndarray
    spin_moment: float
    new_state: Any
    diagnostics: Diagnostics
    fields: ContactFields | None = None


@dataclass(frozen=True)
class CompiledPath:
    """A contact model's compiled time loop of the interaction, with the model's bundle.

    Attributes
    ----------
    loop : numba dispatcher
        ``loop(structures, contact, coupling, excitation, state, out, start, stop) -> int``
        (the loop.py of the model's folder): runs the steps ``[start, stop)`` on the bundles of
        interaction/bundles.py, carrying everything in ``state`` (a ``LoopState`` whose
        ``contact`` is :attr:`state`); returns -1, or the failing step with the reason in
        ``state.failure[0]``.
    contact : NamedTuple
        The model's bundle (``PointLaw``, ``HalfspaceInputs``; the bundles.py of its folder).
    state : Any
        The model's part of the carried state at static equilibrium (fresh arrays for one run).
    snapshot : callable
        ``snapshot(state) -> ContactFields or None``: the contact fields of the committed state
        in ``state`` (the model's part), or None for a model without fields.
    failures : mapping of int to str
        Messages of the model's own failure codes (``str.format`` fields: ``force``, the normal
        force of the step before, N); codes in :attr:`input_failures` are bad input (the named
        configuration field), the others a diverged simulation.
    input_failures : mapping of int to str
        Failure codes that mean bad input, with the field to name.
    work : tuple of str
        Names of the columns of the loop's solver-work output reported in ``result.extra``.
    """

    loop: Callable
    contact: Any
    state: Any
    snapshot: Callable[[Any], ContactFields | None]
    failures: Mapping[int, str] = field(default_factory=dict)
    input_failures: Mapping[int, str] = field(default_factory=dict)
    work: tuple = ()


class ContactModel(Protocol):
    """What the interaction needs of a contact model."""

    time_step: float
    """Time step (s) of a transient step: dx / speed for the half-space model."""

    def initial_state(self) -> Any:
        """State before the first step (unloaded, undeformed)."""

    def solve(self, state, *, approach=None, normal_force=None, creepage=(0.0, 0.0, 0.0),
              shift=None) -> ContactResult:
        """Solve one step from ``state`` (not modified)."""

    def compiled_path(self, static: ContactResult) -> CompiledPath | None:
        """The compiled time loop for this model with its bundle, or None (the interaction then
        runs its Python loop). ``static`` is the solution at static equilibrium under the wheel
        load from :meth:`initial_state` (its ``new_state`` is the state before the first step)."""

