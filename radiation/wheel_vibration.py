r"""The wheel's vibration from a case: per-pole modal velocities at the contact and on the surface.

Every wheel model of the toolkit is a pole-residue system at the contact (fe/greens.py):
``x(s) = Σ_r [R_r / (s - p_r) + conj]``. The contact force history of a case drives each pole
separately with the first-order-hold recursion the interaction itself uses, so that the sum of the
pole responses is the wheel's contact velocity recorded in the case (tested). A pole's response
at the contact is then turned into a surface vibration:

* **stationary wheel**: pole r is the standing mode r with contact shape φ_r (R_r = φ_r φ_rᵀ /
  (2 i ω_d)); its modal velocity is ``q̇_r = φ_r · v_r / |φ_r|²`` and its surface mean-square
  normal velocity ``<v_n²> S = <q̇_r²> ∫|φ_r·n|² dS``.
* **rotating wheels** (moving load, Eulerian): in the fixed frame the eigen-solutions of an
  axisymmetric spinning wheel are travelling waves ``cos(nθ ∓ ω t)``. The pole is matched to the
  stationary mode pair of the same n whose frequency, shifted by 0 or ±nΩ, is nearest; the
  travelling wave's amplitude A is the projection of the pole's contact velocity on the pair's
  contact shape at θ = 0 (the cos partner: the sin partner moves the contact only
  circumferentially), and the wave is A(φ_cos cos ωt + φ_sin sin ωt): its surface mean square is
  ``<A²> (∫|φ_cos·n|² + ∫|φ_sin·n|²) = 2 <A²> ∫|φ_cos·n|² dS`` for n ≥ 1.
  **Assumption**: a travelling wave radiates like the pair of standing waves it is made of; for an
  axisymmetric body the cos nθ and sin nθ patterns are orthogonal over every sphere about the
  axle, so their radiated powers add with the same radiation efficiency (the far-field pressure of
  each is a single azimuthal harmonic; cf. Thompson & Jones 2002, who use one σ per n for both
  partners). The rotation of the surface itself (Mach number ≈ 0.04 at 50 km/h) is neglected.

Modes radiate independently (no cross terms between modes), as in TWINS; poles listed more than
once (same value, same mode) are one vibration and are summed before squaring
(:func:`coincident_poles`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from fe.greens import _first_order_hold_factors

PAIR_TOLERANCE = 1e-6
"""Two modes of the same n are one degenerate pair when their frequencies differ by less than
this fraction."""

SILENT_SHAPE = 1e-6
"""A mode whose contact shape norm is below this fraction of the largest is not excited at the
contact (the sin partners of an axisymmetric model) and is skipped."""


@dataclass(frozen=True)
class PoleVibration:
    """Surface vibration carried by each pole of a wheel model.

    Attributes
    ----------
    pole : (k,) int ndarray
        Index of each pole in the wheel model (poles not excited at the contact are left out).
    frequency : (k,) ndarray
        Damped natural frequency of the pole in the fixed frame, Hz.
    harmonic : (k,) int ndarray
        Nodal diameters n of the matched mode.
    mode : (k,) int ndarray
        Index of the matched stationary mode (wheel_modes.h5 order).
    travelling : bool
        Whether the poles are travelling waves (rotating models).
    velocity : (k, nt) ndarray
        Modal velocity history (amplitude of the matched mode shape), √kg m/s.
    input_power : (k,) ndarray
        Mean power the force puts into each pole over the window, ``<F'·v_r'>`` (W, primes: the
        window means removed; the work of the constant creep and static force over a limit cycle
        is zero, and over a window of not whole periods it would only add ``F̄·Δu/T`` noise).
    axial, radial : (k,) ndarray
        ``∫|φ·n|² dS`` over the axial / radial surface times the travelling-wave factor, m⁴/kg:
        ``<v_n²> S = <velocity²> x axial`` (resp. radial).
    """

    pole: np.ndarray
    frequency: np.ndarray
    harmonic: np.ndarray
    mode: np.ndarray
    travelling: bool
    velocity: np.ndarray
    input_power: np.ndarray
    axial: np.ndarray
    radial: np.ndarray


def pole_velocity_histories(poles, residues, projections, force, time_step, quantity="velocity"):
    """Projected contact velocity (or displacement) of each pole driven by a force history.

    Parameters
    ----------
    poles : (k,) complex array_like
        rad/s.
    residues : (k, 3, 3) complex array_like
        m/(N s).
    projections : (k, 3) array_like
        Row vector c_r applied to the pole's contact velocity (1/(√kg) x m/m ...: any units).
    force : (nt, 3) array_like
        Force deviation from static equilibrium, N (rail on wheel).
    time_step : float
        s.
    quantity : {"velocity", "displacement"}
        What to return.

    Returns
    -------
    (k, nt) ndarray
        ``c_r · v_r(t)`` (or ``c_r · u_r(t)`` with ``u_r = 2 Re x_r``) with ``v_r = 2 Re(p_r x_r + R_r F)`` and ``x_r`` the pole's state under
        first-order-hold force interpolation (the interaction's own discretisation).
    """
    poles = np.asarray(poles, dtype=complex)
    z, k0, k1 = _first_order_hold_factors(poles, time_step)
    row = np.einsum("ri,rij->rj", np.asarray(projections, dtype=complex), np.asarray(residues))
    drive = row @ np.asarray(force, dtype=float).T
    return _ramp_invariant_response(poles, z, k0, k1, np.ascontiguousarray(drive), quantity == "velocity")


@njit(cache=True)
def _ramp_invariant_response(poles, z, k0, k1, drive, velocity):
    """Per pole r: ``x[n] = k0 s[n] + k1 Σ_{m>=1} z^(m-1) s[n-m]`` (the ramp-invariant response of
    1/(s - p) to the drive s), returned as ``2 Re(p x + s)`` (velocity) or ``2 Re x``."""
    k, nt = drive.shape
    out = np.empty((k, nt))
    for r in range(k):
        history = 0.0j  # Σ_{m>=1} z^(m-1) s[n-m]
        for n in range(nt):
            x = k0[r] * drive[r, n] + k1[r] * history
            if velocity:
                out[r, n] = 2.0 * (poles[r] * x + drive[r, n]).real
            else:
                out[r, n] = 2.0 * x.real
            history = z[r] * history + drive[r, n]
    return out


def mode_pairs(frequency, nodal_diameters, contact_shape):
    """Group the modes into degenerate pairs and find each group's cos-partner contact shape.

    Returns
    -------
    group : (m,) int ndarray
        Group index of every mode.
    cos_shape : (g, 3) ndarray
        Contact shape (m/√kg) of the partner with the largest contact motion: the principal
        direction of ``Σ φ φᵀ`` over the group's members, scaled by the square root of its
        eigenvalue.
    """
    frequency = np.asarray(frequency, dtype=float)
    nd = np.asarray(nodal_diameters)
    group = -np.ones(len(frequency), dtype=int)
    shapes = []
    for i in range(len(frequency)):
        if group[i] >= 0:
            continue
        members = [j for j in range(i, len(frequency)) if group[j] < 0 and nd[j] == nd[i]
                   and abs(frequency[j] - frequency[i]) <= PAIR_TOLERANCE * frequency[i]]
        group[members] = len(shapes)
        phi = np.asarray(contact_shape, dtype=float)[members]
        values, vectors = np.linalg.eigh(phi.T @ phi)
        shapes.append(vectors[:, -1] * np.sqrt(max(values[-1], 0.0)))
    return group, np.array(shapes)


def match_poles(pole_frequency, mode_frequency, nodal_diameters, spin):
    """Stationary mode nearest to each pole, allowing the rotational shifts 0 and ±nΩ.

    Parameters
    ----------
    pole_frequency : (k,) array_like
        Hz.
    mode_frequency : (m,) array_like
        Hz.
    nodal_diameters : (m,) array_like
    spin : float
        Ω, rad/s.

    Returns
    -------
    (k,) int ndarray
        Mode index per pole.
    """
    f = np.asarray(mode_frequency, dtype=float)[None, :]
    shift = np.asarray(nodal_diameters, dtype=float)[None, :] * spin / (2.0 * np.pi)
    p = np.asarray(pole_frequency, dtype=float)[:, None]
    distance = np.minimum(np.minimum(np.abs(p - f), np.abs(p - f - shift)), np.abs(p - f + shift))
    return np.argmin(distance, axis=1)


def pole_responses(poles, residues, projections, force, time_step, window):
    """Projected contact velocity of each pole and the power the force puts into it, in one pass.

    Parameters
    ----------
    poles, residues : array_like
        The wheel model (k poles).
    projections : (k, 3) array_like
        Row vector c_r applied to each pole's contact velocity.
    force : (nt, 3) array_like
        Force deviation, N.
    time_step : float
        s.
    window : slice
        Samples over which the input power is averaged.

    Returns
    -------
    velocity : (k, nt) ndarray
        ``c_r · v_r(t)``.
    input_power : (k,) ndarray
        ``<F'·v_r'>`` over the window (means removed), W.
    """
    poles = np.asarray(poles, dtype=complex)
    z, k0, k1 = _first_order_hold_factors(poles, time_step)
    force = np.ascontiguousarray(force, dtype=float)
    start, stop, _ = window.indices(len(force))
    left, right = rank_one_factors(residues)
    velocity, sums = _pole_responses(poles, z, k0, k1, left, right, np.ascontiguousarray(projections, dtype=float),
                                     force, start, stop)
    count = stop - start
    mean_force = force[start:stop].mean(axis=0)
    input_power = sums[:, 0] / count - np.einsum("i,ri->r", mean_force, sums[:, 1:]) / count
    return velocity, input_power


RANK_ONE_TOLERANCE = 1e-6
"""A residue matrix counts as rank one when its second singular value is below this fraction of
the first (every simple pole of a linear system has a rank-one residue)."""


def rank_one_factors(residues):
    """Factors ``a_r``, ``b_r`` (k, 3) with ``R_r = a_r b_rᵀ`` of rank-one residue matrices.

    Raises
    ------
    ValueError
        If a residue is not of rank one (a repeated pole with two independent shapes).
    """
    u, s, vh = np.linalg.svd(np.asarray(residues, dtype=complex))
    bad = s[:, 1] > RANK_ONE_TOLERANCE * s[:, 0]
    if np.any(bad):
        raise ValueError(f"residues of poles {np.flatnonzero(bad)[:5].tolist()} are not of rank one")
    return np.ascontiguousarray(u[:, :, 0] * s[:, :1]), np.ascontiguousarray(vh[:, 0, :])


@njit(cache=True)
def _pole_responses(poles, z, k0, k1, left, right, projections, force, start, stop):
    """Per pole (R = a bᵀ): the ramp-invariant state w of 1/(s - p) driven by bᵀF, the contact
    velocity ``v = 2 Re(a (p w + bᵀF))``, its projection, and over [start, stop) the sums of F·v
    and of v."""
    k = len(poles)
    nt = force.shape[0]
    out = np.empty((k, nt))
    sums = np.zeros((k, 4))
    for r in range(k):
        history = 0.0j
        for n in range(nt):
            drive = right[r, 0] * force[n, 0] + right[r, 1] * force[n, 1] + right[r, 2] * force[n, 2]
            g = poles[r] * (k0[r] * drive + k1[r] * history) + drive
            projected = 0.0
            power = 0.0
            inside = start <= n < stop
            for i in range(3):
                v = 2.0 * (left[r, i] * g).real
                projected += projections[r, i] * v
                power += force[n, i] * v
                if inside:
                    sums[r, 1 + i] += v
            out[r, n] = projected
            if inside:
                sums[r, 0] += power
            history = z[r] * history + drive
    return out, sums


def wheel_vibration(poles, residues, modes, surfaces, force, time_step, travelling, spin=0.0, window=None):
    """Per-pole surface vibration of a wheel model under a force history.

    Parameters
    ----------
    poles, residues : array_like
        The wheel model (stationary: one pole per mode, in the order of ``modes``).
    modes : dict
        :func:`stages.wheel.read_modes` (``frequency``, ``nodal_diameters``, ``contact_shape``).
    surfaces : radiation.surface.ModeSurfaces
        Surface integrals of the modes.
    force : (nt, 3) array_like
        Force deviation, N.
    time_step : float
        s.
    travelling : bool
        False for the stationary model (pole r is mode r, standing), True for the rotating ones.
    spin : float
        Ω, rad/s (rotating models).
    window : slice, optional
        Samples for the input power (default: all).

    Returns
    -------
    PoleVibration
    """
    poles = np.asarray(poles, dtype=complex)
    shape = np.asarray(modes["contact_shape"], dtype=float)
    nd = np.asarray(modes["nodal_diameters"]).astype(int)
    frequency = np.abs(poles.imag) / (2.0 * np.pi)
    if not travelling:
        if len(poles) != len(shape):
            raise ValueError(f"stationary model: {len(poles)} poles for {len(shape)} modes")
        mode = np.arange(len(poles))
        projection_shape = shape
        factor = np.ones(len(poles))
    else:
        group, cos_shape = mode_pairs(modes["frequency"], nd, shape)
        mode = match_poles(frequency, modes["frequency"], nd, spin)
        projection_shape = cos_shape[group[mode]]
        factor = np.where(nd[mode] >= 1, 2.0, 1.0)
    norm2 = np.einsum("ri,ri->r", projection_shape, projection_shape)
    active = norm2 > (SILENT_SHAPE * np.sqrt(norm2.max())) ** 2
    projections = np.zeros_like(projection_shape)
    projections[active] = projection_shape[active] / norm2[active, None]
    index = np.flatnonzero(active)
    window = slice(None) if window is None else window
    label, keep = coincident_poles(poles[index], mode[index])
    residues = np.asarray(residues)[index]
    summed = np.zeros((len(keep), 3, 3), dtype=complex)
    np.add.at(summed, label, residues)
    if len(keep) < len(index) and is_rank_one(summed):
        # one pole per set, with the sum of the residues: the same response at a fraction of the cost
        velocity, input_power = pole_responses(poles[index][keep], summed, projections[index][keep], force,
                                               time_step, window)
    else:
        velocity, input_power = pole_responses(poles[index], residues, projections[index], force, time_step, window)
        velocity, input_power = sum_coincident(label, keep, velocity, input_power)
    index = index[keep]
    if travelling:
        # every member of a pair has the same surface integral; use the group mean
        axial_mode = np.array([surfaces.axial[group == group[m]].mean() for m in mode])
        radial_mode = np.array([surfaces.radial[group == group[m]].mean() for m in mode])
    else:
        axial_mode, radial_mode = surfaces.axial[mode], surfaces.radial[mode]
    return PoleVibration(pole=index, frequency=frequency[index], harmonic=nd[mode][index], mode=mode[index],
                         travelling=bool(travelling), velocity=velocity, input_power=input_power,
                         axial=(factor * axial_mode)[index], radial=(factor * radial_mode)[index])


def coincident_poles(poles, mode, tolerance=PAIR_TOLERANCE):
    """Sets of poles that coincide and carry the same mode: one vibration, not several.

    A wheel model may list one pole several times with residues that add up (the moving-load
    model lists each travelling wave once per partner of its mode pair). Their responses are one
    motion of the same surface pattern, so its mean square is that of their sum, not the sum of
    their mean squares (which would count responses that cancel at the contact as radiating).

    Parameters
    ----------
    poles : (k,) complex ndarray
        rad/s.
    mode : (k,) int ndarray
        Matched mode of each pole.
    tolerance : float
        Two poles coincide when ``|p_i - p_j| <= tolerance |p_i|``.

    Returns
    -------
    label : (k,) int ndarray
        Set of every pole.
    keep : (g,) int ndarray
        The first pole of every set (in the input order).
    """
    label = -np.ones(len(poles), dtype=int)
    keep = []
    for i in range(len(poles)):
        if label[i] >= 0:
            continue
        same = (label < 0) & (mode == mode[i]) & (np.abs(poles - poles[i]) <= tolerance * np.abs(poles[i]))
        label[same] = len(keep)
        keep.append(i)
    return label, np.array(keep, dtype=int)


def is_rank_one(residues):
    """Whether every residue matrix is of rank one (:data:`RANK_ONE_TOLERANCE`)."""
    s = np.linalg.svd(np.asarray(residues, dtype=complex), compute_uv=False)
    return bool(np.all(s[:, 1] <= RANK_ONE_TOLERANCE * s[:, 0]))


def sum_coincident(label, keep, velocity, input_power):
    """Velocities (k, nt) and input powers (k,) of the poles summed per set of
    :func:`coincident_poles`: (g, nt) and (g,)."""
    if len(keep) == len(label):
        return velocity, input_power
    merged = velocity[keep]
    for i in np.flatnonzero(np.arange(len(label)) != keep[label]):  # the poles after the first of their set
        merged[label[i]] += velocity[i]
    return merged, np.bincount(label, weights=input_power, minlength=len(keep))


def contact_response(poles, residues, force, time_step, quantity="velocity"):
    """The wheel's contact velocity (or displacement), (nt, 3) in m/s (m), summed over its poles."""
    k = len(poles)
    columns = []
    for i in range(3):
        projections = np.zeros((k, 3))
        projections[:, i] = 1.0
        columns.append(pole_velocity_histories(poles, residues, projections, force, time_step, quantity).sum(axis=0))
    return np.stack(columns, axis=1)

