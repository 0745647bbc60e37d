"""The contact linearised about steady rolling: the form in which a contact model enters the
linear stability screen (:func:`stability.screen.screen`).

Each contact model's linearisation hook (``linearise`` in :mod:`contact.registry`,
e.g. :func:`contact.point.model.linearise_point_contact`,
:func:`contact.halfspace.linearise.linearise_halfspace_contact`) returns a
:class:`LinearisedContact`. The module imports numpy only, so that a contact model can name it
without importing the screen (scipy.linalg, the rail fit, the compiled root finder).

A friction characteristic of the sliding speed (contact/friction_law.py) enters through
:func:`with_friction_slope`: a model is linearised with its friction coefficient held at the
value of the operating point, and the slope term is added to its creep stiffness.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

__all__ = ["LinearisedContact", "sliding_speed", "with_friction_slope"]


@dataclass(frozen=True)
class LinearisedContact:
    """The contact linearised about its steady rolling state (the form :func:`stability.screen.closed_loop_eigen` takes).

    Attributes
    ----------
    normal_stiffness : float
        k_n = dF_z/dδ at the wheel load, N/m.
    sliding_coefficient : float
        μ_s = ∂F_y/∂F_z at constant creepage, -.
    creep_stiffness : tuple of 2 float
        (c_x, c_y) = (-∂F_x/∂ξ, -∂F_y/∂η), N per unit (effective) creepage.
    relaxation : (2, 3) ndarray or None
        Rows x, y: (b (m), a1 (m), a2 (m²)) of the creep relaxation; None for a steady law.
    saturation : float
        |F_t| / (μ F_z) at the operating point, - (1: full sliding).
    friction_damping : tuple of 2 float
        (d_x, d_y) = the slope term of a friction characteristic of the sliding speed,
        ``-∂F_t/∂μ · dμ/dv`` along each direction, N s/m (:func:`with_friction_slope`; ``Q dμ/dv``
        in full sliding): a force per unit relative tangential velocity that acts at once (the
        friction bound follows the sliding speed without the creep relaxation). (0, 0) for
        Coulomb friction.
    """

    normal_stiffness: float
    sliding_coefficient: float
    creep_stiffness: tuple
    relaxation: np.ndarray | None
    saturation: float
    friction_damping: tuple = (0.0, 0.0)


def sliding_speed(speed, creepage) -> float:
    """The contact's sliding speed ``v = V |(ξ, η)|`` (m/s) at rolling speed V (m/s) and creepages (ξ, η, φ)."""
    return float(speed) * float(np.hypot(float(creepage[0]), float(creepage[1])))


def with_friction_slope(linearised: LinearisedContact, friction, speed, creepage, force_per_friction) -> LinearisedContact:
    """Add the slope of a friction characteristic to a contact linearised at frozen friction.

    With ``μ = μ(v)`` at the sliding speed ``v = V |c|``, ``c = (ξ, η)``, a creep force
    ``F(c, μ)`` changes with the relative tangential velocity ``Δu̇ = V Δc`` through μ by
    ``∂F_i/∂μ μ'(v) c_j/|c| Δu̇_j``. The diagonal of that term, with its sign turned,
    is :attr:`LinearisedContact.friction_damping` (the cross terms, zero for a purely lateral or
    purely longitudinal creepage, are left out). In full sliding ``∂F/∂μ = F/μ = -Q c/|c|``,
    so that for a lateral creepage ``d_y = Q μ'(v)``: the damping ``N dμ/dv`` of the classical
    negative-damping argument (negative on a falling characteristic).

    Parameters
    ----------
    linearised : LinearisedContact
        The linearisation with μ held at ``μ(v)``.
    friction : contact.params.Friction
        The characteristic (``characteristic``, ``coefficient_slope``; constant: no change).
    speed : float
        Rolling speed V, m/s.
    creepage : (3,) sequence of float
        (ξ, η, φ), -, -, 1/m.
    force_per_friction : (2,) sequence of float
        ``∂(F_x, F_y)/∂μ`` at the operating point, N.

    Returns
    -------
    LinearisedContact
        ``linearised`` itself for a constant characteristic or zero creepage.
    """
    if friction.characteristic == "constant":
        return linearised
    xi, eta = float(creepage[0]), float(creepage[1])
    norm = float(np.hypot(xi, eta))
    if norm == 0.0:
        return linearised
    slope = float(friction.coefficient_slope(sliding_speed(speed, creepage)))  # dμ/dv, s/m
    dfx, dfy = (float(f) for f in force_per_friction)
    return replace(linearised, friction_damping=(-dfx * slope * xi / norm, -dfy * slope * eta / norm))
