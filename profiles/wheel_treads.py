"""Wheel tread profiles: the shipped ones (registered by name), user profile files, a pure cone.

A wheel tread profile is a :class:`~profiles.curve.Profile` in the wheel frame: ``y`` from the
flange back (m), ``z`` radial height above the tape circle (m); file format in
:mod:`profiles.curve`. ``[wheel] tread_profile`` names one of :data:`TREAD_NAMES` or a profile
file; :func:`read_tread` reads it, for the wheel section (:func:`mesh.wheel_section.tread_profile`)
and so for the contact geometry, which takes the running surface from the wheel section.

**Adding a shipped tread profile**: put its two-column file under ``profiles/data/`` and add one
entry ``name -> file`` to :data:`TREADS`; ``[wheel] tread_profile = "<name>"`` then selects it
everywhere (its name joins the choices of the study schema).

The parametric 1:40 tread (``tread_profile = "parametric"``) is no file: its cone and flange are
drawn from the ``[wheel]`` dimensions by the wheel section (:mod:`mesh.wheel_section`), as one
piece of the section outline; :func:`contact_geometry.wheel_surface.parametric_wheel_profile`
resamples it for the contact search.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from squealcore.errors import InputError

from .curve import Profile, read_profile
from .s1002 import DATA_FILE as S1002_DATA_FILE

__all__ = ["TREADS", "TREAD_NAMES", "read_tread", "s1002_profile", "cone_profile"]

#: Shipped tread profiles: ``[wheel] tread_profile`` name -> data file (format of :mod:`profiles.curve`).
TREADS = {"S1002": S1002_DATA_FILE}
#: ``tread_profile`` values that name no file: the parametric cone and flange, then the shipped profiles.
TREAD_NAMES = ("parametric", *TREADS)


def read_tread(name: str, field: str = "wheel.tread_profile") -> Profile | None:
    """The tread profile ``name`` (a ``[wheel] tread_profile`` value); None for ``"parametric"``.

    Parameters
    ----------
    name : str
        ``"parametric"``, a key of :data:`TREADS` (the profile is named after it) or the path of a
        two-column profile file (named after the path).
    field : str
        Field named in error messages.

    Returns
    -------
    Profile or None

    Raises
    ------
    InputError
        Naming ``field``, the file and the problem (unreadable, not two numeric columns, too few
        points, non-monotonic or self-intersecting).
    """
    if name == "parametric":
        return None
    path = TREADS[name] if name in TREADS else Path(name)
    try:
        return read_profile(path, name=name if name in TREADS else str(path))
    except InputError as exc:
        raise InputError(field, f"{exc.field}: {exc.message}") from None


def s1002_profile() -> Profile:
    """The S1002 profile from the shipped data file ``profiles/data/s1002.txt``."""
    return read_profile(S1002_DATA_FILE, name="S1002 (profiles/data/s1002.txt)")


def cone_profile(conicity: float = 0.025, tape_offset: float = 0.070, width: float = 0.130,
                 step: float = 2e-4) -> Profile:
    """A pure cone without flange: ``z = -conicity (y - tape_offset)`` for y in [0, width] (m)."""
    y = np.arange(0.0, width + 0.5 * step, step)
    return Profile(y, -conicity * (y - tape_offset), f"cone 1:{1 / conicity:g}" if conicity else "cylinder")
