r"""Receptances and discrete Green's kernels of modal (pole-residue) systems.

A linear structure observed at one point in three directions is described by poles
:math:`p_r` (rad/s, ``Re p_r < 0``) and residue matrices :math:`R_r` (m/(N s), 3×3):

.. math::

    H(s) = \sum_r \left[ \frac{R_r}{s - p_r} + \frac{\bar R_r}{s - \bar p_r} \right], \qquad
    g(t) = \sum_r 2\,\mathrm{Re}\left(R_r e^{p_r t}\right), \; t \ge 0.

For a mass-normalised, viscously damped mode with contact-point shape :math:`\phi_r`
(m/√kg), natural frequency :math:`\omega_r` and damping ratio :math:`\zeta_r`,
:math:`p_r = -\zeta_r\omega_r + i\omega_{dr}` and :math:`R_r = \phi_r\phi_r^T / (2 i \omega_{dr})`,
which reproduces :math:`H_{ij}(\omega) = \sum_r \phi_{ir}\phi_{jr}/(\omega_r^2-\omega^2+2i\zeta_r\omega_r\omega)`
and :math:`g(t) = \sum_r \phi_r\phi_r^T e^{-\zeta_r\omega_r t}\sin(\omega_{dr}t)/\omega_{dr}`.
The same form carries the rotating-wheel models, whose residues are not symmetric.

Discrete kernel (docs/design.md §3): ``u[n] = Σ_m k[m] F[n-m]`` with the force linearly interpolated
between samples (ramp-invariant / first-order hold). For one pole, with :math:`z = e^{p\Delta t}`,

.. math::

    k[0] = R\,\frac{z - 1 - p\Delta t}{p^2 \Delta t}, \qquad
    k[m] = R\,\frac{(z-1)^2}{p^2\Delta t} z^{m-1} \; (m \ge 1),

plus the complex conjugate. Because ``k[m]`` is geometric for ``m ≥ 1``, the convolution is an
exact first-order recursion per pole (:func:`recursion_coefficients`): with
``h[n] = z (h[n-1] + F[n-1])``, ``u[n] = k[0] F[n] + Σ_r 2 Re(c_r R_r h_r[n])`` where
``c = (z-1)^2 / (z p^2 Δt)``.
"""

from __future__ import annotations

import numpy as np


def modal_poles_residues(natural_frequency_hz, damping_ratio, shapes):
    """Poles and residues of viscously damped, mass-normalised modes.

    Parameters
    ----------
    natural_frequency_hz : (m,) array_like
        Undamped natural frequencies (Hz), > 0.
    damping_ratio : (m,) array_like
        Modal viscous damping ratios (-), in [0, 1).
    shapes : (m, 3) array_like
        Mass-normalised modal displacements at the observation/force point (m/√kg).

    Returns
    -------
    poles : (m,) complex ndarray
        rad/s, upper half plane.
    residues : (m, 3, 3) complex ndarray
        m/(N s).
    """
    omega = 2.0 * np.pi * np.asarray(natural_frequency_hz, dtype=float)
    zeta = np.asarray(damping_ratio, dtype=float)
    phi = np.asarray(shapes, dtype=float)
    if np.any(omega <= 0) or np.any((zeta < 0) | (zeta >= 1)):
        raise ValueError("modes need f > 0 and 0 <= damping ratio < 1")
    omega_d = omega * np.sqrt(1.0 - zeta**2)
    poles = -zeta * omega + 1j * omega_d
    residues = np.einsum("mi,mj->mij", phi, phi) / (2j * omega_d)[:, None, None]
    return poles, residues


def receptance(poles, residues, frequency_hz):
    """Receptance of a pole-residue system.

    Parameters
    ----------
    poles : (m,) complex array_like
        rad/s.
    residues : (m, 3, 3) complex array_like
        m/(N s).
    frequency_hz : (nf,) array_like
        Hz.

    Returns
    -------
    (nf, 3, 3) complex ndarray
        m/N, ``H[f, i, j]``: displacement i per unit force j, for ``exp(+iωt)`` time dependence.
    """
    s = 2j * np.pi * np.asarray(frequency_hz, dtype=float)[:, None]
    poles = np.asarray(poles)
    residues = np.asarray(residues)
    a = 1.0 / (s - poles[None, :])
    b = 1.0 / (s - np.conj(poles)[None, :])
    return np.einsum("fm,mij->fij", a, residues) + np.einsum("fm,mij->fij", b, np.conj(residues))


