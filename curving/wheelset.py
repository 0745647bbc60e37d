"""Forces on one wheelset in steady curving, from its position, angle of attack and rotation.

For each wheel (side s = +1 outer, -1 inner, wheel displacement ``y_w = s y``) the tread
contact(s) of the geometry and, when the flange is in contact, the flange contact with a given
normal force. Per contact, in the wheel's frame (:mod:`curving.kinematics`): creepages, creep
forces (Fx, Fy) from the creep law and the normal force N. The wheel's load Q (normal to the
track plane) fixes the tread normal force by the wheel's vertical equilibrium

    ``N_t cos δ_t + Fy_t sin δ_t = Q - (N_f cos δ_f + Fy_f sin δ_f)``

(solved by fixed-point iteration, Fy depending on N). Between two rows of a contact table the
tread contact is both rows' contacts, each solved at the full load and weighted by its share
(1 - w, w): forces and normal loads are interpolated linearly between the rows. The wheel's force in the track plane towards its
field side is ``Σ_c (Fy_c cos δ_c - N_c sin δ_c)``. Summed over the two wheels, in the track
frame (y towards the outer rail, yaw positive turning the heading towards the outer rail):

* lateral force ``F_y = Σ s (Fy cos δ - N sin δ)``;
* yaw moment about the wheelset centre ``M_z = -Σ s l Fx`` (l the contact's arm);
* torque about the axle ``T = Σ Fx r`` (zero: no traction or braking).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .creep import CreepLaw
from .geometry import ContactGeometry, WheelsetGeometry
from .kinematics import creepages

__all__ = ["ContactState", "WheelState", "WheelsetState", "wheelset_forces", "SIDES"]

#: Side labels by sign.
SIDES = {1: "outer", -1: "inner"}
_MAX_NORMAL_ITERATIONS = 60


@dataclass(frozen=True)
class ContactState:
    """One contact's solution (SI units): geometry, load share, creepages, normal and creep forces."""

    geometry: ContactGeometry
    share: float
    creepage: tuple
    normal_force: float
    creep_force: tuple
    mu: float

    @property
    def field_force(self) -> float:
        """Force on the wheel in the track plane towards its field side (N)."""
        d = self.geometry.contact_angle
        return self.creep_force[1] * math.cos(d) - self.normal_force * math.sin(d)

    @property
    def vertical_force(self) -> float:
        """Force on the wheel normal to the track plane (N)."""
        d = self.geometry.contact_angle
        return self.normal_force * math.cos(d) + self.creep_force[1] * math.sin(d)


@dataclass(frozen=True)
class WheelState:
    """One wheel: side (+1 outer, -1 inner), load Q (N) and its contacts (tread first)."""

    side: int
    load: float
    contacts: tuple

    @property
    def field_force(self) -> float:
        return sum(c.field_force for c in self.contacts)

    @property
    def vertical_force(self) -> float:
        return sum(c.vertical_force for c in self.contacts)

    @property
    def flange_force(self) -> float:
        """Lateral force of the flange contact pushing the wheel towards its gauge side (N); 0 without."""
        return sum(-c.field_force for c in self.contacts if c.geometry.kind == "flange")


@dataclass(frozen=True)
class WheelsetState:
    """A wheelset's wheels and force resultants (track frame, SI units)."""

    wheels: tuple
    lateral_force: float
    yaw_moment: float
    torque: float


def _wheel(geometry: WheelsetGeometry, law: CreepLaw, side: int, y: float, yaw: float, rotation: float,
           curvature: float, load: float, flange_normal: float | None, mu: float, mu_flange: float,
           spin: bool) -> WheelState:
    r0 = geometry.nominal_radius
    contacts = []
    carried = load
    if flange_normal is not None:
        fg = geometry.flange()
        cf = creepages(fg, side, y, yaw, rotation, curvature, r0, spin)
        ff = law.force(fg, mu_flange, flange_normal, cf)
        flange = ContactState(fg, 0.0, cf, float(flange_normal), (float(ff[0]), float(ff[1])), mu_flange)
        carried = load - flange.vertical_force
    else:
        flange = None
    for share, g in geometry.tread(side * y):
        if share <= 0.0:
            continue
        c = creepages(g, side, y, yaw, rotation, curvature, r0, spin)
        target = carried
        cos_d, sin_d = math.cos(g.contact_angle), math.sin(g.contact_angle)
        n = target / cos_d
        f = law.force(g, mu, n, c)
        for _ in range(_MAX_NORMAL_ITERATIONS):
            n_new = (target - f[1] * sin_d) / cos_d
            f = law.force(g, mu, n_new, c)
            if abs(n_new - n) <= 1e-13 * max(abs(load), 1.0):
                n = n_new
                break
            n = n_new
        # each table row's contact at the full load, weighted by its share: the wheel's forces are
        # interpolated linearly between the rows (splitting the load instead would not reproduce a
        # single contact between two equal rows: Kalker's forces grow as N^(2/3))
        contacts.append(ContactState(g, share, c, float(share * n), (float(share * f[0]), float(share * f[1])), mu))
    if flange is not None:
        contacts.append(flange)
    return WheelState(side, float(load), tuple(contacts))


def wheelset_forces(geometry: WheelsetGeometry, law: CreepLaw, y: float, yaw: float, rotation: float,
                    curvature: float, loads: tuple, flange_normal: dict, mu: float, mu_flange: float,
                    spin: bool = True) -> WheelsetState:
    """Contacts and force resultants of one wheelset (module docstring).

    Parameters
    ----------
    geometry : WheelsetGeometry
    law : CreepLaw
    y : float
        Lateral displacement towards the outer rail (m).
    yaw : float
        Angle of attack ψ (rad).
    rotation : float
        ω = Ω r0 / V (-).
    curvature : float
        1 / R (1/m).
    loads : (float, float)
        Wheel loads (Q_outer, Q_inner) (N).
    flange_normal : dict
        Side (+1, -1) -> normal force of that wheel's flange contact (N), for the flanges in contact.
    mu, mu_flange : float
        Friction coefficients of tread and flange contacts (-).
    spin : bool
        Include the spin creepage.
    """
    wheels = []
    fy = mz = t = 0.0
    for side, load in zip((1, -1), loads):
        w = _wheel(geometry, law, side, y, yaw, rotation, curvature, load, flange_normal.get(side), mu, mu_flange,
                   spin)
        wheels.append(w)
        for c in w.contacts:
            fy += side * c.field_force
            mz -= side * c.geometry.arm * c.creep_force[0]
            t += c.creep_force[0] * c.geometry.rolling_radius
    return WheelsetState(tuple(wheels), fy, mz, t)


def contact_record(c: ContactState, law: CreepLaw) -> dict:
    """A JSON-ready record of a contact (NaN as None)."""
    a, b = law.semi_axes(c.geometry, c.mu, c.normal_force)
    g = c.geometry

    def num(v):
        v = float(v)
        return None if math.isnan(v) else v

    bound = c.mu * c.normal_force
    return {"kind": g.kind, "load_share": c.share if g.kind == "tread" else None,
            "creepage": [float(x) for x in c.creepage], "contact_angle": g.contact_angle,
            "rolling_radius": g.rolling_radius, "lateral_arm": g.arm, "wheel_lateral": num(g.wheel_lateral),
            "rail_lateral": num(g.rail_lateral), "normal_force": c.normal_force,
            "creep_force": list(c.creep_force), "semi_axes": [a, b],
            "friction_use": float(np.hypot(*c.creep_force) / bound) if bound > 0 else None}
