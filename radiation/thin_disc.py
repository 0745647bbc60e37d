r"""A thin closed disc for the boundary-element model of a baffled circular piston.

A closed cylinder of radius a and small thickness t, centred on the plane z = 0, whose two flat
faces move outwards with the same uniform speed (the top face along +z, the bottom face along
-z) while its rim is at rest, is symmetric about z = 0: the normal velocity on that plane is zero
outside the disc. In the limit t → 0 each half-space therefore sees a circular piston in an
infinite rigid baffle, and the free-field radiated power is twice the piston's. Over the two
moving faces the radiation efficiency is the baffled piston's (Rayleigh; Kinsler et al.,
*Fundamentals of Acoustics*, 4th ed. 2000; Pierce, *Acoustics*, 1989: the piston's radiation resistance)::

    σ = 1 - J₁(2ka) / (ka)

The surface is meshed with gmsh (triangles), finer near the two rim edges where the velocity
jumps and where the two faces' nearly-coincident influence must be resolved.
"""

from __future__ import annotations

import gmsh
import numpy as np
from scipy.special import j1

from mesh.wheel_mesh import gmsh_model
from squealcore.errors import InputError


def baffled_piston_efficiency(ka):
    """Radiation efficiency (-) of a rigid circular piston in an infinite rigid baffle.

    Parameters
    ----------
    ka : float or array_like
        Wavenumber times piston radius (-), > 0.

    Returns
    -------
    float or ndarray
        ``σ = 1 - J₁(2ka)/(ka)`` (Rayleigh); → (ka)²/2 for ka → 0, oscillating about 1 above ka ≈ 1.5.
    """
    ka = np.asarray(ka, dtype=float)
    return 1.0 - j1(2.0 * ka) / ka


def thin_disc_triangles(radius, thickness, face_size, rim_size, grading_distance=None):
    """Outward-oriented triangles of a closed thin disc (cylinder) centred on the origin, axis z.

    Parameters
    ----------
    radius : float
        a, m, > 0.
    thickness : float
        t, m, 0 < t < radius.
    face_size : float
        Element size at the disc's centre, m (the largest).
    rim_size : float
        Element size at the two rim edges and on the rim, m, ≤ face_size.
    grading_distance : float, optional
        Distance from the rim edges over which the size grows linearly from rim_size to
        face_size, m (default: the radius).

    Returns
    -------
    vertices : (V, 3) ndarray
        m.
    triangles : (T, 3) int ndarray
        Vertex indices, counter-clockwise seen from outside (normals into the air).
    """
    if not radius > 0.0:
        raise InputError("radius", f"must be > 0 m, got {radius}")
    if not 0.0 < thickness < radius:
        raise InputError("thickness", f"must lie in (0, radius = {radius}) m, got {thickness}")
    if not 0.0 < rim_size <= face_size:
        raise InputError("rim_size", f"must lie in (0, face_size = {face_size}] m, got {rim_size}")
    with gmsh_model("thin_disc"):
        gmsh.model.occ.addCylinder(0.0, 0.0, -0.5 * thickness, 0.0, 0.0, thickness, radius)
        gmsh.model.occ.synchronize()
        edges = [tag for dim, tag in gmsh.model.getEntities(1)]
        distance = gmsh.model.mesh.field.add("Distance")
        gmsh.model.mesh.field.setNumbers(distance, "CurvesList", edges)
        gmsh.model.mesh.field.setNumber(distance, "Sampling", 200)
        grading = gmsh.model.mesh.field.add("Threshold")
        gmsh.model.mesh.field.setNumber(grading, "InField", distance)
        gmsh.model.mesh.field.setNumber(grading, "SizeMin", rim_size)
        gmsh.model.mesh.field.setNumber(grading, "SizeMax", face_size)
        gmsh.model.mesh.field.setNumber(grading, "DistMin", 0.0)
        gmsh.model.mesh.field.setNumber(grading, "DistMax", radius if grading_distance is None else grading_distance)
        gmsh.model.mesh.field.setAsBackgroundMesh(grading)
        gmsh.option.setNumber("Mesh.MeshSizeExtendFromBoundary", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromPoints", 0)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.model.mesh.generate(2)
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        _, element_nodes = gmsh.model.mesh.getElementsByType(2)  # 3-node triangles
    order = np.argsort(node_tags)
    vertices_all = coords.reshape(-1, 3)[order]
    tags_sorted = node_tags[order]
    triangles = np.searchsorted(tags_sorted, element_nodes).reshape(-1, 3)
    used, triangles = np.unique(triangles, return_inverse=True)
    triangles = triangles.reshape(-1, 3)
    vertices = vertices_all[used]
    # the cylinder is convex and centred on the origin: an outward normal points away from it
    xyz = vertices[triangles]
    normal = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])
    inward = np.einsum("ti,ti->t", normal, xyz.mean(axis=1)) < 0.0
    triangles[inward] = triangles[inward][:, [0, 2, 1]]
    return vertices, triangles


def piston_normal_velocity(vertices, triangles):
    """Normal velocity (T,) of the symmetric pair of pistons: 1 m/s on both flat faces, 0 on the rim.

    Both faces move outwards (the top along +z, the bottom along -z), so v_n = +1 on each; a
    triangle belongs to a face when its unit normal is within 45° of ±z.
    """
    xyz = np.asarray(vertices)[triangles]
    normal = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])
    normal_z = normal[:, 2] / np.linalg.norm(normal, axis=1)
    return (np.abs(normal_z) > np.sqrt(0.5)).astype(float)
