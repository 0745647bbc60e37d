"""Section properties of a meshed rail cross-section, computed by quadrature on the mesh.

Includes the Saint-Venant torsion constant and the shear centre from a warping-function
finite-element solve on the same mesh.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from waveguide.shape import element_geometry

logger = logging.getLogger(__name__)

__all__ = ["SectionProperties", "section_properties", "warping_function"]


@dataclasses.dataclass(frozen=True)
class SectionProperties:
    """Properties of a rail cross-section (SI units).

    Attributes
    ----------
    area : float
        Cross-section area (m^2).
    centroid : tuple of float
        (y_c, z_c) in m.
    i_vertical : float
        Second moment of area for **vertical** bending, int (z - z_c)^2 dA (m^4)
        (bending about the horizontal, lateral axis).
    i_lateral : float
        Second moment of area for **lateral** bending, int (y - y_c)^2 dA (m^4).
    i_yz : float
        Product of area int (y - y_c)(z - z_c) dA (m^4); 0 for a symmetric rail.
    polar_centroid : float
        Polar moment of area about the centroid, i_vertical + i_lateral (m^4).
    torsion_constant : float
        Saint-Venant torsion constant J (m^4).
    shear_centre : tuple of float
        (y_s, z_s) in m.
    polar_shear_centre : float
        Polar moment of area about the shear centre (m^4).
    mass_per_length : float
        Mass per metre (kg/m).
    warping_constant : float
        Gamma = int w_s^2 dA with w_s the warping function about the shear centre (m^6).
    """

    area: float
    centroid: tuple
    i_vertical: float
    i_lateral: float
    i_yz: float
    polar_centroid: float
    torsion_constant: float
    shear_centre: tuple
    polar_shear_centre: float
    mass_per_length: float
    warping_constant: float


def _laplace_matrix(mesh, dn, wdet):
    e, q, n, _ = dn.shape
    ke = np.einsum("eqak,eqbk,eq->eab", dn, dn, wdet)
    rows = np.repeat(mesh.cells, n, axis=1).ravel()
    cols = np.tile(mesh.cells, (1, n)).ravel()
    return sp.csr_matrix((ke.ravel(), (rows, cols)), shape=(mesh.n_nodes,) * 2)


def warping_function(mesh, centre):
    """Saint-Venant warping function about ``centre`` (laplace(w) = 0,
    dw/dn = (z - z0) n_y - (y - y0) n_z on the boundary), normalised to zero mean.

    Parameters
    ----------
    mesh : mesh.rail_mesh.RailMesh
    centre : (float, float)
        Reference point (y0, z0) in m.

    Returns
    -------
    omega : ndarray (N,)
        Nodal warping function (m^2).
    torsion_constant : float
        J = I_p - int (z w_y - y w_z) dA about ``centre`` (m^4).
    """
    n, dn, wdet, xq = element_geometry(mesh.nodes, mesh.cells, mesh.element_type, order=4)
    y = xq[..., 0] - centre[0]
    z = xq[..., 1] - centre[1]
    k = _laplace_matrix(mesh, dn, wdet)
    # weak form: int grad v . grad w = int (z v_y - y v_z) dA (by the divergence theorem)
    fe = np.einsum("eq,eqa->ea", wdet * z, dn[..., 0]) - np.einsum("eq,eqa->ea", wdet * y, dn[..., 1])
    f = np.bincount(mesh.cells.ravel(), fe.ravel(), minlength=mesh.n_nodes)
    # fix the rigid constant with a penalty-free approach: ground node 0, then remove the mean
    free = np.arange(1, mesh.n_nodes)
    omega = np.zeros(mesh.n_nodes)
    omega[free] = spla.spsolve(k[free][:, free].tocsc(), f[free])
    area = wdet.sum()
    omega -= np.einsum("eq,qa,ea->", wdet, n, omega[mesh.cells]) / area
    ip = np.sum(wdet * (y**2 + z**2))
    j = ip - float(f @ omega)
    return omega, j


def section_properties(mesh, density: float | None = None) -> SectionProperties:
    """Area, centroid, second moments, torsion constant and shear centre of a meshed section.

    Parameters
    ----------
    mesh : mesh.rail_mesh.RailMesh
    density : float, optional
        Density (kg/m^3); defaults to ``mesh.density``.

    Returns
    -------
    SectionProperties
    """
    rho = mesh.density if density is None else density
    n, dn, wdet, xq = element_geometry(mesh.nodes, mesh.cells, mesh.element_type, order=4)
    area = float(wdet.sum())
    yc = float(np.sum(wdet * xq[..., 0]) / area)
    zc = float(np.sum(wdet * xq[..., 1]) / area)
    y, z = xq[..., 0] - yc, xq[..., 1] - zc
    iv = float(np.sum(wdet * z**2))
    il = float(np.sum(wdet * y**2))
    iyz = float(np.sum(wdet * y * z))
    omega, j = warping_function(mesh, (yc, zc))
    wq = np.einsum("qa,ea->eq", n, omega[mesh.cells])
    iwy = float(np.sum(wdet * wq * y))
    iwz = float(np.sum(wdet * wq * z))
    # shear centre (Trefftz): the warping function about it is orthogonal to y and z
    det = iv * il - iyz**2
    zs = zc + (iwy * iv - iwz * iyz) / det
    ys = yc - (iwz * il - iwy * iyz) / det
    ip_s = iv + il + area * ((ys - yc) ** 2 + (zs - zc) ** 2)
    # warping function about the shear centre: w_s = w_c - (z_s - z_c) y + (y_s - y_c) z
    ws = wq - (zs - zc) * y + (ys - yc) * z
    ws = ws - np.sum(wdet * ws) / area
    gamma = float(np.sum(wdet * ws**2))
    props = SectionProperties(warping_constant=gamma, area=area, centroid=(yc, zc), i_vertical=iv, i_lateral=il, i_yz=iyz,
                              polar_centroid=iv + il, torsion_constant=j, shear_centre=(ys, zs),
                              polar_shear_centre=ip_s, mass_per_length=rho * area)
    logger.info("section: A=%.4g m^2, I_v=%.4g m^4, I_l=%.4g m^4, J=%.4g m^4", area, iv, il, j)
    return props
