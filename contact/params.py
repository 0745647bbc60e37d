"""Contact parameters: material, friction, the study's ``[contact]`` section and the case-file tables.

Both bodies (wheel and rail) are taken as quasi-identical: one combined shear modulus ``G``
and one Poisson ratio ``nu`` describe the pair, as in Kalker's theory, so that the normal and
tangential problems decouple.

The parameters shared by the study's ``[contact]`` section and the contact command's case files
(friction coefficient, Poisson ratio, Young's modulus) are declared once here
(:data:`FRICTION_COEFFICIENT`, :data:`POISSON_RATIO`, :data:`YOUNGS_MODULUS`). :class:`Material`
and :class:`Friction` are plain values built from validated parameters
(:meth:`ContactParams.to_material`, :meth:`ContactParams.to_friction` and the case file's tables in
:mod:`contact.config`); they do not check again.
"""

from __future__ import annotations

import numbers
from dataclasses import dataclass

from interaction.params import OperatingParams
from mesh.wheel_section import WheelParams
from squealcore.errors import InputError
from squealcore.schema import REQUIRED, Param, defaults, param, section

from contact.friction_law import (CHARACTERISTICS, CONSTANT_LAW, EXPONENTIAL, LINEAR, FrictionLaw, sliding_factor,
                                  sliding_factor_slope)
from contact.registry import DEFAULT_MODEL, contact_model_names

__all__ = ["Material", "Friction", "ContactParams", "CASE_SECTIONS", "CONTACT_GEOMETRY_SOURCES",
           "DEFAULT_CURVATURES", "DEFAULT_NORMAL_FORCE", "FRICTION_COEFFICIENT", "FRICTION_CHARACTERISTIC",
           "KINETIC_FRICTION", "FRICTION_REFERENCE_SPEED", "FRICTION_SLOPE", "check_characteristic", "POISSON_RATIO",
           "YOUNGS_MODULUS", "CREEPAGE", "MIN_ELEMENTS_PER_SEMI_AXIS", "MAX_GRID_SIDE", "contact_curvatures", "check_creepage"]

#: Most elements of a half-space grid along one side (the grid's own check and the case schema's).
MAX_GRID_SIDE = 2000

#: Where the contact's position, angle, rolling radius, curvatures and spin come from.
CONTACT_GEOMETRY_SOURCES = ("profiles", "manual")

FRICTION_COEFFICIENT = Param(
    "number", 0.3, low=0.0, high=5.0, low_open=True,
    doc="Coulomb friction coefficient (static; the kinetic one equals it unless given).")
"""The friction coefficient: study ``contact.friction`` and case file ``friction.coefficient``."""

FRICTION_CHARACTERISTIC = Param(
    "choice", "constant", choices=CHARACTERISTICS,
    doc="How the sliding friction coefficient depends on the sliding speed v: constant (Coulomb); "
        "exponential, mu(v) = mu_k + (mu_s - mu_k) exp(-v / v_ref) (falling); linear, "
        "mu(v) = max(mu_0 (1 + slope v), 0) (rising with a positive slope, as with a friction modifier).")
"""The friction characteristic: study ``contact.friction_characteristic``, case file ``friction.characteristic``."""

KINETIC_FRICTION = Param(
    "number", None, low=0.0, high=5.0, low_open=True,
    doc="Kinetic coefficient mu_k, <= the (static) coefficient: the sliding coefficient of the constant "
        "characteristic, the high-speed limit of the exponential one (which needs it); not with linear. "
        "Default: the coefficient.")
"""The kinetic coefficient: study ``contact.kinetic_friction``, case file ``friction.kinetic``."""

FRICTION_REFERENCE_SPEED = Param(
    "number", None, unit="m/s", low=0.0, high=1000.0, low_open=True,
    doc="Reference speed v_ref of the exponential characteristic (needed by it, not allowed with the others): "
        "mu falls from mu_s to mu_k over a few v_ref.")
"""v_ref: study ``contact.friction_reference_speed``, case file ``friction.reference_speed``."""

FRICTION_SLOPE = Param(
    "number", 0.0, unit="s/m", low=-100.0, high=100.0,
    doc="Slope of the linear characteristic (0 unless characteristic = linear): positive for a friction "
        "modifier's rising friction, negative for a falling one.")
