"""Contact models by name (kept apart from model.py, which the models themselves import)."""

from __future__ import annotations

from contact.model import ContactModel
from contact.registry import contact_spec

__all__ = ["create_model"]


def create_model(name: str, **kwargs) -> ContactModel:
    """Build a contact model by name with its class's keyword arguments.

    ``"halfspace"``: :class:`~contact.halfspace.model.HalfspaceContact`; ``"point"``:
    :class:`~contact.point.model.PointContact` (the classes of the registry's models,
    :mod:`contact.registry`).
    """
    return contact_spec(name, "model").hook("model_class")(**kwargs)
