"""The operating contact of the wheel on the rail, as the interaction uses it.

Stand-in of helper "frame" with the fields agreed in the issue-14 interfaces; the
``contact-geometry`` stage (helper "geomstage") owns this module, the fields are the same.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

__all__ = ["ContactPoint"]


@dataclass(frozen=True)
class ContactPoint:
    """One wheel/rail contact (SI units).

    Attributes
    ----------
    lateral_displacement : float
        Lateral displacement of the wheel relative to the rail, m.
    wheel_lateral : float
        Contact position on the wheel from the flange back, m.
    rail_lateral : float
        Contact position on the rail from its centre line, track frame (inclined rail), m.
    rail_section_lateral, rail_section_height : float
        The same point in the rail section's own upright frame (y from the centre line, z from the
        foot bottom), m.
    rolling_radius : float
        m.
    contact_angle : float
        Angle of the contact normal to the vertical, track frame, positive leaning towards the
        gauge side, rad.
    rail_section_angle : float
        The same normal in the rail section's upright frame (contact angle minus the inclination
        tilt), rad.
    curvature_long, curvature_lat : float
        Relative principal curvatures, 1/m.
    semi_axis_a, semi_axis_b : float
        Hertz semi-axes at ``normal_force``, m.
    normal_force : float
        Wheel load / cos(contact_angle), N.
    spin : float
        Geometric spin sin(contact_angle) / rolling_radius, 1/m.
    n_contacts : int
        1 or 2.
    """

    lateral_displacement: float
    wheel_lateral: float
    rail_lateral: float
    rail_section_lateral: float
    rail_section_height: float
    rolling_radius: float
    contact_angle: float
    rail_section_angle: float
    curvature_long: float
    curvature_lat: float
    semi_axis_a: float
    semi_axis_b: float
    normal_force: float
    spin: float
    n_contacts: int = 1

    def to_dict(self) -> dict:
        """JSON-able dict of the fields (NaN as None)."""
        return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in asdict(self).items()}