"""The slope s of the linear characteristic: study ``contact.friction_slope``, case file ``friction.slope``."""


def check_characteristic(prefix, names, static, kinetic, characteristic, reference_speed, slope) -> None:
    """Checks between the friction keys (each range is checked by its declaration).

    Parameters
    ----------
    prefix : str
        Table of the keys (``"contact"``, ``"friction"``).
    names : dict
        Key names of ``"static"``, ``"kinetic"``, ``"characteristic"``, ``"reference_speed"``, ``"slope"``.
    static, kinetic, characteristic, reference_speed, slope
        The values (kinetic and reference_speed None when not given).

    Raises
    ------
    InputError
        Naming the key at fault and what it may be.
    """
    def key(name):
        return f"{prefix}.{names[name]}"

    if kinetic is not None and kinetic > static:
        raise InputError(key("kinetic"), f"must lie in (0, {names['static']} = {static:g}], got {kinetic:g}")
    if characteristic == "exponential":
        if kinetic is None:
            raise InputError(key("kinetic"), f"must be given, in (0, {names['static']} = {static:g}], "
                                             f"with {names['characteristic']} = exponential")
        if reference_speed is None:
            raise InputError(key("reference_speed"), "must be given, > 0 m/s, with "
                                                     f"{names['characteristic']} = exponential")
    elif reference_speed is not None:
        raise InputError(key("reference_speed"), f"applies to {names['characteristic']} = exponential only "
                                                 f"(got {characteristic})")
    if characteristic == "linear":
        if kinetic is not None:
            raise InputError(key("kinetic"), f"not with {names['characteristic']} = linear (its mu_0 is "
                                             f"{names['static']})")
    elif slope != 0.0:
        raise InputError(key("slope"), f"must be 0 unless {names['characteristic']} = linear (got {characteristic})")


POISSON_RATIO = Param("number", 0.3, low=0.0, high=0.5, high_open=True,
                      doc="Poisson's ratio of both bodies.")
"""Poisson's ratio of the contact: study ``contact.poisson_ratio`` and case file ``material.poisson_ratio``."""

YOUNGS_MODULUS = Param("number", 210e9, unit="Pa", low=0.0, high=1e13, low_open=True,
                       doc="Young's modulus of both bodies.")
"""Young's modulus of the contact: study ``contact.youngs_modulus``, case file ``material.young_modulus``."""

CREEPAGE = Param("numbers", [0.0, 0.0, 0.0], unit="-, -, 1/m", low=-1e3, high=1e3, length=3,
                 doc="Creepages [xi, eta, phi] (longitudinal, lateral, spin).")
"""The creepages of a contact case (case file ``rolling.creepage``)."""


@dataclass(frozen=True)
class Material:
    """Combined elastic constants of the two bodies (validated values; see the module doc).

    Parameters
    ----------
    shear_modulus : float
        Combined shear modulus G (Pa), > 0.
    poisson_ratio : float
        Combined Poisson ratio nu (-), in [0, 0.5).
    """

    shear_modulus: float
    poisson_ratio: float

    @property
    def contact_modulus(self) -> float:
        """Plane-strain contact modulus E* (Pa) with 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 = (1-nu)/G."""
        return self.shear_modulus / (1.0 - self.poisson_ratio)

    @classmethod
    def from_young(cls, young_modulus: float, poisson_ratio: float) -> "Material":
        """Build from Young's modulus E (Pa) and Poisson ratio (-) of one steel: G = E / (2 (1 + nu))."""
        return cls(young_modulus / (2.0 * (1.0 + poisson_ratio)), poisson_ratio)


