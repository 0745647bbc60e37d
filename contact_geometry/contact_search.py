"""Rigid wheel/rail contact search by the minimum vertical distance between the profiles.

The wheel profile (wheel frame, see :mod:`geometry.profile`) is placed on the rail profile with
its flange back at ``flange_back + y_w`` (rail frame), ``y_w`` the lateral displacement of the
wheel relative to the rail (positive towards the field side, i.e. the flange moves towards the
rail's gauge face). The wheel is lowered until it touches: with ``z_w`` the wheel's radial
height and ``z_r`` the rail height, the vertical gap at rail position ``y`` is, up to a constant,
``-(z_r(y) + z_w(y - y_0))``, so contact is where ``f(y) = z_r(y) + z_w(y - y_0)`` is largest
(``y_0 = flange_back + y_w``). ``f`` is evaluated on a lateral grid for all displacements at once
(vectorised), its maximum refined by Newton's method on ``f'(y) = 0`` with the splines'
derivatives. A second contact is reported when another local maximum of ``f``, separated from the
first by a dip deeper than ``two_point_tol``, comes within ``two_point_tol`` of it (tread and
flange touching together).

Per contact (SI units):

* lateral position on the wheel (from the flange back) and on the rail (from its centre line);
* rolling radius ``r = r0 + z_w``;
* contact angle ``delta = atan(z_r')`` (rad), positive when the contact normal leans towards the
  gauge side (flange side of the wheel); at a smooth contact ``z_r' = -z_w'``;
* principal relative curvatures: longitudinal ``cos(delta) / r`` for the wheel (Meusnier: the
  normal curvature of the rolling circle in the contact plane; = 1/r at a flat tread) and 0 for
  the rail; lateral ``k_w + k_r`` with the convex profile curvatures
  ``k = -z'' / (1 + z'^2)^1.5`` of the wheel and of the rail;
* Hertz semi-axes (:func:`contact.hertz.hertz_from_curvatures`) with gap curvatures
  ``A, B`` = half the relative curvatures and normal load ``Q / cos(delta)`` for a vertical wheel
  load ``Q`` (NaN where the contact is conformal or concave, B <= 0);
* geometric spin ``sin(delta) / r`` (1/m, spin creepage per unit rolling speed).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from contact.hertz import hertz_from_curvatures
from contact.params import Material
from profiles.curve import Profile
from squealcore.errors import InputError, require_range

logger = logging.getLogger(__name__)

__all__ = ["WheelRailPair", "ContactTable", "contact_table", "contact_exists", "contact_interval",
           "STEEL_CONTACT_MODULUS"]

#: Contact modulus E* = G / (1 - nu) of steel on steel (E = 210 GPa, nu = 0.3) (Pa).
STEEL_CONTACT_MODULUS = Material.from_young(210e9, 0.3).contact_modulus
_NEWTON_STEPS = 8
#: Bound of |f''| (1/m) assumed when comparing grid values of f: a 70 deg flange face of 12 mm
#: radius has z'' = (1 + tan^2 70)^1.5 / 0.012 ~ 2000 1/m; with the rail's 13 mm corner ~ 4000.
_MAX_F2 = 8000.0


@dataclass(frozen=True)
class WheelRailPair:
    """A wheel profile on a rail profile.

    Parameters
    ----------
    wheel : Profile
        Wheel profile: y from the flange back (m), z radial height above the tape circle (m).
    rail : Profile
        Rail head profile: y from the rail centre line (m), z height (m).
    nominal_radius : float
        Rolling radius of the tape circle (m), where ``wheel.z = 0``.
    flange_back : float
        Lateral position of the flange back in the rail frame at zero displacement (m); see
        :func:`geometry.track.flange_back_position`.
    rail_tilt : float
        Inclination of the rail (rad, counter-clockwise: field side up; ``atan(1/n)`` for 1:n),
        only used to express contact points in the rail section's frame.
    rail_pivot_height : float
        Height (m, section frame) of the point on the rail's centre line about which the
        section was turned (the top of the upright section, see
        :func:`~profiles.rail_head.inclined_outline`).
    """

    wheel: Profile
    rail: Profile
    nominal_radius: float
    flange_back: float
    rail_tilt: float = 0.0
    rail_pivot_height: float = 0.0

    def __post_init__(self):
        require_range("geometry.nominal_radius", self.nominal_radius, 0.1, 1.0, unit="m")
        require_range("geometry.flange_back", self.flange_back, -1.0, 1.0, unit="m")
        require_range("geometry.rail_tilt", self.rail_tilt, -0.2, 0.2, unit="rad")

    def rail_section_point(self, y, z):
        """A point (y, z) of the track frame in the rail section's own upright frame (m).

        Undoes the inclination: the section was turned by :attr:`rail_tilt` (counter-clockwise,
        field side up) about the point ``(0, rail_pivot_height)``.
        """
        c, s = np.cos(self.rail_tilt), np.sin(self.rail_tilt)
        dz = np.asarray(z, dtype=float) - self.rail_pivot_height
        y = np.asarray(y, dtype=float)
        return c * y + s * dz, -s * y + c * dz + self.rail_pivot_height


@dataclass(frozen=True)
class ContactTable:
    """Contact points over a range of lateral displacements (two slots per displacement).

    Slot 0 is the contact of smallest gap; slot 1 a second contact (two-point contact) or NaN.
    Arrays of per-contact quantities have shape (n, 2); NaN in unused slots.

    Attributes
    ----------
    displacement : ndarray (n,)
        Lateral wheel displacement y_w (m).
    n_contacts : ndarray (n,) of int
        1 or 2.
    y_wheel, y_rail : ndarray (n, 2)
        Lateral contact position on the wheel (from the flange back) and the rail (from its
        centre line) (m).
    rolling_radius : ndarray (n, 2)
        (m).
    contact_angle : ndarray (n, 2)
        (rad).
    curvature_long, curvature_lat : ndarray (n, 2)
        Relative principal curvatures, longitudinal and lateral (1/m).
    separation : ndarray (n, 2)
        Vertical gap of the contact above the first one (m): 0 in slot 0.
    semi_axis_a, semi_axis_b : ndarray (n, 2)
        Hertz semi-axes, longitudinal and lateral (m), each contact at the full normal load.
    normal_force : ndarray (n, 2)
        Wheel load / cos(contact angle) (N).
    spin : ndarray (n, 2)
        Geometric spin sin(delta) / r (1/m).
    """

    displacement: np.ndarray
    n_contacts: np.ndarray
    y_wheel: np.ndarray
    y_rail: np.ndarray
    rolling_radius: np.ndarray
    contact_angle: np.ndarray
    curvature_long: np.ndarray
    curvature_lat: np.ndarray
    separation: np.ndarray
    semi_axis_a: np.ndarray
    semi_axis_b: np.ndarray
    normal_force: np.ndarray
    spin: np.ndarray


def _newton_max(pair: WheelRailPair, y, offset, lo, hi):
    """Refine maxima of f(y) = z_r(y) + z_w(y - offset) by Newton steps kept within [lo, hi]."""
    for _ in range(_NEWTON_STEPS):
        g = pair.rail.height(y, 1) + pair.wheel.height(y - offset, 1)
        h = pair.rail.height(y, 2) + pair.wheel.height(y - offset, 2)
        step = np.where(h < 0.0, -g / np.where(h < 0.0, h, -1.0), 0.0)
        y = np.clip(y + step, lo, hi)
    return y


def _second_candidates(f, valid, i1, threshold, dip_min, min_gap_points):
    """Grid index per row of the highest other local maximum of ``f`` (-1 if none).

    A candidate lies at least ``min_gap_points`` from the first maximum ``i1``, within
    ``threshold`` of it, and is separated from it by a dip of ``f`` deeper than ``dip_min``
    (otherwise both belong to one contact zone).
    """
    n, m = f.shape
    out = np.full(n, -1)
    fmax = f[np.arange(n), i1]
    inner = np.zeros_like(valid)
    inner[:, 1:-1] = valid[:, 1:-1] & valid[:, :-2] & valid[:, 2:]
    local = np.zeros_like(valid)
    local[:, 1:-1] = (f[:, 1:-1] >= f[:, :-2]) & (f[:, 1:-1] > f[:, 2:])
    cand = local & inner & (f >= fmax[:, None] - threshold)
    cand &= np.abs(np.arange(m)[None, :] - i1[:, None]) > min_gap_points
    for row in np.flatnonzero(cand.any(axis=1)):
        best = -1
        for j in np.flatnonzero(cand[row]):
            a, b = sorted((int(i1[row]), int(j)))
            dip = min(f[row, j], fmax[row]) - f[row, a:b + 1].min()
            if dip > dip_min and (best < 0 or f[row, j] > f[row, best]):
                best = j
        out[row] = best
    return out


def _grid_search(pair: WheelRailPair, d: np.ndarray, grid_step: float):
    """Evaluate ``f`` on the lateral grid for every displacement and locate its grid maximum.

    Returns the grid (m), the flange-back positions (m), the mask of grid points the wheel
    covers, ``f`` (m, -inf off the wheel), the index of the maximum per row and the rows without
    a contact inside both profiles (maximum at the end of a profile, or < 3 common points).
    """
    rail, wheel = pair.rail, pair.wheel
    r_lo, r_hi = rail.bounds
    w_lo, w_hi = wheel.bounds
    ygrid = np.arange(r_lo, r_hi + 0.5 * grid_step, grid_step)
    ygrid[-1] = min(ygrid[-1], r_hi)
    offset = pair.flange_back + d
    yw = ygrid[None, :] - offset[:, None]
    valid = (yw >= w_lo) & (yw <= w_hi)
    f = np.where(valid, rail.height(ygrid)[None, :] + wheel.height(np.clip(yw, w_lo, w_hi)), -np.inf)
    i1 = np.argmax(f, axis=1)
    n_valid = valid.sum(axis=1)
    first = np.argmax(valid, axis=1)
    last = valid.shape[1] - 1 - np.argmax(valid[:, ::-1], axis=1)
    bad = (n_valid < 3) | (i1 == first) | (i1 == last)
    return ygrid, offset, valid, f, i1, bad


def contact_exists(pair: WheelRailPair, displacement, grid_step: float = 1e-4) -> np.ndarray:
    """Where the wheel meets the rail inside both profiles (the condition of :func:`contact_table`).

    Parameters
    ----------
    pair : WheelRailPair
    displacement : array_like
        Lateral wheel displacements y_w (m).
    grid_step : float
        Lateral spacing of the search grid (m), as for :func:`contact_table`.

    Returns
    -------
    ndarray of bool
        False where the closest approach lies at the end of a profile.
    """
    d = np.atleast_1d(np.asarray(displacement, dtype=float))
    return ~_grid_search(pair, d, grid_step)[-1]


def contact_interval(pair: WheelRailPair, low: float, high: float, step: float = 1e-4,
                     grid_step: float = 1e-4):
    """The displacements in [low, high] at which the profiles meet, as one closed interval.

    Parameters
    ----------
    pair : WheelRailPair
    low, high : float
        Range searched (m).
    step : float
        Spacing of the displacements tried (m); the interval ends are exact to this step.
    grid_step : float
        As for :func:`contact_table`.

    Returns
    -------
    (float, float) or None
        The contiguous run of displacements with contact that contains 0 (or, without contact at
        0, the widest run); None if there is no contact anywhere.
    """
    n = max(2, int(round((high - low) / step)) + 1)
    d = np.linspace(low, high, n)
    ok = contact_exists(pair, d, grid_step)
    if not ok.any():
        return None
    edges = np.flatnonzero(np.diff(np.r_[0, ok.astype(int), 0]))
    runs = list(zip(edges[::2], edges[1::2] - 1))
    home = [r for r in runs if d[r[0]] <= 0.0 <= d[r[1]]]
    start, stop = home[0] if home else max(runs, key=lambda r: r[1] - r[0])
    return float(d[start]), float(d[stop])


def contact_table(pair: WheelRailPair, displacement, wheel_load: float = 50e3,
                  contact_modulus: float = STEEL_CONTACT_MODULUS, grid_step: float = 1e-4,
                  two_point_tol: float = 1e-5) -> ContactTable:
    """Contact points and contact geometry for lateral displacements of the wheel.

    Parameters
    ----------
    pair : WheelRailPair
    displacement : array_like
        Lateral wheel displacements y_w (m), positive towards the field side.
    wheel_load : float
        Vertical wheel load Q (N), > 0.
    contact_modulus : float
        E* (Pa) for :func:`~contact.hertz.hertz_from_curvatures`.
    grid_step : float
        Lateral spacing of the search grid (m), in [1e-6, 1e-3].
    two_point_tol : float
        Gap tolerance for a second contact (m), in [0, 1e-3].

    Returns
    -------
    ContactTable

    Raises
    ------
    InputError
        If for some displacement the closest approach lies at the end of a profile (the
        profiles do not cover the contact, or do not overlap at all); the message names both
        profiles and the displacement.
    """
    d = np.atleast_1d(np.asarray(displacement, dtype=float))
    if d.ndim != 1 or not np.all(np.isfinite(d)):
        raise InputError("geometry.displacement", "must be finite numbers (m)")
    wheel_load = require_range("geometry.wheel_load", wheel_load, 0.0, None, low_open=True, unit="N")
    grid_step = require_range("geometry.grid_step", grid_step, 1e-6, 1e-3, unit="m")
    two_point_tol = require_range("geometry.two_point_tol", two_point_tol, 0.0, 1e-3, unit="m")
    rail, wheel = pair.rail, pair.wheel
    r_lo, r_hi = rail.bounds
    w_lo, w_hi = wheel.bounds
    ygrid, offset, valid, f, i1, bad = _grid_search(pair, d, grid_step)
    if np.any(bad):
        k = int(np.argmax(bad))
        raise InputError("geometry.displacement",
                         f"no contact between the wheel profile '{wheel.name}' and the rail profile "
                         f"'{rail.name}' at y_w = {d[k]:.6g} m: the closest approach lies at the end "
                         f"of a profile (the profiles must cover the contact; rail y in [{r_lo:.4g}, "
                         f"{r_hi:.4g}] m, wheel flange back at {offset[k]:.4g} m)")
    # grid values of f lie below the true maxima by up to |f''| h^2 / 8: compare refined values
    slack = _MAX_F2 * grid_step**2 / 8.0
    i2 = _second_candidates(f, valid, i1, two_point_tol + slack, two_point_tol, max(1, int(round(1e-3 / grid_step))))
    idx = np.column_stack([i1, np.where(i2 >= 0, i2, i1)])
    lo = np.clip(idx - 1, 0, ygrid.size - 1)
    hi = np.clip(idx + 1, 0, ygrid.size - 1)
    # keep the refinement inside the wheel's extent as well
    y_lo = np.maximum(ygrid[lo], offset[:, None] + w_lo)
    y_hi = np.minimum(ygrid[hi], offset[:, None] + w_hi)
    yr = _newton_max(pair, ygrid[idx], offset[:, None], y_lo, y_hi)
    ywc = yr - offset[:, None]
    fval = rail.height(yr) + wheel.height(ywc)
    swap = fval[:, 1] > fval[:, 0]  # slot 0 holds the smallest gap
    for arr in (yr, ywc, fval):
        arr[swap] = arr[swap][:, ::-1]
    second = (i2 >= 0) & (fval[:, 1] >= fval[:, 0] - two_point_tol)
    has2 = np.column_stack([np.ones(d.size, bool), second])
    radius = pair.nominal_radius + wheel.height(ywc)
    slope_r = rail.height(yr, 1)
    delta = np.arctan(slope_r)
    k_rail = -rail.curvature(yr)
    k_wheel = -wheel.curvature(ywc)
    c_long = np.cos(delta) / radius
    c_lat = k_wheel + k_rail
    normal = wheel_load / np.cos(delta)
    a = np.full(idx.shape, np.nan)
    b = np.full(idx.shape, np.nan)
    for i, j in zip(*np.nonzero(has2)):
        A, B = 0.5 * c_long[i, j], 0.5 * c_lat[i, j]
        if A > 0.0 and B > 0.0 and max(A, B) / min(A, B) <= 1e6:
            sol = hertz_from_curvatures(float(A), float(B), float(normal[i, j]), contact_modulus)
            a[i, j], b[i, j] = sol.a, sol.b
        else:
            logger.debug("no Hertz contact at y_w = %g m (A = %g, B = %g 1/m)", d[i], A, B)
    sep = fval[:, :1] - fval

    def slots(x):
        return np.where(has2, x, np.nan)

    return ContactTable(
        displacement=d, n_contacts=1 + second.astype(int), y_wheel=slots(ywc), y_rail=slots(yr),
        rolling_radius=slots(radius), contact_angle=slots(delta), curvature_long=slots(c_long),
        curvature_lat=slots(c_lat), separation=slots(sep), semi_axis_a=a, semi_axis_b=b,
        normal_force=slots(normal), spin=slots(np.sin(delta) / radius))
