"""A measured or designed transverse profile (wheel or rail) as a smooth curve z(y).

File format (what profilometers export, reduced to two columns): one point a line, lateral
position ``y`` then height ``z``, separated by blanks, a comma or a semicolon; ``#`` starts a
comment. Units are metres unless a header comment line ``# units: mm`` says millimetres. UTF-8
text (a byte-order mark and Windows line ends are fine), at most :data:`MAX_FILE_BYTES`. The
formats of profile measuring devices (MiniProf ``.whl``/``.ban`` and others) have no public
description we could find; export or convert them to these two columns. The points must run
with strictly increasing ``y`` (a profile is a graph z(y) over the part used for contact).

Heights: for a **rail** ``z`` is the height of the head surface (m, up); for a **wheel** ``z`` is
the radial height of the running surface above the tape circle (m, outwards from the axle, so the
flange tip is positive), as in the EN 13715 drawings; the lateral position of a wheel is measured
from the flange back, that of a rail from its centre line, both positive towards the field side
(``docs/conventions.md``).
"""

from __future__ import annotations

import logging
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from squealcore.errors import InputError

if TYPE_CHECKING:  # for the annotation only: the spline is imported where it is built (see Profile)
    from scipy.interpolate import CubicSpline

logger = logging.getLogger(__name__)

__all__ = ["Profile", "read_profile", "write_profile", "excerpt", "MIN_POINTS", "MAX_FILE_BYTES"]

#: Fewest points a profile may have (a cubic spline needs 4).
MIN_POINTS = 4
_UNITS = {"m": 1.0, "mm": 1e-3}
#: Largest profile file read (bytes): a profile has hundreds to a few thousand points.
MAX_FILE_BYTES = 5_000_000
#: Characters of a file line quoted in an error message.
EXCERPT_CHARS = 40
_UNITS_RE = re.compile(r"^\s*#\s*units\s*:\s*(\S+)\s*$", re.IGNORECASE)


def _self_intersecting(y: np.ndarray, z: np.ndarray) -> bool:
    """True if two non-adjacent edges of the open polyline (y, z) cross."""
    p = np.column_stack([y, z])
    a, b = p[:-1], p[1:]
    n = len(a)
    if n < 3:
        return False
    i, j = np.triu_indices(n, k=2)

    def orient(p0, p1, p2):
        return np.sign((p1[:, 0] - p0[:, 0]) * (p2[:, 1] - p0[:, 1])
                       - (p1[:, 1] - p0[:, 1]) * (p2[:, 0] - p0[:, 0]))

    o1, o2 = orient(a[i], b[i], a[j]), orient(a[i], b[i], b[j])
    o3, o4 = orient(a[j], b[j], a[i]), orient(a[j], b[j], b[i])
    return bool(np.any((o1 * o2 < 0) & (o3 * o4 < 0)))


@dataclass(frozen=True)
class Profile:
    """A transverse profile z(y), interpolated by a cubic spline (not-a-knot).

    Parameters
    ----------
    y : array_like, shape (n,)
        Lateral positions (m), strictly increasing.
    z : array_like, shape (n,)
        Heights (m); see the module docstring for wheels and rails.
    name : str
        Where the profile comes from (file path or a label); named in error messages.

    Raises
    ------
    InputError
        Fewer than :data:`MIN_POINTS` points, non-finite values, or ``y`` not strictly
        increasing (the message says whether the polyline also crosses itself).
    """

    y: np.ndarray
    z: np.ndarray
    name: str = "profile"
    _spline: CubicSpline = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        y = np.asarray(self.y, dtype=float).ravel()
        z = np.asarray(self.z, dtype=float).ravel()
        if y.shape != z.shape:
            raise InputError(self.name, f"y and z must have the same length, got {y.size} and {z.size}")
        if y.size < MIN_POINTS:
            raise InputError(self.name, f"too few points: at least {MIN_POINTS} (y, z) points needed, got {y.size}")
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise InputError(self.name, "non-finite value (nan or inf) among the points")
        if np.any(np.diff(y) <= 0.0):
            k = int(np.argmax(np.diff(y) <= 0.0))
            what = ("self-intersecting profile" if _self_intersecting(y, z)
                    else "non-monotonic profile")
            raise InputError(self.name, f"{what}: lateral positions must increase strictly, but point "
                                        f"{k + 1} (y = {y[k + 1]:.6g} m) does not follow point {k} "
                                        f"(y = {y[k]:.6g} m)")
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        # lazy: scipy.interpolate (with scipy.optimize) is 0.25-0.45 s of import (python -X importtime),
        # paid otherwise by every importer of mesh.wheel_section's parameters, such as the contact command
        from scipy.interpolate import CubicSpline
        object.__setattr__(self, "_spline", CubicSpline(y, z))

    @property
    def bounds(self) -> tuple[float, float]:
        """Lateral extent (y_min, y_max) (m)."""
        return float(self.y[0]), float(self.y[-1])

    def height(self, y, derivative: int = 0):
        """Height z (m) or its derivative of order ``derivative`` (m^(1-k)) at ``y`` (m)."""
        return self._spline(y, derivative)

    def curvature(self, y):
        """Signed curvature z'' / (1 + z'^2)^1.5 (1/m) at ``y`` (m); > 0 where z is convex upwards."""
        d1 = self._spline(y, 1)
        return self._spline(y, 2) / (1.0 + d1 * d1) ** 1.5


