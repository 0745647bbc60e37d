"""The contact geometry of a study: its wheel/rail pair, operating contact(s) and tables.

Reads the study sections ``[wheel]`` (running surface, rolling radius), ``[rail]`` (head profile,
inclination), ``[operating]`` (``wheel_load``, ``lateral_displacement``) and ``[geometry]`` (the
table range). Used by the ``contact-geometry`` stage (stages/geometry.py) and by the
``geometry`` command, which computes in memory.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from mesh.wheel_section import WheelParams
from profiles.rail_head import OUTLINE_STEP, gauge_point, rail_profile_from_params
from profiles.rail_section import RailParams, rail_outline
from squealcore.errors import InputError
from squealcore.study import get_section

from .contact_point import ContactPoint
from .contact_search import ContactTable, WheelRailPair, contact_exists, contact_interval, contact_table
from .params import MAX_DISPLACEMENT, GeometryParams
from .track import flange_back_position
from .wheel_surface import wheel_profile_from_params, wheel_tape_radius
from .wheelset import equivalent_conicity, rolling_radius_difference

logger = logging.getLogger(__name__)

__all__ = ["StudyGeometry", "pair_from_study", "rail_inclination", "check_contact", "operating_contacts",
           "main_contact", "study_geometry"]

#: Spacing of the displacements tried when the allowed range is reported (m).
RANGE_STEP = 1e-4


def rail_inclination(study) -> int:
    """n of the study's rail inclination 1:n (``rail.inclination``)."""
    return RailParams.from_mapping(get_section(study, "rail"), "rail").inclination


def pair_from_study(study) -> WheelRailPair:
    """The wheel/rail pair of a study: running surface on the inclined rail head, nominal gauge.

    Parameters
    ----------
    study : dict
        A validated study (only ``[wheel]`` and ``[rail]`` are read).

    Returns
    -------
    WheelRailPair
        With the rail tilt and its pivot, so contact points can be given in the rail section's frame.
    """
    wheel = WheelParams.from_mapping(get_section(study, "wheel"), "wheel")
    rail = RailParams.from_mapping(get_section(study, "rail"), "rail")
    profile, inclination = rail.profile, rail.inclination
    wheel_profile = wheel_profile_from_params(wheel)
    rail_profile = rail_profile_from_params(rail)
    tilt = math.atan(1.0 / inclination) if inclination else 0.0
    pivot = float(np.asarray(rail_outline(profile, size=OUTLINE_STEP))[:, 1].max())
    return WheelRailPair(wheel_profile, rail_profile, wheel_tape_radius(wheel),
                         flange_back_position(gauge_point(profile, inclination)), rail_tilt=tilt,
                         rail_pivot_height=pivot)


def check_contact(pair: WheelRailPair, low: float, high: float, field: str) -> None:
    """Refuse displacements in [low, high] (m) at which the wheel does not meet the rail.

    Raises
    ------
    InputError
        Naming ``field``, both profiles and the displacements at which they do meet (within
        +-:data:`~contact_geometry.params.MAX_DISPLACEMENT`).
    """
    tried = np.linspace(low, high, max(2, int(math.ceil((high - low) / RANGE_STEP)) + 1))
    if contact_exists(pair, tried).all():
        return
    allowed = contact_interval(pair, -MAX_DISPLACEMENT, MAX_DISPLACEMENT, RANGE_STEP)
    where = f"{low:.6g} m" if low == high else f"[{low:.6g}, {high:.6g}] m"
    span = ("they meet nowhere within +-0.02 m" if allowed is None else
            f"allowed range for these profiles: [{allowed[0]:.4g}, {allowed[1]:.4g}] m")
    raise InputError(field, f"the wheel profile '{pair.wheel.name}' does not meet the rail profile "
                            f"'{pair.rail.name}' at {where} (the closest approach lies at the end of a "
                            f"profile); {span}; or set the contact by hand (contact.geometry = \"manual\")")


