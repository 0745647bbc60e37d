"""Each wheel's operating point in a curve, in the squeal study's conventions (issue 35, item 2).

:func:`wheel_operating_points` turns a steady-curving result (:func:`curving.solve_bogie` or
:func:`curving.solve_wheelset`) into one :class:`WheelOperatingPoint` per wheel, keyed
``"leading_inner"``, ``"leading_outer"``, ``"trailing_inner"``, ``"trailing_outer"`` (a free wheelset:
``"single_inner"``, ``"single_outer"``): what a squeal case of that wheel needs.

**Frame and sign convention** — those of the squeal study's keys ``contact.longitudinal_creepage``,
``contact.lateral_creepage``, ``contact.spin``, ``operating.lateral_displacement`` and
``operating.wheel_load`` (docs/conventions.md): each wheel in its own contact frame, x along the
rolling direction, y from the wheel's flange (gauge side) towards its field side, z along the
contact normal; creepages of the wheel relative to the rail (slip velocity of the wheel's material
over the speed), so that Kalker's linear theory reads ``Fx = -C11 ξ``, ``Fy = -C22 η - C23 φ``
for the force of the rail on the wheel. The curving package computes its creepages in this frame
(:mod:`curving.kinematics`), so no sign is changed here.

What that means in a curve: the leading wheelset runs with a positive angle of attack ψ (its
heading turned towards the outer rail, about the wheelbase over R for a rigid bogie in flange
contact). Rolling along its heading while it follows the track, the material of both its wheels
slips **inwards** (towards the curve's centre) over the rails at ``V ψ``, and the creep forces on
both wheels point outwards, balanced by the outer wheel's flange force. Inwards is the inner
wheel's field side and the outer wheel's flange side, so

* leading inner wheel: ``η = +ψ cos δ`` (positive: the wheel slides towards its field side; the
  creep force on it points towards its flange);
* leading outer wheel: ``η = -ψ cos δ``.

The paper's hand-set cases (``contact.lateral_creepage`` = -0.3 ... -1.5 %) therefore have the
sign of the leading *outer* wheel (or of a wheelset with a negative angle of attack) in this
convention; the leading inner wheel of a curve has the opposite sign.

The spin is the curving's: ``φ = -ω sin δ / r0 - s cos δ / R`` (the wheel's rotation and the
curve's yaw rate, s = +1 outer, -1 inner wheel); the study's profile contact alone imposes only
``-sin δ / r``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from squealcore.errors import InputError

__all__ = ["WheelOperatingPoint", "wheel_operating_points", "WHEEL_LABELS", "wheel_label"]

#: Labels of a bogie's wheels, leading wheelset first.
WHEEL_LABELS = ("leading_inner", "leading_outer", "trailing_inner", "trailing_outer")


def wheel_label(wheelset: str, side: str) -> str:
    """``"<wheelset>_<side>"``, e.g. ``"leading_inner"``."""
    return f"{wheelset}_{side}"


@dataclass(frozen=True)
class WheelOperatingPoint:
    """One wheel's operating point in a curve (SI units; frame and signs: module docstring).

    Attributes
    ----------
    label : str
        ``"leading_inner"`` ... ``"trailing_outer"``, or ``"single_inner"``, ``"single_outer"``.
    wheelset, side : str
        ``"leading"``, ``"trailing"`` or ``"single"``; ``"inner"`` or ``"outer"``.
    longitudinal_creepage, lateral_creepage : float
        ξ, η (-) of the wheel's tread contact (the one with the larger load share).
    spin : float
        φ (1/m) of that contact.
    normal_force : float
        Normal force of the tread contact(s) (N): between two rows of a profile table the sum of
        the two contacts' shares.
    wheel_load : float
        The wheel's load normal to the track plane, Q (N), tread and flange together.
    tread_load : float
        The part of the wheel load the tread's normal force carries, ``N cos δ`` (N): the
        ``operating.wheel_load`` of a squeal case at this wheel, whose static normal force is
        ``wheel_load / cos δ``.
    wheel_displacement : float
        Lateral displacement of the wheel on its rail (m), positive with the flange towards the
        rail's gauge face (``operating.lateral_displacement``): ``+y`` for the outer wheel, ``-y``
        for the inner one, y the wheelset's displacement towards the outer rail.
    wheel_lateral : float
        Contact position on the wheel from the flange back (m); NaN for a conical geometry.
    rail_lateral : float
        Contact position on the rail from its centre line (m); NaN for a conical geometry.
    contact_angle : float
        δ (rad), positive leaning towards the gauge side.
    rolling_radius : float
        (m).
    angle_of_attack : float
        ψ of the wheelset (rad), positive with its heading turned towards the outer rail.
    speed : float
        Vehicle speed V (m/s).
    flange_contact : bool
        The wheel's flange touches its rail.
    flange_force : float
        Lateral force of the flange contact pushing the wheel towards its gauge side (N); 0 without.
    friction_use : float
        ``|F| / (μ N)`` of the tread contact (-): 1 is full sliding.
    """

    label: str
    wheelset: str
    side: str
    longitudinal_creepage: float
    lateral_creepage: float
    spin: float
    normal_force: float
    wheel_load: float
    tread_load: float
    wheel_displacement: float
    wheel_lateral: float
    rail_lateral: float
    contact_angle: float
    rolling_radius: float
    angle_of_attack: float
    speed: float
    flange_contact: bool
    flange_force: float
    friction_use: float

    @property
    def creepage(self) -> tuple[float, float, float]:
        """(ξ, η, φ): -, -, 1/m."""
        return (self.longitudinal_creepage, self.lateral_creepage, self.spin)

    def to_dict(self) -> dict:
        """JSON-ready (NaN as None)."""
        return {k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in asdict(self).items()}


def _num(value) -> float:
    return math.nan if value is None else float(value)


def wheel_operating_points(result: dict) -> dict:
    """Every wheel's operating point of a steady-curving result.

    Parameters
    ----------
    result : dict
        What :func:`curving.solve_bogie` or :func:`curving.solve_wheelset` returned.

    Returns
    -------
    dict
        Label -> :class:`WheelOperatingPoint`, leading wheelset first, inner wheel before outer.

    Raises
    ------
    InputError
        If ``result`` is not such a dict (field ``curving``).
    """
    try:
        wheelsets = {w["position"]: w for w in result["wheelsets"]}
        speed = float(result["inputs"]["speed"])
        wheels = list(result["wheels"])
    except (KeyError, TypeError):
        raise InputError("curving", "expected the dict of curving.solve_bogie or curving.solve_wheelset") from None
    points = {}
    order = {"leading": 0, "single": 0, "trailing": 1, "inner": 0, "outer": 1}
    for wheel in sorted(wheels, key=lambda w: (order[w["wheelset"]], order[w["side"]])):
        wheelset = wheelsets[wheel["wheelset"]]
        sign = 1.0 if wheel["side"] == "outer" else -1.0
        treads = [c for c in wheel["contacts"] if c["kind"] == "tread"]
        main = max(treads, key=lambda c: c["load_share"])
        normal = sum(float(c["normal_force"]) for c in treads)
        angle = float(main["contact_angle"])
        label = wheel_label(wheel["wheelset"], wheel["side"])
        points[label] = WheelOperatingPoint(
            label=label, wheelset=wheel["wheelset"], side=wheel["side"],
            longitudinal_creepage=float(main["creepage"][0]), lateral_creepage=float(main["creepage"][1]),
            spin=float(main["creepage"][2]), normal_force=normal, wheel_load=float(wheel["wheel_load"]),
            tread_load=normal * math.cos(angle), wheel_displacement=sign * float(wheelset["lateral_displacement"]),
            wheel_lateral=_num(main["wheel_lateral"]), rail_lateral=_num(main["rail_lateral"]), contact_angle=angle,
            rolling_radius=float(main["rolling_radius"]), angle_of_attack=float(wheelset["angle_of_attack"]),
            speed=speed, flange_contact=any(c["kind"] == "flange" for c in wheel["contacts"]),
            flange_force=float(wheel["flange_force"]), friction_use=_num(main["friction_use"]))
    return points