@dataclass(frozen=True)
class Friction:
    """Friction of the contact: Coulomb (static and kinetic coefficients) or a characteristic of the sliding speed.

    Validated values (see the module doc); the characteristics are those of
    :mod:`contact.friction_law`.

    Parameters
    ----------
    static : float
        Static coefficient mu_s (-), > 0: bound of |p_t| / p_z in stick; mu_0 = mu(0) of the
        linear characteristic.
    kinetic : float or None
        Kinetic coefficient mu_k (-), in (0, mu_s]: |p_t| / p_z in slip (constant), the limit at
        high sliding speed (exponential). Default: mu_s; the linear characteristic takes mu_s.
    characteristic : str
        ``"constant"``, ``"exponential"`` or ``"linear"`` (:data:`contact.friction_law.CHARACTERISTICS`).
    reference_speed : float or None
        v_ref of the exponential characteristic, m/s, > 0 (needed by it only).
    slope : float
        s of the linear characteristic, s/m: mu(v) = max(mu_0 (1 + s v), 0).
    """

    static: float
    kinetic: float | None = None
    characteristic: str = "constant"
    reference_speed: float | None = None
    slope: float = 0.0

    def __post_init__(self):
        if self.kinetic is None or self.characteristic == "linear":
            object.__setattr__(self, "kinetic", float(self.static))

    def law(self) -> FrictionLaw:
        """The speed dependence ``φ(v)`` (rate per m/s) of ``mu(v) = kinetic * φ(v)``."""
        if self.characteristic == "exponential":
            if self.reference_speed is None:
                raise ValueError("the exponential friction characteristic needs a reference speed")
            return FrictionLaw(EXPONENTIAL, float(self.static) / float(self.kinetic) - 1.0,
                               1.0 / float(self.reference_speed))
        if self.characteristic == "linear":
            return FrictionLaw(LINEAR, 0.0, float(self.slope))
        return CONSTANT_LAW

    def coefficient(self, speed):
        """The sliding friction coefficient mu(v) (-) at sliding speeds ``speed`` (m/s; the sign is ignored)."""
        return float(self.kinetic) * sliding_factor(self.law(), speed)

    def frozen(self, speed) -> "Friction":
        """Coulomb friction with the coefficient held at ``mu(speed)`` (static = kinetic; the
        linearisations' operating point, stability/linearised_contact.py)."""
        return Friction(float(self.coefficient(speed)))

    def coefficient_slope(self, speed):
        """d mu / d v (s/m) at sliding speeds ``speed`` (m/s, >= 0): 0 for the constant characteristic."""
        return float(self.kinetic) * sliding_factor_slope(self.law(), speed)


def contact_curvatures(rolling_radius, wheel_transverse_curvature, rail_head_radius):
    """Hertz curvatures (A, B) of the gap h = A x^2 + B y^2 between wheel and rail head (1/m).

    Parameters
    ----------
    rolling_radius : float
        Wheel rolling radius (m).
    wheel_transverse_curvature : float
        Transverse curvature of the tread (1/m; negative: hollow).
    rail_head_radius : float
        Transverse radius of the rail head (m).

    Returns
    -------
    (float, float)
        ``A = 1 / (2 r0)``, ``B = (k_wheel + 1 / R_rail) / 2``.
    """
    return 0.5 / rolling_radius, 0.5 * (wheel_transverse_curvature + 1.0 / rail_head_radius)


