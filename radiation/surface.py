"""Surface integrals of the wheel's mode shapes: how much each mode moves the air.

For a mass-normalised mode φ (m/√kg) the radiating surface S of the wheel is split into the faces
whose outward normal is mainly axial (the web, the rim and hub sides: the *axial* surface) and
those whose normal is mainly radial (tread, flange, rim underside: the *radial* surface), as in
Thompson & Jones (2002). Per mode and part the integral ``I = ∫ |φ·n|² dS`` (m⁴/kg) is returned:
a modal velocity ``q̇`` (√kg m/s) then gives the surface mean-square normal velocity
``<v_n²> S = |q̇|² I``. The bore, where the axle sits, is not a radiating surface.

Two mode-shape formats are read: the 3D 20-node meshes (shapes at the nodes, the integral over
the boundary faces of the hexahedra: the true 3D field, so the cos²(nθ) of a standing mode is in
it) and the axisymmetric section (harmonic amplitudes (u_r, u_z, u_θ) at the section nodes: the
circumferential integral ∫cos²nθ dθ = π (n ≥ 1) or 2π (n = 0) is applied analytically).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Corner nodes of the six faces of a 20-node hexahedron (VTK order, docs/conventions.md).
HEX_FACES = ((0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7))
#: Corner nodes of the four edges of an 8-node quadrilateral (VTK order).
QUAD_EDGES = ((0, 1), (1, 2), (2, 3), (3, 0))

BORE_TOLERANCE = 1.02
"""A radial-facing face whose mean radius is below this multiple of the smallest radius of the
mesh belongs to the bore (covered by the axle) and does not radiate."""

_GAUSS = np.array([-1.0, 1.0]) / np.sqrt(3.0)


@dataclass(frozen=True)
class ModeSurfaces:
    """Surface integrals of the modes.

    Attributes
    ----------
    axial : (m,) ndarray
        ``∫ |φ·n|² dS`` over the axial-facing surface, m⁴/kg.
    radial : (m,) ndarray
        The same over the radial-facing surface, m⁴/kg.
    area_axial, area_radial : float
        Areas of the two surfaces, m².
    outer_radius : float
        Largest radius of the wheel surface, m.
    rim_width : float
        Axial extent of the radial-facing surface at the outer radius (tread and flange), m.
    """

    axial: np.ndarray
    radial: np.ndarray
    area_axial: float
    area_radial: float
    outer_radius: float
    rim_width: float


def boundary_faces(cells, faces, with_cells=False):
    """Faces of a mesh that belong to one cell only.

    Parameters
    ----------
    cells : (E, k) int array_like
        Cell connectivity.
    faces : tuple of tuple of int
        Local node indices of each face of a cell.
    with_cells : bool
        Also return the index of the cell each boundary face belongs to.

    Returns
    -------
    (F, len(faces[0])) ndarray
        Global node indices of the boundary faces, in the local order of the cell
        (and, if asked, the (F,) cell indices).
    """
    cells = np.asarray(cells)
    all_faces = np.concatenate([cells[:, list(face)] for face in faces])
    owner = np.tile(np.arange(len(cells)), len(faces))
    keys = np.sort(all_faces, axis=1)
    _, index, counts = np.unique(keys, axis=0, return_index=True, return_counts=True)
    chosen = index[counts == 1]
    if with_cells:
        return all_faces[chosen], owner[chosen]
    return all_faces[chosen]


def hex_mode_surfaces(nodes, cells, shapes):
    """Surface integrals of 3D mode shapes on a hexahedral mesh (bilinear faces, 2x2 Gauss).

    Parameters
    ----------
    nodes : (N, 3) array_like
        Node coordinates (X, Y, Z), m; the axle is the Y axis.
    cells : (E, 20) int array_like
        20-node hexahedra (only their corners are used: the faces are taken as bilinear).
    shapes : (m, N, 3) array_like
        Mass-normalised mode shapes, m/√kg.

    Returns
    -------
    ModeSurfaces
    """
    nodes = np.asarray(nodes, dtype=float)
    faces = boundary_faces(cells, HEX_FACES)
    xyz = nodes[faces]  # (F, 4, 3)
    radius = np.hypot(xyz[..., 0], xyz[..., 2])
    centre = xyz.mean(axis=1)
    e_r = np.stack([centre[:, 0], np.zeros(len(centre)), centre[:, 2]], axis=1)
    e_r /= np.linalg.norm(e_r, axis=1)[:, None]
    axial_sum = np.zeros(shapes.shape[0])
    radial_sum = np.zeros(shapes.shape[0])
    area_axial = area_radial = 0.0
    normals_mean = np.zeros((len(faces), 3))
    weights_all = []
    for s in _GAUSS:
        for t in _GAUSS:
            n = 0.25 * np.array([(1 - s) * (1 - t), (1 + s) * (1 - t), (1 + s) * (1 + t), (1 - s) * (1 + t)])
            ds = 0.25 * np.array([-(1 - t), (1 - t), (1 + t), -(1 + t)])
            dt = 0.25 * np.array([-(1 - s), -(1 + s), (1 + s), (1 - s)])
            cross = np.cross(np.einsum("a,fai->fi", ds, xyz), np.einsum("a,fai->fi", dt, xyz))
            normals_mean += cross
            weights_all.append((n, cross))
    unit = normals_mean / np.linalg.norm(normals_mean, axis=1)[:, None]
    is_axial = np.abs(unit[:, 1]) > np.abs(np.einsum("fi,fi->f", unit, e_r))
    is_bore = (~is_axial) & (radius.mean(axis=1) < BORE_TOLERANCE * radius.min())
    keep = ~is_bore
    face_shapes = np.asarray(shapes)[:, faces[keep], :].astype(float)  # (m, F, 4, 3)
    for n, cross in weights_all:
        u = np.einsum("a,mfai->mfi", n, face_shapes)
        un2 = np.einsum("mfi,fi->mf", u, cross[keep]) ** 2 / np.linalg.norm(cross[keep], axis=1)[None, :]
        jac = np.linalg.norm(cross[keep], axis=1)
        axial_sum += un2[:, is_axial[keep]].sum(axis=1)
        radial_sum += un2[:, ~is_axial[keep]].sum(axis=1)
        area_axial += jac[is_axial[keep]].sum()
        area_radial += jac[~is_axial[keep]].sum()
    outer = radius.max()
    near_outer = (~is_axial) & (radius.mean(axis=1) > 0.9 * outer)
    axial_y = xyz[near_outer][..., 1]
    width = float(axial_y.max() - axial_y.min()) if axial_y.size else 0.0
    return ModeSurfaces(axial_sum, radial_sum, float(area_axial), float(area_radial), float(outer), width)


def section_mode_surfaces(section_nodes, section_cells, amplitudes, harmonics):
    """Surface integrals of axisymmetric harmonic modes (section boundary, 2-point Gauss).

    Parameters
    ----------
    section_nodes : (Ns, 2) array_like
        (r, z), m.
    section_cells : (E, 8) int array_like
        8-node quadrilaterals (corners used: straight edges).
    amplitudes : (m, Ns, 3) array_like
        Harmonic amplitudes (U_r, U_z, U_θ) of the mass-normalised 3D modes, m/√kg.
    harmonics : (m,) int array_like
        Number of nodal diameters n of each mode.

    Returns
    -------
    ModeSurfaces
    """
    rz = np.asarray(section_nodes, dtype=float)
    edges = boundary_faces(section_cells, QUAD_EDGES)
    ends = rz[edges]  # (F, 2, 2)
    tangent = ends[:, 1] - ends[:, 0]
    length = np.linalg.norm(tangent, axis=1)
    normal = np.stack([tangent[:, 1], -tangent[:, 0]], axis=1) / length[:, None]  # (n_r, n_z)
    is_axial = np.abs(normal[:, 1]) > np.abs(normal[:, 0])
    mean_r = ends[:, :, 0].mean(axis=1)
    keep = ~((~is_axial) & (mean_r < BORE_TOLERANCE * rz[:, 0].min()))
    amplitudes = np.asarray(amplitudes, dtype=float)
    around = np.where(np.asarray(harmonics) == 0, 2.0 * np.pi, np.pi)
    axial_sum = np.zeros(amplitudes.shape[0])
    radial_sum = np.zeros(amplitudes.shape[0])
    area_axial = area_radial = 0.0
    for g in _GAUSS:
        w = np.array([0.5 * (1 - g), 0.5 * (1 + g)])
        r = np.einsum("a,fa->f", w, ends[:, :, 0])
        u = np.einsum("a,mfai->mfi", w, amplitudes[:, edges, :2])  # (U_r, U_z)
        un2 = np.einsum("mfi,fi->mf", u, normal) ** 2
        jac = 0.5 * length * r
        part = un2 * jac[None, :] * keep[None, :]
        axial_sum += part[:, is_axial].sum(axis=1)
        radial_sum += part[:, ~is_axial].sum(axis=1)
        area_axial += 2.0 * np.pi * (jac * keep)[is_axial].sum()
        area_radial += 2.0 * np.pi * (jac * keep)[~is_axial].sum()
    outer = rz[:, 0].max()
    near_outer = (~is_axial) & (mean_r > 0.9 * outer)
    z = ends[near_outer][..., 1]
    width = float(z.max() - z.min()) if z.size else 0.0
    return ModeSurfaces(axial_sum * around, radial_sum * around, float(area_axial), float(area_radial), float(outer),
                        width)
