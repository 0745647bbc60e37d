"""Modes of the wheel at its contact point, from either solver, classified the same way.

:func:`solve_hex20` runs the 3D 20-node hexahedron model, :func:`solve_axisymmetric` the
harmonic (Fourier) section model. Both return :class:`WheelModes`: frequencies, classification
(nodal diameters, nodal circles, family; fe/classify.py) and the mass-normalised modal
displacement at the contact point in the contact frame (docs/conventions.md), which is all the
receptances and Green's kernels need.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from fe.assembly import apply_dirichlet, assemble_hex20, expand
from fe.axisymmetric import reconstruct, solve_axisymmetric_modes
from fe.classify import classify_section_mode, harmonic_projection
from fe.cyclic import solve_cyclic
from fe.eigen import solve_modes
from fe.material import isotropic_elasticity

logger = logging.getLogger(__name__)


@dataclass
class WheelModes:
    """Wheel modes below ``f_max``.

    Attributes
    ----------
    frequency : (m,) ndarray
        Natural frequencies, Hz, ascending.
    nodal_diameters : (m,) int ndarray
        Circumferential harmonic n.
    nodal_circles : (m,) int ndarray
    family : (m,) str ndarray
        ``"axial"``, ``"radial"`` or ``"circumferential"``.
    orientation : (m,) str ndarray
        ``"cos"``/``"sin"`` member of a pair for the axisymmetric solver (docs/conventions.md);
        ``""`` for the 3D solver, whose pair members have arbitrary orientation.
    contact_shape : (m, 3) ndarray
        Mass-normalised displacement at the contact point in the contact frame, m/√kg.
    shapes : ndarray
        Full shapes: (m, N, 3) Cartesian at the hex20 nodes, or (m, Ns, 3) section amplitudes
        (U_r, U_z, U_θ) for the axisymmetric solver; m/√kg.
    solver : str
        ``"hex20"`` or ``"axisymmetric"``.
    """

    frequency: np.ndarray
    nodal_diameters: np.ndarray
    nodal_circles: np.ndarray
    family: np.ndarray
    orientation: np.ndarray
    contact_shape: np.ndarray
    shapes: np.ndarray
    solver: str


def modal_damping(nodal_diameters, damping_ratio, damping_ratio_low_order, low_order_max_n):
    """Modal damping ratios: ``damping_ratio_low_order`` for n <= ``low_order_max_n``, else ``damping_ratio``."""
    n = np.asarray(nodal_diameters)
    return np.where(n <= low_order_max_n, damping_ratio_low_order, damping_ratio).astype(float)


def solve_hex20(nodes, cells, clamped_nodes, contact_node, youngs_modulus, poisson_ratio, density, f_max,
                n_sectors=None, n_max_classify=None):
    """Modes of the 3D wheel mesh.

    With ``n_sectors`` (the mesh is the revolution of a section in that many equal steps) the
    block-circulant structure of the same 3D matrices is used (fe/cyclic.py: one sector per
    harmonic, identical eigenvalues); without it the full matrices are solved by shift-invert
    Lanczos (fe/eigen.py).

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m, wheel frame of docs/conventions.md.
    cells : (E, 20) int ndarray
        VTK hex20 order.
    clamped_nodes : (c,) int ndarray
        Nodes with all displacements fixed.
    contact_node : int
        Node at the contact point (θ = 0).
    youngs_modulus, poisson_ratio, density : float
        Pa, -, kg/m³.
    f_max : float
        Hz.
    n_sectors : int, optional
        Revolve steps of the mesh, to use cyclic symmetry.
    n_max_classify : int, optional
        Highest harmonic considered in the classification (default: resolvable by the mesh).

    Returns
    -------
    WheelModes
    """
    D = isotropic_elasticity(youngs_modulus, poisson_ratio, prefix="wheel.fe.")
    if n_sectors:
        freq, shapes, _ = solve_cyclic(nodes, cells, clamped_nodes, n_sectors, D, density, f_max)
    else:
        K, M = assemble_hex20(nodes, cells, D, density)
        fixed = (3 * np.asarray(clamped_nodes)[:, None] + np.arange(3)).ravel()
        K_ff, M_ff, free = apply_dirichlet(K, M, fixed)
        logger.info("hex20: %d elements, %d free DOF", len(cells), len(free))
        freq, phi_free = solve_modes(K_ff, M_ff, f_max)
        phi = expand(phi_free, free, K.shape[0])  # (ndof, m)
        shapes = phi.T.reshape(len(freq), -1, 3)
    if n_max_classify is None:
        r = np.hypot(nodes[:, 0], nodes[:, 2])
        ring_count = np.count_nonzero(np.isclose(r, r[contact_node]) & np.isclose(nodes[:, 1], nodes[contact_node, 1]))
        n_max_classify = max(ring_count // 2, 1)
    n, section, ring_rz, _ = harmonic_projection(nodes, shapes, n_max_classify)
    family, circles = _classify_all(ring_rz, section)
    return WheelModes(freq, n, circles, family, np.full(len(freq), ""), shapes[:, contact_node, :].copy(), shapes,
                      "hex20")


def solve_axisymmetric(section_nodes, section_cells, clamped_nodes, contact_node, youngs_modulus, poisson_ratio,
                       density, f_max):
    """Modes of the wheel from the axisymmetric harmonic element on its section mesh.

    Parameters
    ----------
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    section_cells : (Es, 8) int ndarray
        VTK quad8 order.
    clamped_nodes : (c,) int ndarray
        Section nodes fixed all around.
    contact_node : int
        Section node at the contact point.
    youngs_modulus, poisson_ratio, density : float
        Pa, -, kg/m³.
    f_max : float
        Hz.

    Returns
    -------
    WheelModes
    """
    modes = solve_axisymmetric_modes(section_nodes, section_cells, clamped_nodes, youngs_modulus, poisson_ratio,
                                     density, f_max)
    contact = np.array([
        reconstruct(shape[[contact_node]], n, fam, section_nodes[[contact_node]], np.array([0.0]))[0, 0]
        for shape, n, fam in zip(modes.shapes, modes.harmonic, modes.family)
    ]).reshape(-1, 3)
    family, circles = _classify_all(section_nodes, modes.shapes)
    return WheelModes(modes.frequency, modes.harmonic.astype(int), circles, family, np.asarray(modes.family, dtype=str),
                      contact, modes.shapes, "axisymmetric")


def _classify_all(section_rz, amplitudes):
    families, circles = [], []
    for amp in amplitudes:
        family, count, _ = classify_section_mode(section_rz, amp)
        families.append(family)
        circles.append(count)
    return np.array(families, dtype=str), np.array(circles, dtype=int)
