r"""Linear stability of the wheel in full sliding: complex-eigenvalue analyses of the wheel on a
rigid rail (or on a modal rail) with the contact linearised in full sliding.

These are the independent references of the time-domain interaction (the linear time-domain
reference itself, a linear contact law and the coupled frequency response, is
:mod:`interaction.linear_contact`):

- :func:`stability_eigenvalues` builds the continuous-time coupled system (wheel and rail modal
  equations, contact spring, sliding friction coupling) and returns its eigenvalues: a pole with
  positive real part is an instability at frequency ``Im λ / 2π``.
- :func:`pole_residue_eigenvalues` does the same for a wheel given as poles and residues at the
  contact (any wheel model, including the rotating ones, whose modes are not real) on a rigid
  rail: the closed loop of ``H(s) = Σ R_k / (s - p_k) + conj`` with the sliding contact.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg


def stability_eigenvalues(wheel_modes, rail_modes, normal_stiffness, sliding_coefficient):
    """Eigenvalues of the coupled continuous-time system with a sliding contact.

    Parameters
    ----------
    wheel_modes, rail_modes : tuple
        ``(frequency_hz (m,), damping_ratio (m,), shapes (m, 3))``: mass-normalised modal data at
        the contact point (contact frame).
    normal_stiffness : float
        Linearised contact stiffness k_n, N/m.
    sliding_coefficient : float
        ΔF_y / ΔF_z in full sliding (±μ), -.

    Returns
    -------
    (2(mw + mr),) complex ndarray
        Eigenvalues λ (1/s); the motion grows where Re λ > 0, at ``Im λ / 2π`` Hz.
    """
    blocks = []
    for freq, zeta, shapes in (wheel_modes, rail_modes):
        w = 2 * np.pi * np.asarray(freq, dtype=float)
        blocks.append((w, np.asarray(zeta, dtype=float), np.asarray(shapes, dtype=float)))
    (ww, zw, pw), (wr, zr, pr) = blocks
    mw, mr = ww.size, wr.size
    n = mw + mr
    # Relative displacement wheel - rail along z: B q with q = [q_w, q_r]; the wheel receives F,
    # the rail -F, F = -k_n (B q) (e_z + μ e_y).
    B = np.concatenate([pw[:, 2], -pr[:, 2]])
    direction = np.array([0.0, sliding_coefficient, 1.0])
    Phi_T = np.concatenate([pw @ direction, -(pr @ direction)])  # generalised force per unit F_z
    K = np.diag(np.concatenate([ww**2, wr**2])) + normal_stiffness * np.outer(Phi_T, B)
    C = np.diag(np.concatenate([2 * zw * ww, 2 * zr * wr]))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -C]])
    return scipy.linalg.eigvals(A)


def pole_residue_eigenvalues(poles, residues, normal_stiffness, sliding_coefficient):
    """Eigenvalues of a pole-residue wheel on a rigid rail with a sliding contact.

    The contact force on the wheel is ``F = -k_n u_z (0, μ_s, 1)`` (full sliding: the lateral
    force follows the normal force), and the wheel's displacement at the contact is
    ``u(s) = H(s) F(s)`` with ``H(s) = Σ_k R_k / (s - p_k) + conj(R_k) / (s - conj(p_k))`` (the
    form of :func:`fe.greens.receptance`). The characteristic equation
    ``1 + k_n Σ_k r_k / (s - p_k) = 0`` over all 2m poles, with ``r_k = e_zᵀ R_k (0, μ_s, 1)``, is
    that of the state-space loop ``x' = (diag(p) - k_n 1 rᵀ) x``; its eigenvalues are returned.

    Parameters
    ----------
    poles : (m,) complex array_like
        rad/s, one of each conjugate pair.
    residues : (m, 3, 3) complex array_like
        m/(N s).
    normal_stiffness : float
        Linearised contact stiffness k_n, N/m.
    sliding_coefficient : float
        ``ΔF_y / ΔF_z`` in full sliding (±μ), -.

    Returns
    -------
    (2m,) complex ndarray
        Eigenvalues λ (1/s); growth where ``Re λ > 0``, at ``Im λ / 2π`` Hz.
    """
    poles = np.asarray(poles, dtype=complex)
    residues = np.asarray(residues, dtype=complex)
    direction = np.array([0.0, sliding_coefficient, 1.0])
    r = residues[:, 2, :] @ direction
    all_poles = np.concatenate([poles, np.conj(poles)])
    all_r = np.concatenate([r, np.conj(residues[:, 2, :]) @ direction])
    loop = np.diag(all_poles) - normal_stiffness * np.outer(np.ones(all_poles.size), all_r)
    return scipy.linalg.eigvals(loop)


def growing_poles(eigenvalues):
    """The growing eigenvalues (``Re λ > 0``, ``Im λ >= 0``), fastest growth first; list of dict.

    Each has ``frequency`` (Hz, ``Im λ / 2π``) and ``growth_rate`` (1/s, ``Re λ``).
    """
    eigenvalues = np.asarray(eigenvalues)
    growing = eigenvalues[(eigenvalues.real > 0) & (eigenvalues.imag >= 0)]
    return [{"frequency": float(lam.imag / (2 * np.pi)), "growth_rate": float(lam.real)}
            for lam in sorted(growing, key=lambda v: -v.real)]


def sliding_instabilities(wheel_modes, normal_stiffness, sliding_coefficient, rail_modes=None):
    """Unstable poles of the wheel in full sliding, each attributed to its nearest wheel mode.

    The complex-eigenvalue analysis of :func:`stability_eigenvalues` (rigid rail unless
    ``rail_modes`` are given), reduced to the growing poles (``Re λ > 0``, one of each conjugate
    pair), fastest growth first.

    Parameters
    ----------
    wheel_modes : tuple
        ``(frequency_hz (m,), damping_ratio (m,), shapes (m, 3))`` at the contact, mass-normalised.
    normal_stiffness : float
        Linearised contact stiffness, N/m.
    sliding_coefficient : float
        ``ΔF_y / ΔF_z`` in full sliding: ``+μ`` when the lateral force on the wheel is positive
        (negative lateral creepage), ``-μ`` otherwise.
    rail_modes : tuple, optional
        Same form as ``wheel_modes``; default none (rigid rail).

    Returns
    -------
    list of dict
        ``frequency`` (Hz, ``Im λ / 2π``), ``growth_rate`` (1/s, ``Re λ``) and ``mode`` (index of the
        wheel mode whose frequency is nearest).
    """
    if rail_modes is None:
        rail_modes = (np.zeros(0), np.zeros(0), np.zeros((0, 3)))
    eigenvalues = stability_eigenvalues(wheel_modes, rail_modes, normal_stiffness, sliding_coefficient)
    wheel_hz = np.asarray(wheel_modes[0], dtype=float)
    out = growing_poles(eigenvalues)
    for pole in out:
        pole["mode"] = int(np.argmin(np.abs(wheel_hz - pole["frequency"])))
    return out