def operating_contacts(study, pair: WheelRailPair | None = None) -> list[ContactPoint]:
    """The contact(s) at the study's ``operating.lateral_displacement``, slot 0 (smallest gap) first.

    Raises
    ------
    InputError
        Naming ``operating.lateral_displacement`` if the wheel does not meet the rail there.
    """
    pair = pair_from_study(study) if pair is None else pair
    operating = get_section(study, "operating")
    geometry = GeometryParams.from_mapping(get_section(study, "geometry"))
    d = float(operating.get("lateral_displacement", 0.0))
    check_contact(pair, d, d, "operating.lateral_displacement")
    table = contact_table(pair, [d], wheel_load=operating["wheel_load"], two_point_tol=geometry.two_point_tolerance)
    return [ContactPoint.from_table(table, 0, slot, pair) for slot in range(int(table.n_contacts[0]))]


def main_contact(contacts: list[ContactPoint]) -> ContactPoint:
    """The contact the interaction uses: the only one, or with two-point contact the tread contact
    (smaller |contact angle|); a WARNING says the flange contact is ignored."""
    if len(contacts) == 1:
        return contacts[0]
    tread, flange = sorted(contacts, key=lambda c: abs(c.contact_angle))
    logger.warning("two-point contact at lateral displacement %.4g m: the interaction uses the tread contact "
                   "(contact angle %.3g rad) and ignores the flange contact (contact angle %.3g rad, rail "
                   "position %.4g m)", tread.lateral_displacement, tread.contact_angle, flange.contact_angle,
                   flange.rail_lateral)
    return tread


@dataclass(frozen=True)
class StudyGeometry:
    """Everything the ``contact-geometry`` stage stores.

    Attributes
    ----------
    pair : WheelRailPair
    operating : list of ContactPoint
        The contact(s) at ``operating.lateral_displacement``, slot 0 first.
    table : ContactTable
        Over ``geometry.displacement_min .. displacement_max``.
    dr_displacement, dr : ndarray
        Wheelset displacements (m, table values with |y| within both ends of the range) and the
        rolling radius difference r(+y) - r(-y) there (m).
    conicity_amplitude : float
        (m).
    equivalent_conicity : float
        (-), harmonic linearisation of dr at that amplitude (:mod:`contact_geometry.wheelset`).
    """

    pair: WheelRailPair
    operating: list
    table: ContactTable
    dr_displacement: np.ndarray
    dr: np.ndarray
    conicity_amplitude: float
    equivalent_conicity: float


def study_geometry(study) -> StudyGeometry:
    """Contact geometry of a study (operating contacts, tables, rolling radius difference, conicity).

    Raises
    ------
    InputError
        Naming ``operating.lateral_displacement``, ``geometry.displacement_min`` /
        ``displacement_max`` or ``geometry.conicity_amplitude`` when the wheel does not meet the rail
        at those displacements, with the allowed range.
    """
    pair = pair_from_study(study)
    geometry = GeometryParams.from_mapping(get_section(study, "geometry"))
    load = get_section(study, "operating")["wheel_load"]
    operating = operating_contacts(study, pair)
    lo, hi = geometry.displacement_min, geometry.displacement_max
    check_contact(pair, lo, lo, "geometry.displacement_min")
    check_contact(pair, hi, hi, "geometry.displacement_max")
    check_contact(pair, lo, hi, "geometry.displacement_min")
    amp = geometry.conicity_amplitude
    check_contact(pair, -amp, amp, "geometry.conicity_amplitude")
    kwargs = {"wheel_load": load, "two_point_tol": geometry.two_point_tolerance}
    table = contact_table(pair, np.linspace(lo, hi, geometry.displacement_count), **kwargs)
    half = min(-lo, hi)
    y_dr = table.displacement[np.abs(table.displacement) <= half + 1e-15]
    dr = rolling_radius_difference(pair, y_dr, **kwargs) if y_dr.size else np.zeros(0)
    conicity = equivalent_conicity(pair, amp, **kwargs)
    logger.info("contact geometry: %d displacements, %d with two-point contact; equivalent conicity %.4g at "
                "%.3g mm", table.displacement.size, int((table.n_contacts == 2).sum()), conicity, amp * 1e3)
    return StudyGeometry(pair, operating, table, y_dr, dr, amp, conicity)
