"""An independent check of the contact geometry: brute-force contact on the exact profiles.

The contact search of :mod:`contact_geometry.contact_search` works on splines through sampled
profiles (the S1002 data file at 0.05 mm, the rail outline polygon at 0.25 mm) with a 0.1 mm
grid refined by Newton steps. This module computes the same quantities a different way, for the
S1002 wheel on a published rail head (``profiles/data/rail_heads.json``), so that the two can be
compared (``tests/test_conicity_reference.py``, ``benchmarks/conicity_reference.py``):

* **wheel**: the S1002 piecewise definition (:func:`profiles.s1002.s1002_height`) evaluated exactly,
  not the sampled data file;
* **rail**: the head built here from the published radii and tangent points of the JSON entry
  (crown arc centred on the rail axis, shoulder and corner arcs each tangent to the previous one,
  the corner arc tangent to the flank widening 1:``flank_slope`` downwards), turned by the
  inclination 1:n about the top of the upright head on its axis, the gauge side going down;
  its height ``z(y)`` is evaluated exactly (arcs and lines, no polygon, no spline);
* **placement**: as :func:`contact_geometry.track.flange_back_position` prescribes (gauge
  1435 mm measured 14 mm below the top of the inclined head, back-to-back 1360 mm), the gauge
  point found on the exact head by bisection;
* **contact**: for each lateral wheel displacement the wheel is lowered onto the rail and the
  contact is the largest value of ``f = z_rail(y) + z_wheel(y - y0)`` (the smallest vertical
  gap) over a dense lateral grid, by plain ``argmax`` (no Newton step, no spline), vectorised
  with numpy;
* **wheelset**: the same kinematics as :mod:`contact_geometry.wheelset`: rigid wheelset, roll
  neglected, each wheel lowered onto its rail on its own, ``dr(y) = r(+y) - r(-y)``, and the
  equivalent conicity by the same harmonic linearisation (:func:`equivalent_conicity`).

Grid error: with a lateral step ``h`` the contact found lies within ``h/2`` of the true largest
value of ``f`` where that maximum is single, so the rolling radius is off by at most
``|z_w'| h / 2`` (0.02 um on the tread for h = 1 um, 1.4 um on the 70 deg flange face). Near a
contact jump (two maxima of equal height) the side chosen may differ from the spline search's
over one displacement step.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

import numpy as np

from profiles.rail_section import HEADS_FILE
from profiles.s1002 import S1002_TAPE_OFFSET, s1002_height

__all__ = ["ExactRailHead", "exact_s1002", "BruteForceContacts", "brute_force_contacts", "brute_force_dr",
           "harmonic_conicity", "brute_force_conicity", "RAIL_HEADS_FILE", "GAUGE", "BACK_TO_BACK",
           "GAUGE_DEPTH"]

#: The published rail heads (radii and tangent points, mm).
RAIL_HEADS_FILE = HEADS_FILE
#: Nominal track gauge (m), measured GAUGE_DEPTH below the top of the rail (EN 13848-1).
GAUGE = 1.435
#: Nominal wheelset back-to-back distance (m).
BACK_TO_BACK = 1.360
#: Depth below the top of the rail at which the gauge is measured (m).
GAUGE_DEPTH = 0.014
#: Lateral extent of the S1002 definition used (m, from the flange back): as the shipped data
#: file, the vertical first 0.5 mm of the flange back left out.
S1002_RANGE = (0.0005, 0.130)
#: Depth of flank kept below the corner tangent point (m): the head is used down to here.
FLANK_LENGTH = 0.010


def exact_s1002(y_wheel):
    """S1002 radial height (m) above the tape circle at ``y_wheel`` (m from the flange back)."""
    return s1002_height((np.asarray(y_wheel, dtype=float) - S1002_TAPE_OFFSET) * 1e3) * 1e-3


@dataclass(frozen=True)
class _Piece:
    """One piece of the head surface between ``y_lo`` and ``y_hi`` (m): an arc (upper half of the
    circle of centre ``c`` and ``radius``) or a line through ``c`` with slope ``slope``."""

    y_lo: float
    y_hi: float
    c: tuple
    radius: float = 0.0
    slope: float = 0.0

    def height(self, y):
        if self.radius > 0.0:
            return self.c[1] + np.sqrt(np.clip(self.radius**2 - (y - self.c[0]) ** 2, 0.0, None))
        return self.c[1] + self.slope * (y - self.c[0])


class ExactRailHead:
    """The upper surface of a published rail head, inclined 1:n, evaluated exactly.

    Frame (m): ``y`` lateral from the rail's centre line, positive towards the field side; ``z``
    up, 0 at the top of the upright head on its axis (the pivot of the inclination).

    Parameters
    ----------
    profile : str
        A key of ``profiles/data/rail_heads.json`` (``"60E1"``).
    inclination : int
        n of the inclination 1:n (0: upright).
    """

    def __init__(self, profile: str = "60E1", inclination: int = 40):
        entry = json.loads(RAIL_HEADS_FILE.read_text(encoding="utf-8"))[profile]
        mm = {k: float(entry[k]) * 1e-3 for k in ("crown_radius", "crown_half_width", "shoulder_radius",
                                                   "shoulder_half_width", "corner_radius", "head_half_width")}
        r1, r2, r3 = mm["crown_radius"], mm["shoulder_radius"], mm["corner_radius"]
        n_flank = float(entry["flank_slope"])
        # field side, upright; angles from the vertical, positions (sin t, cos t) on each arc
        c1 = np.array([0.0, -r1])
        t1 = math.asin(mm["crown_half_width"] / r1)
        c2 = c1 + (r1 - r2) * np.array([math.sin(t1), math.cos(t1)])
        t2 = math.asin((mm["shoulder_half_width"] - c2[0]) / r2)
        c3 = c2 + (r2 - r3) * np.array([math.sin(t2), math.cos(t2)])
        t3 = math.atan2(1.0, 1.0 / n_flank)  # the corner's normal is the flank's: tangency
        tangent = c3 + r3 * np.array([math.sin(t3), math.cos(t3)])
        self.name = f"exact {profile} head 1:{inclination}" if inclination else f"exact {profile} head upright"
        self.profile, self.inclination = profile, inclination
        self.corner_flank_point = tangent  # upright, field side (m)
        alpha = math.atan(1.0 / inclination) if inclination else 0.0
        self.tilt = alpha
        ca, sa = math.cos(alpha), math.sin(alpha)

        def turn(p):  # counter-clockwise about the origin: the field side rises
            return np.array([ca * p[0] - sa * p[1], sa * p[0] + ca * p[1]])

        pieces = []
        for side in (-1.0, 1.0):
            mirror = np.array([side, 1.0])
            for c, r, lo, hi in ((c2, r2, t1, t2), (c3, r3, t2, t3)):
                cc = turn(c * mirror)
                a, b = side * lo - alpha, side * hi - alpha
                ys = sorted((cc[0] + r * math.sin(a), cc[0] + r * math.sin(b)))
                pieces.append(_Piece(ys[0], ys[1], tuple(cc), radius=r))
            start = turn(tangent * mirror)
            end = turn((tangent + FLANK_LENGTH * np.array([1.0 / n_flank, -1.0])) * mirror)
            ys = sorted((start[0], end[0]))
            pieces.append(_Piece(ys[0], ys[1], tuple(start), slope=(end[1] - start[1]) / (end[0] - start[0])))
        cc = turn(c1)
        pieces.append(_Piece(cc[0] + r1 * math.sin(-t1 - alpha), cc[0] + r1 * math.sin(t1 - alpha), tuple(cc),
                             radius=r1))
        pieces.sort(key=lambda p: p.y_lo)
        self.pieces = pieces
        self.bounds = (pieces[0].y_lo, pieces[-1].y_hi)
        # the highest point: the top of the turned crown circle (it lies on the crown arc)
        self.top = (cc[0], cc[1] + r1)

    def height(self, y):
        """Head height z (m) at ``y`` (m), sorted or not; NaN outside :attr:`bounds`."""
        y = np.asarray(y, dtype=float)
        z = np.full(y.shape, np.nan)
        for p in self.pieces:
            inside = (y >= p.y_lo) & (y <= p.y_hi)
            z[inside] = p.height(y[inside])
        return z

    def height_sorted(self, y):
        """As :meth:`height` for increasing ``y``, by slices (the fast path of the search)."""
        z = np.full(y.shape, np.nan)
        for p in self.pieces:
            i0, i1 = np.searchsorted(y, p.y_lo, "left"), np.searchsorted(y, p.y_hi, "right")
            z[i0:i1] = p.height(y[i0:i1])
        return z

    def slope(self, y):
        """dz/dy of the head at ``y`` (m) (one-sided at the tangent points, where it is continuous)."""
        y = np.asarray(y, dtype=float)
        s = np.full(y.shape, np.nan)
        for p in self.pieces:
            inside = (y >= p.y_lo) & (y <= p.y_hi)
            if p.radius > 0.0:
                dy = y[inside] - p.c[0]
                s[inside] = -dy / np.sqrt(np.clip(p.radius**2 - dy * dy, 1e-30, None))
            else:
                s[inside] = p.slope
        return s

    def gauge_point(self, depth: float = GAUGE_DEPTH) -> float:
        """Lateral position (m, < 0) of the gauge side of the head ``depth`` below its highest point
        (bisection on the exact surface, to 1e-12 m)."""
        level = self.top[1] - depth
        lo, hi = self.bounds[0], self.top[0]
        if not self.height(lo) < level:
            raise ValueError(f"{self.name}: the flank kept does not reach {depth * 1e3:g} mm below the top")
        for _ in range(200):
            mid = 0.5 * (lo + hi)
            if self.height(mid) < level:
                lo = mid
            else:
                hi = mid
            if hi - lo < 1e-12:
                break
        return 0.5 * (lo + hi)

    def flange_back(self, gauge: float = GAUGE, back_to_back: float = BACK_TO_BACK) -> float:
        """Flange-back position (m, rail frame) of a wheel of a centred wheelset."""
        return self.gauge_point() - 0.5 * (gauge - back_to_back)


@dataclass(frozen=True)
class BruteForceContacts:
    """Contacts of the brute-force search (SI units), one per wheel displacement.

    Attributes
    ----------
    displacement : ndarray (n,)
        Lateral wheel displacement y_w (m), positive towards the field side (flange to the rail).
    y_wheel, y_rail : ndarray (n,)
        Contact position on the wheel (from the flange back) and the rail (from its centre line) (m).
    rolling_radius : ndarray (n,)
        (m).
    contact_angle : ndarray (n,)
        atan of the rail's slope at the contact (rad).
    step : float
        Lateral grid step used (m).
    """

    displacement: np.ndarray
    y_wheel: np.ndarray
    y_rail: np.ndarray
    rolling_radius: np.ndarray
    contact_angle: np.ndarray
    step: float


def brute_force_contacts(head: ExactRailHead, displacement, nominal_radius: float = 0.39,
                         step: float = 1e-6, flange_back: float | None = None) -> BruteForceContacts:
    """The contact of an S1002 wheel on ``head`` for each wheel displacement, by dense search.

    Parameters
    ----------
    head : ExactRailHead
    displacement : array_like
        Lateral wheel displacements y_w (m).
    nominal_radius : float
        Rolling radius of the tape circle (m).
    step : float
        Lateral grid step (m); the wheel is sampled once on this grid in its own frame and the
        rail evaluated exactly at the same points for each displacement.
    flange_back : float, optional
        Flange-back position at zero displacement (m); default :meth:`ExactRailHead.flange_back`.

    Returns
    -------
    BruteForceContacts
    """
    d = np.atleast_1d(np.asarray(displacement, dtype=float))
    fb = head.flange_back() if flange_back is None else float(flange_back)
    yw = np.arange(S1002_RANGE[0], S1002_RANGE[1] + 0.5 * step, step)
    zw = exact_s1002(yw)
    lo, hi = head.bounds
    yc, rc = np.empty(d.size), np.empty(d.size)
    for i, di in enumerate(d):
        y0 = fb + di
        k0 = int(np.searchsorted(yw, lo - y0, "left"))
        k1 = int(np.searchsorted(yw, hi - y0, "right"))
        if k0 == 0 or k1 == yw.size:
            raise ValueError(f"the S1002 wheel does not cover the rail head at y_w = {di:g} m")
        yr = y0 + yw[k0:k1]
        f = head.height_sorted(yr) + zw[k0:k1]
        j = int(np.nanargmax(f))
        if j in (0, f.size - 1):
            raise ValueError(f"closest approach at the end of the rail head at y_w = {di:g} m")
        yc[i], rc[i] = yw[k0 + j], zw[k0 + j]
    y_rail = fb + d + yc
    return BruteForceContacts(d, yc, y_rail, nominal_radius + rc, np.arctan(head.slope(y_rail)), step)


def brute_force_dr(head: ExactRailHead, y, **kwargs) -> np.ndarray:
    """Rolling radius difference r(+y) - r(-y) (m) of a symmetric wheelset (roll neglected)."""
    y = np.atleast_1d(np.asarray(y, dtype=float))
    r = brute_force_contacts(head, np.concatenate([y, -y]), **kwargs).rolling_radius
    return r[:y.size] - r[y.size:]


def harmonic_conicity(dr_function, amplitude: float = 0.003, n_phase: int = 256) -> float:
    """Equivalent conicity (-) of ``dr_function`` (m -> m) by harmonic linearisation at ``amplitude``.

    ``c1 = (1/pi) int_0^2pi dr(A sin phi) sin phi dphi`` (trapezoidal rule over ``n_phase``
    points), ``gamma_e = c1 / (2 A)``: the definition of :mod:`contact_geometry.wheelset`.
    """
    phi = 2.0 * np.pi * np.arange(n_phase) / n_phase
    dr = np.asarray(dr_function(amplitude * np.sin(phi)), dtype=float)
    return float(2.0 * np.mean(dr * np.sin(phi)) / (2.0 * amplitude))


def brute_force_conicity(head: ExactRailHead, amplitude: float = 0.003, n_phase: int = 256, **kwargs) -> float:
    """Equivalent conicity of the brute-force dr at ``amplitude`` (m) (:func:`harmonic_conicity`)."""
    return harmonic_conicity(lambda y: brute_force_dr(head, y, **kwargs), amplitude, n_phase)
