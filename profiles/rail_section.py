"""Rail cross-sections (outlines) and the ``[rail]`` study parameters.

Coordinates of the section: ``y`` lateral (m, positive towards the field side), ``z`` vertical
(m, up). The origin is at the centre of the **foot bottom**; the top of the head lies at
``z = height`` and the default contact point is the head top at ``y = 0``.

Below the head the outlines are *parametric* (straight foot edge, sloped foot top, straight web
with two equal fillets, sloped fishing surfaces). BV50's free dimensions are tuned to its nominal
area; 60E1's and 54E1's to the published area, both second moments and the centroid height of
the British Steel EN 13674-1 table (tests/test_rail_profiles_standard.py; what is published and
what is fitted: docs/user-guide.md, Profiles).

The **head** (the running surface the contact geometry uses) is either

* the **published head** of the profile, read from ``profiles/data/rail_heads.json`` with its source
  (60E1: crown R300, shoulder R80, corner R13 with the published tangent points, flanks
  widening 1:20 downwards), down to where the flank meets the fishing surface; 54E1 uses the
  same arcs, **assumed** (no reachable source), with tangent points derived for its 70 mm head
  (the data file says so); or
* parametric (BV50, no published drawing found): crown radius, corner radius, vertical sides.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import math
import os
from pathlib import Path

import numpy as np

from squealcore.errors import InputError
from squealcore.schema import param, section

logger = logging.getLogger(__name__)

__all__ = ["RailParams", "ProfileDims", "HeadArcs", "PROFILES", "ALIASES", "HEADS", "rail_outline",
           "validate_outline", "polygon_area", "head_arcs", "shoulder_end_by_tangency", "INCLINATIONS",
           "SWEDISH_INCLINATION"]

#: Published rail heads (arcs and flank slope, mm, with their sources).
HEADS_FILE = Path(__file__).with_name("data") / "rail_heads.json"

#: Allowed rail inclinations n of 1:n (0: upright), see :mod:`profiles.rail_head`.
INCLINATIONS = (0, 20, 30, 40)
#: Inclination of Swedish BV50 / 60E1 track: 1:30 (source and status in docs/user-guide.md,
#: Profiles).
SWEDISH_INCLINATION = 30


@dataclasses.dataclass(frozen=True)
class HeadArcs:
    """A published rail head (lengths in m): crown arc (centre on the axis) to the tangent point
    at ``crown_half_width``, shoulder arc to ``shoulder_half_width``, corner arc down to
    ``head_half_width`` where the flank, widening downwards with slope 1:``flank_slope``,
    continues it. ``source`` names where the numbers come from."""

    crown_radius: float
    crown_half_width: float
    shoulder_radius: float
    shoulder_half_width: float
    corner_radius: float
    head_half_width: float
    flank_slope: float
    source: str = ""

    @classmethod
    def from_json(cls, entry: dict) -> "HeadArcs":
        mm = {k: float(entry[k]) * 1e-3 for k in ("crown_radius", "crown_half_width", "shoulder_radius",
                                                   "shoulder_half_width", "corner_radius", "head_half_width")}
        return cls(**mm, flank_slope=float(entry["flank_slope"]), source=str(entry.get("source", "")))


def _load_heads() -> dict:
    data = json.loads(HEADS_FILE.read_text())
    return {k: HeadArcs.from_json(v) for k, v in data.items() if not k.startswith("_")}


#: Published heads by profile name (see ``profiles/data/rail_heads.json``).
HEADS = _load_heads()


@dataclasses.dataclass(frozen=True)
class ProfileDims:
    """Dimensions of a parametric rail profile (all in m).

    ``height``, ``head_width``, ``foot_width`` and ``web_thickness`` are the nominal
    dimensions; the others shape the outline (``foot_edge`` thickness of the foot tip,
    ``foot_root`` height of the foot top where it meets the web fillet, ``head_bottom`` height
    of the fishing surface at the web fillet, ``head_side_bottom`` height where the fishing
    surface meets the head side, ``corner_radius`` head corner radius, ``crown_radius`` head
    top radius, ``fillet`` radius of the web fillets).
    """

    height: float
    head_width: float
    foot_width: float
    web_thickness: float
    foot_edge: float
    foot_root: float
    head_bottom: float
    head_side_bottom: float
    corner_radius: float
    crown_radius: float
    fillet: float
    #: Published head replacing crown, corner radius and vertical sides (``None``: parametric).
    head: HeadArcs | None = None

    def __post_init__(self):
        # negative or zero dimensions are refused by name (they would otherwise surface as a
        # self-intersecting outline, or not at all)
        for f in dataclasses.fields(self):
            if f.name == "head":
                continue
            v = getattr(self, f.name)
            if not (isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) and v > 0):
                raise InputError(f"rail.profile.{f.name}", f"must be a positive length (m), got {v!r}")


# BV50: parametric, tuned to the nominal area (~6290 mm^2 = 49.4 kg/m at 7850 kg/m^3).
# 60E1, 54E1: height, head, foot and web widths and the head depth (head_bottom = height - E)
# from the British Steel EN 13674-1 table; fishing-surface slope (head_side_bottom), fillet,
# foot edge and foot root FITTED (0.1 mm steps) to the table's area, both second moments and
# the centroid height (60E1: 7670 mm^2, 3038 / 512.3 cm^4, 80.9 mm; 54E1: 6977 mm^2,
# 2338 / 419.2 cm^4, 75.1 mm). Sources and what is fitted: docs/user-guide.md, Profiles.
PROFILES = {
    "BV50": ProfileDims(height=0.155, head_width=0.070, foot_width=0.133, web_thickness=0.015,
                        foot_edge=0.0100, foot_root=0.024, head_bottom=0.1110,
                        head_side_bottom=0.1255, corner_radius=0.013, crown_radius=0.300,
                        fillet=0.012),
    "60E1": ProfileDims(height=0.172, head_width=0.072, foot_width=0.150, web_thickness=0.0165,
                        foot_edge=0.0104, foot_root=0.0223, head_bottom=0.172 - 0.051,
                        head_side_bottom=0.1370, corner_radius=0.013, crown_radius=0.300,
                        fillet=0.0314, head=HEADS["60E1"]),
    "54E1": ProfileDims(height=0.159, head_width=0.070, foot_width=0.140, web_thickness=0.016,
                        foot_edge=0.0102, foot_root=0.0221, head_bottom=0.159 - 0.0494,
                        head_side_bottom=0.1258, corner_radius=0.013, crown_radius=0.300,
                        fillet=0.0291, head=HEADS["54E1"]),
}

#: Former names of the EN 13674-1 profiles: EN 13674-1 renamed UIC 60 to 60E1 (ThyssenKrupp GfT
#: Railway Track Manual, page 211-02, see docs/user-guide.md, Profiles).
ALIASES = {"UIC60": "60E1"}

ELEMENT_TYPES = ("quad8", "tri6")


def _arc(centre, radius, a0, a1, n):
    """Points on a circular arc from angle a0 to a1 (rad), endpoints included, (n+1, 2)."""
    a = np.linspace(a0, a1, n + 1)
    return np.column_stack([centre[0] + radius * np.cos(a), centre[1] + radius * np.sin(a)])


def _n_seg(length, size):
    return max(1, int(np.ceil(length / size)))


def head_arcs(head: HeadArcs, height: float):
    """Centres, tangent points and angles of a published head (field side, m).

    Returns a dict with ``centres`` (3, 2) of the crown, shoulder and corner arcs, ``tangents``
    (3, 2): crown/shoulder, shoulder/corner and corner/flank tangent points, and ``angles``
    (3,): the polar angle (rad, from +y towards +z) of each tangent point on the arc ending there.
    """
    r1, r2, r3 = head.crown_radius, head.shoulder_radius, head.corner_radius
    c1 = np.array([0.0, height - r1])
    a1 = math.asin(head.crown_half_width / r1)  # from the vertical
    c2 = c1 + (r1 - r2) * np.array([math.sin(a1), math.cos(a1)])
    a2 = math.asin((head.shoulder_half_width - c2[0]) / r2)
    c3 = c2 + (r2 - r3) * np.array([math.sin(a2), math.cos(a2)])
    a3 = math.asin((head.head_half_width - c3[0]) / r3)
    t = [c + r * np.array([math.sin(a), math.cos(a)]) for c, r, a in ((c1, r1, a1), (c2, r2, a2), (c3, r3, a3))]
    return {"centres": np.array([c1, c2, c3]), "tangents": np.array(t),
            "angles": np.pi / 2 - np.array([a1, a2, a3])}


def shoulder_end_by_tangency(crown_radius, crown_half_width, shoulder_radius, corner_radius,
                             head_half_width, flank_slope):
    """Half-width where the shoulder arc ends so that the corner arc meets the flank (widening
    1:``flank_slope`` downwards) tangentially at ``head_half_width``, the crown ending at
    ``crown_half_width`` (any consistent length unit). Used for the 54E1 head (assumed arcs,
    see ``profiles/data/rail_heads.json``); on 60E1 it returns the published 26.0265 mm."""
    a1 = math.asin(crown_half_width / crown_radius)
    c2y = (crown_radius - shoulder_radius) * math.sin(a1)
    a3 = math.atan2(1.0, 1.0 / flank_slope)  # corner/flank tangent point, from the vertical
    s2 = (head_half_width - corner_radius * math.sin(a3) - c2y) / (shoulder_radius - corner_radius)
    if not 0.0 < s2 < 1.0:
        raise InputError("rail.profile", "no shoulder arc joins this crown and corner")
    return c2y + shoulder_radius * s2


def _published_head(d: ProfileDims, fish_point, fish_slope, size):
    """Field-side head from the fishing surface (line through ``fish_point`` with slope
    ``fish_slope``) up the flank and the corner, shoulder and crown arcs to the top centre."""
    g = head_arcs(d.head, d.height)
    c, t, ang = g["centres"], g["tangents"], g["angles"]
    # flank: from the corner tangent point t[2] downwards, y = t3y + (t3z - z) / flank_slope;
    # fishing line: z = fz + fish_slope (y - fy)
    k = 1.0 / d.head.flank_slope
    fy, fz = fish_point
    # z = fz + s (t3y + k (t3z - z) - fy)  ->  z (1 + s k) = fz + s (t3y + k t3z - fy)
    z = (fz + fish_slope * (t[2, 0] + k * t[2, 1] - fy)) / (1 + fish_slope * k)
    y = t[2, 0] + k * (t[2, 1] - z)
    if z >= t[2, 1]:
        raise InputError("rail.profile", "fishing surface meets the head above the flank")
    radii = (d.head.crown_radius, d.head.shoulder_radius, d.head.corner_radius)
    pts = [np.array([[y, z]])]
    # corner arc from the flank tangent point up to the shoulder tangent point, then shoulder,
    # then crown up to the top (polar angles increase towards the axis)
    starts = (ang[2], ang[1], ang[0])
    ends = (ang[1], ang[0], np.pi / 2)
    for i, (a0, a1) in zip((2, 1, 0), zip(starts, ends)):
        r = radii[i]
        pts.append(_arc(c[i], r, a0, a1, _n_seg(r * (a1 - a0), size))[(0 if i == 2 else 1):])
    return pts


def _half_outline(d: ProfileDims, size: float):
    """Field-side half (y >= 0) of the outline, from the foot bottom centre to the head top
    centre, counter-clockwise, as (n, 2) points in m."""
    bf, bh, tw = d.foot_width / 2, d.head_width / 2, d.web_thickness / 2
    pts = [np.array([[0.0, 0.0], [bf, 0.0], [bf, d.foot_edge]])]
    # foot top: straight line from the foot tip to the root of the lower web fillet
    # lower fillet: circle tangent to the web face y = tw and to the foot top line
    slope = (d.foot_root - d.foot_edge) / (bf - tw)  # foot-top line z = foot_edge + slope (bf - y)
    # foot top line through p_tip and (tw, foot_root); unit normal pointing into the air (up)
    t = np.array([tw - bf, d.foot_root - d.foot_edge])
    t /= np.linalg.norm(t)
    nrm = np.array([-t[1], t[0]])
    if nrm[1] < 0:
        nrm = -nrm
    r = d.fillet
    # centre c: c_y = tw + r, and distance r above the foot-top line
    cy = tw + r
    cz = d.foot_edge + slope * (bf - cy) + r * np.hypot(1, slope)
    c = np.array([cy, cz])
    a_start = np.arctan2(-nrm[1], -nrm[0])  # tangent point on the foot top
    a_end = -np.pi  # tangent point on the web face (clockwise from the foot top)
    arc_n = _n_seg(r * abs(a_end - a_start), size)
    pts.append(_arc(c, r, a_start, a_end, arc_n)[:])
    z_web_low = cz
    # upper fillet: tangent to the web face and to the fishing surface (line through
    # (tw, head_bottom) and (bh, head_side_bottom)), centre at y = tw + r below that line
    s2 = (d.head_side_bottom - d.head_bottom) / (bh - tw)
    cy2 = tw + r
    cz2 = d.head_bottom + s2 * (cy2 - tw) - r * np.hypot(1, s2)
    c2 = np.array([cy2, cz2])
    if cz2 <= z_web_low:
        raise InputError("rail.profile", "web too short for its fillets")
    t2 = np.array([1.0, s2]) / np.hypot(1, s2)
    n2 = np.array([-t2[1], t2[0]])  # points up-left (towards the head)
    a2_end = np.arctan2(n2[1], n2[0])
    pts.append(_arc(c2, r, np.pi, a2_end, _n_seg(r * abs(np.pi - a2_end), size)))
    if d.head is not None:
        pts.extend(_published_head(d, (tw, d.head_bottom), s2, size))
    else:
        # fishing surface to the head side, head side up to the corner arc
        rc, R = d.corner_radius, d.crown_radius
        crown_c = np.array([0.0, d.height - R])
        cc_y = bh - rc
        cc_z = crown_c[1] + np.sqrt((R - rc) ** 2 - cc_y**2)
        pts.append(np.array([[bh, d.head_side_bottom]]))
        a_corner_end = np.arctan2(cc_z - crown_c[1], cc_y - crown_c[0])
        pts.append(_arc((cc_y, cc_z), rc, 0.0, a_corner_end, _n_seg(rc * a_corner_end, size)))
        a_top = np.pi / 2
        pts.append(_arc(crown_c, R, a_corner_end, a_top, _n_seg(R * (a_top - a_corner_end), size))[1:])
    out = np.vstack(pts)
    # drop consecutive duplicates
    keep = np.r_[True, np.linalg.norm(np.diff(out, axis=0), axis=1) > 1e-9]
    return out[keep]


def rail_outline(profile: str | ProfileDims, size: float = 0.004):
    """Closed counter-clockwise outline of a rail section.

    Parameters
    ----------
    profile : str or ProfileDims
        ``"BV50"``, ``"60E1"``, ``"54E1"`` (or an alias), a :class:`ProfileDims`, or the path
        of a text file with one ``y z`` pair (m) per line describing a closed outline (first
        point not repeated, or repeated; either orientation).
    size : float
        Target length of the straight pieces that approximate arcs (m).

    Returns
    -------
    ndarray (n, 2)
        Outline points (y, z) in m, counter-clockwise, first point not repeated.
    """
    if isinstance(profile, ProfileDims):
        dims = profile
    elif isinstance(profile, str) and ALIASES.get(profile, profile) in PROFILES:
        dims = PROFILES[ALIASES.get(profile, profile)]
    else:
        return _read_outline(profile)
    half = _half_outline(dims, size)
    mirror = half[::-1][1:-1] * np.array([-1.0, 1.0])
    outline = np.vstack([half, mirror])
    validate_outline(outline, "rail.profile")
    return outline


def profile_names():
    """Names accepted for ``rail.profile`` (profiles and their aliases), sorted."""
    return sorted([*PROFILES, *ALIASES])


def _read_outline(path: str):
    if not isinstance(path, str) or not os.path.isfile(path):
        raise InputError("rail.profile", f"must be one of {profile_names()} or an existing outline file, got {path!r}")
    try:
        pts = np.loadtxt(path, ndmin=2)
    except ValueError as exc:
        raise InputError("rail.profile", f"cannot read outline file {path!r}: {exc}") from None
    if pts.shape[1] != 2:
        raise InputError("rail.profile", "outline file must have two columns y z (m)")
    if len(pts) > 1 and np.allclose(pts[0], pts[-1]):
        pts = pts[:-1]
    validate_outline(pts, "rail.profile")
    if polygon_area(pts) < 0:
        pts = pts[::-1]
    return pts


def polygon_area(points):
    """Signed area (m^2) of a polygon (n, 2), positive when counter-clockwise."""
    y, z = np.asarray(points).T
    return 0.5 * float(np.sum(y * np.roll(z, -1) - np.roll(y, -1) * z))


def validate_outline(points, field: str = "rail.profile"):
    """Check that ``points`` (n, 2) is a simple closed polygon of positive size.

    The outline is closed implicitly (last point joins the first). Raises
    :class:`~squealcore.errors.InputError` if it has fewer than 3 points, non-finite values,
    zero area or self-intersections.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2 or len(pts) < 3:
        raise InputError(field, "outline needs at least 3 (y, z) points")
    if not np.all(np.isfinite(pts)):
        raise InputError(field, "outline has non-finite coordinates")
    if abs(polygon_area(pts)) < 1e-10:
        raise InputError(field, "outline encloses no area (> 1e-10 m^2 required)")
    a, b = pts, np.roll(pts, -1, axis=0)
    n = len(pts)
    if np.any(np.linalg.norm(b - a, axis=1) < 1e-12):
        raise InputError(field, "outline has repeated consecutive points")
    # pairwise segment intersection test (proper crossings and touching), non-adjacent only
    i, j = np.triu_indices(n, k=2)
    adj = (i == 0) & (j == n - 1)
    i, j = i[~adj], j[~adj]

    def orient(p, q, r):
        return np.sign((q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1])
                       - (q[..., 1] - p[..., 1]) * (r[..., 0] - p[..., 0]))

    o1 = orient(a[i], b[i], a[j])
    o2 = orient(a[i], b[i], b[j])
    o3 = orient(a[j], b[j], a[i])
    o4 = orient(a[j], b[j], b[i])
    cross = (o1 * o2 <= 0) & (o3 * o4 <= 0) & ~((o1 == 0) & (o2 == 0) & (o3 == 0) & (o4 == 0))
    if np.any(cross):
        k = int(np.argmax(cross))
        raise InputError(field, f"outline is self-intersecting (segments {i[k]} and {j[k]})")


