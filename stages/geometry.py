"""STAND-IN (helper "frame") for the ``contact-geometry`` stage of helper "geomstage".

Only what the downstream stages need while the real stage is built in parallel: the operating
contact at ``operating.lateral_displacement`` (default 0) of the parametric wheel tread on the
rail head inclined 1:30, written to ``contact_geometry.h5`` as ``/operating/<field>``, and
:func:`read_operating_contact`. The integrator keeps geomstage's module instead of this one.
"""

from __future__ import annotations

import math

import numpy as np

from contact_geometry.contact_point import ContactPoint
from contact_geometry.contact_search import WheelRailPair, contact_table
from contact_geometry.rail_profiles import SWEDISH_INCLINATION, gauge_point, inclined_outline, rail_head_profile
from contact_geometry.track import flange_back_position
from contact_geometry.wheel_profiles import parametric_wheel_profile
from mesh.rail_section import RailParams
from mesh.wheel_section import WheelParams
from squealcore.artefacts import add_dataset, open_artefact, read_dataset
from squealcore.study import get_section

FIELDS = ("lateral_displacement", "wheel_lateral", "rail_lateral", "rail_section_lateral", "rail_section_height",
          "rolling_radius", "contact_angle", "rail_section_angle", "curvature_long", "curvature_lat",
          "semi_axis_a", "semi_axis_b", "normal_force", "spin")


def operating_contact(study) -> ContactPoint:
    """The main contact of the study's wheel on its rail at ``operating.lateral_displacement``."""
    wheel = WheelParams.from_mapping(get_section(study, "wheel"), "wheel")
    rail = RailParams.from_mapping(get_section(study, "rail"), "rail")
    inclination = int(study["rail"].get("inclination", SWEDISH_INCLINATION))
    displacement = float(study["operating"].get("lateral_displacement", 0.0))
    rail_profile = rail_head_profile(rail.profile, inclination)
    pair = WheelRailPair(parametric_wheel_profile(wheel), rail_profile, wheel.rolling_radius,
                         flange_back_position(gauge_point(rail.profile, inclination)))
    table = contact_table(pair, [displacement], wheel_load=study["operating"]["wheel_load"])
    tilt = 0.0 if inclination == 0 else math.atan(1.0 / inclination)
    top = float(inclined_outline(rail.profile, 0)[:, 1].max())
    y, z = float(table.y_rail[0, 0]), float(rail_profile.height(table.y_rail[0, 0]))
    c, s = math.cos(tilt), math.sin(tilt)
    section_y, section_z = c * y + s * (z - top), -s * y + c * (z - top) + top  # turned back about (0, top)
    angle = float(table.contact_angle[0, 0])
    return ContactPoint(
        lateral_displacement=displacement, wheel_lateral=float(table.y_wheel[0, 0]), rail_lateral=y,
        rail_section_lateral=section_y, rail_section_height=section_z,
        rolling_radius=float(table.rolling_radius[0, 0]), contact_angle=angle, rail_section_angle=angle - tilt,
        curvature_long=float(table.curvature_long[0, 0]), curvature_lat=float(table.curvature_lat[0, 0]),
        semi_axis_a=float(table.semi_axis_a[0, 0]), semi_axis_b=float(table.semi_axis_b[0, 0]),
        normal_force=float(table.normal_force[0, 0]), spin=float(table.spin[0, 0]),
        n_contacts=int(table.n_contacts[0]))


def build_contact_geometry(ctx):
    """``contact-geometry`` (stand-in): the operating contact as ``/operating/<field>``."""
    point = operating_contact(ctx.study)
    with ctx.writer() as f:
        for name in FIELDS:
            add_dataset(f, f"operating/{name}", float(getattr(point, name)), "")
        add_dataset(f, "operating/n_contacts", int(point.n_contacts), "")


def read_operating_contact(path) -> ContactPoint:
    """The main contact of ``contact_geometry.h5``."""
    with open_artefact(path, "contact_geometry", 1) as f:
        values = {name: float(read_dataset(f, f"operating/{name}", "")) for name in FIELDS}
        values["n_contacts"] = int(np.asarray(read_dataset(f, "operating/n_contacts", "")))
    return ContactPoint(**values)