@section("contact")
@dataclass(frozen=True)
class ContactParams:
    """Wheel/rail contact of the interaction: model, friction, creepages, profiles, grid, material."""

    model: str = param(DEFAULT_MODEL, choices=contact_model_names,
                       doc="The contact model: one of the registry's (contact/registry.py); "
                           "halfspace: Kalker-type, as in the paper; point: fast.")
    friction: float = FRICTION_COEFFICIENT.field()
    friction_characteristic: str = FRICTION_CHARACTERISTIC.field()
    kinetic_friction: float = param(0.0, low=0.0, high=5.0,
                                    doc="Kinetic coefficient mu_k, <= friction: the sliding coefficient of the constant "
                                        "characteristic, the high-speed limit of the exponential one (which needs it "
                                        "> 0); not with linear. 0 (default): not set, mu_k = friction.")
    friction_reference_speed: float = param(0.0, unit="m/s", low=0.0, high=1000.0,
                                            doc="Reference speed v_ref of the exponential characteristic (which needs "
                                                "it > 0; not with the others): mu falls from friction to "
                                                "kinetic_friction over a few v_ref. 0 (default): not set.")
    friction_slope: float = FRICTION_SLOPE.field()
    longitudinal_creepage: float = param(0.0, low=-0.5, high=0.5, doc="Longitudinal creepage xi.")
    lateral_creepage: float = param(-0.01, low=-0.5, high=0.5,
                                    doc="Lateral creepage eta, switched on at t = 0.")
    spin: float = param(0.0, unit="1/m", low=-100.0, high=100.0, doc="Spin creepage phi.")
    rail_head_radius: float = param(0.3, unit="m", low=0.0, high=100.0, low_open=True,
                                    doc="Transverse radius of the rail head.")
    wheel_transverse_curvature: float = param(0.0, unit="1/m", low=-100.0, high=100.0,
                                              doc="Transverse curvature of the tread (0: flat across; "
                                                  "negative: hollow).")
    geometry: str = param("profiles", choices=CONTACT_GEOMETRY_SOURCES,
                          doc="profiles: contact position, angle, rolling radius, curvatures and spin from the "
                              "contact-geometry stage; manual: the hand-set wheel.contact_offset, "
                              "wheel.rolling_radius, track.contact_lateral_position, contact.rail_head_radius, "
                              "contact.wheel_transverse_curvature, contact.spin and contact.contact_angle "
                              "(an override).")
    contact_angle: float = param(0.0, unit="rad", low=-1.4, high=1.4,
                                 doc="Contact angle of the hand-set contact (geometry = manual only): the "
                                     "normal's angle to the vertical, positive leaning towards the gauge side.")
    grid_dy: float = param(5e-4, unit="m", low=0.0, high=0.01, low_open=True,
                           doc="Lateral element size of the half-space grid and strip width of the point "
                               "model's strips (dx = speed x time_step).")
    point_tangential: str = param("strip", choices=("strip", "relaxation"),
                                  doc="Tangential part of the point model: strip = transient strip model (elastic "
                                      "displacements carried through the patch, stick and slip per element); "
                                      "relaxation = the former saturated creep law on relaxed creepages (overshoots "
                                      "stick/slip limit cycles into bouncing; kept for comparison).")
    youngs_modulus: float = YOUNGS_MODULUS.field()
    poisson_ratio: float = POISSON_RATIO.field()

    #: Key names of the friction in this table (:func:`check_characteristic`).
    FRICTION_KEYS = {"static": "friction", "kinetic": "kinetic_friction", "characteristic": "friction_characteristic",
                     "reference_speed": "friction_reference_speed", "slope": "friction_slope"}

    def cross_check(self, prefix: str = "contact") -> None:
        """A hollow tread must curve less than the rail head; the friction keys fit together
        (:func:`check_characteristic`). Raises :class:`InputError`."""
        check_characteristic(prefix, self.FRICTION_KEYS, self.friction, self._given(self.kinetic_friction),
                             self.friction_characteristic, self._given(self.friction_reference_speed),
                             self.friction_slope)
        if self.rail_head_radius * self.wheel_transverse_curvature <= -1.0:
            raise InputError(f"{prefix}.wheel_transverse_curvature",
                             "a hollow tread must curve less than the rail head "
                             f"(must be > -1/rail_head_radius = {-1.0 / self.rail_head_radius:g} 1/m)")

    def to_material(self) -> Material:
        """The contact's :class:`Material` (G from Young's modulus and Poisson's ratio)."""
        return Material.from_young(self.youngs_modulus, self.poisson_ratio)

    def to_friction(self) -> Friction:
        """The contact's :class:`Friction` (static ``friction``; kinetic ``kinetic_friction``, default the same)."""
        return Friction(self.friction, self._given(self.kinetic_friction), self.friction_characteristic,
                        self._given(self.friction_reference_speed), self.friction_slope)

    @staticmethod
    def _given(value):
        """A study's optional friction value: 0 stands for not set (a study's keys all have a default)."""
        return None if value == 0.0 else value


def check_creepage(creepage) -> tuple[float, float, float]:
    """Return the creepages (xi, eta, phi) as floats; xi, eta (-), spin phi (1/m), checked by :data:`CREEPAGE`.

    Raises
    ------
    InputError
        Naming ``rolling.creepage``.
    """
    try:
        values = [float(v) if isinstance(v, numbers.Real) and not isinstance(v, bool) else v for v in creepage]
    except TypeError:
        raise InputError("rolling.creepage", f"must be {CREEPAGE.allowed()}, got {creepage!r}") from None
    return tuple(CREEPAGE.check("rolling.creepage", values))


# ---- the tables of a contact case file (pipeline.py contact CASE.toml) ----

CASE_KINDS = ("steady", "transient", "shift")

