"""The ``[track]`` study section: rail material, continuous support and load patch."""

from __future__ import annotations

import dataclasses
from typing import Mapping

from squealcore.errors import InputError, require_range

__all__ = ["TrackParams"]

# field -> (low, high, low_open, unit)
_RANGES = {
    "youngs_modulus": (0.0, 1e13, True, "Pa"),
    "poisson_ratio": (0.0, 0.49, False, ""),
    "loss_factor": (0.0, 1.0, False, ""),
    "pad_vertical_stiffness": (0.0, 1e12, True, "N/m per m"),
    "pad_lateral_stiffness": (0.0, 1e12, True, "N/m per m"),
    "pad_loss_factor": (0.0, 2.0, False, ""),
    "pad_longitudinal_stiffness": (0.0, 1e12, True, "N/m per m"),
    "ballast_longitudinal_stiffness": (0.0, 1e12, True, "N/m per m"),
    "sleeper_mass": (0.0, 1e5, False, "kg/m"),
    "ballast_vertical_stiffness": (0.0, 1e12, True, "N/m per m"),
    "ballast_lateral_stiffness": (0.0, 1e12, True, "N/m per m"),
    "ballast_loss_factor": (0.0, 5.0, False, ""),
    "contact_lateral_position": (-0.05, 0.05, False, "m"),
    "load_patch_width": (0.0, 0.05, True, "m"),
    "load_patch_length": (0.0, 0.05, True, "m"),
    "max_frequency": (100.0, 2e5, False, "Hz"),
    "kernel_tolerance": (1e-8, 0.1, False, ""),
    "damping_reference_frequency": (0.1, 1e5, False, "Hz"),
    "damping_low_frequency": (0.01, 1e5, False, "Hz"),
    "damping_high_frequency": (1.0, 1e6, False, "Hz"),
}

DAMPING_MODELS = ("causal", "zener", "hysteretic")


