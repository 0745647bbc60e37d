"""How the wheel models are built: the :class:`WheelState` they are built from and the paper's three.

The models are registered in :mod:`interaction.wheel_models` (name, labels, styles, and these
functions as its hooks, named ``"fe.wheel_models:<function>"`` so that the registry is light to
import). Each hook takes a :class:`WheelState`:

* :func:`stationary_poles` — the wheel's modes at rest (:func:`fe.greens.modal_poles_residues`);
* :func:`moving_load_poles` (and :func:`moving_load_kernel`) — a stationary wheel with the load
  travelling round it (:mod:`fe.moving_load`);
* :func:`eulerian_poles` — the rotating wheel in Eulerian modal coordinates (:mod:`fe.rotation`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from fe import moving_load
from fe.greens import modal_poles_residues

__all__ = ["WheelState", "stationary_poles", "moving_load_poles", "moving_load_kernel", "eulerian_poles"]


@dataclass(frozen=True)
class WheelState:
    """What the wheel models are built from, at one speed and contact point (SI units).

    Attributes
    ----------
    frequency : (m,) ndarray
        Natural frequencies of the wheel at rest, Hz.
    damping_ratio : (m,) ndarray
        Modal damping ratios (-).
    contact_shape : (m, 3) ndarray
        Mass-normalised mode shapes at the contact point, contact frame, m/√kg.
    spin : float
        Rotation rate, rad/s (speed over rolling radius).
    eulerian : fe.rotation.EulerianModel
        The spinning wheel's modal model at the contact point.
    switches : dict
        ``gyroscopic``, ``convective``, ``centrifugal`` terms of the Eulerian model (bool).
    axisymmetric : dict
        The harmonics of the exact moving-load path: ``frequency`` (Hz), ``damping_ratio``,
        ``harmonic`` (n), ``family``, ``contact_amplitude`` (m/√kg).
    ring : fe.moving_load.RingInterpolant or None
        The interpolated moving-load path's ring through the contact (None: the exact path).
    """

    frequency: np.ndarray
    damping_ratio: np.ndarray
    contact_shape: np.ndarray
    spin: float
    eulerian: Any
    switches: dict
    axisymmetric: dict
    ring: Any = None



def stationary_poles(state: WheelState):
    """The wheel at rest: its modes' poles and residues at the contact (:func:`fe.greens.modal_poles_residues`)."""
    return modal_poles_residues(state.frequency, state.damping_ratio, state.contact_shape)


def moving_load_poles(state: WheelState):
    """The stationary wheel with the load moving round it (:mod:`fe.moving_load`): the exact harmonic
    path, or the interpolated ring path when ``state.ring`` is set."""
    if state.ring is None:
        axi = state.axisymmetric
        return moving_load.moving_poles_residues_axisymmetric(axi["frequency"], axi["damping_ratio"], axi["harmonic"],
                                                              axi["family"], axi["contact_amplitude"], state.spin)
    return moving_load.moving_poles_residues_interpolated(state.ring, state.frequency, state.damping_ratio, state.spin)


def moving_load_kernel(state: WheelState, time_step, n_samples):
    """The interpolated path's discrete Green's function (m/N; no exact recursion: the time loop
    convolves with it), or None on the exact path (its poles' recursion is exact)."""
    if state.ring is None:
        return None
    return moving_load.moving_kernel_quadrature(state.ring, state.frequency, state.damping_ratio, state.spin,
                                                time_step, n_samples)


def eulerian_poles(state: WheelState):
    """The rotating wheel in Eulerian modal coordinates (:mod:`fe.rotation`) at ``state.spin``."""
    return state.eulerian.poles_residues(state.spin, **state.switches)
