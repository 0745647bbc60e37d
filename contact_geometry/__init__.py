"""Rigid wheel/rail contact geometry (contact points, radii, angles, Hertz, conicity) on the profiles of
package ``profiles`` (curves, S1002, tread files, rail heads, inclination, gauge point).

Modules: :mod:`.wheel_surface` (the running surface of a study's wheel, as its section is built),
:mod:`.track` (gauge and back-to-back), :mod:`.contact_search` (contact tables),
:mod:`.wheelset` (dr and equivalent conicity), :mod:`.contact_point` (one contact),
:mod:`.params` (the ``[geometry]`` section), :mod:`.study` (a study's pair and contacts),
:mod:`.artefact` (``contact_geometry.h5``), :mod:`.plots`, :mod:`.reference` (brute-force check on
the exact profiles).
"""

from .contact_point import ContactPoint
from .contact_search import ContactTable, WheelRailPair, contact_exists, contact_interval, contact_table
from .track import BACK_TO_BACK, TRACK_GAUGE, flange_back_position
from .wheel_surface import parametric_wheel_profile, wheel_profile_from_params
from .wheelset import equivalent_conicity, rolling_radius_difference

__all__ = ["ContactPoint", "ContactTable", "WheelRailPair", "contact_table", "contact_exists", "contact_interval",
           "BACK_TO_BACK", "TRACK_GAUGE", "flange_back_position", "parametric_wheel_profile", "equivalent_conicity",
           "rolling_radius_difference", "wheel_profile_from_params"]