@dataclasses.dataclass(frozen=True)
class TrackParams:
    """Rail material, continuous two-layer support and load patch (SI units).

    Attributes
    ----------
    youngs_modulus : float
        Rail Young's modulus (Pa).
    poisson_ratio : float
        Rail Poisson's ratio (-).
    loss_factor : float
        Rail loss factor (-), applied as a complex Young's modulus (see ``damping_model``).
    pad_vertical_stiffness, pad_lateral_stiffness : float
        Rail pad stiffness per metre of rail (N/m per m = N/m^2).
    pad_loss_factor : float
        Pad loss factor (-).
    pad_longitudinal_stiffness, ballast_longitudinal_stiffness : float
        Longitudinal stiffness per metre (N/m per m) of pad and ballast (*assumed* equal to
        the lateral ones); without them the rail's longitudinal receptance has no static
        limit and its kernel never decays.
    sleeper_mass : float
        Sleeper mass per metre of rail (kg/m); 0 makes pad and ballast act in series
        without mass.
    ballast_vertical_stiffness, ballast_lateral_stiffness : float
        Ballast stiffness per metre of rail (N/m per m).
    ballast_loss_factor : float
        Ballast loss factor (-).
    contact_lateral_position : float
        y of the load (contact point) on the head top (m), field side positive.
    load_patch_width, load_patch_length : float
        Lateral width and longitudinal length of the uniform load patch (m).
    max_frequency : float
        Range of the reduced cross-section model (Hz): its basis is built up to 1.25 times
        min(max_frequency, 1 / time step), and the receptances and dispersion curves of
        ``rail-greens`` end there. The moving kernel's fine frequency grid crosses over to
        coarse ones there; its grids run on to 8 / time step (the aliases of the held
        spectrum, see :mod:`waveguide.greens`), with the reduced model's continuation.
    kernel_tolerance : float
        Truncation tolerance of the moving kernel relative to its peak (-).
    supported : bool
        ``False`` removes the support (free rail, used by tests).
    damping_model : {"causal", "zener", "hysteretic"}
        How the loss factors become complex stiffnesses (:mod:`waveguide.damping`).
        ``"causal"`` (default): rail and pad as generalised Zener series (loss factor
        nearly constant over ``[damping_low_frequency, damping_high_frequency]``, storage
        stiffness nominal at ``damping_reference_frequency``), ballast as a spring with a
        viscous dashpot whose loss factor equals ``ballast_loss_factor`` at
        ``damping_reference_frequency`` (its static stiffness stays nominal; a constant loss
        factor of 1 would need a 20-fold rise of stiffness over the band).
        ``"zener"``: Zener series for all three. ``"hysteretic"``: k (1 + i eta sign omega),
        not causal.
    damping_reference_frequency : float
        Frequency (Hz) at which the storage stiffnesses equal the nominal values (and the
        viscous ballast has its nominal loss factor).
    damping_low_frequency, damping_high_frequency : float
        Band (Hz) of nearly constant loss factor of the Zener series.
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    loss_factor: float = 0.01
    pad_vertical_stiffness: float = 200e6
    pad_lateral_stiffness: float = 50e6
    pad_loss_factor: float = 0.25
    pad_longitudinal_stiffness: float = 50e6
    ballast_longitudinal_stiffness: float = 40e6
    sleeper_mass: float = 200.0
    ballast_vertical_stiffness: float = 80e6
    ballast_lateral_stiffness: float = 40e6
    ballast_loss_factor: float = 1.0
    contact_lateral_position: float = 0.0
    load_patch_width: float = 0.01
    load_patch_length: float = 0.01
    max_frequency: float = 10000.0
    kernel_tolerance: float = 1e-3
    supported: bool = True
    damping_model: str = "causal"
    damping_reference_frequency: float = 200.0
    damping_low_frequency: float = 20.0
    damping_high_frequency: float = 20000.0

    @classmethod
    def from_mapping(cls, mapping: Mapping | None, prefix: str = "track") -> "TrackParams":
        """Build and validate from a mapping (e.g. the parsed ``[track]`` TOML table).

        Unknown keys and out-of-range values raise
        :class:`~squealcore.errors.InputError` naming ``<prefix>.<key>``.
        """
        mapping = dict(mapping or {})
        kw = {}
        for key, value in mapping.items():
            field = f"{prefix}.{key}"
            if key == "supported":
                if not isinstance(value, bool):
                    raise InputError(field, f"must be true or false, got {value!r}")
                kw[key] = value
            elif key == "damping_model":
                if value not in DAMPING_MODELS:
                    raise InputError(field, f"must be one of {list(DAMPING_MODELS)}, got {value!r}")
                kw[key] = value
            elif key in _RANGES:
                lo, hi, lo_open, unit = _RANGES[key]
                kw[key] = require_range(field, value, lo, hi, low_open=lo_open, unit=unit)
            else:
                raise InputError(field, "unknown key; allowed: "
                                        f"{sorted(list(_RANGES) + ['supported', 'damping_model'])}")
        lo = kw.get("damping_low_frequency", cls.damping_low_frequency)
        hi = kw.get("damping_high_frequency", cls.damping_high_frequency)
        if not lo < hi:
            raise InputError(f"{prefix}.damping_low_frequency",
                             f"must be below damping_high_frequency = {hi:g} Hz, got {lo:g} Hz")
        return cls(**kw)

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) (Pa)."""
        return self.youngs_modulus / (2 * (1 + self.poisson_ratio))

    def support_layers(self):
        """(pad, ballast) stiffness per metre for the x, y, z directions (N/m per m)."""
        return ((self.pad_longitudinal_stiffness, self.ballast_longitudinal_stiffness),
                (self.pad_lateral_stiffness, self.ballast_lateral_stiffness),
                (self.pad_vertical_stiffness, self.ballast_vertical_stiffness))
