"""Contact models by name (kept apart from model.py, which the models themselves import)."""

from __future__ import annotations

from squealcore.errors import InputError

from .halfspace import HalfspaceContact
from .model import ContactModel
from .point import PointContact

__all__ = ["create_model"]


def create_model(name: str, **kwargs) -> ContactModel:
    """Build a contact model by name: ``"halfspace"`` or ``"point"``.

    Keyword arguments go to :class:`~interaction.contact.halfspace.HalfspaceContact` or
    :class:`~interaction.contact.point.PointContact`.
    """
    if name == "halfspace":
        return HalfspaceContact(**kwargs)
    if name == "point":
        return PointContact(**kwargs)
    raise InputError("model", f"must be 'halfspace' or 'point', got {name!r}")
