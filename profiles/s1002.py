"""The S1002 wheel profile (EN 13715, formerly UIC 510-2) from its piecewise definition.

The standard defines the running surface by eight pieces over the lateral coordinate ``s`` (mm)
measured from the tape circle (70 mm from the flange back), positive towards the field side; the
function ``F(s)`` (mm) is the radial height above the tape circle (the flange tip is at
F = 28 mm). Pieces, from the field side to the flange back:

====  =====================  ==========================================================
A     32.15796 <= s <= 60    straight 1:15 chamfer  F = a0 - a1 s
B     -26 <= s < 32.15796    polynomial of degree 8 (tread)
C     -35 <= s < -26         polynomial of degree 7 (tread to flange root)
D     -38.4267 <= s < -35    circular arc, radius 13 mm (flange root)
E     -39.7645 <= s < -38.4267  straight flange face at 70 deg (slope 2.7475)
F     -49.6625 <= s < -39.7645  circular arc, radius 20 mm (flange face to tip)
G     -62.7647 <= s < -49.6625  circular arc, radius 12 mm (flange tip)
H     -70 <= s < -62.7647    circular arc, radius 20.5 mm (flange back)
====  =====================  ==========================================================

The coefficients are those of the standard's piecewise definition as circulated in multibody
codes (e.g. the implementation attributed to H. Netter, DLR); they were not checked against the
standard's own text. ``tests/test_geometry.py`` checks continuity of height and slope at the
joints (the published rounding leaves jumps up to 1.2e-4 mm), the flange height (28 mm) and the
flange thickness (32.5 mm, 10 mm above the tape circle).

Rewrite the sampled data file ``profiles/data/s1002.txt`` with
``python -c "from profiles.s1002 import write_data_file; write_data_file()"``.
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from .curve import Profile, write_profile

logger = logging.getLogger(__name__)

__all__ = ["s1002_height", "S1002_JOINTS_MM", "S1002_TAPE_OFFSET", "DATA_FILE", "sample_s1002",
           "write_data_file"]

#: Joints between the pieces H|G|F|E|D|C|B|A and the two ends, in s (mm), increasing.
S1002_JOINTS_MM = np.array([-70.0, -62.764705882, -49.662510381, -39.764473993, -38.426669071,
                            -35.0, -26.0, 32.15796, 60.0])
#: Distance of the tape circle from the flange back (m).
S1002_TAPE_OFFSET = 0.070
#: Sampled profile shipped with the package.
DATA_FILE = Path(__file__).with_name("data") / "s1002.txt"

_A = (1.364323640, 0.066666667)
_B = (0.0, -3.358537058e-02, 1.565681624e-03, -2.810427944e-05, 5.844240864e-08,
      -1.562379023e-08, 5.309217349e-15, -5.957839843e-12, 2.646656573e-13)
_C = (-4.320221063e+03, -1.038384026e+03, -1.065501873e+02, -6.051367875, -2.054332446e-01,
      -4.169739389e-03, -4.687195829e-05, -2.252755540e-07)
# circular pieces: F = offset + sign * sqrt(radius^2 - (s + centre)^2)
_ARCS = {"D": (16.446, -1.0, 13.0, 26.210665), "F": (8.834924130, 1.0, 20.0, 58.558326413),
         "G": (16.0, 1.0, 12.0, 55.0), "H": (9.519259302, 1.0, 20.5, 49.5)}
_E = (-93.576667419, -2.747477419)


def _arc(s, piece):
    off, sign, rad, centre = _ARCS[piece]
    return off + sign * np.sqrt(np.clip(rad * rad - (s + centre) ** 2, 0.0, None))


def s1002_height(s_mm):
    """Radial height F (mm) of the S1002 profile above the tape circle.

    Parameters
    ----------
    s_mm : array_like
        Lateral coordinate from the tape circle (mm), positive towards the field side, in
        [-70, 60].

    Returns
    -------
    ndarray
        F(s) (mm); NaN outside [-70, 60].
    """
    s = np.asarray(s_mm, dtype=float)
    j = S1002_JOINTS_MM
    pieces = [
        _arc(s, "H"), _arc(s, "G"), _arc(s, "F"), _E[0] + _E[1] * s, _arc(s, "D"),
        np.polynomial.polynomial.polyval(s, _C), np.polynomial.polynomial.polyval(s, _B),
        _A[0] - _A[1] * s,
    ]
    conds = [(s >= j[k]) & (s < j[k + 1]) for k in range(8)]
    conds[-1] = (s >= j[7]) & (s <= j[8])
    return np.select(conds, pieces, default=np.nan)


def sample_s1002(step: float = 5e-5) -> Profile:
    """S1002 sampled in the wheel frame: y from the flange back (m), z radial height (m).

    The first 0.5 mm of the flange back (vertical at y = 0, where the profile is no graph z(y)
    and no rail contact can occur) is left out.

    Parameters
    ----------
    step : float
        Lateral sample spacing (m).

    Returns
    -------
    Profile
    """
    y = np.arange(0.0005, 0.130 + 0.5 * step, step)
    y = np.union1d(y, S1002_JOINTS_MM[1:] * 1e-3 + S1002_TAPE_OFFSET)
    y = y[np.r_[True, np.diff(y) > 1e-7]]
    z = s1002_height((y - S1002_TAPE_OFFSET) * 1e3) * 1e-3
    return Profile(y, z, "S1002")


def write_data_file(path: Path = DATA_FILE) -> None:
    """Write the sampled S1002 data file (0.05 mm spacing plus the joints)."""
    write_profile(path, sample_s1002(), header=(
        "S1002 wheel profile (EN 13715 / UIC 510-2), sampled from its piecewise definition\n"
        "by profiles/s1002.py (write_data_file).\n"
        "y: lateral position from the flange back (m), positive towards the field side;\n"
        "z: radial height above the tape circle (m) at y = 0.070 m (flange tip z = 0.028 m)."))
    logger.info("wrote %s", path)
