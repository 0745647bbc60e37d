"""The running surface of a study's wheel, as the wheel section is built: the tread profile of
``[wheel] tread_profile`` (S1002 or a file, from :mod:`profiles.wheel_treads`), the parametric 1:40
cone with flange of the section outline, or the outer edge of a section outline file.

A wheel profile is a :class:`~profiles.curve.Profile` in the wheel frame: ``y`` from the
flange back (m), ``z`` radial height above the tape circle (m); see :mod:`profiles.curve`.
:func:`wheel_profile_from_params` is the one source of the running surface of a study's wheel:
the wheel mesh (:mod:`mesh.wheel_section`) is built on the same points.
"""

from __future__ import annotations

import numpy as np

from mesh.wheel_section import WheelParams, build_outline, tread_profile
from profiles.curve import Profile
from squealcore.errors import InputError

__all__ = ["parametric_wheel_profile", "outline_wheel_profile", "wheel_profile_from_params", "wheel_tape_radius"]

#: Lateral sample spacing used to resample the parametric outline (m).
RESAMPLE_STEP = 2e-4
#: Steepest slope |dr/dz| of a section file's outer edge that still counts as running surface: a
#: steeper piece (a face of the rim or the hub, a flange back) ends it (about 84 deg).
CLIFF_SLOPE = 10.0


def wheel_profile_from_params(params: WheelParams) -> Profile:
    """The running surface of the study's wheel, as meshed (``[wheel] tread_profile``).

    Parameters
    ----------
    params : WheelParams
        Validated wheel parameters.

    Returns
    -------
    Profile
        ``"parametric"``: :func:`parametric_wheel_profile` (the outline's cone and flange,
        resampled); ``"S1002"`` or a file: the profile points the wheel section is built on
        (:func:`mesh.wheel_section.tread_profile`), height 0 at ``rolling_radius``. With
        ``profile_file`` set (a full section outline), its outer boundary as for the parametric
        wheel.
    """
    if params.profile_file:
        return outline_wheel_profile(params)
    surface = tread_profile(params)
    return parametric_wheel_profile(params) if surface is None else surface


def wheel_tape_radius(params: WheelParams) -> float:
    """Radius (m) at which the study's wheel profile has height 0: ``rolling_radius``, or with
    ``profile_file`` the section's outer radius at ``contact_offset`` (the mesh's contact node)."""
    if params.profile_file:
        return float(build_outline(params).contact_point[0])
    return params.rolling_radius


def outline_wheel_profile(params: WheelParams, step: float = RESAMPLE_STEP) -> Profile:
    """Running surface of a section read from a file (``[wheel] profile_file``).

    The outer edge of the closed outline seen from outside: the largest radius of the outline
    at each axial position ``y`` (its polygon, sampled every ``step`` and at every vertex), kept
    between the steep pieces (|dr/dy| > :data:`CLIFF_SLOPE`: rim or hub faces, a flange back)
    nearest to ``contact_offset`` on either side. Height ``z = r - r_c``, with ``r_c`` the outer
    radius at ``contact_offset`` (:func:`wheel_tape_radius`). The profile's name is the file.

    Raises
    ------
    InputError
        Naming ``wheel.profile_file`` and the file if fewer than 4 points of running surface are
        left around ``contact_offset``.
    """
    outline = build_outline(params)
    pts = outline.polygon
    r_c = float(outline.contact_point[0])
    name = f"{params.profile_file} (outer edge of wheel.profile_file)"
    a, b = pts, np.roll(pts, -1, axis=0)
    lo, hi = float(pts[:, 1].min()), float(pts[:, 1].max())
    y = np.union1d(np.arange(lo, hi, step), pts[:, 1])
    y = y[(y > lo) & (y < hi)]
    # largest radius among the edges that reach each y (horizontal edges: their larger end)
    za, zb = a[:, 1][None, :], b[:, 1][None, :]
    ra, rb = a[:, 0][None, :], b[:, 0][None, :]
    yy = y[:, None]
    span = (np.minimum(za, zb) <= yy) & (yy <= np.maximum(za, zb))
    flat = za == zb
    t = np.where(flat, 0.0, (yy - za) / np.where(flat, 1.0, zb - za))
    r_at = np.where(flat, np.maximum(ra, rb), ra + t * (rb - ra))
    r = np.where(span, r_at, -np.inf).max(axis=1)
    keep = np.isfinite(r)
    y, r = y[keep], r[keep]
    c = params.contact_offset
    cliffs = np.flatnonzero(np.abs(np.diff(r)) > CLIFF_SLOPE * np.diff(y))  # between y[i] and y[i + 1]
    left, right = cliffs[y[cliffs + 1] <= c], cliffs[y[cliffs] >= c]
    first = int(left.max()) + 1 if left.size else 0
    last = int(right.min()) if right.size else y.size - 1
    y, r = y[first:last + 1], r[first:last + 1]
    if y.size < 4:
        raise InputError("wheel.profile_file", f"{params.profile_file}: the outer edge of the section around "
                                               f"wheel.contact_offset = {params.contact_offset:g} m has no running "
                                               "surface of at least 4 points between steep faces")
    return Profile(y, r - r_c, name)


def parametric_wheel_profile(params: WheelParams | None = None, step: float = RESAMPLE_STEP) -> Profile:
    """Running surface of the parametric wheel section (conical tread and flange).

    Uses the outline of :func:`mesh.wheel_section.build_outline` (lines and exact arcs) and
    keeps its outer boundary between the flange back and the field face, resampled every
    ``step`` along each piece. ``z = r - rolling_radius``.

    Parameters
    ----------
    params : WheelParams, optional
        Default: ``WheelParams()`` (1:40 cone, r = 0.39 m at 70 mm from the flange back).
    step : float
        Sample spacing along the outline (m).
    """
    p = WheelParams() if params is None else params
    outline = build_outline(p)
    # Segment.discretise steps arcs by 2 deg and gives lines by their ends only; the spline of
    # the profile needs dense points on the exact lines and arcs, hence the resampling here.
    pts = []
    for seg in outline.segments:
        if seg.kind == "line":
            a, b = seg.points
            n = max(2, int(np.ceil(np.linalg.norm(b - a) / step)) + 1)
            pts.append(a + np.linspace(0.0, 1.0, n)[:, None] * (b - a))
        elif seg.kind == "arc":
            start, centre, end = seg.points
            a0 = np.arctan2(*(start - centre)[::-1])
            a1 = np.arctan2(*(end - centre)[::-1])
            sweep = (a1 - a0 + np.pi) % (2.0 * np.pi) - np.pi
            rad = np.linalg.norm(start - centre)
            n = max(2, int(np.ceil(abs(sweep) * rad / step)) + 1)
            ang = a0 + sweep * np.linspace(0.0, 1.0, n)
            pts.append(centre + rad * np.column_stack([np.cos(ang), np.sin(ang)]))
        else:  # spline through points (outline files): its points as they are
            pts.append(np.asarray(seg.points, dtype=float))
    pts = np.vstack(pts)
    tol = 1e-9
    keep = (pts[:, 1] > tol) & (pts[:, 1] < p.rim_width - tol) & (pts[:, 0] > p.rim_inner_radius + tol)
    r, y = pts[keep, 0], pts[keep, 1]
    order = np.argsort(y)
    y, r = y[order], r[order]
    distinct = np.r_[True, np.diff(y) > 1e-9]
    return Profile(y[distinct], r[distinct] - p.rolling_radius, "parametric wheel (WheelParams)")

