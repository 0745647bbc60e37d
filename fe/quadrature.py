"""Fields at the Gauss points of the wheel meshes: values and gradients of nodal fields.

Shared by the modal integrals of the rotating wheel (:mod:`fe.rotation`) and the centrifugal
prestress (:mod:`fe.centrifugal`), so that both integrate at the same points: 3×3×3 Gauss
points per hex20 element, 3×3 (by default) per quad8 section element.
"""

from __future__ import annotations

import numpy as np

from fe import hex20, quad8
from squealcore.errors import InputError


def hex20_quadrature_chunks(nodes, cells, shapes, chunk_size=64):
    """Mode fields at the 3×3×3 Gauss points of a hex20 mesh, element chunk by chunk.

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m.
    cells : (E, 20) int ndarray
        VTK hex20 order.
    shapes : (m, N, 3) ndarray
        Cartesian nodal shapes (any unit u).
    chunk_size : int
        Elements per chunk.

    Yields
    ------
    start, stop : int
        Element range of the chunk.
    weight : (e, G) ndarray
        Gauss weight × det J (m³).
    position : (e, G, 3) ndarray
        Gauss-point coordinates (m).
    value : (m, e, G, 3) ndarray
        Shapes at the points (u).
    gradient : (m, e, G, 3, 3) ndarray
        ``gradient[..., c, j] = ∂u_c/∂x_j`` (u/m).
    """
    pts, wts = hex20.gauss_points(3)
    n_shape = hex20.shape_functions(pts)
    dn = hex20.shape_derivatives(pts)
    for start in range(0, cells.shape[0], chunk_size):
        stop = min(start + chunk_size, cells.shape[0])
        cell = cells[start:stop]
        xe = nodes[cell]
        jac = np.einsum("gai,eaj->egij", dn, xe)
        det = np.linalg.det(jac)
        if np.any(det <= 0.0):
            raise InputError("mesh.cells", "elements must have a positive Jacobian determinant")
        inv = np.linalg.inv(jac)
        dndx = np.einsum("egji,gai->egaj", inv, dn)
        ue = shapes[:, cell, :]  # (m, e, 20, 3)
        value = np.einsum("ga,keac->kegc", n_shape, ue, optimize=True)
        gradient = np.einsum("egaj,keac->kegcj", dndx, ue, optimize=True)
        position = np.einsum("ga,eaj->egj", n_shape, xe)
        yield start, stop, det * wts[None, :], position, value, gradient


def section_quadrature(section_nodes, section_cells, order=3):
    """Quad8 Gauss data on the section.

    Returns
    -------
    n_shape : (G, 8) ndarray
        Shape functions at the Gauss points.
    dn_dx : (E, G, 8, 2) ndarray
        ``∂N/∂r, ∂N/∂z`` (1/m).
    radius : (E, G) ndarray
        m.
    w_rda : (E, G) ndarray
        Gauss weight × det J × r (m³): ``Σ f w_rda = ∫ f r dr dz``.
    """
    nodes = np.asarray(section_nodes, dtype=float)
    cells = np.asarray(section_cells)
    pts, wts = quad8.gauss_points(order)
    n_shape = quad8.shape_functions(pts)
    dn = quad8.shape_derivatives(pts)
    x = nodes[cells]
    jac = np.einsum("eia,gib->egab", x, dn)
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    if np.any(det <= 0.0):
        raise InputError("fe.cells", "quad8 elements must be counter-clockwise in (r, z) (det J > 0)")
    inv = np.linalg.inv(jac)
    dn_dx = np.einsum("gib,egba->egia", dn, inv)
    radius = np.einsum("gi,ei->eg", n_shape, x[..., 0])
    return n_shape, dn_dx, radius, wts[None, :] * det * radius
