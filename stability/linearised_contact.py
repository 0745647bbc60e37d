"""The contact linearised about steady rolling: the form in which a contact model enters the
linear stability screen (:func:`stability.screen.screen`).

Each contact model's linearisation hook (``linearise`` in :mod:`contact.registry`,
e.g. :func:`contact.point.model.linearise_point_contact`,
:func:`contact.halfspace.linearise.linearise_halfspace_contact`) returns a
:class:`LinearisedContact`. The module imports numpy only, so that a contact model can name it
without importing the screen (scipy.linalg, the rail fit, the compiled root finder).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["LinearisedContact"]


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
    """

    normal_stiffness: float
    sliding_coefficient: float
    creep_stiffness: tuple
    relaxation: np.ndarray | None
    saturation: float
