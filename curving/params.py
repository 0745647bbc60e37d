"""The inputs of a steady-curving computation: curve, vehicle, suspension, friction (SI units).

:class:`CurvingParams` is frozen and validated on construction; a value out of range raises
:class:`squealcore.errors.InputError` naming the field (``curving.<name>``) and the allowed range.
The wheel/rail contact geometry is a separate object (:mod:`curving.geometry`), given as
``CurvingParams.geometry``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from squealcore.errors import InputError, require_range

from .geometry import ConicalGeometry, WheelsetGeometry

__all__ = ["CurvingParams", "GRAVITY"]

#: Standard gravity (m/s²).
GRAVITY = 9.81


def _stiffness(name: str, value) -> float:
    """A primary stiffness (N/m): a positive number, or ``math.inf`` for a rigid connection."""
    if isinstance(value, (int, float)) and not isinstance(value, bool) and value == math.inf:
        return math.inf
    return require_range(f"curving.{name}", value, 1e4, 1e10, unit="N/m (or inf: rigid)")


@dataclass(frozen=True)
class CurvingParams:
    """A two-axle bogie on a circular curve, running at constant speed (quasi-static).

    Parameters
    ----------
    radius : float
        Curve radius R (m), in [20, inf]; ``math.inf`` is straight track. The curve turns
        towards the inner rail; lateral positions are positive towards the outer rail.
    speed : float
        Vehicle speed V (m/s), in (0, 100].
    cant : float
        Cant h (m): height of the outer rail above the inner one, in [0, 0.2]. The cant angle
        is ``asin(h / (2 l0))`` with l0 the geometry's half contact spacing.
    wheelbase : float
        Bogie wheelbase 2b (m), in [1, 4].
    axle_load : float
        Vertical load per axle P (N) on level track at rest, wheelset and its share of frame and
        body, in [1e3, 5e5].
    centre_of_gravity_height : float
        Height above the rails of the mass carried by the axles (m), in [0, 3]: the quasi-static
        load transfer from the outer to the inner wheel is ``F_u h_cg / (2 l0)``.
    longitudinal_stiffness, lateral_stiffness : float
        Primary suspension stiffness per axle box, longitudinal k_x and lateral k_y (N/m), in
        [1e4, 1e10], or ``math.inf`` (default) for a rigid bogie (frame and wheelsets one body).
        Both infinite or both finite.
    axlebox_half_spacing : float
        Lateral half-distance d between a wheelset's two axle boxes (m), in [0.5, 1.5]: the
        wheelset's yaw stiffness relative to the frame is ``2 k_x d²``.
    friction : float
        Friction coefficient μ of the tread contacts (-), in (0, 1].
    flange_friction : float or None
        Friction coefficient of flange contacts (-), in [0, 1]; None: ``friction``. 0 is a
        perfectly lubricated flange (no creep force there).
    spin : bool
        Include the spin creepage in the creep law (default True).
    geometry : WheelsetGeometry
        Wheel/rail contact geometry of every wheelset: :class:`~curving.geometry.ConicalGeometry`
        (default: conicity 0.05, flangeway clearance 8 mm) or
        :class:`~curving.geometry.ProfileGeometry` (the project's contact-geometry tables).
    """

    radius: float
    speed: float
    cant: float = 0.0
    wheelbase: float = 2.5
    axle_load: float = 100e3
    centre_of_gravity_height: float = 1.2
    longitudinal_stiffness: float = math.inf
    lateral_stiffness: float = math.inf
    axlebox_half_spacing: float = 1.0
    friction: float = 0.3
    flange_friction: float | None = None
    spin: bool = True
    geometry: WheelsetGeometry = field(default_factory=ConicalGeometry)

    def __post_init__(self):
        if not (isinstance(self.radius, (int, float)) and self.radius == math.inf):
            require_range("curving.radius", self.radius, 20.0, None, unit="m (or inf: straight track)")
        require_range("curving.speed", self.speed, 0.0, 100.0, low_open=True, unit="m/s")
        require_range("curving.cant", self.cant, 0.0, 0.2, unit="m")
        require_range("curving.wheelbase", self.wheelbase, 1.0, 4.0, unit="m")
        require_range("curving.axle_load", self.axle_load, 1e3, 5e5, unit="N")
        require_range("curving.centre_of_gravity_height", self.centre_of_gravity_height, 0.0, 3.0, unit="m")
        kx = _stiffness("longitudinal_stiffness", self.longitudinal_stiffness)
        ky = _stiffness("lateral_stiffness", self.lateral_stiffness)
        if math.isinf(kx) != math.isinf(ky):
            raise InputError("curving.longitudinal_stiffness",
                             "give both primary stiffnesses finite, or both inf (rigid bogie)")
        require_range("curving.axlebox_half_spacing", self.axlebox_half_spacing, 0.5, 1.5, unit="m")
        require_range("curving.friction", self.friction, 0.0, 1.0, low_open=True, unit="-")
        if self.flange_friction is not None:
            require_range("curving.flange_friction", self.flange_friction, 0.0, 1.0, unit="-")
        if not isinstance(self.spin, bool):
            raise InputError("curving.spin", f"must be true or false, got {self.spin!r}")
        if not isinstance(self.geometry, WheelsetGeometry):
            raise InputError("curving.geometry", "must be a ConicalGeometry or a ProfileGeometry "
                             f"(curving.geometry), got {type(self.geometry).__name__}")
        if self.cant >= 2.0 * self.geometry.contact_half_spacing:
            raise InputError("curving.cant", "must be below the contact spacing 2 l0")

    @property
    def rigid(self) -> bool:
        """True for a rigid bogie (infinite primary stiffness)."""
        return math.isinf(self.longitudinal_stiffness)

    @property
    def semi_wheelbase(self) -> float:
        """b = wheelbase / 2 (m)."""
        return 0.5 * self.wheelbase

    @property
    def curvature(self) -> float:
        """1 / R (1/m); 0 on straight track."""
        return 0.0 if math.isinf(self.radius) else 1.0 / self.radius

    @property
    def cant_angle(self) -> float:
        """Cant angle θ = asin(h / (2 l0)) (rad)."""
        return math.asin(self.cant / (2.0 * self.geometry.contact_half_spacing))

    @property
    def flange_mu(self) -> float:
        """Friction coefficient of flange contacts (-)."""
        return self.friction if self.flange_friction is None else float(self.flange_friction)
