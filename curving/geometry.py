"""Wheel/rail contact geometry of a wheelset for steady curving.

A wheelset geometry answers, for one wheel displaced by ``y_w`` towards its flange (the frame of
:mod:`contact_geometry`: ``y_w > 0`` moves the flange towards the rail's gauge face), where the
tread touches the rail (:meth:`WheelsetGeometry.tread`), and where the flange touches it once
``y_w`` reaches the flangeway clearance (:meth:`WheelsetGeometry.flange`, at
:attr:`WheelsetGeometry.flange_limit`). For a wheelset displaced by ``y`` towards the outer rail
the outer wheel is at ``y_w = +y`` and the inner one at ``y_w = -y`` (same profiles both sides).

Two geometries:

* :class:`ConicalGeometry` — a cone of conicity λ (``r = r0 + λ y_w``, contact angle atan λ) with
  a flange contact at the flangeway clearance; for the closed-form checks;
* :class:`ProfileGeometry` — the project's rigid-profile contact search
  (:func:`contact_geometry.contact_search.contact_table`) on a fine grid of displacements: the
  tread contact between two rows is the pair of the rows' contacts with linear weights (so a
  jump of the contact point is a smooth transfer of load between the two contacts), and the
  flange limit is the first displacement at which a contact angle exceeds
  ``flange_angle_threshold``.

Every contact is a :class:`ContactGeometry` (SI units).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field, replace

import numpy as np

from contact_geometry.contact_search import WheelRailPair, contact_interval, contact_table
from contact_geometry.study import pair_from_study
from contact_geometry.track import BACK_TO_BACK, TRACK_GAUGE
from squealcore.errors import InputError, require_range

logger = logging.getLogger(__name__)

__all__ = ["ContactGeometry", "WheelsetGeometry", "ConicalGeometry", "ProfileGeometry", "profile_geometry"]

#: Largest ratio of the two relative curvatures passed to the Hertz solution: nearly conformal
#: contacts (flange root on the gauge corner) are given this ratio (semi-axis ratio about 8, inside
#: Kalker's tables, which end at 10).
MAX_CURVATURE_RATIO = 25.0


@dataclass(frozen=True)
class ContactGeometry:
    """One wheel/rail contact of a wheel (SI units).

    Attributes
    ----------
    kind : str
        ``"tread"`` or ``"flange"``.
    rolling_radius : float
        r (m).
    contact_angle : float
        δ (rad): angle of the contact normal to the vertical, positive leaning towards the wheel's
        gauge (flange) side.
    arm : float
        Lateral distance of the contact from the wheelset's centre (m).
    curvature_long, curvature_lat : float
        Relative principal curvatures, longitudinal and lateral (1/m), for the Hertz patch.
    wheel_lateral, rail_lateral : float
        Contact position on the wheel from the flange back and on the rail from its centre line
        (m); NaN for the conical geometry.
    """

    kind: str
    rolling_radius: float
    contact_angle: float
    arm: float
    curvature_long: float
    curvature_lat: float
    wheel_lateral: float = math.nan
    rail_lateral: float = math.nan

    def hertz_curvatures(self) -> tuple[float, float]:
        """Gap curvatures (A, B) (1/m), half the relative ones, the ratio kept within
        :data:`MAX_CURVATURE_RATIO` (conformal contacts)."""
        a = max(0.5 * self.curvature_long, 1e-6)
        b = 0.5 * self.curvature_lat
        b = min(max(b, a / MAX_CURVATURE_RATIO), a * MAX_CURVATURE_RATIO)
        return a, b


class WheelsetGeometry:
    """Interface of a wheelset's contact geometry (see the module docstring).

    Attributes
    ----------
    nominal_radius : float
        r0 (m), the rolling radius of the centred wheelset.
    contact_half_spacing : float
        l0 (m), the arm of the centred wheelset's tread contacts.
    flange_limit : float
        Wheel displacement y_w (m) at which the flange touches (flangeway clearance).
    """

    nominal_radius: float
    contact_half_spacing: float
    flange_limit: float

    def tread(self, y_wheel: float) -> list[tuple[float, ContactGeometry]]:
        """Tread contact(s) at a wheel displacement y_w (m): pairs (load share, contact), shares summing to 1."""
        raise NotImplementedError

    def flange(self) -> ContactGeometry:
        """The flange contact at y_w = :attr:`flange_limit`."""
        raise NotImplementedError

    def describe(self) -> dict:
        """A JSON-ready description."""
        raise NotImplementedError


@dataclass(frozen=True)
class ConicalGeometry(WheelsetGeometry):
    """Conical wheels on rails with a flange contact at the flangeway clearance (assumed defaults).

    Parameters
    ----------
    wheel_radius : float
        r0 (m), in [0.2, 0.7].
    contact_half_spacing : float
        l0 (m), in [0.5, 1.0].
    conicity : float
        λ (-), in [0, 0.5]: ``r = r0 + λ y_w``, contact angle ``atan λ``.
    flangeway_clearance : float
        Wheel displacement at which the flange touches (m), in (0, 0.03].
    flange_angle : float
        Contact angle of the flange contact (rad), in (0.3, π/2]; π/2 is a vertical flange face.
    flange_radius_offset : float
        Rolling radius of the flange contact above r0 (m), in [0, 0.04].
    flange_offset : float
        Lateral distance from the tread contact to the flange contact, towards the wheelset centre
        (m), in [0, 0.1].
    rail_crown_radius : float
        Rail head crown radius (m), in [0.05, 1]: the tread contact's lateral curvature (straight cone).
    flange_lateral_curvature : float
        Relative lateral curvature of the flange contact (1/m), in (0, 1000]: default the rail's
        R13 gauge corner in a concave R20 flange root, 1/0.013 - 1/0.020.
    """

    wheel_radius: float = 0.45
    contact_half_spacing: float = 0.75
    conicity: float = 0.05
    flangeway_clearance: float = 0.008
    flange_angle: float = 1.2
    flange_radius_offset: float = 0.015
    flange_offset: float = 0.06
    rail_crown_radius: float = 0.3
    flange_lateral_curvature: float = 1.0 / 0.013 - 1.0 / 0.020

    def __post_init__(self):
        require_range("curving.geometry.wheel_radius", self.wheel_radius, 0.2, 0.7, unit="m")
        require_range("curving.geometry.contact_half_spacing", self.contact_half_spacing, 0.5, 1.0, unit="m")
        require_range("curving.geometry.conicity", self.conicity, 0.0, 0.5, unit="-")
        require_range("curving.geometry.flangeway_clearance", self.flangeway_clearance, 0.0, 0.03,
                      low_open=True, unit="m")
        require_range("curving.geometry.flange_angle", self.flange_angle, 0.3, math.pi / 2, low_open=True, unit="rad")
        require_range("curving.geometry.flange_radius_offset", self.flange_radius_offset, 0.0, 0.04, unit="m")
        require_range("curving.geometry.flange_offset", self.flange_offset, 0.0, 0.1, unit="m")
        require_range("curving.geometry.rail_crown_radius", self.rail_crown_radius, 0.05, 1.0, unit="m")
        require_range("curving.geometry.flange_lateral_curvature", self.flange_lateral_curvature, 0.0, 1000.0,
                      low_open=True, unit="1/m")

    @property
    def nominal_radius(self) -> float:
        return self.wheel_radius

    @property
    def flange_limit(self) -> float:
        return self.flangeway_clearance

    def tread(self, y_wheel):
        # curvatures at the nominal radius: one Hertz shape (and creep model) for every y_w
        return [(1.0, ContactGeometry("tread", self.wheel_radius + self.conicity * y_wheel,
                                      math.atan(self.conicity), self.contact_half_spacing - y_wheel,
                                      1.0 / self.wheel_radius, 1.0 / self.rail_crown_radius))]

    def flange(self):
        radius = self.wheel_radius + self.flange_radius_offset
        return ContactGeometry("flange", radius, self.flange_angle,
                               self.contact_half_spacing - self.flangeway_clearance - self.flange_offset,
                               math.cos(self.flange_angle) / radius, self.flange_lateral_curvature)

    def describe(self):
        return {"kind": "conical", "wheel_radius": self.wheel_radius,
                "contact_half_spacing": self.contact_half_spacing, "conicity": self.conicity,
                "flangeway_clearance": self.flangeway_clearance, "flange_angle": self.flange_angle,
                "flange_radius_offset": self.flange_radius_offset, "flange_offset": self.flange_offset}


@dataclass(frozen=True, eq=False)
class ProfileGeometry(WheelsetGeometry):
    """The contact geometry of a wheel/rail profile pair, tabulated (see the module docstring).

    Build it with :meth:`from_pair` or :func:`profile_geometry`.

    Attributes
    ----------
    pair : WheelRailPair
    displacement : ndarray (n,)
        Wheel displacements of the table rows (m), evenly spaced.
    rows : tuple of ContactGeometry
        The tread contact (slot 0, smallest gap) of each row below the flange limit.
    flange_contact : ContactGeometry
        The flange contact at the flange limit.
    flange_limit : float
        (m).
    half_back_to_back : float
        Distance from the wheelset centre to a flange back (m).
    """

    pair: WheelRailPair
    displacement: np.ndarray
    rows: tuple
    flange_contact: ContactGeometry
    flange_limit: float
    half_back_to_back: float = 0.5 * BACK_TO_BACK
    name: str = field(default="")

    @classmethod
    def from_pair(cls, pair: WheelRailPair, step: float = 5e-5, flange_angle_threshold: float = 1.0,
                  search: float = 0.02, back_to_back: float = BACK_TO_BACK) -> "ProfileGeometry":
        """Tabulate a pair's contacts from ``-flange_limit`` to ``+flange_limit``.

        Parameters
        ----------
        pair : WheelRailPair
        step : float
            Spacing of the table rows (m), in [1e-6, 1e-3].
        flange_angle_threshold : float
            A contact steeper than this (rad) is a flange contact, in [0.2, 1.4]. The default
            1.0 rad (57°) lies between a flange root's contact angles (up to 36° for S1002 on
            60E1 at 1:40, a root contact that is part of the tread rows) and the flanks' (70° for
            S1002 and the parametric flange); 0.6 rad took that root contact for the flange, and
            the bogie, held there, found no equilibrium at R = 150 m.
        search : float
            Largest wheel displacement searched for the flange (m), in (0, 0.03].
        back_to_back : float
            Wheelset back-to-back distance (m).

        Raises
        ------
        InputError
            ``curving.geometry`` if no flange contact is found within ``search`` or the profiles
            do not meet over the table's range.
        """
        step = require_range("curving.geometry.step", step, 1e-6, 1e-3, unit="m")
        threshold = require_range("curving.geometry.flange_angle_threshold", flange_angle_threshold, 0.2, 1.4,
                                  unit="rad")
        search = require_range("curving.geometry.search", search, 0.0, 0.03, low_open=True, unit="m")
        interval = contact_interval(pair, -search, search)
        if interval is None:
            raise InputError("curving.geometry", f"the wheel profile '{pair.wheel.name}' does not meet the rail "
                             f"profile '{pair.rail.name}' within +-{search:g} m")
        coarse = np.arange(0.0, interval[1] + 0.5 * step, step)
        table = contact_table(pair, coarse)
        steep = np.nanmax(np.abs(table.contact_angle), axis=1) >= threshold
        if not steep.any():
            raise InputError("curving.geometry", f"no flange contact (contact angle >= {threshold:g} rad) within "
                             f"{coarse[-1]:.4g} m of the centred wheelset for '{pair.wheel.name}' on "
                             f"'{pair.rail.name}'")
        k = int(np.argmax(steep))
        limit = float(coarse[k])
        if -limit < interval[0]:
            raise InputError("curving.geometry", f"the wheel does not meet the rail at {-limit:.4g} m (inner wheel "
                             f"at the flange limit); contact only in [{interval[0]:.4g}, {interval[1]:.4g}] m")
        slot = int(np.nanargmax(np.abs(table.contact_angle[k])))
        flange = cls._contact(table, k, slot, "flange", 0.5 * back_to_back)
        n = int(round(limit / step))
        d = np.linspace(-limit, limit, 2 * n + 1)[:-1]  # rows below the flange limit
        rows_table = contact_table(pair, d)
        rows = tuple(cls._contact(rows_table, i, 0, "tread", 0.5 * back_to_back) for i in range(d.size))
        logger.debug("profile geometry %s / %s: flange limit %.4g m, %d rows", pair.wheel.name, pair.rail.name,
                     limit, d.size)
        return cls(pair, d, rows, flange, limit, 0.5 * back_to_back, f"{pair.wheel.name} on {pair.rail.name}")

    @staticmethod
    def _contact(table, i, slot, kind, half_b2b) -> ContactGeometry:
        wl = float(table.y_wheel[i, slot])
        return ContactGeometry(kind, float(table.rolling_radius[i, slot]), float(table.contact_angle[i, slot]),
                               half_b2b + wl, float(table.curvature_long[i, slot]),
                               float(table.curvature_lat[i, slot]), wl, float(table.y_rail[i, slot]))

    @property
    def nominal_radius(self) -> float:
        return float(self.pair.nominal_radius)

    @property
    def contact_half_spacing(self) -> float:
        return float(self.tread(0.0)[0][1].arm)

    def tread(self, y_wheel):
        d = self.displacement
        step = d[1] - d[0]
        u = (float(y_wheel) - d[0]) / step
        if u <= 0.0 or u >= d.size - 1:
            # outside the table (only while the solver iterates): the end row, its radius extrapolated
            i = 0 if u <= 0.0 else d.size - 1
            j = 1 if i == 0 else i - 1
            row = self.rows[i]
            slope = (self.rows[i].rolling_radius - self.rows[j].rolling_radius) / (d[i] - d[j])
            return [(1.0, replace(row, rolling_radius=row.rolling_radius + slope * (float(y_wheel) - d[i])))]
        i = int(math.floor(u))
        w = u - i
        return [(1.0 - w, self.rows[i]), (w, self.rows[i + 1])]

    def flange(self):
        return self.flange_contact

    def describe(self):
        return {"kind": "profiles", "profiles": self.name, "nominal_radius": self.nominal_radius,
                "contact_half_spacing": self.contact_half_spacing, "flange_limit": self.flange_limit,
                "flange_angle": self.flange_contact.contact_angle, "table_step": float(self.displacement[1]
                                                                                      - self.displacement[0])}


def profile_geometry(study, track_gauge: float = TRACK_GAUGE, **kwargs) -> ProfileGeometry:
    """The contact geometry of a study's wheel and rail profiles (``[wheel]``, ``[rail]``) for curving.

    Parameters
    ----------
    study : dict
        A validated study (e.g. ``stages.config.load_study()``).
    track_gauge : float
        Track gauge (m), in [1.0, 1.7]: places the flange back (back-to-back 1.360 m).
    **kwargs
        Passed to :meth:`ProfileGeometry.from_pair`.
    """
    track_gauge = require_range("curving.track_gauge", track_gauge, 1.0, 1.7, unit="m")
    pair = pair_from_study(study)
    if track_gauge != TRACK_GAUGE:
        # the flange back lies (gauge - back-to-back) / 2 to the gauge side of the rail's gauge point
        # (contact_geometry.track.flange_back_position): a wider gauge moves it by half the difference
        pair = replace(pair, flange_back=pair.flange_back - 0.5 * (track_gauge - TRACK_GAUGE))
    return ProfileGeometry.from_pair(pair, **kwargs)
