"""Modes of the wheel at its contact point, from either solver, classified the same way.

:func:`solve_hex20` runs the 3D 20-node hexahedron model, :func:`solve_axisymmetric` the
harmonic (Fourier) section model. Both return :class:`WheelModes`: frequencies, classification
(nodal diameters, nodal circles, family; fe/classify.py) and the mass-normalised modal
displacement at the contact point in the contact frame (docs/conventions.md), which is all the
receptances and Green's kernels need.

The contact point is either the mesh node at the hand-set contact (``contact_node``) or, for a
contact computed from the profiles, any point of the running surface: :func:`running_surface_point`
finds the boundary side of the section mesh (a quad8 side: a 3-node quadratic edge) that contains
it and :func:`contact_shapes_at` interpolates the modes there with the edge's shape functions.
At θ = 0 the point lies on the edge that the tread's hex20 faces (quad8) share with the section
plane θ = 0 of the revolved mesh, where the quad8 face functions are those of that edge, so one
interpolation serves both solvers.
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
from squealcore.errors import InputError

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


QUAD8_SIDES = ((0, 4, 1), (1, 5, 2), (2, 6, 3), (3, 7, 0))
"""Sides of a VTK quad8 as (corner, mid-side node, corner): the 3-node edges of the section mesh."""

SURFACE_RADIUS_TOLERANCE = 5e-4
"""Largest difference (m) between the mesh surface's radius at the contact and the geometry's rolling
radius before a warning is logged (the mesh follows the profile within its element size)."""


def edge3_shape_functions(xi):
    """Shape functions of the 3-node quadratic edge at the natural coordinate ``xi`` in [-1, 1].

    Node order (start corner at -1, mid-side node at 0, end corner at +1):
    ``(xi (xi - 1) / 2, 1 - xi², xi (xi + 1) / 2)``. They interpolate quadratics exactly.
    """
    xi = float(xi)
    return np.array([0.5 * xi * (xi - 1.0), 1.0 - xi * xi, 0.5 * xi * (xi + 1.0)])


@dataclass(frozen=True)
class SurfacePoint:
    """A point of the wheel's running surface on an edge of the section mesh.

    Attributes
    ----------
    nodes : (3,) int ndarray
        Section nodes of the edge (corner, mid-side node, corner).
    weights : (3,) ndarray
        Their edge3 shape functions at the point (sum 1).
    position : (2,) ndarray
        (r, z) of the point on the mesh surface, m.
    """

    nodes: np.ndarray
    weights: np.ndarray
    position: np.ndarray


def _boundary_sides(section_cells):
    """(k, 3) node triples of the quad8 sides that belong to one cell only (the outline)."""
    cells = np.asarray(section_cells)
    sides = np.concatenate([cells[:, list(side)] for side in QUAD8_SIDES])
    keys = np.sort(sides[:, [0, 2]], axis=1)
    _, inverse, counts = np.unique(keys, axis=0, return_inverse=True, return_counts=True)
    return sides[counts[inverse.reshape(-1)] == 1]


def _edge_coordinate(z, target):
    """Natural coordinates xi in [-1, 1] with ``Σ N_k(xi) z_k = target`` on a quadratic edge."""
    a = 0.5 * (z[0] + z[2]) - z[1]
    b = 0.5 * (z[2] - z[0])
    c = z[1] - target
    if abs(a) <= 1e-12 * max(abs(b), 1e-300):
        roots = [-c / b] if b != 0.0 else []
    else:
        disc = b * b - 4.0 * a * c
        if disc < 0.0:
            return []
        q = -0.5 * (b + np.copysign(np.sqrt(disc), b))
        roots = [q / a] + ([c / q] if q != 0.0 else [])
    return [min(max(x, -1.0), 1.0) for x in roots if -1.0 - 1e-9 <= x <= 1.0 + 1e-9]


def running_surface_point(section_nodes, section_cells, wheel_lateral, rolling_radius=None):
    """The point of the running surface at ``wheel_lateral`` from the flange back, on the section mesh.

    Among the outline edges of the section mesh that reach the axial position ``z = wheel_lateral``
    the outermost one (largest radius there) is the running surface, as for the hand-set contact
    node (mesh/wheel_mesh.py).

    Parameters
    ----------
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    section_cells : (Es, 8) int ndarray
        VTK quad8 order.
    wheel_lateral : float
        Axial position of the contact from the flange back, m.
    rolling_radius : float, optional
        Rolling radius of the contact geometry, m: a warning is logged when the mesh surface lies
        farther than :data:`SURFACE_RADIUS_TOLERANCE` from it.

    Returns
    -------
    SurfacePoint

    Raises
    ------
    InputError
        If no outline edge reaches ``wheel_lateral`` (naming ``operating.lateral_displacement``).
    """
    nodes = np.asarray(section_nodes, dtype=float)
    best = None
    for side in _boundary_sides(section_cells):
        r, z = nodes[side, 0], nodes[side, 1]
        if not min(z) - 1e-12 <= wheel_lateral <= max(z) + 1e-12:
            continue
        for xi in _edge_coordinate(z, float(wheel_lateral)):
            weights = edge3_shape_functions(xi)
            radius = float(weights @ r)
            if best is None or radius > best.position[0]:
                best = SurfacePoint(np.array(side), weights, np.array([radius, float(weights @ z)]))
    if best is None:
        raise InputError("operating.lateral_displacement",
                         f"the contact at {wheel_lateral:.6g} m from the flange back lies outside the wheel section "
                         f"(z from {nodes[:, 1].min():.4g} to {nodes[:, 1].max():.4g} m)")
    if rolling_radius is not None and abs(best.position[0] - rolling_radius) > SURFACE_RADIUS_TOLERANCE:
        logger.warning("wheel mesh surface at %.4f m from the flange back has radius %.5f m, the contact "
                       "geometry's rolling radius is %.5f m", wheel_lateral, best.position[0], rolling_radius)
    return best


def contact_shapes_at(point, modes, section_nodes, hex_nodes=None):
    """Mode shapes (m, 3) at a running-surface point, contact frame at θ = 0, m/√kg.

    Parameters
    ----------
    point : SurfacePoint
        From :func:`running_surface_point`.
    modes : WheelModes
        With ``shapes``: hex20 shapes at the 3D nodes or axisymmetric section amplitudes.
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    hex_nodes : (N, 3) ndarray, optional
        The hex20 nodes (needed for ``modes.solver == "hex20"``): the edge's nodes are the 3D
        nodes of the section plane θ = 0, at ``(0, z, -r)``.

    Returns
    -------
    (m, 3) ndarray
        ``Σ_k N_k φ_k`` over the edge's three nodes.
    """
    section_nodes = np.asarray(section_nodes, dtype=float)
    if modes.solver == "hex20":
        index = hex_nodes_at(point, section_nodes, hex_nodes)
        values = np.asarray(modes.shapes)[:, index, :].astype(float)  # (m, 3 nodes, 3)
    else:
        values = np.array([
            reconstruct(np.asarray(shape, dtype=float)[point.nodes], n, fam, section_nodes[point.nodes],
                        np.array([0.0]))[0]
            for shape, n, fam in zip(modes.shapes, modes.nodal_diameters, modes.orientation)])
    return np.einsum("k,mkc->mc", point.weights, values)


def hex_nodes_at(point, section_nodes, hex_nodes, tolerance=1e-6):
    """The hex20 nodes (3,) of a :class:`SurfacePoint`'s edge: the section nodes at θ = 0, ``(0, z, -r)``.

    Raises ValueError if a node is farther than ``tolerance`` (m) from its place (not a mesh
    revolved from this section).
    """
    section_nodes = np.asarray(section_nodes, dtype=float)
    hex_nodes = np.asarray(hex_nodes, dtype=float)
    r, z = section_nodes[point.nodes, 0], section_nodes[point.nodes, 1]
    targets = np.column_stack([np.zeros(3), z, -r])
    distance = np.linalg.norm(hex_nodes[None, :, :] - targets[:, None, :], axis=2)
    index = np.argmin(distance, axis=1)
    if np.max(distance[np.arange(3), index]) > tolerance:
        raise ValueError("the hex20 mesh has no nodes on the section plane theta = 0 at the contact edge")
    return index
