"""Parametric C20-like wheel cross-section in the (r, z) half plane.

The section is described in the frame of ``docs/conventions.md``: ``r`` is the radius from the
axle centre line and ``z`` the axial position measured from the flange back (the inner face of
the flange), positive towards the field side. All lengths are in metres.

The parametric outline is a polygon whose corners may be rounded (flange tip, flange root,
web/rim and web/hub fillets). It runs, counter-clockwise in (r, z), along the hub bore (the
clamped edge), the field-side hub face, the web, the field face of the rim, the tread (with the
contact point), the flange, the flange back, the web again and back to the bore. Alternatively
the outline is read from a text file (``profile_file``).

The running surface (tread and flange, from the flange back to the field face) can instead come
from a tread profile (``tread_profile``: the shipped S1002 or a two-column profile file, see
:mod:`profiles.curve`; shipped ones registered in :mod:`profiles.wheel_treads`) while hub, web and the rim below it stay parametric: the profile
height 0 (the tape circle) sits at ``rolling_radius``, so that turning a wheel is a smaller
``rolling_radius`` with the same tread shape (:func:`tread_profile`, :func:`_tread_outline`).

The defaults describe a plausible C20-like metro wheel (rolling radius 0.39 m); ``hub_length``
was tuned so that the default wheel weighs 213 kg (the paper's value).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from profiles.curve import Profile
from profiles.wheel_treads import TREAD_NAMES, read_tread
from squealcore.errors import InputError
from squealcore.schema import param, section

logger = logging.getLogger(__name__)

#: Largest angle (rad) of one straight piece when arcs are discretised for the outline points.
ARC_STEP = math.radians(2.0)
#: Relative tolerance on lengths used in the geometric checks (fraction of the section size).
GEOM_RTOL = 1e-9
#: Turning angle (rad) above which a vertex of a file outline is treated as a sharp corner.
FILE_CORNER_ANGLE = math.radians(30.0)
#: Ratio of neighbouring point spacings of a file outline above which the spline is split.
FILE_SPACING_RATIO = 2.0
#: Distance (m) within which the last point of a file outline must equal the first one.
FILE_CLOSE_TOL = 1e-6
#: Thinnest rim allowed under a tread profile (m): the radial distance from ``rim_inner_radius``
#: to the lowest point of the running surface. A geometric floor (the rim must hold a layer of
#: elements), not a wear limit; operators' limits for turning are larger.
MIN_RIM_THICKNESS = 0.010
#: Largest turning (rad) of the tread profile's tangent within one outline segment: the profile
#: is split there so that a quadratic element edge spans a moderately curved piece only.
TREAD_SEGMENT_TURN = math.radians(45.0)


@section("wheel")
@dataclass(frozen=True)
class WheelParams:
    """Geometry and mesh of the wheel cross-section (the ``[wheel]`` study section, SI units).

    Each field is declared once with its unit, range and description (:func:`squealcore.schema.param`);
    :meth:`from_mapping` validates a table against these declarations and then checks the
    geometry as a whole (:meth:`cross_check`). With ``profile_file`` set, only
    ``contact_offset``, ``density`` and the mesh sizes are used; with a ``tread_profile`` other
    than ``"parametric"``, the tread and flange keys (``tread_conicity``, ``flange_*``) are not.
    """

    rolling_radius: float = param(0.39, unit="m", low=0.1, high=1.0,
                                  doc="Radius of the tape circle, at z = contact_offset.")
    contact_offset: float = param(0.070, unit="m", low=0.0, high=0.3,
                                  doc="Axial position of the tape circle and contact point from the flange back.")
    tread_conicity: float = param(0.025, low=0.0, high=0.5,
                                  doc="Tread slope: r(z) = rolling_radius - tread_conicity (z - contact_offset).")
    rim_width: float = param(0.135, unit="m", low=0.0, high=0.5, low_open=True,
                             doc="Axial rim width, flange back to field face.")
    rim_inner_radius: float = param(0.345, unit="m", low=0.0, high=1.0, low_open=True, high_open=True,
                                    doc="Radius of the inner (bottom) surface of the rim.")
    flange_height: float = param(0.028, unit="m", low=0.0, high=0.1, low_open=True,
                                 doc="Height of the flange tip above the rolling radius.")
    flange_thickness: float = param(0.032, unit="m", low=0.0, high=0.1, low_open=True,
                                    doc="Axial position of the flange root (flange thickness at the tread level).")
    flange_angle_deg: float = param(70.0, unit="deg", low=30.0, high=89.0,
                                    doc="Angle of the flange face to the axle.")
    flange_root_radius: float = param(0.012, unit="m", low=0.0, high=0.1,
                                      doc="Radius of the flange root (tread/flange) fillet.")
    flange_tip_radius: float = param(0.008, unit="m", low=0.0, high=0.1,
                                     doc="Radius of the two flange tip corners.")
    web_thickness: float = param(0.020, unit="m", low=0.0, high=0.5, low_open=True,
                                 doc="Axial web thickness.")
    web_offset: float = param(0.0, unit="m", low=-0.25, high=0.25,
                              doc="Axial offset of the web centre from the rim centre, positive to the field side.")
    hub_bore_radius: float = param(0.080, unit="m", low=0.0, high=1.0, low_open=True, high_open=True,
                                   doc="Bore (axle seat) radius of the hub; the bore is clamped.")
    hub_outer_radius: float = param(0.122, unit="m", low=0.0, high=1.0, low_open=True, high_open=True,
                                    doc="Outer radius of the hub.")
    hub_length: float = param(0.15881, unit="m", low=0.0, high=1.0, low_open=True,
                              doc="Axial hub length (tuned: the default wheel weighs 213 kg, the paper's mass).")
    hub_offset: float = param(0.0, unit="m", low=-0.5, high=0.5,
                              doc="Axial offset of the hub centre from the rim centre.")
    fillet_radius: float = param(0.020, unit="m", low=0.0, high=0.1,
                                 doc="Radius of the web/rim and web/hub fillets.")
    density: float = param(7850.0, unit="kg/m^3", low=0.0, high=30000.0, low_open=True,
                           doc="Mass density of the wheel steel.")
    tread_profile: str = param("parametric", kind="file", choices=TREAD_NAMES,
                               doc='Running surface (tread and flange): "parametric" (the 1:40 cone and flange of '
                                   'the keys above), "S1002" (EN 13715, shipped) or a two-column tread profile file '
                                   '(y from the flange back, height above the tape circle; docs/user-guide.md, '
                                   'Profiles). Its height 0 sits at rolling_radius: turning the wheel = a smaller '
                                   'rolling_radius. Hub, web and rim inside stay parametric.')
    profile_file: str = param("", kind="file", doc='"" for the parametric outline, or a text file of (r, z) points (m, two '
                                      'columns, # comments) of the closed outline, the last point repeating the first.')
    section_element_size: float = param(0.015, unit="m", low=0.001, high=0.1,
                                        doc="Target element size in the cross-section (108 elements by default).")
    elements_around: int = param(72, low=4, high=720,
                                 doc="Number of elements around the circumference of the 3D wheel "
                                     "(72: 3.4 cm around the tread, as in the paper).")

    def cross_check(self, prefix: str = "wheel") -> None:
        """Check geometric consistency by building the outline (raises :class:`InputError`)."""
        build_outline(self, prefix)

    def replace(self, **changes) -> "WheelParams":
        """Return a validated copy with some fields changed."""
        return WheelParams.from_mapping({**dataclasses.asdict(self), **changes})


@dataclass(frozen=True)
class Segment:
    """One piece of the section outline.

    Attributes
    ----------
    kind : str
        ``"line"`` (``points`` = start, end), ``"arc"`` (start, centre, end; a circular arc of
        less than pi) or ``"spline"`` (points the curve passes through, start to end).
    points : ndarray, shape (k, 2)
        Defining points in (r, z) (m).
    """

    kind: str
    points: np.ndarray

    def discretise(self) -> np.ndarray:
        """Points along the segment from start to end, excluding the end, shape (m, 2) (m)."""
        if self.kind == "arc":
            start, centre, end = self.points
            a0 = math.atan2(*(start - centre)[::-1])
            a1 = math.atan2(*(end - centre)[::-1])
            sweep = (a1 - a0 + math.pi) % (2.0 * math.pi) - math.pi
            n = max(1, int(math.ceil(abs(sweep) / ARC_STEP)))
            ang = a0 + sweep * np.arange(n) / n
            rad = np.linalg.norm(start - centre)
            return centre + rad * np.column_stack([np.cos(ang), np.sin(ang)])
        return np.asarray(self.points[:-1], dtype=float)


@dataclass(frozen=True)
class Outline:
    """Closed counter-clockwise section outline made of segments.

    Attributes
    ----------
    segments : list of Segment
        Consecutive segments; the end of the last one is the start of the first.
    bore_segment : int
        Index of the straight bore segment (clamped edge, at constant r).
    contact_vertex : int
        Index of the segment that starts at the contact point.
    contact_point : ndarray, shape (2,)
        Contact point (r_c, z_c) on the tread (m).
    polygon : ndarray, shape (P, 2) or None
        For outlines read from a file, the polygon of the file points (with the contact point)
        that the mesh follows; None for the parametric outline.
    """

    segments: list
    bore_segment: int
    contact_vertex: int
    contact_point: np.ndarray
    polygon: np.ndarray | None = None


def _polygon_first_moment(points: np.ndarray) -> tuple[float, float]:
    """Signed area (m^2) and first moment about the axle ``int r dA`` (m^3) of a polygon."""
    r, z = points[:, 0], points[:, 1]
    r1, z1 = np.roll(r, -1), np.roll(z, -1)
    cross = r * z1 - r1 * z
    return 0.5 * cross.sum(), (cross * (r + r1)).sum() / 6.0


def _segments_intersect(points: np.ndarray) -> bool:
    """True if two non-adjacent edges of the closed polygon ``points`` cross or touch."""
    p = points
    q = np.roll(points, -1, axis=0)
    n = len(p)
    d = q - p
    # Orientation tests of every edge pair (vectorised, n x n).
    def orient(a, b, c):
        return (b[..., 0] - a[..., 0]) * (c[..., 1] - a[..., 1]) - (b[..., 1] - a[..., 1]) * (c[..., 0] - a[..., 0])
    P1, Q1 = p[:, None, :], q[:, None, :]
    P2, Q2 = p[None, :, :], q[None, :, :]
    o1 = orient(P1, Q1, P2)
    o2 = orient(P1, Q1, Q2)
    o3 = orient(P2, Q2, P1)
    o4 = orient(P2, Q2, Q1)
    scale = np.abs(d).max() ** 2 * 1e-12
    cross = (o1 * o2 < -scale) & (o3 * o4 < -scale)
    idx = np.arange(n)
    gap = np.abs(idx[:, None] - idx[None, :])
    nonadjacent = (gap > 1) & (gap < n - 1)
    if np.any(cross & nonadjacent):
        return True
    # Touching vertices: any two distinct, non-consecutive vertices that coincide.
    dist = np.linalg.norm(p[:, None, :] - p[None, :, :], axis=-1)
    close = dist < np.abs(d).max() * 1e-9
    return bool(np.any(close & (gap > 0)))


def _rounded_polygon(vertices, radii, names, prefix) -> tuple[list, list]:
    """Round the corners of a closed polygon.

    Parameters
    ----------
    vertices : ndarray, shape (n, 2)
        Polygon corners (m), counter-clockwise.
    radii : sequence of float
        Rounding radius at each corner (m); 0 keeps the corner sharp.
    names : sequence of str
        Parameter responsible for each radius (used in error messages).
    prefix : str
        Dotted prefix for the field names.

    Returns
    -------
    segments : list of Segment
        Lines and arcs; segment ``2 i`` is the arc (or nothing) at corner i when rounded.
    starts : list of int
        For each polygon edge i (from corner i to i+1) the index of its line segment.
    """
    v = np.asarray(vertices, dtype=float)
    n = len(v)
    tangent_in = np.empty_like(v)
    tangent_out = np.empty_like(v)
    dist = np.zeros(n)
    centres = [None] * n
    for i in range(n):
        a, b, c = v[i - 1], v[i], v[(i + 1) % n]
        u1 = (a - b) / np.linalg.norm(a - b)
        u2 = (c - b) / np.linalg.norm(c - b)
        half = 0.5 * math.acos(float(np.clip(u1 @ u2, -1.0, 1.0)))
        rho = radii[i]
        if rho > 0.0:
            if half > math.radians(89.9):
                raise InputError(f"{prefix}.{names[i]}", "cannot round a straight corner; must be 0")
            dist[i] = rho / math.tan(half)
            bis = (u1 + u2) / np.linalg.norm(u1 + u2)
            centres[i] = b + bis * rho / math.sin(half)
        tangent_in[i] = b + u1 * dist[i]
        tangent_out[i] = b + u2 * dist[i]
    # Each edge must hold the two tangent lengths at its ends.
    for i in range(n):
        j = (i + 1) % n
        length = np.linalg.norm(v[j] - v[i])
        if dist[i] + dist[j] > length * (1.0 - GEOM_RTOL):
            k = i if radii[i] >= radii[j] else j
            limit = radii[k] * length / (dist[i] + dist[j])
            raise InputError(f"{prefix}.{names[k]}",
                             f"too large for the neighbouring edges; must be < {limit:.6g} m "
                             f"with the other dimensions (got {radii[k]:g})")
    segments = []
    edge_index = []
    for i in range(n):
        if dist[i] > 0.0:
            segments.append(Segment("arc", np.array([tangent_in[i], centres[i], tangent_out[i]])))
        j = (i + 1) % n
        edge_index.append(len(segments))
        segments.append(Segment("line", np.array([tangent_out[i], tangent_in[j]])))
    return segments, edge_index


def tread_profile(params: WheelParams, prefix: str = "wheel") -> Profile | None:
    """The tread profile named by ``params.tread_profile`` (None for ``"parametric"``).

    Parameters
    ----------
    params : WheelParams
    prefix : str
        Dotted prefix for error field names.

    Returns
    -------
    Profile or None
        ``y`` from the flange back (m), ``z`` radial height above the tape circle (m), as read
        (a shipped one from ``profiles/data/``, see :data:`profiles.wheel_treads.TREADS`); None for the parametric running surface.

    Raises
    ------
    InputError
        Naming ``<prefix>.tread_profile``, the file and the problem (unreadable, not two numeric
        columns, too few points, non-monotonic or self-intersecting).
    """
    return read_tread(params.tread_profile, f"{prefix}.tread_profile")


def _parametric_outline(p: WheelParams, prefix: str) -> Outline:
    """Outline of the parametric wheel (see module docstring); checks consistency."""
    surface = tread_profile(p, prefix)
    f = lambda name: f"{prefix}.{name}"  # noqa: E731
    W, r0, zc = p.rim_width, p.rolling_radius, p.contact_offset
    tread = lambda z: r0 - p.tread_conicity * (z - zc)  # noqa: E731
    r_field = tread(W)
    rb, rh, ri = p.hub_bore_radius, p.hub_outer_radius, p.rim_inner_radius
    tw, fr = p.web_thickness, p.fillet_radius
    if rb >= rh:
        raise InputError(f("hub_bore_radius"), f"must be < hub_outer_radius = {rh:g} m (got {rb:g})")
    if rh >= ri:
        raise InputError(f("hub_outer_radius"), f"must lie in (hub_bore_radius, rim_inner_radius) = "
                                                f"({rb:g}, {ri:g}) m (got {rh:g})")
    if surface is not None:
        _check_tread_fits(p, surface, prefix)
    else:
        r_tread_min = min(r0, r_field, tread(p.flange_thickness))
        if ri >= r_tread_min:
            raise InputError(f("rim_inner_radius"), f"must lie in (hub_outer_radius, tread radius) = "
                                                    f"({rh:g}, {r_tread_min:.6g}) m (got {ri:g})")
        if p.flange_thickness >= W:
            raise InputError(f("flange_thickness"), f"must be < rim_width = {W:g} m (got {p.flange_thickness:g})")
    if tw >= W:
        raise InputError(f("web_thickness"), f"web thicker than the rim is wide: must be < "
                                             f"rim_width = {W:g} m (got {tw:g})")
    if tw + 2.0 * fr >= W:
        raise InputError(f("fillet_radius"), f"web fillets too large for the rim: must be < "
                                             f"(rim_width - web_thickness) / 2 = {(W - tw) / 2:.6g} m "
                                             f"(got {fr:g})")
    zw = 0.5 * W + p.web_offset
    off_max = 0.5 * W - 0.5 * tw - fr
    if abs(p.web_offset) >= off_max:
        raise InputError(f("web_offset"), f"web must stay within the rim: must lie in "
                                          f"({-off_max:.6g}, {off_max:.6g}) m (got {p.web_offset:g})")
    L = p.hub_length
    if L <= tw:
        raise InputError(f("hub_length"), f"hub shorter than the web is thick: must be > "
                                          f"web_thickness = {tw:g} m (got {L:g})")
    if L <= tw + 2.0 * fr:
        raise InputError(f("fillet_radius"), f"web fillets too large for the hub: must be < "
                                             f"(hub_length - web_thickness) / 2 = {(L - tw) / 2:.6g} m "
                                             f"(got {fr:g})")
    zh = 0.5 * W + p.hub_offset
    lo = p.web_offset - (0.5 * L - 0.5 * tw - fr)
    hi = p.web_offset + (0.5 * L - 0.5 * tw - fr)
    if not lo < p.hub_offset < hi:
        raise InputError(f("hub_offset"), f"the web must land on the hub: must lie in "
                                          f"({lo:.6g}, {hi:.6g}) m (got {p.hub_offset:g})")
    if ri - rh <= 2.0 * fr:
        raise InputError(f("fillet_radius"), f"web too short for its fillets: must be < "
                                             f"(rim_inner_radius - hub_outer_radius) / 2 = "
                                             f"{(ri - rh) / 2:.6g} m (got {fr:g})")
    if surface is not None:
        return _tread_outline(p, surface, prefix, zh, zw)
    # Flange: root on the tread at z = flange_thickness, face at flange_angle to the axle,
    # flat tip at r0 + flange_height, back face at z = 0.
    r_tip = r0 + p.flange_height
    r_root = tread(p.flange_thickness)
    if r_tip <= r_root:
        raise InputError(f("flange_height"), f"flange tip below the tread at the flange root: must be > "
                                             f"{r_root - r0:.6g} m (got {p.flange_height:g})")
    z_tip = p.flange_thickness - (r_tip - r_root) / math.tan(math.radians(p.flange_angle_deg))
    if z_tip <= 0.0:
        raise InputError(f("flange_thickness"), f"flange too thin for its height and angle: must be > "
                                                f"{p.flange_thickness - z_tip:.6g} m (got {p.flange_thickness:g})")
    vertices = [
        (rb, zh - 0.5 * L), (rb, zh + 0.5 * L),          # 0, 1: bore edge (clamped)
        (rh, zh + 0.5 * L), (rh, zw + 0.5 * tw),         # 2, 3: hub field side, web/hub
        (ri, zw + 0.5 * tw), (ri, W),                    # 4, 5: web/rim, rim field side
        (r_field, W), (r_root, p.flange_thickness),      # 6, 7: field face top, flange root
        (r_tip, z_tip), (r_tip, 0.0),                    # 8, 9: flange tip corners
        (ri, 0.0), (ri, zw - 0.5 * tw),                  # 10, 11: rim back, web/rim
        (rh, zw - 0.5 * tw), (rh, zh - 0.5 * L),         # 12, 13: web/hub, hub back side
    ]
    radii = [0, 0, 0, fr, fr, 0, 0, p.flange_root_radius, p.flange_tip_radius,
             p.flange_tip_radius, 0, fr, fr, 0]
    names = ["hub_length", "hub_length", "hub_length", "fillet_radius", "fillet_radius",
             "rim_width", "rim_width", "flange_root_radius", "flange_tip_radius",
             "flange_tip_radius", "rim_width", "fillet_radius", "fillet_radius", "hub_length"]
    # The list above runs clockwise in (r, z); reverse it. Edge i (vertex i -> i + 1) of the
    # list becomes edge n - 2 - i of the reversed polygon.
    n = len(vertices)
    segments, edge_index = _rounded_polygon(np.array(vertices[::-1]), radii[::-1], names[::-1], prefix)
    bore_edge, tread_edge = n - 2 - 0, n - 2 - 6
    # Split the tread line (flange root -> field face) at the contact point.
    k = edge_index[tread_edge]
    start, end = segments[k].points
    if not start[1] + 1e-12 < zc < end[1] - 1e-12:
        raise InputError(f("contact_offset"), f"contact point must lie on the straight tread: must lie in "
                                              f"({start[1]:.6g}, {end[1]:.6g}) m (got {zc:g})")
    contact = np.array([r0, zc])
    segments[k:k + 1] = [Segment("line", np.array([start, contact])),
                         Segment("line", np.array([contact, end]))]
    bore = edge_index[bore_edge] + (1 if edge_index[bore_edge] > k else 0)
    outline = Outline(segments, bore_segment=bore, contact_vertex=k + 1, contact_point=contact)
    pts = np.vstack([s.discretise() for s in segments])
    if _segments_intersect(pts) or _polygon_first_moment(pts)[0] <= 0.0:
        raise InputError(prefix, "the parameters give a self-intersecting section outline")
    return outline


def _check_tread_fits(p: WheelParams, surface: Profile, prefix: str) -> None:
    """Check that a tread profile fits the parametric rim (raises :class:`InputError`).

    The profile must lie within the rim's axial extent [0, rim_width], hold the contact point
    (``contact_offset``) and leave at least :data:`MIN_RIM_THICKNESS` of rim under its lowest
    point; the last check names ``rolling_radius`` (turning a wheel lowers it) and its limit.
    """
    y0, y1 = surface.bounds
    if y0 < 0.0:
        raise InputError(f"{prefix}.tread_profile", f"{surface.name}: lateral positions must be >= 0 m "
                                                    f"(from the flange back), got {y0:.6g} m")
    if y1 > p.rim_width:
        raise InputError(f"{prefix}.rim_width", f"must be >= the width of the tread profile {surface.name} "
                                                f"= {y1:.6g} m (got {p.rim_width:g})")
    if not y0 < p.contact_offset < y1:
        raise InputError(f"{prefix}.contact_offset", f"must lie within the tread profile {surface.name}: "
                                                     f"({y0:.6g}, {y1:.6g}) m (got {p.contact_offset:g})")
    lowest = float(surface.z.min())
    limit = p.rim_inner_radius + MIN_RIM_THICKNESS - lowest
    if p.rolling_radius < limit:
        raise InputError(f"{prefix}.rolling_radius",
                         f"rim too thin under the tread profile {surface.name}: must be >= {limit:.6g} m "
                         f"(rim_inner_radius {p.rim_inner_radius:g} m + {MIN_RIM_THICKNESS:g} m of rim "
                         f"+ {-lowest:.6g} m from the tape circle down to the profile's lowest point; "
                         f"got {p.rolling_radius:g})")


def _tread_breaks(points: np.ndarray, keep: list) -> list:
    """Indices where the tread chain ``points`` (P, 2) is split into outline segments.

    Always the two ends and ``keep``; in between, wherever the tangent has turned by more
    than :data:`TREAD_SEGMENT_TURN` since the last split.
    """
    d = np.diff(points, axis=0)
    angle = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
    breaks = {0, len(points) - 1, *keep}
    ref = angle[0]
    for i in range(1, len(d)):
        if i in breaks:
            ref = angle[i]
        elif abs(angle[i] - ref) > TREAD_SEGMENT_TURN:
            breaks.add(i)
            ref = angle[i]
    return sorted(breaks)


def _tread_outline(p: WheelParams, surface: Profile, prefix: str, zh: float,
                   zw: float) -> Outline:
    """Outline with a tread profile as running surface (hub, web and rim inside parametric).

    The rim is the region between ``r = rim_inner_radius`` and the profile placed at
    ``r = rolling_radius + z(y)``; straight lines join the rim's inner corners (ri, 0) and
    (ri, rim_width) to the first and last profile points. The profile chain (with the contact
    point inserted at ``y = contact_offset``) becomes spline segments split at the contact
    point, the flange tip (highest point) and every :data:`TREAD_SEGMENT_TURN` of tangent
    turning; ``polygon`` holds the whole outline for the placement of mid-side nodes.
    """
    W, r0, zc = p.rim_width, p.rolling_radius, p.contact_offset
    rb, rh, ri = p.hub_bore_radius, p.hub_outer_radius, p.rim_inner_radius
    tw, fr, L = p.web_thickness, p.fillet_radius, p.hub_length
    y, z = surface.y, surface.z
    chain = np.column_stack([r0 + z, y])                       # (r, z) of the running surface
    near = np.flatnonzero(np.abs(y - zc) <= 1e-9)
    if near.size:
        ic = int(near[0])
    else:
        ic = int(np.searchsorted(y, zc))
        chain = np.insert(chain, ic, [r0 + float(surface.height(zc)), zc], axis=0)
    contact = chain[ic].copy()
    first, last = chain[0], chain[-1]
    vertices = [
        (rb, zh - 0.5 * L), (rb, zh + 0.5 * L),          # 0, 1: bore edge (clamped)
        (rh, zh + 0.5 * L), (rh, zw + 0.5 * tw),         # 2, 3: hub field side, web/hub
        (ri, zw + 0.5 * tw), (ri, W),                    # 4, 5: web/rim, rim field side
        tuple(last), tuple(first),                       # 6, 7: tread profile ends (placeholder edge)
        (ri, 0.0), (ri, zw - 0.5 * tw),                  # 8, 9: rim back, web/rim
        (rh, zw - 0.5 * tw), (rh, zh - 0.5 * L),         # 10, 11: web/hub, hub back side
    ]
    radii = [0, 0, 0, fr, fr, 0, 0, 0, 0, fr, fr, 0]
    names = ["hub_length", "hub_length", "hub_length", "fillet_radius", "fillet_radius", "rim_width",
             "tread_profile", "tread_profile", "rim_width", "fillet_radius", "fillet_radius", "hub_length"]
    n = len(vertices)
    segments, edge_index = _rounded_polygon(np.array(vertices[::-1]), radii[::-1], names[::-1], prefix)
    k = edge_index[n - 2 - 6]                            # the placeholder line, first -> last
    breaks = _tread_breaks(chain, [ic, int(np.argmax(chain[:, 0]))])
    pieces = [chain[a:b + 1] for a, b in zip(breaks[:-1], breaks[1:])]
    segments[k:k + 1] = [Segment("line" if len(c) == 2 else "spline", c) for c in pieces]
    contact_vertex = k + breaks.index(ic)
    b = edge_index[n - 2 - 0]
    bore = b + (len(pieces) - 1 if b > k else 0)
    coarse = np.vstack([s.discretise() if s.kind == "arc" else s.points[:1] for s in segments])
    polygon = np.vstack([s.discretise() for s in segments])
    # The chain is a graph over y in [0, rim_width] above r = ri + MIN_RIM_THICKNESS, where no
    # other part of the outline enters: crossings can only occur among the parametric parts,
    # checked on the outline with the chain reduced to its split points.
    if _segments_intersect(coarse) or _polygon_first_moment(polygon)[0] <= 0.0:
        raise InputError(prefix, "the parameters give a self-intersecting section outline")
    return Outline(segments, bore_segment=bore, contact_vertex=contact_vertex, contact_point=contact,
                   polygon=polygon)


def read_profile(path: str | Path, field: str = "wheel.profile_file") -> np.ndarray:
    """Read and check a closed section outline from a text file.

    Parameters
    ----------
    path : str or Path
        Text file with two columns r, z (m), one point a line, ``#`` starts a comment. The
        outline must be closed: the last point repeats the first one (within 1e-6 m).
    field : str
        Field name used in error messages.

    Returns
    -------
    ndarray, shape (P, 2)
        The outline points (r, z) in metres, counter-clockwise, without the repeated point.

    Raises
    ------
    InputError
        If the file cannot be read, is not two numeric columns, has fewer than 3 distinct
        points, is open, self-intersecting, or reaches r <= 0.
    """
    try:
        data = np.loadtxt(path, comments="#", dtype=float, ndmin=2)
    except (OSError, ValueError) as exc:
        raise InputError(field, f"cannot read a two-column (r, z) table from {str(path)!r}: {exc}") from None
    if data.ndim != 2 or data.shape[1] != 2:
        raise InputError(field, f"{path}: must have exactly 2 columns (r, z) in m, got shape {data.shape}")
    if not np.all(np.isfinite(data)):
        raise InputError(field, f"{path}: contains non-finite values")
    if len(data) < 4 or np.linalg.norm(data[-1] - data[0]) > FILE_CLOSE_TOL:
        raise InputError(field, f"{path}: outline is open: the last point must repeat the first one "
                                f"(within {FILE_CLOSE_TOL:g} m) and there must be at least 3 distinct points")
    pts = data[:-1]
    if np.any(pts[:, 0] <= 0.0):
        raise InputError(field, f"{path}: all points must have r > 0 m (the section may not reach the axle)")
    steps = np.linalg.norm(np.roll(pts, -1, axis=0) - pts, axis=1)
    if np.any(steps <= FILE_CLOSE_TOL):
        raise InputError(field, f"{path}: consecutive points must be distinct (> 1e-6 m apart)")
    if _segments_intersect(pts):
        raise InputError(field, f"{path}: outline is self-intersecting")
    area, _ = _polygon_first_moment(pts)
    if area < 0.0:
        pts = pts[::-1].copy()
    return pts


def _file_outline(p: WheelParams, prefix: str) -> Outline:
    """Outline from ``p.profile_file``: bore at the minimum radius, contact at max r on z_c."""
    field = f"{prefix}.profile_file"
    pts = read_profile(p.profile_file, field)
    n = len(pts)
    scale = np.ptp(pts, axis=0).max()
    tol = scale * 1e-9
    # Bore: the edge whose two ends are both at the minimum radius.
    rmin = pts[:, 0].min()
    at_min = np.abs(pts[:, 0] - rmin) <= tol
    bore = [i for i in range(n) if at_min[i] and at_min[(i + 1) % n]]
    if len(bore) != 1:
        raise InputError(field, f"outline must have exactly one straight edge at the minimum radius "
                                f"(the clamped bore), found {len(bore)}")
    # Contact: the outermost crossing of the line z = contact_offset.
    zc = p.contact_offset
    q = np.roll(pts, -1, axis=0)
    z0, z1 = pts[:, 1], q[:, 1]
    crossing = (np.minimum(z0, z1) <= zc) & (np.maximum(z0, z1) >= zc) & (z0 != z1)
    if not np.any(crossing):
        raise InputError(f"{prefix}.contact_offset", f"must lie within the axial extent of the profile "
                                                     f"[{pts[:, 1].min():.6g}, {pts[:, 1].max():.6g}] m (got {zc:g})")
    t = np.where(crossing, (zc - z0) / np.where(z0 != z1, z1 - z0, 1.0), 0.0)
    r_cross = np.where(crossing, pts[:, 0] + t * (q[:, 0] - pts[:, 0]), -np.inf)
    e = int(np.argmax(r_cross))
    contact = np.array([r_cross[e], zc])
    # Insert the contact point (or reuse a vertex that coincides with it).
    if np.linalg.norm(pts[e] - contact) <= tol:
        ic = e
    elif np.linalg.norm(q[e] - contact) <= tol:
        ic = (e + 1) % n
    else:
        pts = np.insert(pts, e + 1, contact, axis=0)
        ic = e + 1
        if bore[0] > e:
            bore[0] += 1
        n += 1
    ib = bore[0]
    # Break points: sharp corners, the bore edge ends and the contact point.
    prev = pts - np.roll(pts, 1, axis=0)
    nxt = np.roll(pts, -1, axis=0) - pts
    cosang = np.einsum("ij,ij->i", prev, nxt) / (np.linalg.norm(prev, axis=1) * np.linalg.norm(nxt, axis=1))
    corner = np.arccos(np.clip(cosang, -1, 1)) > FILE_CORNER_ANGLE
    # Also break where the point spacing jumps: gmsh splines are parametrised per point, so a
    # spline mixing dense and sparse points would get a very uneven mesh.
    len_prev, len_next = np.linalg.norm(prev, axis=1), np.linalg.norm(nxt, axis=1)
    jump = np.maximum(len_prev, len_next) > FILE_SPACING_RATIO * np.minimum(len_prev, len_next)
    breaks = set(np.flatnonzero(corner | jump).tolist())
    breaks |= {ib, (ib + 1) % n, ic}
    order = sorted(breaks)
    # Rotate so that the outline starts at the first break; build lines/splines between breaks.
    segments = []
    bore_segment = contact_vertex = -1
    for k, b in enumerate(order):
        b_next = order[(k + 1) % len(order)]
        idx = np.arange(b, b_next + (n if b_next <= b else 0) + 1) % n
        chunk = pts[idx]
        kind = "line" if len(chunk) == 2 else "spline"
        if b == ib:
            bore_segment = len(segments)
        if b == ic:
            contact_vertex = len(segments)
        segments.append(Segment(kind, chunk))
    return Outline(segments, bore_segment=bore_segment, contact_vertex=contact_vertex,
                   contact_point=contact, polygon=pts)


def build_outline(params: WheelParams, prefix: str = "wheel") -> Outline:
    """Segments of the closed, counter-clockwise section outline (validates the geometry).

    Parameters
    ----------
    params : WheelParams
    prefix : str
        Dotted prefix for error field names.

    Returns
    -------
    Outline
    """
    if params.profile_file:
        return _file_outline(params, prefix)
    return _parametric_outline(params, prefix)


def section_outline(params: WheelParams) -> tuple[np.ndarray, dict]:
    """Closed counter-clockwise outline of the section as points.

    Arcs are discretised in steps of at most ``ARC_STEP``; file outlines are returned as read
    (plus the inserted contact point).

    Parameters
    ----------
    params : WheelParams

    Returns
    -------
    points : ndarray, shape (P, 2)
        Outline points (r, z) in m, counter-clockwise, the first point not repeated.
    labels : dict
        ``"bore"``: int array (2,) with the indices of the two ends of the bore (clamped)
        edge; ``"contact"``: index of the contact point.
    """
    outline = build_outline(params)
    pieces = [s.discretise() for s in outline.segments]
    starts = np.cumsum([0] + [len(x) for x in pieces])
    points = np.vstack(pieces)
    b = outline.bore_segment
    labels = {
        "bore": np.array([starts[b], starts[b + 1] % len(points)]),
        "contact": int(starts[outline.contact_vertex]),
    }
    return points, labels


def outline_area_moment(points: np.ndarray) -> tuple[float, float]:
    """Area (m^2) and first moment ``int r dA`` (m^3) of a closed polygon in (r, z)."""
    return _polygon_first_moment(np.asarray(points, dtype=float))


def outline_mass(params: WheelParams) -> float:
    """Mass of the wheel from the outline by Pappus' theorem (kg).

    ``m = density * 2 pi * int r dA``, the integral taken over the polygon of
    :func:`section_outline` (independent of any mesh).
    """
    points, _ = section_outline(params)
    _, moment = outline_area_moment(points)
    return params.density * 2.0 * math.pi * moment
