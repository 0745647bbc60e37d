r"""The contact frame inclined by the contact angle, and the rotation of the structures into it.

A body's frame at the contact is (x longitudinal, y lateral from the gauge side to the field
side, z up): the track frame for the wheel standing upright on the track, the rail section's
own upright frame for the rail (docs/conventions.md). The **contact frame** is that frame turned
about x by the angle ``α`` of the contact normal to the body's vertical (positive: the normal
leans towards the gauge side, -y):

.. math::

    e_x' = e_x, \quad e_y' = (0, \cos α, \sin α), \quad e_z' = n = (0, -\sin α, \cos α),

so that a vector ``v`` of the body's frame has the contact-frame components ``v' = R v`` with
the rows of ``R`` the axes ``e'``, and a receptance, Green's kernel or pole residue (3×3,
displacement per force) becomes ``H' = R H R^T``. The wheel is turned by the contact angle
(track frame), the rail by the same normal seen in its upright section, ``rail_section_angle``
(the contact angle minus the rail's inclination). The rotation is applied once to the inputs
of the time loop (residues, kernels), so the loops themselves work in the contact frame
without knowing it.

**Static preload**: the normal force ``N`` along ``n`` balances the vertical wheel load ``Q``,
``N cos α = Q``, i.e. ``N = Q / cos α``; its lateral track-frame component ``-N sin α = -Q tan α``
(towards the gauge side) is carried by the wheelset (the other wheel and the axle), which the
one-wheel model does not include.
"""

from __future__ import annotations

import math

import numpy as np

from squealcore.errors import require_range

__all__ = ["MAX_CONTACT_ANGLE", "contact_rotation", "to_contact_frame", "vectors_to_contact_frame", "to_body_frame",
           "static_normal_force"]

MAX_CONTACT_ANGLE = 1.4
"""Largest |contact angle| accepted, rad (80°: steeper than any flange face)."""


def contact_rotation(angle: float) -> np.ndarray:
    """The rotation ``R`` (3, 3) from a body's frame to the contact frame inclined by ``angle`` (rad).

    Rows: the contact-frame axes ``e_x'``, ``e_y'``, ``e_z' = n`` in the body's frame (see the
    module doc). ``R`` is the identity for ``angle = 0``.
    """
    angle = require_range("contact.contact_angle", angle, -MAX_CONTACT_ANGLE, MAX_CONTACT_ANGLE, unit="rad")
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, s], [0.0, -s, c]])


def to_contact_frame(matrices, angle: float):
    """Matrices (..., 3, 3) of a body's frame (receptances, kernels, residues) in the contact frame.

    ``H' = R H R^T`` with ``R`` of :func:`contact_rotation`, for real or complex arrays of any
    leading shape. For ``angle == 0`` the input is returned as it is (the same values bit for bit,
    no arithmetic), so an upright contact reproduces the results of the upright model exactly.

    Parameters
    ----------
    matrices : (..., 3, 3) array_like
        Displacement per force, any unit.
    angle : float
        Inclination of the contact normal in the body's frame, rad.

    Returns
    -------
    (..., 3, 3) ndarray
    """
    matrices = np.asarray(matrices)
    if matrices.shape[-2:] != (3, 3):
        raise ValueError(f"expected (..., 3, 3) matrices, got shape {matrices.shape}")
    if angle == 0.0:
        return matrices
    rotation = contact_rotation(angle)
    return np.einsum("ik,...kl,jl->...ij", rotation, matrices, rotation)


def vectors_to_contact_frame(vectors, angle: float) -> np.ndarray:
    """Vectors (..., 3) of a body's frame (mode shapes, forces) in the contact frame: ``v' = R v``.

    Returned as they are for ``angle == 0`` (see :func:`to_contact_frame`).
    """
    vectors = np.asarray(vectors)
    if angle == 0.0:
        return vectors
    return vectors @ contact_rotation(angle).T


def to_body_frame(vectors, angle: float) -> np.ndarray:
    """Vectors (..., 3) of the contact frame (forces, displacements) in the body's frame: ``v = R^T v'``."""
    vectors = np.asarray(vectors, dtype=float)
    if angle == 0.0:
        return vectors
    return vectors @ contact_rotation(angle)


def static_normal_force(wheel_load: float, angle: float) -> float:
    """Normal force (N) along the inclined normal that balances the vertical wheel load: ``Q / cos α``.

    Parameters
    ----------
    wheel_load : float
        Vertical wheel load Q, N (> 0).
    angle : float
        Contact angle α, rad.
    """
    angle = require_range("contact.contact_angle", angle, -MAX_CONTACT_ANGLE, MAX_CONTACT_ANGLE, unit="rad")
    return float(wheel_load) / math.cos(angle)
