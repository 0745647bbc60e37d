r"""The linear reference of the time-domain interaction: a linear contact law and the coupled
frequency response of the discrete-time loop with it.

- :class:`LinearContact` is a contact model (the interface of contact/model.py)
  whose force is linear in the approach and the creepages,
  ``F_z = Q + k_n (δ - δ_s)``, ``F_x = -c_x ξ``, ``F_y = -c_y η + μ_s F_z``. With ``μ_s = 0`` it
  is the linearisation of rolling contact about a non-saturated state; with ``c = 0`` and
  ``μ_s = ±μ`` that of full sliding, where the lateral force follows the normal force.
- :func:`coupled_response` solves the same discrete-time system in the frequency domain for a
  harmonic excitation of the approach (e.g. a roughness): with the kernels' DTFTs ``K_w``,
  ``K_r``, relative displacement ``Δu = (K_w + K_r) ΔF`` and the backward-difference velocity
  ``(1 - e^{-iωΔt}) Δu / Δt``, the force amplitude follows from one 3×3 solve per frequency.

The complex-eigenvalue analyses of the same linearised loop are in :mod:`stability.linear`
(rigid or modal rail) and :mod:`stability.screen` (flexible rail).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from contact.model import ContactResult, Diagnostics

__all__ = ["LinearContact", "coupled_response"]


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