#: Default geometry: the default study's contact (rolling radius, flat tread, rail head radius), 1/m.
DEFAULT_CURVATURES = list(contact_curvatures(defaults(WheelParams)["rolling_radius"],
                                             defaults(ContactParams)["wheel_transverse_curvature"],
                                             defaults(ContactParams)["rail_head_radius"]))
#: Default load: the default study's wheel load (N).
DEFAULT_NORMAL_FORCE = defaults(OperatingParams)["wheel_load"]
#: Default shear modulus (Pa) when neither shear_modulus nor young_modulus is given.
DEFAULT_SHEAR_MODULUS = 82e9


@section("")
@dataclass(frozen=True)
class CaseTop:
    """Model and kind of problem."""

    model: str = param(REQUIRED, kind="choice", choices=contact_model_names,
                       doc="halfspace: Kalker-type grid model; point: one-point model.")
    kind: str = param("steady", choices=CASE_KINDS,
                      doc="steady rolling, transient rolling (creepage switched on at step 1), or shift "
                          "(Cattaneo-Mindlin shifts, half-space only).")


@section("geometry")
@dataclass(frozen=True)
class GeometryTable:
    """Undeformed gap between the bodies: give at most one key."""

    semi_axes: list | None = param(None, kind="numbers", length=2, unit="m", low=0.0, low_open=True,
                                   doc="Hertz semi-axes [a, b] at the given load.")
    curvatures: list | None = param(None, kind="numbers", length=2, unit="1/m", low=0.0, low_open=True,
                                    doc="[A, B] of the gap h = A x^2 + B y^2. Default, when no geometry is "
                                        f"given: [{DEFAULT_CURVATURES[0]:.6g}, {DEFAULT_CURVATURES[1]:.6g}], "
                                        "the default study's contact (rolling radius 0.39 m, rail head radius 0.3 m).")
    gap_file: str | None = param(None, kind="string",
                                 doc="CSV of the gap (m) on the grid, nx rows x ny columns, relative to the case "
                                     "file (half-space model; needs grid.dx and grid.dy).")

    def cross_check(self, prefix: str = "geometry") -> None:
        """At most one of the three descriptions."""
        if len(self.given()) > 1:
            raise InputError(prefix, "must have at most one of semi_axes (m), curvatures (1/m), gap_file")

    def given(self) -> list:
        """Names of the keys given."""
        return [k for k in ("semi_axes", "curvatures", "gap_file") if getattr(self, k) is not None]


@section("material")
@dataclass(frozen=True)
class MaterialTable:
    """Elastic constants of both bodies: give shear_modulus or young_modulus."""

    shear_modulus: float | None = param(None, kind="number", unit="Pa", low=0.0, high=1e13, low_open=True,
                                        doc=f"Combined shear modulus G (default {DEFAULT_SHEAR_MODULUS:g} Pa "
                                            "unless young_modulus is given).")
    young_modulus: float | None = YOUNGS_MODULUS.field(default=None)
    poisson_ratio: float = POISSON_RATIO.field(default=0.28)

    def cross_check(self, prefix: str = "material") -> None:
        """Not both moduli."""
        if self.shear_modulus is not None and self.young_modulus is not None:
            raise InputError(prefix, "must have shear_modulus or young_modulus (Pa), not both")

    def to_material(self) -> Material:
        """The :class:`Material` of the case."""
        if self.young_modulus is not None:
            return Material.from_young(self.young_modulus, self.poisson_ratio)
        shear = DEFAULT_SHEAR_MODULUS if self.shear_modulus is None else self.shear_modulus
        return Material(shear, self.poisson_ratio)


MIN_ELEMENTS_PER_SEMI_AXIS = 5
"""A half-space grid whose elements resolve a Hertz semi-axis by fewer than this many gets a
WARNING (contact/config.py): its forces are then a few elements' and can be far from
the continuous solution (the contact benchmark's grids and the default study's use about 10 per
semi-axis)."""


