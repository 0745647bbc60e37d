"""Creepages of a wheel's contact in steady curving (docs/design.md, "Steady curving").

Frames: the track frame has x along the track (direction of travel), y towards the **outer** rail,
in the track plane. A wheelset is displaced by y (m) towards the outer rail and yawed by the
angle of attack ψ (rad) relative to the local radial direction, ψ > 0 when its heading (the
direction it rolls in) is turned towards the outer rail. It turns at the yaw rate V / R of the
curve and rotates at Ω = ω V / r0 about its axle (ω = 1: the nominal rolling speed). Each wheel
is described in its own frame, as the project's contact models expect
(docs/conventions.md): x forward, y from its gauge side towards its field side (outwards for
the outer wheel, s = +1; inwards for the inner wheel, s = -1), z along the contact normal tilted
by the contact angle δ towards the gauge side. Creepages are those of the wheel relative to the
rail (slip velocity of the wheel's material over V):

* longitudinal: the wheelset turns about the curve's centre at V / R, so its material at the
  contact, at ``Y = y + s l`` from the track centre line (``l`` the contact's arm from the
  wheelset centre), moves forward at ``V (1 + Y / R)``; the wheel's surface moves backwards
  relative to it at ``Ω r``, so

      ``ξ = 1 + (y + s l) / R - ω r / r0``

  (for the cone, ``r = r0 + s λ y``, ``l = l0 - s y``, ``ω = 1``: ``ξ = s (l0 / R - λ y / r0)``,
  zero at ``y = r0 l0 / (λ R)``, the pure-rolling offset);
* lateral: the yawed wheelset rolls along its heading, so its material slips sideways at
  ``-V ψ`` (towards the inner rail for ψ > 0); in the wheel's frame (sign s) and projected on the
  contact plane

      ``η = -s ψ cos δ``;

* spin: the angular velocity along the contact normal, from the rotation Ω about the axle
  (``-Ω sin δ``, docs/conventions.md) and the yaw rate V / R of the curve (``-s V cos δ / R``
  in the wheel's frame), over V:

      ``φ = -ω sin δ / r0 - s cos δ / R``.

Neglected: the lateral velocity (steady state), the longitudinal lead of flange contacts and
terms of second order in ψ.
"""

from __future__ import annotations

import math

from .geometry import ContactGeometry

__all__ = ["creepages"]


def creepages(contact: ContactGeometry, side: int, y: float, yaw: float, rotation: float, curvature: float,
              nominal_radius: float, spin: bool = True) -> tuple[float, float, float]:
    """(ξ, η, φ) of one contact in its wheel's frame (module docstring).

    Parameters
    ----------
    contact : ContactGeometry
    side : int
        +1 outer wheel, -1 inner wheel.
    y : float
        Wheelset lateral displacement towards the outer rail (m).
    yaw : float
        Angle of attack ψ (rad).
    rotation : float
        ω = Ω r0 / V (-).
    curvature : float
        1 / R (1/m).
    nominal_radius : float
        r0 (m).
    spin : bool
        False sets φ = 0.

    Returns
    -------
    (float, float, float)
        ξ (-), η (-), φ (1/m).
    """
    delta = contact.contact_angle
    xi = 1.0 + (y + side * contact.arm) * curvature - rotation * contact.rolling_radius / nominal_radius
    eta = -side * yaw * math.cos(delta)
    phi = (-rotation * math.sin(delta) / nominal_radius - side * math.cos(delta) * curvature) if spin else 0.0
    return xi, eta, phi
