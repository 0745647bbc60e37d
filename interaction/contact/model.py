"""The common interface of the contact models, called once (or several times) per time step.

A model is a solver object; its state is an explicit immutable value. ``solve`` is pure with
respect to the state: calling it twice from the same state with the same input returns the
same result, so a time-domain interaction can iterate on the structural coupling within a
step and then commit by keeping ``result.new_state``::

    model = create_model("halfspace", ...)      # or "point"
    state = model.initial_state()
    for n in range(nt):
        for it in range(k):                      # coupling iterations
            res = model.solve(state, approach=d, creepage=(xi, eta, phi))
        state = res.new_state                    # commit

Forces are those of the rail on the wheel in the contact frame (x rolling, y lateral,
z up), ``force[2] > 0`` in compression. Lift-off (approach <= 0 or normal force <= 0)
returns zero force.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, NamedTuple, Protocol

import numpy as np

__all__ = ["Diagnostics", "ContactFields", "ContactResult", "ContactModel", "create_model",
           "freeze"]


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


class ContactModel(Protocol):
    """What the interaction needs of a contact model."""

    time_step: float
    """Time step (s) of a transient step: dx / speed for the half-space model."""

    def initial_state(self) -> Any:
        """State before the first step (unloaded, undeformed)."""

    def solve(self, state, *, approach=None, normal_force=None, creepage=(0.0, 0.0, 0.0),
              shift=None) -> ContactResult:
        """Solve one step from ``state`` (not modified)."""


def create_model(name: str, **kwargs) -> ContactModel:
    """Build a contact model by name: ``"halfspace"`` or ``"point"``.

    Keyword arguments go to :class:`~interaction.contact.halfspace.HalfspaceContact` or
    :class:`~interaction.contact.point.PointContact`.
    """
    from squealcore.errors import InputError

    if name == "halfspace":
        from .halfspace import HalfspaceContact

        return HalfspaceContact(**kwargs)
    if name == "point":
        from .point import PointContact

        return PointContact(**kwargs)
    raise InputError("model", f"must be 'halfspace' or 'point', got {name!r}")
