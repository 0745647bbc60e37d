"""The ``[map]`` study section: options of the squeal maps (``pipeline.py map``) and its grid.

The grid is the free table ``[map.grid]``: dotted configuration keys, each with a list of
values (as ``[sweep]``); every combination is one configuration, screened for every wheel model.
"""

from __future__ import annotations

from dataclasses import dataclass

from squealcore.errors import InputError
from squealcore.schema import param, section

__all__ = ["MapParams"]


@section("map")
@dataclass(frozen=True)
class MapParams:
    """Squeal maps: the rail's rational model and the stability screen (the grid is ``[map.grid]``)."""

    rail_f_min: float = param(20.0, unit="Hz", low=0.0, high=1e5, low_open=True,
                              doc="Lower end of the band the rail's receptance is fitted on.")
    rail_f_max: float = param(8000.0, unit="Hz", low=0.0, high=1e5, low_open=True,
                              doc="Upper end of that band (> rail_f_min); growing poles above it are not counted.")
    rail_frequencies: int = param(200, low=20, high=5000,
                                  doc="Log-spaced samples of the rail's receptance in the band.")
    rail_pole_pairs: int = param(30, low=2, high=200, doc="Pole pairs of the rail's vector fit.")
    rail_iterations: int = param(20, low=1, high=200, doc="Pole-relocation iterations of the vector fit.")
    min_share: float = param(0.1, low=0.0, high=1.0,
                             doc="Smallest participation of a wheel mode listed with a growing pole.")

    def cross_check(self, prefix: str = "map") -> None:
        """The rail band must be ordered (raises :class:`InputError`)."""
        if self.rail_f_max <= self.rail_f_min:
            raise InputError(f"{prefix}.rail_f_max", f"must be larger than rail_f_min = {self.rail_f_min:g} Hz, "
                                                     f"got {self.rail_f_max:g} Hz")
