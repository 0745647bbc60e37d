"""Material and friction parameters of the contact, with input checks.

Both bodies (wheel and rail) are taken as quasi-identical: one combined shear modulus ``G``
and one Poisson ratio ``nu`` describe the pair, as in Kalker's theory, so that the normal and
tangential problems decouple.
"""

from __future__ import annotations

from dataclasses import dataclass

from squealcore.errors import InputError, require_range


@dataclass(frozen=True)
class Material:
    """Combined elastic constants of the two bodies.

    Parameters
    ----------
    shear_modulus : float
        Combined shear modulus G (Pa), > 0.
    poisson_ratio : float
        Combined Poisson ratio nu (-), in [0, 0.5).
    """

    shear_modulus: float
    poisson_ratio: float

    def __post_init__(self):
        require_range("material.shear_modulus", self.shear_modulus, 0.0, None, low_open=True, unit="Pa")
        require_range("material.poisson_ratio", self.poisson_ratio, 0.0, 0.5, high_open=True)

    @property
    def contact_modulus(self) -> float:
        """Plane-strain contact modulus E* (Pa) with 1/E* = (1-nu1^2)/E1 + (1-nu2^2)/E2 = (1-nu)/G."""
        return self.shear_modulus / (1.0 - self.poisson_ratio)

    @classmethod
    def from_young(cls, young_modulus: float, poisson_ratio: float) -> "Material":
        """Build from Young's modulus E (Pa) and Poisson ratio (-) of one steel: G = E / (2 (1 + nu))."""
        require_range("material.young_modulus", young_modulus, 0.0, None, low_open=True, unit="Pa")
        return cls(young_modulus / (2.0 * (1.0 + poisson_ratio)), poisson_ratio)


@dataclass(frozen=True)
class Friction:
    """Coulomb friction with separate static and kinetic coefficients.

    Parameters
    ----------
    static : float
        Static coefficient mu_s (-), >= 0: bound of |p_t| / p_z in stick.
    kinetic : float or None
        Kinetic coefficient mu_k (-), in [0, mu_s]: |p_t| / p_z in slip. Default: mu_s.
    """

    static: float
    kinetic: float | None = None

    def __post_init__(self):
        require_range("friction.coefficient", self.static, 0.0, None)
        if self.kinetic is None:
            object.__setattr__(self, "kinetic", float(self.static))
        require_range("friction.kinetic", self.kinetic, 0.0, self.static)


def check_creepage(creepage) -> tuple[float, float, float]:
    """Return the creepages (xi, eta, phi) as floats; xi, eta (-), spin phi (1/m)."""
    try:
        values = tuple(creepage)
    except TypeError:
        raise InputError("rolling.creepage", f"must be [xi, eta, phi], got {creepage!r}") from None
    if len(values) != 3:
        raise InputError("rolling.creepage", f"must have 3 entries [xi, eta, phi], got {len(values)}")
    names = ("xi", "eta", "phi")
    return tuple(require_range(f"rolling.creepage.{n}", v, -1.0e3, 1.0e3) for n, v in zip(names, values))
