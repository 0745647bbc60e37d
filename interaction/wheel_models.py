"""The wheel models of the interaction, registered once.

A wheel model turns the wheel's modes at the contact point into the poles and residues of the
wheel's receptance there (the :mod:`fe.greens` form), at one speed. The three of the paper are
registered here (their code is in :mod:`fe.wheel_models`):

* ``stationary`` — the wheel's modes at rest, the reference the others are compared with;
* ``moving_load`` — a stationary wheel with the load travelling round it (the exact harmonic path,
  or the interpolated ring path of the 3D mesh, which has no exact recursion and brings its own
  discrete kernel);
* ``eulerian`` — the rotating wheel in Eulerian modal coordinates.

Everything else — the study schema's choices, the wheel-greens stage, the screen, the maps, the
exports, the report and the figures — takes the models from :func:`wheel_models`; a fourth model
joins with one :func:`register` call (like meshio's format registry), and nothing else names a
model (``tests/test_imports.py``). The hooks are ``"module:function"`` names imported at first use
(or callables), so that the schema and the contact command can read the names without importing
the finite elements.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

from squealcore.hooks import resolve_hook

__all__ = ["WheelModel", "register", "wheel_models", "wheel_model", "wheel_model_names", "REFERENCE",
           "rotating_names"]


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
    build : str or callable
        ``build(state) -> (poles rad/s, residues m/(N s))`` for a :class:`fe.wheel_models.WheelState`
        (``"module:function"``, imported at first use, or a callable); :meth:`poles_residues`.
    kernel_hook : str, callable or None
        ``kernel(state, time_step, n_samples) -> (n, 3, 3) m/N`` for a model whose discrete
        Green's function is not the recursion of its poles (it then returns the kernel and the
        time loop convolves with it), else None; may return None for a state that has a
        recursion after all; :meth:`kernel`.
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
    build: str | Callable
    kernel_hook: str | Callable | None = None
    curve_style: dict = field(default_factory=dict)
    spectrum_style: tuple = ("k", "-")
    receptance_style: dict = field(default_factory=dict)

    def poles_residues(self, state):
        """Poles (rad/s) and residues (m/(N s)) of the model for a :class:`fe.wheel_models.WheelState`."""
        return resolve_hook(self.build)(state)

    def kernel(self, state, time_step, n_samples):
        """The model's own discrete Green's function (m/N), or None where its poles' recursion serves."""
        return None if self.kernel_hook is None else resolve_hook(self.kernel_hook)(state, time_step, n_samples)


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


STATIONARY = register(WheelModel(
    "stationary", "stationary wheel", "stationary", False, "fe.wheel_models:stationary_poles",
    curve_style=dict(color="0.25", ls="--", label="stationary wheel"), spectrum_style=("k", "-"),
    receptance_style=dict(color="0.2", ls="--", lw=1.0)))
register(WheelModel(
    "moving_load", "stationary wheel, moving load", "moving load", True, "fe.wheel_models:moving_load_poles",
    kernel_hook="fe.wheel_models:moving_load_kernel",
    curve_style=dict(color="0.65", ls="-", label="stationary wheel, moving load"), spectrum_style=("tab:blue", "--"),
    receptance_style=dict(color="0.6", ls="-", lw=1.6)))
register(WheelModel(
    "eulerian", "rotating wheel (Eulerian)", "Eulerian", True, "fe.wheel_models:eulerian_poles",
    curve_style=dict(color="k", ls="-", label="rotating wheel (Eulerian)"), spectrum_style=("tab:red", ":"),
    receptance_style=dict(color="k", ls="-", lw=0.8)))

REFERENCE = STATIONARY.name
"""The model the rotating ones are compared with (the wheel at rest)."""
