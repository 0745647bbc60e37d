"""Wheel and rail profiles and rigid contact geometry (contact points, radii, angles, Hertz, conicity).

Modules: :mod:`.profile` (profile curves and their text files) and :mod:`.s1002` (the S1002
definition), both re-exported from ``mesh`` (the wheel section is built on them), :mod:`.wheel_profiles`, :mod:`.rail_profiles` (head profile, inclination, gauge
point), :mod:`.track` (gauge and back-to-back), :mod:`.contact_search` (contact tables),
:mod:`.wheelset` (dr and equivalent conicity), :mod:`.contact_point` (one contact),
:mod:`.params` (the ``[geometry]`` section), :mod:`.study` (a study's pair and contacts),
:mod:`.artefact` (``contact_geometry.h5``), :mod:`.plots`.
"""

from .contact_point import ContactPoint
from .contact_search import ContactTable, WheelRailPair, contact_exists, contact_interval, contact_table
from .profile import Profile, read_profile, write_profile
from .rail_profiles import gauge_point, rail_head_profile, rail_profile_from_params
from .track import BACK_TO_BACK, TRACK_GAUGE, flange_back_position
from .wheel_profiles import cone_profile, parametric_wheel_profile, s1002_profile, wheel_profile_from_params
from .wheelset import equivalent_conicity, rolling_radius_difference

__all__ = ["ContactPoint", "ContactTable", "WheelRailPair", "contact_table", "contact_exists", "contact_interval",
           "Profile", "read_profile", "write_profile",
           "gauge_point", "rail_head_profile", "BACK_TO_BACK", "TRACK_GAUGE", "flange_back_position",
           "cone_profile", "parametric_wheel_profile", "s1002_profile", "equivalent_conicity",
           "rolling_radius_difference", "wheel_profile_from_params", "rail_profile_from_params"]
