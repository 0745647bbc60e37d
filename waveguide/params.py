"""The ``[track]`` study section: rail material, continuous support and load patch."""

from __future__ import annotations

import dataclasses

from squealcore.errors import InputError
from squealcore.schema import param, section

__all__ = ["TrackParams"]

DAMPING_MODELS = ("causal", "zener", "hysteretic")

STIFFNESS = "N/m per m"


@section("track")
@dataclasses.dataclass(frozen=True)
class TrackParams:
    """Rail material, continuous two-layer support and load patch (the ``[track]`` study section).

    How the loss factors become complex stiffnesses (``damping_model``, :mod:`waveguide.damping`):
    ``"causal"`` (default): rail and pad as generalised Zener series (loss factor nearly constant
    over ``[damping_low_frequency, damping_high_frequency]``, storage stiffness nominal at
    ``damping_reference_frequency``), ballast as a spring with a viscous dashpot whose loss factor
    equals ``ballast_loss_factor`` at ``damping_reference_frequency`` (its static stiffness stays
    nominal; a constant loss factor of 1 would need a 20-fold rise of stiffness over the band).
    ``"zener"``: Zener series for all three. ``"hysteretic"``: k (1 + i eta sign omega), not causal.

    ``max_frequency`` is the range of the reduced cross-section model: its basis is built up to
    1.25 min(max_frequency, 1 / time step), and the receptances and dispersion curves of
    ``rail-greens`` end there. The moving kernel's fine frequency grid crosses over to coarse ones
    there; its grids run on to 8 / time step (the aliases of the held spectrum, see
    :mod:`waveguide.greens`), with the reduced model's continuation.
    """

    youngs_modulus: float = param(210e9, unit="Pa", low=0.0, high=1e13, low_open=True,
                                  doc="Rail Young's modulus.")
    poisson_ratio: float = param(0.3, low=0.0, high=0.49, doc="Rail Poisson's ratio.")
    loss_factor: float = param(0.01, low=0.0, high=1.0,
                               doc="Rail loss factor, applied as a complex Young's modulus (see damping_model).")
    pad_vertical_stiffness: float = param(200e6, unit=STIFFNESS, low=0.0, high=1e12, low_open=True,
                                          doc="Rail pad vertical stiffness per metre of rail.")
    pad_lateral_stiffness: float = param(50e6, unit=STIFFNESS, low=0.0, high=1e12, low_open=True,
                                         doc="Rail pad lateral stiffness per metre of rail.")
    pad_loss_factor: float = param(0.25, low=0.0, high=2.0, doc="Pad loss factor.")
    pad_longitudinal_stiffness: float = param(
        50e6, unit=STIFFNESS, low=0.0, high=1e12, low_open=True,
        doc="Pad longitudinal stiffness per metre; without it the rail's longitudinal receptance has "
            "no static limit and its kernel never decays.")
    ballast_longitudinal_stiffness: float = param(40e6, unit=STIFFNESS, low=0.0, high=1e12, low_open=True,
                                                  doc="Ballast longitudinal stiffness per metre.")
    sleeper_mass: float = param(200.0, unit="kg/m", low=0.0, high=1e5,
                                doc="Sleeper mass per metre of rail; 0 makes pad and ballast act in series "
                                    "without mass.")
    ballast_vertical_stiffness: float = param(80e6, unit=STIFFNESS, low=0.0, high=1e12, low_open=True,
                                              doc="Ballast vertical stiffness per metre of rail.")
    ballast_lateral_stiffness: float = param(40e6, unit=STIFFNESS, low=0.0, high=1e12, low_open=True,
                                             doc="Ballast lateral stiffness per metre of rail.")
    ballast_loss_factor: float = param(1.0, low=0.0, high=5.0, doc="Ballast loss factor.")
    contact_lateral_position: float = param(0.0, unit="m", low=-0.05, high=0.05,
                                            doc="y of the load (contact point) on the head top, field side positive.")
    load_patch_width: float = param(0.01, unit="m", low=0.0, high=0.05, low_open=True,
                                    doc="Lateral width of the uniform load patch.")
    load_patch_length: float = param(0.01, unit="m", low=0.0, high=0.05, low_open=True,
                                     doc="Longitudinal length of the uniform load patch.")
    max_frequency: float = param(10000.0, unit="Hz", low=100.0, high=2e5,
                                 doc="Range of the reduced rail model (the moving kernel's grids run on to "
                                     "8 / time step).")
    kernel_tolerance: float = param(1e-3, low=1e-8, high=0.1,
                                    doc="The moving kernel is truncated where its tail is below this fraction "
                                        "of its peak.")
    supported: bool = param(True, doc="false removes the support (free rail, used by tests).")
    damping_model: str = param("causal", choices=DAMPING_MODELS,
                               doc="How loss factors become complex stiffnesses: causal (default), zener, "
                                   "or hysteretic (not causal); see the class documentation.")
    damping_reference_frequency: float = param(200.0, unit="Hz", low=0.1, high=1e5,
                                               doc="Frequency at which the storage stiffnesses are nominal.")
    damping_low_frequency: float = param(20.0, unit="Hz", low=0.01, high=1e5,
                                         doc="Lower end of the band of constant loss factor of the Zener series.")
    damping_high_frequency: float = param(20000.0, unit="Hz", low=1.0, high=1e6,
                                          doc="Upper end of the band of constant loss factor of the Zener series.")

    def cross_check(self, prefix: str = "track") -> None:
        """The damping band must be ordered (raises :class:`InputError`)."""
        if not self.damping_low_frequency < self.damping_high_frequency:
            raise InputError(f"{prefix}.damping_low_frequency",
                             f"must be below damping_high_frequency = {self.damping_high_frequency:g} Hz, "
                             f"got {self.damping_low_frequency:g} Hz")

    @property
    def shear_modulus(self) -> float:
        """G = E / (2 (1 + nu)) (Pa)."""
        return self.youngs_modulus / (2 * (1 + self.poisson_ratio))

    def support_layers(self):
        """(pad, ballast) stiffness per metre for the x, y, z directions (N/m per m)."""
        return ((self.pad_longitudinal_stiffness, self.ballast_longitudinal_stiffness),
                (self.pad_lateral_stiffness, self.ballast_lateral_stiffness),
                (self.pad_vertical_stiffness, self.ballast_vertical_stiffness))
