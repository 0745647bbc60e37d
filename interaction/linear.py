r"""Linearised wheel–contact–rail system: a linear contact law, the coupled frequency response
and a complex-eigenvalue stability analysis.

These are the independent references of the time-domain interaction:

- :class:`LinearContact` is a contact model (the interface of interaction/contact/model.py)
  whose force is linear in the approach and the creepages,
  ``F_z = Q + k_n (δ - δ_s)``, ``F_x = -c_x ξ``, ``F_y = -c_y η + μ_s F_z``. With ``μ_s = 0`` it
  is the linearisation of rolling contact about a non-saturated state; with ``c = 0`` and
  ``μ_s = ±μ`` that of full sliding, where the lateral force follows the normal force.
- :func:`coupled_response` solves the same discrete-time system in the frequency domain for a
  harmonic excitation of the approach (e.g. a roughness): with the kernels' DTFTs ``K_w``,
  ``K_r``, relative displacement ``Δu = (K_w + K_r) ΔF`` and the backward-difference velocity
  ``(1 - e^{-iωΔt}) Δu / Δt``, the force amplitude follows from one 3×3 solve per frequency.
- :func:`stability_eigenvalues` builds the continuous-time coupled system (wheel and rail modal
  equations, contact spring, sliding friction coupling) and returns its eigenvalues: a pole with
  positive real part is an instability at frequency ``Im λ / 2π``.
- :func:`pole_residue_eigenvalues` does the same for a wheel given as poles and residues at the
  contact (any wheel model, including the rotating ones, whose modes are not real) on a rigid
  rail: the closed loop of ``H(s) = Σ R_k / (s - p_k) + conj`` with the sliding contact.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg

from interaction.contact.model import ContactResult, Diagnostics


@dataclass(frozen=True)
class LinearContact:
    """Contact force linear in the approach and the creepages.

    Parameters
    ----------
    normal_stiffness : float
        k_n, N/m.
    creep_stiffness : (2,) tuple
        (c_x, c_y): force per unit creepage, N.
    sliding_coefficient : float
        μ_s: lateral force per unit normal force (full-sliding linearisation), -.
    static_load : float
        Q, N; the static approach is ``Q / k_n``.
    time_step : float
        s.
    """

    normal_stiffness: float
    creep_stiffness: tuple
    sliding_coefficient: float
    static_load: float
    time_step: float

    def initial_state(self):
        return None

    def solve(self, state, *, approach=None, normal_force=None, creepage=(0.0, 0.0, 0.0), shift=None):
        delta_static = self.static_load / self.normal_stiffness
        if approach is None:
            approach = delta_static + (normal_force - self.static_load) / self.normal_stiffness
        fz = self.static_load + self.normal_stiffness * (approach - delta_static)
        fx = -self.creep_stiffness[0] * creepage[0]
        fy = -self.creep_stiffness[1] * creepage[1] + self.sliding_coefficient * fz
        diagnostics = Diagnostics(1, 1, 0, 0.0, 1, 0.0, 0.0, float(approach))
        return ContactResult(np.array([fx, fy, fz]), 0.0, None, diagnostics)


def coupled_response(wheel_dtft, rail_dtft, contact, speed, frequency_hz):
    """Force per unit harmonic approach excitation of the discrete-time coupled system.

    Parameters
    ----------
    wheel_dtft, rail_dtft : (nf, 3, 3) complex array_like
        DTFTs of the wheel and rail kernels at ``frequency_hz`` (m/N).
    contact : LinearContact
    speed : float
        m/s.
    frequency_hz : (nf,) array_like
        Hz.

    Returns
    -------
    (nf, 3) complex ndarray
        Force deviation amplitude per metre of excitation, N/m.
    """
    dt = contact.time_step
    omega = 2.0 * np.pi * np.asarray(frequency_hz, dtype=float)
    derivative = (1.0 - np.exp(-1j * omega * dt)) / dt
    G = np.asarray(wheel_dtft) + np.asarray(rail_dtft)
    e_z = np.array([0.0, 0.0, 1.0])
    # ΔF = k_n (r - e_z·G ΔF) (e_z + μ_s e_y) - diag(c_x, c_y, 0) D G ΔF / v
    direction = np.array([0.0, contact.sliding_coefficient, 1.0])
    creep = np.diag([contact.creep_stiffness[0], contact.creep_stiffness[1], 0.0])
    out = np.empty((omega.size, 3), dtype=complex)
    for k in range(omega.size):
        A = np.eye(3) + contact.normal_stiffness * np.outer(direction, e_z @ G[k]) + creep @ G[k] * derivative[k] / speed
        out[k] = np.linalg.solve(A, contact.normal_stiffness * direction)
    return out


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
