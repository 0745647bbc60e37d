"""The ``[geometry]`` study section: the displacement range of the contact-geometry tables.

The operating point itself is ``[operating] lateral_displacement`` (interaction/params.py).
"""

from __future__ import annotations

from dataclasses import dataclass

from squealcore.errors import InputError
from squealcore.schema import param, section

__all__ = ["GeometryParams", "MAX_DISPLACEMENT"]

#: Largest lateral wheel displacement on the rail considered anywhere (m).
MAX_DISPLACEMENT = 0.02


@section("geometry")
@dataclass(frozen=True)
class GeometryParams:
    """Contact-geometry tables over the lateral displacement of the wheel on the rail (stage contact-geometry)."""

    displacement_min: float = param(-0.010, unit="m", low=-MAX_DISPLACEMENT, high=MAX_DISPLACEMENT,
                                    doc="Smallest lateral wheel displacement of the tables (negative: "
                                        "towards the field side).")
    displacement_max: float = param(0.010, unit="m", low=-MAX_DISPLACEMENT, high=MAX_DISPLACEMENT,
                                    doc="Largest lateral wheel displacement of the tables (positive: flange "
                                        "towards the rail's gauge face); > displacement_min.")
    displacement_count: int = param(201, low=2, high=10001,
                                    doc="Number of displacements of the tables, evenly spaced.")
    conicity_amplitude: float = param(0.003, unit="m", low=0.0, high=MAX_DISPLACEMENT, low_open=True,
                                      doc="Amplitude of the lateral wheelset motion at which the equivalent "
                                          "conicity is evaluated (EN 15302 reports 3 mm).")
    two_point_tolerance: float = param(1e-5, unit="m", low=0.0, high=1e-3,
                                       doc="A second local closest approach within this vertical gap of the "
                                           "first counts as a second contact (two-point contact).")

    def cross_check(self, prefix: str = "geometry") -> None:
        """The displacement range must be ordered (raises :class:`InputError`)."""
        if self.displacement_max <= self.displacement_min:
            raise InputError(f"{prefix}.displacement_max",
                             f"must be larger than displacement_min = {self.displacement_min:g} m, "
                             f"got {self.displacement_max:g} m")