def excerpt(text: str, limit: int = EXCERPT_CHARS) -> str:
    """A short, escaped excerpt of file text for an error message: at most ``limit`` characters,
    quoted with Python's escapes (control and non-printable characters never reach the terminal)."""
    short = text if len(text) <= limit else text[:limit] + "..."
    return repr(short)


def read_profile(path: str | Path, name: str | None = None) -> Profile:
    """Read a profile from a two-column text file (format in the module docstring).

    Accepted: blanks, tabs, a comma or a semicolon between the columns; ``#`` comments; a
    ``# units: mm`` line; Windows line ends and a UTF-8 byte-order mark. Every error names the
    file (the field), the line and what is wrong, with at most a short escaped excerpt of the line.

    Parameters
    ----------
    path : str or Path
        The file.
    name : str, optional
        Name used in error messages; default the file path.

    Returns
    -------
    Profile

    Raises
    ------
    InputError
        Unreadable, too large or not UTF-8 text; unknown units; a data line that is not two
        numbers, or holds nan or inf; lateral positions that do not increase (naming both lines);
        too few points; a self-intersecting polyline (see :class:`Profile`). The field is the
        file path (or ``name``).
    """
    label = str(path) if name is None else name
    try:
        size = Path(path).stat().st_size
        if size > MAX_FILE_BYTES:
            raise InputError(label, f"the profile file is {size} bytes, more than the {MAX_FILE_BYTES} "
                                    "bytes a profile may have")
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise InputError(label, f"cannot read the profile file: {exc.strerror}") from None
    try:
        text = raw.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = raw[:exc.start].count(b"\n") + 1
        raise InputError(label, f"line {line}: not a text file (byte {exc.start} is not UTF-8); a profile "
                                "file is two columns of numbers (y z)") from None
    scale = 1.0
    rows, lines = [], []
    for lineno, line in enumerate(text.splitlines(), start=1):
        m = _UNITS_RE.match(line)
        if m:
            unit = m.group(1).lower()
            if unit not in _UNITS:
                raise InputError(label, f"line {lineno}: units must be one of {sorted(_UNITS)}, got "
                                        f"{excerpt(m.group(1), 10)}")
            scale = _UNITS[unit]
            continue
        body = line.split("#", 1)[0].replace(",", " ").replace(";", " ").split()
        if not body:
            continue
        if len(body) != 2:
            hint = (" (text before the data? header lines must start with #)"
                    if not rows and any(c.isalpha() for c in line) else "")
            raise InputError(label, f"line {lineno}: expected 2 columns (y z), got {len(body)}: "
                                    f"{excerpt(line.strip())}{hint}")
        try:
            y, z = float(body[0]), float(body[1])
        except ValueError:
            raise InputError(label, f"line {lineno}: not a number: {excerpt(line.strip())}") from None
        if not (math.isfinite(y) and math.isfinite(z)):
            raise InputError(label, f"line {lineno}: non-finite value (nan or inf): {excerpt(line.strip())}")
        rows.append((y, z))
        lines.append(lineno)
    if not rows:
        raise InputError(label, f"too few points: no data lines (at least {MIN_POINTS} lines of two "
                                "numbers y z needed)")
    data = np.array(rows, dtype=float).reshape(-1, 2) * scale
    steps = np.diff(data[:, 0])
    if np.any(steps <= 0.0) and not _self_intersecting(data[:, 0], data[:, 1]):
        k = int(np.argmax(steps <= 0.0))
        raise InputError(label, f"line {lines[k + 1]}: non-monotonic profile: y = {data[k + 1, 0]:.6g} m does "
                                f"not exceed y = {data[k, 0]:.6g} m of line {lines[k]} (lateral positions must "
                                "increase strictly)")
    return Profile(data[:, 0], data[:, 1], label)


def write_profile(path: str | Path, profile: Profile, header: str = "") -> None:
    """Write a profile in the text format of :func:`read_profile` (metres, 9 significant digits).

    Parameters
    ----------
    path : str or Path
        Output file.
    profile : Profile
    header : str
        Comment lines (without ``#``) written first.
    """
    lines = [f"# {h}" for h in header.splitlines()] + ["# units: m", "# y (m)  z (m)"]
    lines += [f"{a:.9e} {b:.9e}" for a, b in zip(profile.y, profile.z)]
    Path(path).write_text("\n".join(lines) + "\n")
