"""Which contact the Green's artefacts hold, and their layout versions.

``wheel_greens.h5`` and ``rail_greens.h5`` hold the structures at one contact only: the one the
study's ``contact.geometry`` selects (``"manual"``: the hand-set contact; ``"profiles"``: the
one computed from the profiles, ``contact_geometry.h5``). The root attribute
:data:`GEOMETRY_ATTRIBUTE` names it; a reader asking for the other one gets an
:class:`~squealcore.artefacts.ArtefactError` saying how to rebuild. This module imports no
physics, so that the stage graph (stages/engine.py) can read the versions without the solvers.
"""

from __future__ import annotations

from squealcore.artefacts import ArtefactError

WHEEL_GREENS_VERSION = 2
"""Schema version of ``wheel_greens.h5``; 2: the wheel models at the configured contact only
(version 1 held both contacts, the computed one under ``profiles/``)."""

RAIL_GREENS_VERSION = 3
"""Schema version of ``rail_greens.h5``; 3: the moving kernel at the configured contact only
(version 2 held both); 2: the moving kernel's frequency grids run to 8 / dt."""

GEOMETRY_ATTRIBUTE = "contact_geometry"
"""Root attribute of the Green's artefacts: the ``contact.geometry`` they were built for."""

GEOMETRY_KEY = "contact.geometry"
"""The dotted study key that selects the contact (hashed by the Green's stages)."""

DEFAULT_GEOMETRY = "profiles"
"""``contact.geometry`` of a study that does not set it (the schema default)."""


def study_geometry(study):
    """The ``contact.geometry`` of a study (``"manual"`` or ``"profiles"``)."""
    return str(study.get("contact", {}).get("geometry", DEFAULT_GEOMETRY))


def held_geometry(handle, wanted=None):
    """The contact an open Green's artefact holds, checked against the one a reader wants.

    Parameters
    ----------
    handle : h5py.File
        ``wheel_greens.h5`` or ``rail_greens.h5``, open.
    wanted : {"manual", "profiles"}, optional
        The contact the reader needs; None accepts the one held.

    Returns
    -------
    str
        The contact held.

    Raises
    ------
    ArtefactError
        If ``wanted`` is given and is not the contact held.
    """
    held = str(handle.attrs.get(GEOMETRY_ATTRIBUTE, ""))
    if wanted is not None and wanted != held:
        raise ArtefactError(f"{handle.filename}: holds the structure at the {held!r} contact, not at the "
                            f"{wanted!r} one (rebuild it with {GEOMETRY_KEY} = {wanted!r})")
    return held

#: The rail fit (``rail_fit.h5``, the ``rail-fit`` stage and the maps' fits at other rail
#: positions): artefact kind and layout version.
RAIL_FIT_SCHEMA, RAIL_FIT_VERSION = "rail_fit", 1
#: The keys of ``[map]`` the rail fit reads besides ``[rail]`` and ``[track]``.
RAIL_FIT_KEYS = ("map.rail_f_min", "map.rail_f_max", "map.rail_frequencies", "map.rail_pole_pairs",
                 "map.rail_iterations")