@section("grid")
@dataclass(frozen=True)
class GridTable:
    """Grid of the half-space model: number of elements or element size per direction."""

    nx: int | None = param(None, kind="integer", low=3, high=MAX_GRID_SIDE,
                           doc="Elements along x over the Hertz patch + 10 % (default 40, or from dx).")
    ny: int | None = param(None, kind="integer", low=3, high=MAX_GRID_SIDE,
                           doc="Elements along y over the Hertz patch + 10 % (default 40, or from dy).")
    dx: float | None = param(None, kind="number", unit="m", low=0.0, high=1.0, low_open=True,
                             doc="Element size along x (with a size alone, one more element on each side); "
                                 f"fewer than {MIN_ELEMENTS_PER_SEMI_AXIS} elements per Hertz semi-axis get a "
                                 "warning.")
    dy: float | None = param(None, kind="number", unit="m", low=0.0, high=1.0, low_open=True,
                             doc="Element size along y.")
    extent: list | None = param(None, kind="numbers", length=2, unit="m", low=0.0, high=1.0, low_open=True,
                                doc="Explicit grid as in CONTACT: its size [Lx, Ly], centred on the contact "
                                    "point, divided into nx x ny elements (or elements of dx x dy) exactly as "
                                    "given; the contact may reach the border elements (a warning says so).")


@section("load")
@dataclass(frozen=True)
class LoadTable:
    """Normal load: give normal_force or approach."""

    normal_force: float | None = param(None, kind="number", unit="N", low=0.0, high=1e8, low_open=True,
                                       doc=f"Normal force (default {DEFAULT_NORMAL_FORCE:g} N, the default "
                                           "study's wheel load, unless approach is given).")
    approach: float | None = param(None, kind="number", unit="m", low=0.0, high=0.01, low_open=True,
                                   doc="Approach of the bodies instead of the force.")

    def cross_check(self, prefix: str = "load") -> None:
        """Not both."""
        if self.normal_force is not None and self.approach is not None:
            raise InputError(prefix, "must have normal_force (N) or approach (m), not both")

    def solve_arguments(self) -> dict:
        """``{"normal_force": F}`` or ``{"approach": d}`` for the model's ``solve``."""
        if self.approach is not None:
            return {"approach": self.approach}
        return {"normal_force": DEFAULT_NORMAL_FORCE if self.normal_force is None else self.normal_force}


@section("friction")
@dataclass(frozen=True)
class FrictionTable:
    """Friction: Coulomb, or a characteristic of the sliding speed (contact/friction_law.py)."""

    coefficient: float = FRICTION_COEFFICIENT.field()
    kinetic: float | None = KINETIC_FRICTION.field()
    characteristic: str = FRICTION_CHARACTERISTIC.field()
    reference_speed: float | None = FRICTION_REFERENCE_SPEED.field()
    slope: float = FRICTION_SLOPE.field()

    #: Key names of the friction in this table (:func:`check_characteristic`).
    FRICTION_KEYS = {"static": "coefficient", "kinetic": "kinetic", "characteristic": "characteristic",
                     "reference_speed": "reference_speed", "slope": "slope"}

    def cross_check(self, prefix: str = "friction") -> None:
        """The keys fit together (:func:`check_characteristic`): e.g. the kinetic coefficient may not exceed the static one."""
        check_characteristic(prefix, self.FRICTION_KEYS, self.coefficient, self.kinetic, self.characteristic,
                             self.reference_speed, self.slope)

    def to_friction(self) -> Friction:
        """The :class:`Friction` of the case."""
        return Friction(self.coefficient, self.kinetic, self.characteristic, self.reference_speed, self.slope)


@section("rolling")
@dataclass(frozen=True)
class RollingTable:
    """Rolling: creepages, speed and number of steps."""

    creepage: list = CREEPAGE.field()
    speed: float = param(30.0, unit="m/s", low=0.0, high=1000.0, low_open=True, doc="Rolling speed.")
    steps: int = param(1, low=1, high=100000, doc="Number of steps solved.")
    time_step: float | None = param(None, kind="number", unit="s", low=0.0, high=1.0, low_open=True,
                                    doc="Time step of the point model (default: grid dx / speed).")


@section("shift")
@dataclass(frozen=True)
class ShiftTable:
    """Rigid shift per step (kind = "shift" only)."""

    displacement: list = param([0.0, 0.0, 0.0], unit="m, m, rad", low=-1.0, high=1.0,
                               doc="Shift [sx, sy, rotation] per step.")


#: The tables of a case file (contact.config reads them), top level first.
CASE_SECTIONS = (CaseTop, GeometryTable, MaterialTable, GridTable, LoadTable, FrictionTable, RollingTable,
                 ShiftTable)