def impulse_response(poles, residues, time):
    """Continuous Green's function g(t) (m/(N s)) at times ``time`` ≥ 0, shape (nt, 3, 3)."""
    t = np.asarray(time, dtype=float)[:, None]
    e = np.exp(np.asarray(poles)[None, :] * t)
    return 2.0 * np.real(np.einsum("tm,mij->tij", e, np.asarray(residues)))


def _first_order_hold_factors(poles, dt):
    p = np.asarray(poles, dtype=complex)
    z = np.exp(p * dt)
    pdt = p * dt
    # (z - 1 - p dt)/(p^2 dt) and (z - 1)^2/(p^2 dt) lose digits for |p dt| << 1: use series.
    small = np.abs(pdt) < 1e-3
    k0 = np.empty_like(p)
    k1 = np.empty_like(p)
    with np.errstate(divide="ignore", invalid="ignore"):
        k0[~small] = (z[~small] - 1.0 - pdt[~small]) / (p[~small] ** 2 * dt)
        k1[~small] = (z[~small] - 1.0) ** 2 / (p[~small] ** 2 * dt)
    x = pdt[small]
    k0[small] = dt * (0.5 + x / 6.0 + x**2 / 24.0 + x**3 / 120.0)
    # (e^x - 1)^2 / x^2 = 1 + x + 7x^2/12 + x^3/4 + ...
    k1[small] = dt * (1.0 + x + 7.0 * x**2 / 12.0 + x**3 / 4.0)
    return z, k0, k1


def ramp_invariant_kernel(poles, residues, time_step, n_samples):
    """Discrete Green's kernel with first-order-hold (ramp-invariant) force interpolation.

    Parameters
    ----------
    poles : (m,) complex array_like
        rad/s.
    residues : (m, 3, 3) complex array_like
        m/(N s).
    time_step : float
        s.
    n_samples : int
        Kernel length.

    Returns
    -------
    (n_samples, 3, 3) ndarray
        m/N: ``u_i[n] = Σ_m k[m, i, j] F_j[n - m]``.
    """
    z, k0, k1 = _first_order_hold_factors(poles, time_step)
    residues = np.asarray(residues)
    m = np.arange(1, n_samples)
    powers = np.exp(np.log(z)[None, :] * (m[:, None] - 1))  # z^(m-1), stable for |z| <= 1
    kernel = np.empty((n_samples, 3, 3))
    kernel[0] = 2.0 * np.real(np.einsum("m,mij->ij", k0, residues))
    kernel[1:] = 2.0 * np.real(np.einsum("tm,m,mij->tij", powers, k1, residues))
    return kernel


def recursion_coefficients(poles, residues, time_step):
    """Coefficients of the exact per-pole recursion equivalent to :func:`ramp_invariant_kernel`.

    Parameters
    ----------
    poles : (m,) complex array_like
    residues : (m, 3, 3) complex array_like
    time_step : float

    Returns
    -------
    z : (m,) complex ndarray
        ``exp(p Δt)``.
    weights : (m, 3, 3) complex ndarray
        ``c_r R_r`` with ``c = (z-1)^2 / (z p^2 Δt)``, m/N.
    k0 : (3, 3) ndarray
        Instantaneous compliance ``k[0]`` (m/N).

    Notes
    -----
    With ``h_r[n] = z_r (h_r[n-1] + F[n-1])`` (``h_r[0] = 0`` for a system at rest),
    ``u[n] = k0 F[n] + Σ_r 2 Re(weights_r h_r[n])``.
    """
    z, k0, k1 = _first_order_hold_factors(poles, time_step)
    residues = np.asarray(residues)
    weights = (k1 / z)[:, None, None] * residues
    k0_matrix = 2.0 * np.real(np.einsum("m,mij->ij", k0, residues))
    return z, weights, k0_matrix


def static_compliance(poles, residues):
    """Receptance at zero frequency, ``H(0) = -Σ 2 Re(R_r / p_r)`` (m/N)."""
    return -2.0 * np.real(np.einsum("m,mij->ij", 1.0 / np.asarray(poles), np.asarray(residues)))


