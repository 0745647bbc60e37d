"""The wheel as a boundary-element model: its closed surface and the normal velocity of a mode.

The surface is the boundary of the wheel's 3D hexahedral mesh (the same gmsh geometry as the
modes: mesh/wheel_mesh.py), each boundary quadrilateral split into two flat triangles oriented
outwards (away from the centre of the element it bounds). The bore stays in the surface (the
axle is not modelled; the clamped bore does not move). Mode shapes are taken from the 3D modes at
the mesh nodes or, for the axisymmetric solver, built from the section amplitudes at the nodes'
(r, z): ``u = U_r cos nθ e_r + U_z cos nθ e_z + U_θ sin nθ e_θ`` (docs/conventions.md).
"""

from __future__ import annotations

import numpy as np

from radiation.surface import HEX_FACES, boundary_faces


def wheel_surface(nodes, cells):
    """Outward triangles of the boundary of a 20-node hexahedral mesh.

    Returns
    -------
    vertices : (V, 3) ndarray
        m (the corner nodes used, renumbered).
    triangles : (T, 3) int ndarray
    node_index : (V,) int ndarray
        Mesh node of each vertex.
    """
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells)
    faces, owner = boundary_faces(cells, HEX_FACES, with_cells=True)
    centres = nodes[cells[owner, :8]].mean(axis=1)
    triangles = np.concatenate([faces[:, [0, 1, 2]], faces[:, [0, 2, 3]]])
    owner_centres = np.concatenate([centres, centres])
    xyz = nodes[triangles]
    normal = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])
    inward = np.einsum("ti,ti->t", normal, xyz.mean(axis=1) - owner_centres) < 0
    triangles[inward] = triangles[inward][:, [0, 2, 1]]
    node_index, renumbered = np.unique(triangles, return_inverse=True)
    return nodes[node_index], renumbered.reshape(triangles.shape), node_index


def section_mode_at_points(points, section_nodes, amplitudes, harmonic):
    """3D displacement (P, 3) of an axisymmetric cos-family mode at points (X, Y, Z) of the mesh.

    Parameters
    ----------
    points : (P, 3) array_like
        m; each lies on a revolved section node.
    section_nodes : (Ns, 2) array_like
        (r, z), m.
    amplitudes : (Ns, 3) array_like
        (U_r, U_z, U_θ), m/√kg.
    harmonic : int
        n.
    """
    points = np.asarray(points, dtype=float)
    r = np.hypot(points[:, 0], points[:, 2])
    theta = np.arctan2(points[:, 0], -points[:, 2])
    rz = np.asarray(section_nodes, dtype=float)
    nearest = np.argmin((r[:, None] - rz[None, :, 0]) ** 2 + (points[:, 1][:, None] - rz[None, :, 1]) ** 2, axis=1)
    u = np.asarray(amplitudes, dtype=float)[nearest]
    c, s = np.cos(harmonic * theta), np.sin(harmonic * theta)
    e_r = np.stack([np.sin(theta), np.zeros_like(theta), -np.cos(theta)], axis=1)
    e_t = np.stack([np.cos(theta), np.zeros_like(theta), np.sin(theta)], axis=1)
    e_z = np.array([0.0, 1.0, 0.0])
    return (u[:, 0] * c)[:, None] * e_r + (u[:, 1] * c)[:, None] * e_z + (u[:, 2] * s)[:, None] * e_t


def triangle_normal_velocity(vertices, triangles, vertex_velocity):
    """Normal velocity per triangle (T,): the mean of its vertices' velocity on its unit normal."""
    xyz = np.asarray(vertices)[triangles]
    normal = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    return np.einsum("ti,ti->t", np.asarray(vertex_velocity)[triangles].mean(axis=1), normal)
