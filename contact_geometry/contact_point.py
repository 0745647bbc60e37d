"""One wheel/rail contact point with everything downstream needs (position, radius, angle, Hertz).

A :class:`ContactPoint` is one row and slot of a :class:`~contact_geometry.contact_search.ContactTable`,
with the rail contact also expressed in the rail section's own upright frame (the frame of the
waveguide mesh: y from the section's centre line, z from the foot bottom), which differs from the
track frame by the rail inclination (see :meth:`WheelRailPair.rail_section_point`).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from .contact_search import ContactTable, WheelRailPair

__all__ = ["ContactPoint"]


@dataclass(frozen=True)
class ContactPoint:
    """A wheel/rail contact (SI units).

    Attributes
    ----------
    lateral_displacement : float
        Lateral displacement of the wheel relative to the rail (m, positive: flange towards the
        rail's gauge face).
    wheel_lateral : float
        Contact position on the wheel, from the flange back (m).
    rail_lateral : float
        Contact position on the rail, from its centre line, track frame (inclined rail) (m).
    rail_section_lateral, rail_section_height : float
        The same point in the rail section's upright frame: y from the centre line, z from the
        foot bottom (m).
    rolling_radius : float
        (m).
    contact_angle : float
        Angle of the contact normal to the vertical, track frame (rad), positive leaning towards
        the gauge side.
    rail_section_angle : float
        The same normal in the rail section's frame: ``contact_angle - rail tilt`` (rad).
    curvature_long, curvature_lat : float
        Relative principal curvatures, longitudinal and lateral (1/m).
    semi_axis_a, semi_axis_b : float
        Hertz semi-axes, longitudinal and lateral (m), at :attr:`normal_force`; NaN where the
        contact is not Hertzian (conformal or concave).
    normal_force : float
        Wheel load / cos(contact_angle) (N).
    spin : float
        Geometric spin sin(contact_angle) / rolling_radius (1/m).
    n_contacts : int
        Contacts at this displacement (1, or 2 for two-point contact).
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
    n_contacts: int

    @classmethod
    def from_table(cls, table: ContactTable, i: int, slot: int, pair: WheelRailPair) -> "ContactPoint":
        """The contact of row ``i``, slot ``slot`` (0 or 1) of a contact table computed for ``pair``.

        Raises
        ------
        IndexError
            If the slot holds no contact (slot 1 without two-point contact).
        """
        if slot not in (0, 1) or slot >= int(table.n_contacts[i]):
            raise IndexError(f"row {i} of the contact table has {int(table.n_contacts[i])} contact(s), "
                             f"no slot {slot}")
        y_rail = float(table.y_rail[i, slot])
        ys, zs = pair.rail_section_point(y_rail, float(pair.rail.height(y_rail)))
        angle = float(table.contact_angle[i, slot])
        return cls(lateral_displacement=float(table.displacement[i]), wheel_lateral=float(table.y_wheel[i, slot]),
                   rail_lateral=y_rail, rail_section_lateral=float(ys), rail_section_height=float(zs),
                   rolling_radius=float(table.rolling_radius[i, slot]), contact_angle=angle,
                   rail_section_angle=angle - pair.rail_tilt,
                   curvature_long=float(table.curvature_long[i, slot]),
                   curvature_lat=float(table.curvature_lat[i, slot]),
                   semi_axis_a=float(table.semi_axis_a[i, slot]), semi_axis_b=float(table.semi_axis_b[i, slot]),
                   normal_force=float(table.normal_force[i, slot]), spin=float(table.spin[i, slot]),
                   n_contacts=int(table.n_contacts[i]))

    def to_dict(self) -> dict:
        """Every attribute, plus ``semi_axes`` = [a, b] (m); NaN becomes None (JSON null)."""
        out = {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in asdict(self).items()}
        out["semi_axes"] = [out["semi_axis_a"], out["semi_axis_b"]]
        return out
