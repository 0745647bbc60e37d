"""Rail head profile for contact: the upper surface of a rail section, with rail inclination.

The head profile is taken from the section outline of :func:`profiles.rail_section.rail_outline`
(BV50, 60E1 or an outline file): the part of the outline, around its highest point, where the
outward normal points upwards (crown and head corners, down to the vertical head sides).

**Rail inclination** (cant): the rail is tilted towards the track centre by 1:n, n in
:data:`INCLINATIONS` (``[rail] inclination``). European standard-gauge lines use 1:20 (former
practice in Germany and France), 1:40 (UK, Spain) or 1:30. The default 1:30 for Swedish track
with BV50 and 60E1 rails is an **assumption** of this project: a search of the stored public
pages for a Trafikverket source ("Trafikverket rail inclination 1:30", "rälslutning 1:30")
found none, so no document is cited; users with a measured or specified cant set
``[rail] inclination``. ``0`` means an upright rail. The waveguide rail mesh stays upright in its
own section frame: the inclination enters the contact geometry only.

Frame: ``y`` lateral from the rail's centre line (m), positive towards the field side; ``z`` up
(m) with the section's own origin (foot bottom). An inclined section is turned about the top of
its centre line (y = 0 on the crown stays at y = 0), the gauge side going down.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from squealcore.errors import InputError

from .curve import Profile
from .rail_section import INCLINATIONS, SWEDISH_INCLINATION, RailParams, rail_outline

logger = logging.getLogger(__name__)

__all__ = ["INCLINATIONS", "SWEDISH_INCLINATION", "rail_head_profile", "inclined_outline",
           "gauge_point", "GAUGE_POINT_DEPTH", "rail_profile_from_params"]
#: Depth below the top of the rail at which the gauge is measured (m), EN 13848-1: 14 mm.
GAUGE_POINT_DEPTH = 0.014
#: Spacing of the outline points on arcs used to build the head profile (m).
OUTLINE_STEP = 2.5e-4


def _check_inclination(inclination) -> float:
    """Tilt angle (rad) of a 1:n inclination, refusing n outside :data:`INCLINATIONS`."""
    if isinstance(inclination, bool) or inclination not in INCLINATIONS:
        raise InputError("rail.inclination",
                         f"must be one of {INCLINATIONS} (1:n, 0 = upright), got {inclination!r}")
    return 0.0 if inclination == 0 else math.atan(1.0 / inclination)


def inclined_outline(profile: str = "BV50", inclination: int = SWEDISH_INCLINATION,
                     step: float = OUTLINE_STEP) -> np.ndarray:
    """Closed rail section outline (n, 2) (y, z) in m, tilted by 1:``inclination`` towards the gauge side.

    Parameters
    ----------
    profile : str
        ``"BV50"``, ``"60E1"`` or an outline file (see :func:`profiles.rail_section.rail_outline`).
    inclination : int
        n of the inclination 1:n, one of :data:`INCLINATIONS`.
    step : float
        Length of the straight pieces approximating arcs (m).
    """
    alpha = _check_inclination(inclination)
    pts = np.asarray(rail_outline(profile, size=step), dtype=float)
    top = pts[np.argmax(pts[:, 1])]
    pivot = np.array([0.0, top[1]])
    c, s = math.cos(alpha), math.sin(alpha)
    rot = np.array([[c, -s], [s, c]])  # counter-clockwise: the field side (y > 0) rises
    return (pts - pivot) @ rot.T + pivot


def rail_head_profile(profile: str = "BV50", inclination: int = SWEDISH_INCLINATION,
                      step: float = OUTLINE_STEP) -> Profile:
    """Upper surface of the rail head as a :class:`~profiles.curve.Profile`.

    Parameters
    ----------
    profile, inclination, step
        As for :func:`inclined_outline`.

    Returns
    -------
    Profile
        Head surface z(y) (m), from the gauge-side to the field-side head corner.
    """
    pts = inclined_outline(profile, inclination, step)
    n = len(pts)
    k = int(np.argmax(pts[:, 1]))
    # Counter-clockwise outline: going backwards from the top runs to the field side (+y),
    # forwards to the gauge side (-y). Walk while y keeps moving away from the top.
    idx = [k]
    for direction in (-1, 1):
        i = k
        while True:
            j = (i + direction) % n
            dy = pts[j, 0] - pts[i, 0]
            if j == k or (dy <= 1e-12 if direction == -1 else dy >= -1e-12):
                break
            idx.append(j)
            i = j
    idx = np.array(sorted(set(idx), key=lambda t: pts[t, 0]))
    head = pts[idx]
    name = f"rail {profile} 1:{inclination}" if inclination else f"rail {profile} upright"
    return Profile(head[:, 0], head[:, 1], name)


def gauge_point(profile: str = "BV50", inclination: int = SWEDISH_INCLINATION,
                depth: float = GAUGE_POINT_DEPTH, step: float = OUTLINE_STEP) -> float:
    """Lateral position (m, rail frame, < 0) of the gauge face ``depth`` below the top of the rail.

    The gauge face is the gauge-side (smallest y) crossing of the section outline with the
    horizontal line ``depth`` below the highest point of the (inclined) head.
    """
    pts = inclined_outline(profile, inclination, step)
    level = pts[:, 1].max() - depth
    q = np.roll(pts, -1, axis=0)
    z0, z1 = pts[:, 1], q[:, 1]
    crossing = (np.minimum(z0, z1) <= level) & (np.maximum(z0, z1) > level)
    t = (level - z0[crossing]) / (z1[crossing] - z0[crossing])
    y = pts[crossing, 0] + t * (q[crossing, 0] - pts[crossing, 0])
    return float(y.min())


def rail_profile_from_params(params: RailParams) -> Profile:
    """Head profile of the study's rail (``[rail] profile``) tilted by ``[rail] inclination``.

    Parameters
    ----------
    params : RailParams
        Validated rail parameters.

    Returns
    -------
    Profile
        As :func:`rail_head_profile` (track frame: y from the rail's centre line, z up).
    """
    return rail_head_profile(params.profile, params.inclination)
