r"""Complex-eigenvalue stability of the wheel on a flexible rail with a linearised contact.

The wheel (any pole-residue model of :mod:`fe.greens`: stationary, moving load, Eulerian) and
the rail (a :class:`interaction.rational.RationalModel`, e.g. the vector fit of its moving
receptance) are both written as ``H(s) = Σ_k R_k / (s - p_k) + D`` over all poles (each pair
``p, p̄`` with ``R, R̄``). Each residue is factored ``R_k = U_k V_kᵀ`` (SVD, rank r_k: 1 for a
stationary wheel mode ``φφᵀ``), giving the realisation

.. math::

    \dot x_k = p_k x_k + V_k^T F_k, \qquad u = \sum_k U_k x_k + D F,

with ``F`` the force on the structure. The wheel receives the contact force ``F``, the rail
``-F``; the relative displacement wheel - rail at the contact is then
``Δu = u_w - u_r = Σ_w U x + Σ_r U x + (D_w + D_r) F`` (contact frame: x along the rail,
y lateral, z up; the convention of :mod:`interaction.linear`). The linearised contact
(:class:`interaction.linear.LinearContact`) is

.. math::

    F = -k_n Δu_z (0, μ_s, 1) - \frac{1}{v} \mathrm{diag}(c_x, c_y, 0)\, Δ\dot u,

the Hertz normal stiffness k_n, in full sliding (``c = 0``, ``μ_s = ±μ``) the lateral force
following the normal force, below saturation (``μ_s = 0``) the creep forces ``-c ξ``,
``-c η`` with creepages = relative velocity / v (damping-like terms). With
``Δu̇ = Σ U (p x + Vᵀ F_k) + D Ḟ``, where the wheel's states receive ``F`` and the rail's
``-F``, the closed loop is the descriptor system ``E ż = A z`` in ``z = (x, F)``:

.. math::

    \begin{aligned}
    \dot x &= P x + B F, \\
    \tfrac{1}{v} C D\, \dot F &= -\left(k_n d\, e_z^T U + \tfrac{1}{v} C U P\right) x
        - \left(I + k_n d\, e_z^T D + \tfrac{1}{v} C U B\right) F,
    \end{aligned}

(``D = D_w + D_r``, ``d = (0, μ_s, 1)``, ``C = diag(c_x, c_y, 0)``). When ``C D = 0`` (rigid
rail, or no creep terms, or no direct term) F is eliminated and the ordinary eigenproblem of
``P - B M^{-1} N`` is solved; otherwise the generalised one (QZ), whose infinite eigenvalues
(the algebraic part of F) are dropped.

A pole with ``Re λ > 0`` is an instability at ``Im λ / 2π`` Hz growing at ``Re λ`` 1/s.
Its wheel modes are those whose states carry the largest share of the contact displacement
in the eigenvector, ``|U_k x_k|`` summed over the pair ``p_k, p̄_k`` (normalised over the
wheel's modes).
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.linalg

from interaction.rational import RationalModel
from squealcore.errors import InputError, require_range

logger = logging.getLogger(__name__)

__all__ = ["closed_loop_eigen", "closed_loop_eigenvalues", "growing_poles_with_rail"]

#: singular values of a residue below this fraction of its largest are dropped in R = U Vᵀ
RANK_TOLERANCE = 1e-10


def _realisation(poles, residues, sign):
    """States of ``Σ R/(s-p) + R̄/(s-p̄)``: per pole p_k (all 2m), U_k (3, r) and V_k (3, r) with
    ``R_k = U_k V_kᵀ``; ``sign`` (+1 wheel, -1 rail) is the sign of the force the structure
    receives and of its displacement in Δu = u_w - u_r (both U and B carry it).

    Returns (p (n,), U (3, n), B (n, 3), owner (n,) index of the pole pair)."""
    poles = np.asarray(poles, complex)
    residues = np.asarray(residues, complex)
    p_all, u_cols, b_rows, owner = [], [], [], []
    for k, (p, r) in enumerate(zip(poles, residues)):
        for pk, rk in ((p, r), (np.conj(p), np.conj(r))):
            u, sv, vh = np.linalg.svd(rk)
            if sv[0] == 0.0:
                continue
            keep = sv > RANK_TOLERANCE * sv[0]
            for j in np.flatnonzero(keep):
                p_all.append(pk)
                u_cols.append(sign * u[:, j] * sv[j])
                b_rows.append(sign * vh[j])
                owner.append(k)
    n = len(p_all)
    return (np.array(p_all, complex), np.array(u_cols, complex).T.reshape(3, n),
            np.array(b_rows, complex).reshape(n, 3), np.array(owner, int))


def closed_loop_eigen(wheel_poles, wheel_residues, rail: RationalModel, normal_stiffness,
                      sliding_coefficient=0.0, creep_stiffness=(0.0, 0.0), speed=None, wheel_direct=None):
    """Eigenvalues of the wheel-contact-rail loop and the wheel modes' share in each.

    Parameters
    ----------
    wheel_poles : (m,) complex array_like
        rad/s, one of each conjugate pair.
    wheel_residues : (m, 3, 3) complex array_like
        m/(N s), the form of :func:`fe.greens.receptance`.
    rail : RationalModel
        The rail's receptance at the contact (``RationalModel.rigid()`` for a rigid rail); its
        proportional term must be zero.
    normal_stiffness : float
        k_n, N/m, > 0 (Hertz: ``3 Q / (2 δ)`` at the wheel load Q).
    sliding_coefficient : float
        μ_s = ΔF_y / ΔF_z (full sliding: ±μ; below saturation 0), -.
    creep_stiffness : (2,) tuple of float
        (c_x, c_y), N per unit creepage, >= 0 (0 in full sliding).
    speed : float, optional
        v, m/s, > 0; needed when a creep stiffness is non-zero.
    wheel_direct : (3, 3) array_like, optional
        Direct term of the wheel model, m/N (default 0).

    Returns
    -------
    eigenvalues : (n,) complex ndarray
        Finite eigenvalues λ, 1/s.
    participation : (n, m) ndarray
        Share of each wheel pole pair in the contact displacement of the eigenvector, -
        (rows sum to 1 where the wheel moves at all).
    """
    k_n = require_range("contact.normal_stiffness", normal_stiffness, 0.0, None, low_open=True, unit="N/m")
    mu = require_range("contact.sliding_coefficient", sliding_coefficient, -10.0, 10.0)
    cx, cy = (require_range("contact.creep_stiffness", float(c), 0.0, None, unit="N") for c in creep_stiffness)
    if np.any(rail.proportional != 0):
        raise InputError("rail.proportional", "the closed loop takes a rail model without proportional term")
    creep = np.diag([cx, cy, 0.0])
    if cx or cy:
        speed = require_range("operating.speed", speed, 0.0, 200.0, low_open=True, unit="m/s")
        creep = creep / speed
    pw, uw, bw, owner = _realisation(wheel_poles, wheel_residues, +1.0)
    pr, ur, br, _ = _realisation(rail.poles, rail.residues, -1.0)
    p = np.concatenate([pw, pr])
    u = np.concatenate([uw, ur], axis=1)  # Δu = U x + D F
    b = np.concatenate([bw, br], axis=0)  # ẋ = P x + B F
    direct = np.asarray(rail.direct, float) + (0.0 if wheel_direct is None else np.asarray(wheel_direct))
    d = np.array([0.0, mu, 1.0])
    e_z = np.array([0.0, 0.0, 1.0])
    n = p.size
    a21 = -(k_n * np.outer(d, e_z @ u) + creep @ (u * p[None, :]))
    a22 = -(np.eye(3) + k_n * np.outer(d, e_z @ direct) + creep @ (u @ b))
    e22 = creep @ direct
    if not np.any(e22):
        loop = np.diag(p) - b @ np.linalg.solve(a22, a21)
        lam, vec = scipy.linalg.eig(loop)
        x = vec
    else:
        a = np.block([[np.diag(p), b], [a21, a22]])
        e = np.zeros((n + 3, n + 3), complex)
        e[:n, :n] = np.eye(n)
        e[n:, n:] = e22
        (alpha, beta), vec = scipy.linalg.eig(a, e, right=True, homogeneous_eigvals=True)
        finite = np.abs(beta) > 1e-12 * np.abs(alpha).max()
        lam = alpha[finite] / beta[finite]
        x = vec[:n, finite]
    nw = pw.size
    contrib = np.abs(uw[:, :, None] * x[None, :nw, :])  # (3, nw, n_eig)
    share_state = np.sqrt(np.sum(contrib**2, axis=0))  # (nw, n_eig)
    m = np.asarray(wheel_poles).size
    part = np.zeros((lam.size, m))
    np.add.at(part.T, owner, share_state)
    tot = part.sum(axis=1, keepdims=True)
    part = np.divide(part, tot, out=np.zeros_like(part), where=tot > 0)
    return lam, part


def closed_loop_eigenvalues(*args, **kwargs):
    """The eigenvalues λ (1/s) of :func:`closed_loop_eigen` (same arguments)."""
    return closed_loop_eigen(*args, **kwargs)[0]


def growing_poles_with_rail(wheel_poles, wheel_residues, rail: RationalModel, normal_stiffness,
                            sliding_coefficient=0.0, creep_stiffness=(0.0, 0.0), speed=None,
                            min_share=0.1):
    """The growing poles of the wheel-contact-rail loop, fastest first.

    Parameters are those of :func:`closed_loop_eigen`; ``min_share`` (-) is the smallest
    participation of a wheel mode that is listed.

    Returns
    -------
    list of dict
        Per growing pole (``Re λ > 0``, ``Im λ >= 0``): ``frequency`` (Hz, ``Im λ / 2π``),
        ``growth_rate`` (1/s, ``Re λ``), ``eigenvalue`` (complex, 1/s), ``wheel_modes`` (indices
        into ``wheel_poles``, largest participation first, those with at least ``min_share``),
        ``participation`` (their shares, -), ``in_band`` (False when ``|λ| / 2π`` lies above the
        rail model's fitted band, where the rail is an extrapolation and the pole may be an
        artefact of the fit).
    """
    lam, part = closed_loop_eigen(wheel_poles, wheel_residues, rail, normal_stiffness,
                                  sliding_coefficient, creep_stiffness, speed)
    out = []
    for i in np.flatnonzero((lam.real > 0) & (lam.imag >= 0)):
        order = np.argsort(-part[i])
        order = [int(k) for k in order if part[i, k] >= min_share]
        out.append({"frequency": float(lam[i].imag / (2 * np.pi)), "growth_rate": float(lam[i].real),
                    "eigenvalue": complex(lam[i]), "wheel_modes": order,
                    "participation": [float(part[i, k]) for k in order],
                    "in_band": bool(rail.band is None or abs(lam[i]) / (2 * np.pi) <= rail.band[1])})
    out.sort(key=lambda d: -d["growth_rate"])
    return out