@section("rail")
@dataclasses.dataclass(frozen=True)
class RailParams:
    """Cross-section and mesh of the rail (the ``[rail]`` study section, SI units)."""

    profile: str = param("BV50", kind="file", choices=(*PROFILES, *ALIASES),
                         doc=f"Rail profile: one of {', '.join(PROFILES)} (60E1 with its published head, 54E1 "
                             "with the 60E1 arcs assumed; below the head fitted to the published "
                             "section figures; alias "
                             f"{', '.join(f'{a} = {b}' for a, b in ALIASES.items())}), or the path of an "
                             "outline file (y z in m per line).")
    inclination: int = param(SWEDISH_INCLINATION, low=0, high=40,
                             doc=f"Rail inclination (cant) 1:n towards the track centre, n one of "
                                 f"{', '.join(map(str, INCLINATIONS))} (0: upright); enters the contact "
                                 f"geometry only, the rail mesh stays upright in its section frame.")
    element_size: float = param(0.010, unit="m", low=0.001, high=0.05,
                                doc="Target element size of the section mesh.")
    element_type: str = param("quad8", choices=ELEMENT_TYPES,
                              doc="8-node quadrilaterals or 6-node triangles.")
    density: float = param(7850.0, unit="kg/m^3", low=0.0, high=30000.0, low_open=True,
                           doc="Mass density of the rail steel.")

    def cross_check(self, prefix: str = "rail") -> None:
        """Check that the profile names a known profile or an existing file and the inclination is
        one of :data:`INCLINATIONS` (raises :class:`InputError`)."""
        if ALIASES.get(self.profile, self.profile) not in PROFILES and not os.path.isfile(self.profile):
            raise InputError(f"{prefix}.profile",
                             f"must be one of {profile_names()} or an existing outline file, got {self.profile!r}")
        if self.inclination not in INCLINATIONS:
            raise InputError(f"{prefix}.inclination",
                             f"must be one of {INCLINATIONS} (1:n, 0 = upright), got {self.inclination!r}")

    def outline(self):
        """Closed counter-clockwise outline (n, 2) in m, see :func:`rail_outline`."""
        return rail_outline(self.profile, size=self.element_size / 2)

    @property
    def height(self):
        """Rail height (m): the top of the outline."""
        return float(self.outline()[:, 1].max())
