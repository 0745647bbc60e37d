"""Typed bundle of the point model's compiled path (a numba-compatible named tuple).

:class:`PointLaw` is the whole point-contact law of one step: the Python model and the compiled
time loop hand the same constants to the same law (see contact/halfspace/bundles.py for how
numba takes such bundles).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from contact.friction_law import FrictionLaw

__all__ = ["PointLaw"]


class PointLaw(NamedTuple):
    """Constants of the point-contact law (contact/point/model.py documents the model).

    Attributes
    ----------
    reference_force : float
        Normal force of the Hertz reference solution, N.
    reference_approach : float
        Approach of the Hertz reference solution, m.
    shear_modulus : float
        Combined shear modulus G, Pa.
    ab : float
        Product of the semi-axes a b at the reference force, m².
    c11, c22, c23 : float
        Kalker's creep coefficients (-).
    kinetic_friction : float
        Kinetic friction coefficient: the saturation bound is ``kinetic_friction * φ(v) * Fn`` (-).
    distance : float
        Rolled distance per time step, m.
    semi_axis : float
        Semi-axis a at the reference force, m; ``<= 0`` selects the steady creep law (no
        relaxation, no strips).
    semi_axis_b : float
        Semi-axis b at the reference force, m.
    relaxation : (2, 3) ndarray
        Rows x (for xi) and y (for eta and phi): non-dimensional (beta, alpha1, alpha2) of
        ``alpha2 a² y'' + alpha1 a y' + y = u + beta a u'``.
    tangential : int
        ``point_kernels.STRIP`` (transient strip model) or ``point_kernels.RELAXATION``
        (saturated creep law on relaxed creepages).
    strip_x : (nx,) ndarray
        Element centres along the rolling direction, m, descending (element 0 at the leading
        edge), spaced by ``distance``; empty for the creep law.
    strip_y : (ny,) ndarray
        Strip centres across, m; empty for the creep law.
    strip_dy : float
        Strip width, m.
    strip_creep_factor : float
        The strip model's creep coefficients are Kalker's times this (-): it sets where the
        strips reach full slip (contact/point/model.py, :data:`STRIP_CREEP_FACTOR`).
    rolling_speed : float
        Rolling speed V, m/s: the contact's sliding speed is ``V |(xi, eta)|``.
    friction_law : FrictionLaw
        The factor ``φ(v)`` of the kinetic coefficient at the contact's sliding speed v
        (contact/friction_law.py, rate per m/s; ``CONSTANT_LAW``: Coulomb friction).
    """

    reference_force: float
    reference_approach: float
    shear_modulus: float
    ab: float
    c11: float
    c22: float
    c23: float
    kinetic_friction: float
    distance: float
    semi_axis: float
    semi_axis_b: float
    relaxation: np.ndarray
    tangential: int
    strip_x: np.ndarray
    strip_y: np.ndarray
    strip_dy: float
    strip_creep_factor: float
    rolling_speed: float
    friction_law: FrictionLaw
