"""The contact models, registered once.

Each model registers here what the rest of the product asks of it: its name (``contact.model``),
how a study builds it for a time-domain case, how the stability screen linearises it, how the
stand-alone contact command builds it from a case file, and what it can do (problem kinds, traction
fields, a gap given as a file). Stages, the screen, the maps' confirmations, the exports, the
contact command and the study schema look the models up here and never branch on a model's name;
a model joins with one :func:`register` call in its own folder's ``__init__.py``
(``contact/halfspace/``, ``contact/point/``), like meshio's format registry; the package's
``__init__`` imports the folders of the models it ships, so importing this module registers them.

The hooks are named ``"module:function"`` and imported at first use: the models' modules compile
numba kernels and are not imported by the schema (a callable may be given instead, e.g. by a
test or a plugin). Hook signatures:

* ``build(setup: ContactSetup) -> ContactModel`` — the transient model of a case;
* ``linearise(setup: ContactSetup, normal_force, creepage) -> stability.linearised_contact.LinearisedContact``;
* ``command(setup: ContactSetup, grid, gap, kind) -> ContactModel`` — the contact command's
  model (``grid``/``gap`` of the case file, ``kind`` one of the model's ``kinds``).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from squealcore.errors import InputError
from squealcore.hooks import resolve_hook

__all__ = ["ContactSetup", "ContactModelSpec", "register", "contact_model_names", "contact_spec", "DEFAULT_MODEL"]


@dataclass(frozen=True)
class ContactSetup:
    """What a contact model is built from (SI units).

    Attributes
    ----------
    material : contact.params.Material
    friction : contact.params.Friction
    hertz : contact.hertz.HertzContact or None
        The Hertz solution at the static normal force (None: the contact command's gap file).
    speed : float
        Rolling speed, m/s.
    time_step : float or None
        s (None: the model's own choice, the contact command's default).
    tolerance : float
        Solver tolerance relative to the load and the traction scale (-).
    options : Any
        The study's ``[contact]`` section (:class:`contact.params.ContactParams`:
        e.g. ``grid_dy``, ``point_tangential``), or None for the contact command.
    grid_load_factor : float
        A grid-based model covers the Hertz patch at this multiple of the normal force.
    """

    material: Any
    friction: Any
    hertz: Any
    speed: float
    time_step: float | None
    tolerance: float = 1e-6
    options: Any = None
    grid_load_factor: float = 3.0


@dataclass(frozen=True)
class ContactModelSpec:
    """One contact model and what the product asks of it.

    Attributes
    ----------
    name : str
        Its ``contact.model`` value.
    doc : str
        One sentence for the study's parameter documentation.
    model_class : str or callable
        The model's class (``"module:Class"``), for :func:`contact.factory.create_model`.
    build, linearise, command : str or callable
        Hooks (see the module docstring): ``"module:function"`` or a callable.
    kinds : tuple of str
        Problems the contact command may give it (``steady``, ``transient``, ``shift``).
    traction_fields : bool
        Its solutions carry traction fields (``export case --steps``).
    solves_on_grid : bool
        It discretises the patch on a grid (a gap file may replace the Hertz geometry; the contact
        command warns on a coarse grid).
    fast : bool
        Cheap per time step (a point model rather than a grid): the maps' time-domain
        confirmations run the fast models first.
    """

    name: str
    doc: str
    model_class: str | Callable
    build: str | Callable
    linearise: str | Callable
    command: str | Callable
    kinds: tuple = ("steady", "transient")
    traction_fields: bool = False
    solves_on_grid: bool = False
    fast: bool = False

    def hook(self, which: str) -> Callable:
        """The hook ``which`` (``"model_class"``, ``"build"``, ``"linearise"``, ``"command"``) as a callable."""
        return resolve_hook(getattr(self, which))


_REGISTRY: dict[str, ContactModelSpec] = {}


def register(spec: ContactModelSpec) -> ContactModelSpec:
    """Add ``spec`` to the registry (its name must be new); returns it."""
    if spec.name in _REGISTRY:
        raise ValueError(f"contact model {spec.name!r} is registered already")
    _REGISTRY[spec.name] = spec
    return spec


def contact_model_names() -> tuple[str, ...]:
    """Names of the registered contact models (the ``contact.model`` choices), in order."""
    return tuple(_REGISTRY)


def contact_spec(name: str, field: str = "contact.model") -> ContactModelSpec:
    """The registered model ``name``; :class:`InputError` naming ``field`` and the choices otherwise."""
    try:
        return _REGISTRY[name]
    except (KeyError, TypeError):
        raise InputError(field, f"must be one of {', '.join(repr(n) for n in _REGISTRY)}, got {name!r}") from None


DEFAULT_MODEL = "halfspace"
"""The contact model of the paper and of the default study."""
