"""The ``[curve]`` study section: a curve and a bogie whose steady curving feeds the squeal cases.

With ``curve.enabled = true`` the cases take one wheel's operating point (``curve.wheel``) from the
quasi-static steady curving of a two-axle bogie on the study's wheel and rail profiles
(:mod:`curving`, docs/design.md §4.11): its creepages, the tread's normal load and the lateral
position of the wheel on its rail replace the hand-set ``contact.*`` and ``operating.*`` values
(:mod:`stages.curve`). The bogie's defaults are :class:`curving.CurvingParams`' (a metro bogie:
2.5 m wheelbase, 100 kN axle load, rigid).
"""

from __future__ import annotations

from dataclasses import dataclass

from squealcore.errors import InputError
from squealcore.schema import param, section

__all__ = ["CurveParams", "WHEELS"]

#: The wheels of the bogie (curving.WHEEL_LABELS), leading wheelset first.
WHEELS = ("leading_inner", "leading_outer", "trailing_inner", "trailing_outer")


@section("curve")
@dataclass(frozen=True)
class CurveParams:
    """A curve and a bogie: with enabled = true, the cases take one wheel's creepages, load and contact position from its steady curving."""

    enabled: bool = param(False, doc="Feed the cases from the curve: contact.longitudinal_creepage, "
                                     "contact.lateral_creepage, contact.spin, operating.wheel_load, "
                                     "operating.lateral_displacement (and operating.speed with curve.speed) come "
                                     "from the steady curving of the bogie for curve.wheel; setting one of them "
                                     "by hand too is an error. Needs contact.geometry = \"profiles\".")
    radius: float = param(300.0, unit="m", low=20.0, high=1e5, doc="Curve radius.")
    speed: float = param(0.0, unit="m/s", low=0.0, high=100.0,
                         doc="Vehicle speed in the curve; 0 (default): the study's operating.speed. Given, it is "
                             "also the cases' operating.speed.")
    cant: float = param(0.0, unit="m", low=0.0, high=0.2, doc="Cant: height of the outer rail above the inner one.")
    wheel: str = param(WHEELS[0], choices=WHEELS,
                       doc="The wheel whose operating point feeds the cases (the leading inner wheel squeals "
                           "most often in the field).")
    wheelbase: float = param(2.5, unit="m", low=1.0, high=4.0, doc="Bogie wheelbase.")
    axle_load: float = param(100e3, unit="N", low=1e3, high=5e5,
                             doc="Vertical load per axle on level track at rest (wheelset and its share of frame "
                                 "and body).")
    centre_of_gravity_height: float = param(1.2, unit="m", low=0.0, high=3.0,
                                            doc="Height above the rails of the mass the axles carry (quasi-static "
                                                "load transfer to the outer wheel).")
    rigid_bogie: bool = param(True, doc="Rigid bogie (frame and wheelsets one body); false: the primary "
                                        "suspension's stiffnesses below.")
    longitudinal_stiffness: float = param(1e7, unit="N/m", low=1e4, high=1e10,
                                          doc="Primary longitudinal stiffness per axle box (rigid_bogie = false "
                                              "only).")
    lateral_stiffness: float = param(5e6, unit="N/m", low=1e4, high=1e10,
                                     doc="Primary lateral stiffness per axle box (rigid_bogie = false only).")
    axlebox_half_spacing: float = param(1.0, unit="m", low=0.5, high=1.5,
                                        doc="Half the lateral distance between a wheelset's axle boxes.")
    friction: float = param(0.3, low=0.0, high=1.0, low_open=True,
                            doc="Friction coefficient of the tread contacts in the curving solution (the cases' "
                                "own is contact.friction, so a friction sweep of the cases runs on one curving "
                                "solution).")
    flange_friction: float = param(-1.0, low=-1.0, high=1.0,
                                   doc="Friction coefficient of flange contacts; -1 (default): curve.friction; "
                                       "0: a lubricated flange.")
    track_gauge: float = param(1.435, unit="m", low=1.0, high=1.7,
                               doc="Track gauge (places the flange backs: wheelset back-to-back 1.360 m).")

    def cross_check(self, prefix: str = "curve") -> None:
        """``flange_friction`` is -1 or in [0, 1] (raises :class:`InputError`)."""
        if self.flange_friction < 0.0 and self.flange_friction != -1.0:
            raise InputError(f"{prefix}.flange_friction",
                             f"must be -1 (curve.friction) or lie in [0, 1], got {self.flange_friction:g}")
