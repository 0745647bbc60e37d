"""Quasi-static loads of a bogie on a canted curve: unbalanced lateral force and wheel loads.

In the plane of the track (tilted by the cant angle θ), a mass m = P / g running at speed V on
radius R feels, per axle,

* the unbalanced lateral force ``F_u = P (V² / (g R) cos θ - sin θ)``, towards the outer rail when
  positive (cant deficiency), towards the inner rail when negative (cant excess);
* the load normal to the track plane ``P_n = P (cos θ + V² / (g R) sin θ)``.

``F_u`` acts at the height h_cg above the rails, so the outer wheel carries
``Q_o = P_n / 2 + F_u h_cg / (2 l0)`` and the inner one ``Q_i = P_n / 2 - F_u h_cg / (2 l0)``
(rigid roll: the suspension's roll flexibility and the body's lateral shift are neglected). The
cant deficiency in metres is ``2 l0 V² / (g R) - h``, to first order in θ.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from .params import GRAVITY, CurvingParams

__all__ = ["AxleLoads", "axle_loads"]


@dataclass(frozen=True)
class AxleLoads:
    """Quasi-static loads per axle (SI units).

    Attributes
    ----------
    unbalanced_force : float
        F_u (N), in the track plane, positive towards the outer rail.
    normal_load : float
        P_n (N), normal to the track plane.
    outer, inner : float
        Wheel loads Q_o, Q_i normal to the track plane (N).
    cant_deficiency : float
        (m), negative for a cant excess.
    lateral_acceleration : float
        Unbalanced lateral acceleration in the track plane F_u / m (m/s²).
    """

    unbalanced_force: float
    normal_load: float
    outer: float
    inner: float
    cant_deficiency: float
    lateral_acceleration: float


def axle_loads(params: CurvingParams) -> AxleLoads:
    """The quasi-static loads per axle of ``params`` (module docstring)."""
    theta = params.cant_angle
    ratio = params.speed ** 2 * params.curvature / GRAVITY  # V² / (g R)
    p = params.axle_load
    fu = p * (ratio * math.cos(theta) - math.sin(theta))
    pn = p * (math.cos(theta) + ratio * math.sin(theta))
    l0 = params.geometry.contact_half_spacing
    transfer = fu * params.centre_of_gravity_height / (2.0 * l0)
    return AxleLoads(fu, pn, 0.5 * pn + transfer, 0.5 * pn - transfer, 2.0 * l0 * ratio - params.cant,
                     fu / p * GRAVITY)
