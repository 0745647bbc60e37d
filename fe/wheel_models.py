"""The wheel models of the interaction, registered once.

A wheel model turns the wheel's modes at the contact point into the poles and residues of the
wheel's receptance there (the :mod:`fe.greens` form), at one speed. The three of the paper are
registered here:

* ``stationary`` — the wheel's modes at rest (:func:`fe.greens.modal_poles_residues`), the
  reference the others are compared with;
* ``moving_load`` — a stationary wheel with the load travelling round it
  (:mod:`fe.moving_load`: the exact harmonic path, or the interpolated ring path of the 3D mesh,
  which has no exact recursion and brings its own discrete kernel);
* ``eulerian`` — the rotating wheel in Eulerian modal coordinates (:mod:`fe.rotation`).

Everything else — the study schema's choices, the wheel-greens stage, the screen, the maps, the
exports, the report and the figures — takes the models from :func:`wheel_models`; a fourth model
joins with one :func:`register` call (like meshio's format registry), and nothing else names a
model. A model's hooks receive a :class:`WheelState`, the quantities every model is built from at
one speed and contact point.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from fe import moving_load
from fe.greens import modal_poles_residues

__all__ = ["WheelState", "WheelModel", "register", "wheel_models", "wheel_model", "wheel_model_names",
           "REFERENCE", "rotating_names"]


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


@dataclass(frozen=True)
class WheelModel:
    """One wheel model and how it is built.

    Attributes
    ----------
    name : str
        Its name in study files, case ids and artefacts (``simulation.wheel_model``).
    label : str
        How figures and the report name it.
    short_label : str
        Its short name in tables and legends of the wheel's receptances ("moving load").
    rotating : bool
        It models the wheel's rotation (it is compared with the reference model).
    poles_residues : callable
        ``poles_residues(state) -> (poles rad/s, residues m/(N s))`` for a :class:`WheelState`.
    kernel : callable or None
        ``kernel(state, time_step, n_samples) -> (n, 3, 3) m/N`` for a model whose discrete
        Green's function is not the recursion of its poles (it then returns the kernel and the
        time loop convolves with it), else None; may return None for a state that has a
        recursion after all.
    curve_style : dict
        matplotlib line properties of its curves in the interaction's figures (``label`` included).
    spectrum_style : tuple
        (colour, line style) of its spectra in the radiation figure.
    receptance_style : dict
        matplotlib line properties of its receptance and Campbell curves (:mod:`fe.plots`).
    """

    name: str
    label: str
    short_label: str
    rotating: bool
    poles_residues: Callable
    kernel: Callable | None = None
    curve_style: dict = field(default_factory=dict)
    spectrum_style: tuple = ("k", "-")
    receptance_style: dict = field(default_factory=dict)


_REGISTRY: dict[str, WheelModel] = {}


def register(model: WheelModel) -> WheelModel:
    """Add ``model`` to the registry (its name must be new); returns it."""
    if model.name in _REGISTRY:
        raise ValueError(f"wheel model {model.name!r} is registered already")
    _REGISTRY[model.name] = model
    return model


def wheel_models() -> tuple[WheelModel, ...]:
    """The registered wheel models, the reference first, in the order of registration."""
    return tuple(_REGISTRY.values())


def wheel_model_names() -> tuple[str, ...]:
    """Names of the registered wheel models (the study schema's choices), in order."""
    return tuple(_REGISTRY)


def wheel_model(name: str) -> WheelModel:
    """The registered model ``name`` (KeyError naming the known ones if there is none)."""
    try:
        return _REGISTRY[name]
    except KeyError:
        raise KeyError(f"no wheel model {name!r}; known: {', '.join(_REGISTRY)}") from None


def rotating_names() -> tuple[str, ...]:
    """Names of the models that include the wheel's rotation (compared with :data:`REFERENCE`)."""
    return tuple(m.name for m in _REGISTRY.values() if m.rotating)


# --------------------------------------------------------------------------- the paper's three models

def _stationary(state: WheelState):
    return modal_poles_residues(state.frequency, state.damping_ratio, state.contact_shape)


def _moving_load(state: WheelState):
    if state.ring is None:
        axi = state.axisymmetric
        return moving_load.moving_poles_residues_axisymmetric(axi["frequency"], axi["damping_ratio"], axi["harmonic"],
                                                              axi["family"], axi["contact_amplitude"], state.spin)
    return moving_load.moving_poles_residues_interpolated(state.ring, state.frequency, state.damping_ratio, state.spin)


def _moving_load_kernel(state: WheelState, time_step, n_samples):
    # the interpolated moving Green's function has no exact recursion: the time loop convolves
    if state.ring is None:
        return None
    return moving_load.moving_kernel_quadrature(state.ring, state.frequency, state.damping_ratio, state.spin,
                                                time_step, n_samples)


def _eulerian(state: WheelState):
    return state.eulerian.poles_residues(state.spin, **state.switches)


STATIONARY = register(WheelModel(
    "stationary", "stationary wheel", "stationary", False, _stationary,
    curve_style=dict(color="0.25", ls="--", label="stationary wheel"), spectrum_style=("k", "-"),
    receptance_style=dict(color="0.2", ls="--", lw=1.0)))
register(WheelModel(
    "moving_load", "stationary wheel, moving load", "moving load", True, _moving_load, kernel=_moving_load_kernel,
    curve_style=dict(color="0.65", ls="-", label="stationary wheel, moving load"), spectrum_style=("tab:blue", "--"),
    receptance_style=dict(color="0.6", ls="-", lw=1.6)))
register(WheelModel(
    "eulerian", "rotating wheel (Eulerian)", "Eulerian", True, _eulerian,
    curve_style=dict(color="k", ls="-", label="rotating wheel (Eulerian)"), spectrum_style=("tab:red", ":"),
    receptance_style=dict(color="k", ls="-", lw=0.8)))

REFERENCE = STATIONARY.name
"""The model the rotating ones are compared with (the wheel at rest)."""
