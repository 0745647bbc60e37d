"""Layout of the contact-geometry artefact ``contact_geometry.h5``: writing and reading.

Written by the ``contact-geometry`` stage (stages/geometry.py); schema ``contact_geometry``,
version 1; every dataset has a ``units`` attribute:

``operating/<quantity>`` (k,)
    The k = 1 or 2 contacts at ``operating.lateral_displacement`` (slot 0, the smallest gap,
    first), one dataset per field of :class:`contact_geometry.ContactPoint`
    (``lateral_displacement``, ``n_contacts`` scalars).
``table/displacement`` (n,) m, ``table/n_contacts`` (n,), and (n, 2) per slot (NaN in an unused
    slot): ``y_wheel``, ``y_rail`` m, ``rolling_radius`` m, ``contact_angle`` rad,
    ``curvature_long``, ``curvature_lat`` 1/m, ``separation`` m, ``semi_axis_a``, ``semi_axis_b``
    m, ``normal_force`` N, ``spin`` 1/m (:class:`contact_geometry.ContactTable`).
``wheelset/displacement`` (m) and ``wheelset/rolling_radius_difference`` (m), dr = r(+y) - r(-y);
    ``wheelset/equivalent_conicity`` (1) at ``wheelset/conicity_amplitude`` (m).
``profiles/wheel``, ``profiles/rail`` (m, 2) (y, z) m, attribute ``name``; ``profiles/nominal_radius``,
    ``profiles/flange_back``, ``profiles/rail_pivot_height`` m, ``profiles/rail_tilt`` rad (the
    :class:`contact_geometry.WheelRailPair`).
"""

from __future__ import annotations

from dataclasses import fields

import numpy as np

from profiles.curve import Profile
from squealcore.artefacts import add_dataset, open_artefact, read_dataset

from .contact_point import ContactPoint
from .contact_search import ContactTable, WheelRailPair
from .study import StudyGeometry, main_contact

__all__ = ["SCHEMA", "VERSION", "write_geometry", "read_operating_contacts", "read_operating_contact", "read_table",
           "read_pair", "read_wheelset"]

SCHEMA, VERSION = "contact_geometry", 1

#: Units of the ContactPoint fields and of the ContactTable arrays.
POINT_UNITS = {"lateral_displacement": "m", "wheel_lateral": "m", "rail_lateral": "m", "rail_section_lateral": "m",
               "rail_section_height": "m", "rolling_radius": "m", "contact_angle": "rad", "rail_section_angle": "rad",
               "curvature_long": "1/m", "curvature_lat": "1/m", "semi_axis_a": "m", "semi_axis_b": "m",
               "normal_force": "N", "spin": "1/m", "n_contacts": ""}
TABLE_UNITS = {"displacement": "m", "n_contacts": "", "y_wheel": "m", "y_rail": "m", "rolling_radius": "m",
               "contact_angle": "rad", "curvature_long": "1/m", "curvature_lat": "1/m", "separation": "m",
               "semi_axis_a": "m", "semi_axis_b": "m", "normal_force": "N", "spin": "1/m"}
_SCALARS = ("lateral_displacement", "n_contacts")


def write_geometry(f, geometry: StudyGeometry) -> None:
    """Write the datasets of the layout (module docstring) into an open artefact ``f``."""
    pair, table = geometry.pair, geometry.table
    for name, units in POINT_UNITS.items():
        values = [getattr(c, name) for c in geometry.operating]
        add_dataset(f, f"operating/{name}", values[0] if name in _SCALARS else np.asarray(values, float), units)
    for name, units in TABLE_UNITS.items():
        add_dataset(f, f"table/{name}", getattr(table, name), units)
    add_dataset(f, "wheelset/displacement", geometry.dr_displacement, "m")
    add_dataset(f, "wheelset/rolling_radius_difference", geometry.dr, "m")
    add_dataset(f, "wheelset/equivalent_conicity", geometry.equivalent_conicity, "1")
    add_dataset(f, "wheelset/conicity_amplitude", geometry.conicity_amplitude, "m")
    for name, profile in (("wheel", pair.wheel), ("rail", pair.rail)):
        add_dataset(f, f"profiles/{name}", np.column_stack([profile.y, profile.z]), "m").attrs["name"] = profile.name
    add_dataset(f, "profiles/nominal_radius", pair.nominal_radius, "m")
    add_dataset(f, "profiles/flange_back", pair.flange_back, "m")
    add_dataset(f, "profiles/rail_tilt", pair.rail_tilt, "rad")
    add_dataset(f, "profiles/rail_pivot_height", pair.rail_pivot_height, "m")


def read_operating_contacts(path) -> list[ContactPoint]:
    """All contacts at the operating displacement (slot 0, the smallest gap, first)."""
    with open_artefact(path, SCHEMA, VERSION) as f:
        n = int(read_dataset(f, "operating/n_contacts", ""))
        data = {name: read_dataset(f, f"operating/{name}", units, None if name in _SCALARS else (n,))
                for name, units in POINT_UNITS.items()}
    names = [fld.name for fld in fields(ContactPoint)]
    return [ContactPoint(**{k: (int(data[k]) if k == "n_contacts" else
                                float(data[k]) if k in _SCALARS else float(data[k][slot])) for k in names})
            for slot in range(n)]


def read_operating_contact(path) -> ContactPoint:
    """The contact the interaction uses (:func:`~contact_geometry.study.main_contact`: the only one,
    or with two-point contact the tread contact, with a WARNING that the flange contact is ignored)."""
    return main_contact(read_operating_contacts(path))


def read_table(path) -> ContactTable:
    """The contact table over the displacement range."""
    with open_artefact(path, SCHEMA, VERSION) as f:
        d = read_dataset(f, "table/displacement", "m", (None,))
        arrays = {name: read_dataset(f, f"table/{name}", units, (d.size,) if name in ("displacement", "n_contacts")
                                     else (d.size, 2)) for name, units in TABLE_UNITS.items()}
    return ContactTable(**arrays)


def read_pair(path) -> WheelRailPair:
    """The wheel/rail pair the artefact was computed for."""
    with open_artefact(path, SCHEMA, VERSION) as f:
        profiles = {}
        for name in ("wheel", "rail"):
            points = read_dataset(f, f"profiles/{name}", "m", (None, 2))
            profiles[name] = Profile(points[:, 0], points[:, 1], str(f[f"profiles/{name}"].attrs["name"]))
        return WheelRailPair(profiles["wheel"], profiles["rail"],
                             float(read_dataset(f, "profiles/nominal_radius", "m")),
                             float(read_dataset(f, "profiles/flange_back", "m")),
                             rail_tilt=float(read_dataset(f, "profiles/rail_tilt", "rad")),
                             rail_pivot_height=float(read_dataset(f, "profiles/rail_pivot_height", "m")))


def read_wheelset(path) -> dict:
    """``displacement`` (m), ``rolling_radius_difference`` (m), ``equivalent_conicity`` (1) and
    ``conicity_amplitude`` (m)."""
    with open_artefact(path, SCHEMA, VERSION) as f:
        y = read_dataset(f, "wheelset/displacement", "m", (None,))
        return {"displacement": y,
                "rolling_radius_difference": read_dataset(f, "wheelset/rolling_radius_difference", "m", (y.size,)),
                "equivalent_conicity": float(read_dataset(f, "wheelset/equivalent_conicity", "1")),
                "conicity_amplitude": float(read_dataset(f, "wheelset/conicity_amplitude", "m"))}