def held_spectrum(poles, residues, frequency_hz, time_step, n_alias=2000):
    """Discrete-time frequency response that a first-order-hold kernel must have.

    ``K(ω) = Σ_k H(ω + k ω_s) sinc²((ω + k ω_s) Δt / 2)`` summed over ``|k| ≤ n_alias``: the
    receptance seen through linear interpolation of the force and sampling of the response.
    Used to verify kernels independently of how they were computed.

    Parameters
    ----------
    poles, residues : see :func:`receptance`
    frequency_hz : (nf,) array_like
        Hz, below the Nyquist frequency.
    time_step : float
        s.
    n_alias : int
        Number of alias bands on each side.

    Returns
    -------
    (nf, 3, 3) complex ndarray
        m/N.
    """
    f = np.asarray(frequency_hz, dtype=float)
    fs = 1.0 / time_step
    total = np.zeros((f.size, 3, 3), dtype=complex)
    for k in range(-n_alias, n_alias + 1):
        fk = f + k * fs
        weight = np.sinc(fk * time_step) ** 2  # numpy sinc(x) = sin(pi x)/(pi x); pi fk dt = wk dt/2
        total += receptance(poles, residues, fk) * weight[:, None, None]
    return total


def kernel_spectrum(kernel, frequency_hz, time_step):
    """Discrete-time Fourier transform ``Σ_m k[m] e^{-iωmΔt}`` of a kernel (nt, 3, 3) -> (nf, 3, 3)."""
    m = np.arange(kernel.shape[0])
    phase = np.exp(-2j * np.pi * np.outer(np.asarray(frequency_hz, dtype=float), m) * time_step)
    return np.einsum("fm,mij->fij", phase, kernel)


def frequency_grid(f_min, f_max, poles, n_base=4000, points_per_peak=41, half_widths=20.0):
    """Frequency grid that resolves every resonance peak.

    A log-spaced base grid plus, around each pole, ``points_per_peak`` points spanning
    ``±half_widths`` half-power bandwidths (the peaks of lightly damped wheel modes are far
    narrower than any practical uniform grid).

    Parameters
    ----------
    f_min, f_max : float
        Band (Hz), ``0 < f_min < f_max``.
    poles : (m,) complex array_like
        rad/s.
    n_base : int
        Points of the base grid.
    points_per_peak : int
        Points around each peak.
    half_widths : float
        Extent of each refinement in half-power bandwidths ``|Re p| / π`` (Hz).

    Returns
    -------
    (nf,) ndarray
        Sorted, unique frequencies in Hz.
    """
    poles = np.asarray(poles)
    base = np.geomspace(f_min, f_max, n_base)
    centre = np.abs(poles.imag) / (2.0 * np.pi)
    width = np.maximum(np.abs(poles.real) / np.pi, 1e-6 * np.maximum(centre, 1.0))
    offsets = np.linspace(-half_widths, half_widths, points_per_peak)
    local = (centre[:, None] + 0.5 * width[:, None] * offsets[None, :]).ravel()
    grid = np.concatenate([base, local[(local >= f_min) & (local <= f_max)]])
    return np.unique(grid)


def kernel_dtft(poles, residues, time_step, frequency_hz):
    """Closed-form DTFT ``Σ_{m≥0} k[m] e^{-iωmΔt}`` of the infinite ramp-invariant kernel.

    With ``k[m] = 2 Re(R k1 z^{m-1})`` for ``m ≥ 1`` the tail is a geometric series, so the
    transform is exact (no truncation): used by the frequency-domain checks of the interaction.

    Parameters
    ----------
    poles, residues : see :func:`receptance`
    time_step : float
        s.
    frequency_hz : (nf,) array_like
        Hz.

    Returns
    -------
    (nf, 3, 3) complex ndarray
        m/N.
    """
    z, k0, k1 = _first_order_hold_factors(poles, time_step)
    residues = np.asarray(residues)
    e = np.exp(-2j * np.pi * np.asarray(frequency_hz, dtype=float) * time_step)[:, None]
    direct = k1[None, :] * e / (1.0 - z[None, :] * e)
    mirror = np.conj(k1)[None, :] * e / (1.0 - np.conj(z)[None, :] * e)
    k0_matrix = 2.0 * np.real(np.einsum("m,mij->ij", k0, residues))
    return (k0_matrix[None] + np.einsum("fm,mij->fij", direct, residues)
            + np.einsum("fm,mij->fij", mirror, np.conj(residues)))
