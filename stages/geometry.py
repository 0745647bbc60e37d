"""Stage ``contact-geometry``: wheel/rail contact points from the profiles -> ``contact_geometry.h5``.

The physics is :func:`contact_geometry.study.study_geometry`; the artefact layout and its readers
are in :mod:`contact_geometry.artefact` (re-exported here for the stages that read it).
"""

from __future__ import annotations

import logging

from contact_geometry.artefact import (SCHEMA, VERSION, read_operating_contact, read_operating_contacts, read_pair,
                                       read_table, read_wheelset, write_geometry)
from contact_geometry.study import main_contact, study_geometry

logger = logging.getLogger(__name__)

__all__ = ["SCHEMA", "VERSION", "build_contact_geometry", "read_operating_contacts", "read_operating_contact",
           "read_table", "read_pair", "read_wheelset"]


def build_contact_geometry(ctx):
    """``contact-geometry``: contact(s) at the operating displacement, tables, dr and conicity."""
    geometry = study_geometry(ctx.config())
    main = main_contact(geometry.operating)
    logger.info("contact at y_w = %.4g m: wheel %.2f mm from the flange back, rail %.2f mm from the centre line, "
                "r = %.5f m, contact angle %.4f rad", main.lateral_displacement, main.wheel_lateral * 1e3,
                main.rail_lateral * 1e3, main.rolling_radius, main.contact_angle)
    with ctx.writer() as f:
        write_geometry(f, geometry)
