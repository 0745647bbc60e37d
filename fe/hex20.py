"""Serendipity 20-node hexahedron (isoparametric, linear elasticity, consistent mass).

Node order: VTK / Abaqus C3D20 (see docs/conventions.md). Corners 0-3 on zeta = -1, corners 4-7
on zeta = +1, then mid-edge nodes 8-11 (bottom face edges), 12-15 (top face edges), 16-19
(vertical edges). Element DOF order: ``3 * local_node + component`` (X, Y, Z).
"""

from __future__ import annotations

import logging

import numpy as np

from squealcore.errors import InputError

logger = logging.getLogger(__name__)

#: Natural coordinates (xi, eta, zeta) of the 20 nodes, shape (20, 3).
NODE_COORDS = np.array(
    [
        [-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
        [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1],
        [0, -1, -1], [1, 0, -1], [0, 1, -1], [-1, 0, -1],
        [0, -1, 1], [1, 0, 1], [0, 1, 1], [-1, 0, 1],
        [-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0],
    ],
    dtype=float,
)
NODE_COORDS.setflags(write=False)

#: Local node numbers of the six faces (4 corners counter-clockwise seen from outside, then the
#: 4 mid-edge nodes), shape (6, 8). Order: zeta=-1, zeta=+1, eta=-1, xi=+1, eta=+1, xi=-1.
FACES = np.array(
    [
        [0, 3, 2, 1, 11, 10, 9, 8],
        [4, 5, 6, 7, 12, 13, 14, 15],
        [0, 1, 5, 4, 8, 17, 12, 16],
        [1, 2, 6, 5, 9, 18, 13, 17],
        [2, 3, 7, 6, 10, 19, 14, 18],
        [3, 0, 4, 7, 11, 16, 15, 19],
    ]
)

NODES_PER_ELEMENT = 20
DOFS_PER_ELEMENT = 60

_CORNER = np.arange(8)
_MID = np.arange(8, 20)


def _as_points(points):
    pts = np.asarray(points, dtype=float)
    if pts.ndim == 1:
        pts = pts[None, :]
    if pts.ndim != 2 or pts.shape[1] != 3:
        raise ValueError(f"points must have shape (npts, 3), got {pts.shape}")
    return pts


def shape_functions(points):
    """Serendipity shape functions at points in natural coordinates.

    Parameters
    ----------
    points : array_like, shape (npts, 3)
        Natural coordinates (xi, eta, zeta) in [-1, 1] (dimensionless).

    Returns
    -------
    ndarray, shape (npts, 20)
        N[p, a], the value of node a's shape function at point p.
    """
    pts = _as_points(points)
    x = pts[:, None, :]  # (npts, 1, 3)
    c = NODE_COORDS[None, :, :]  # (1, 20, 3)
    lin = 1.0 + x * c  # (npts, 20, 3): 1 + xi xi_a etc.
    n = np.empty((pts.shape[0], 20))
    # corners: 1/8 (1+xi xi_a)(1+eta eta_a)(1+zeta zeta_a)(xi xi_a + eta eta_a + zeta zeta_a - 2)
    lc = lin[:, _CORNER, :]
    n[:, _CORNER] = 0.125 * lc.prod(axis=2) * (lc.sum(axis=2) - 5.0)
    # mid-edge nodes: the coordinate that is 0 at the node contributes (1 - s^2), others (1+s s_a)
    cm = NODE_COORDS[_MID]
    zero = cm == 0.0  # (12, 3)
    factors = np.where(zero[None], 1.0 - x**2, lin[:, _MID, :])
    n[:, _MID] = 0.25 * factors.prod(axis=2)
    return n


def shape_derivatives(points):
    """Derivatives of the shape functions with respect to the natural coordinates.

    Parameters
    ----------
    points : array_like, shape (npts, 3)
        Natural coordinates (xi, eta, zeta) (dimensionless).

    Returns
    -------
    ndarray, shape (npts, 20, 3)
        dN[p, a, i] = dN_a / d xi_i at point p.
    """
    pts = _as_points(points)
    npts = pts.shape[0]
    x = pts[:, None, :]
    dn = np.empty((npts, 20, 3))
    # corners
    cc = NODE_COORDS[_CORNER][None]  # (1, 8, 3)
    lc = 1.0 + x * cc  # (npts, 8, 3)
    s = lc.sum(axis=2) - 5.0  # (npts, 8)
    prod = lc.prod(axis=2)  # (npts, 8)
    for i in range(3):
        others = np.prod(np.delete(lc, i, axis=2), axis=2)
        # d/dxi_i [prod * s] = c_i * others * s + prod * c_i
        dn[:, _CORNER, i] = 0.125 * cc[..., i] * (others * s + prod)
    # mid-edge nodes
    cm = NODE_COORDS[_MID][None]  # (1, 12, 3)
    zero = cm == 0.0
    f = np.where(zero, 1.0 - x**2, 1.0 + x * cm)  # (npts, 12, 3)
    df = np.where(zero, -2.0 * np.broadcast_to(x, f.shape), np.broadcast_to(cm, f.shape))
    for i in range(3):
        others = np.prod(np.delete(f, i, axis=2), axis=2)
        dn[:, _MID, i] = 0.25 * df[..., i] * others
    return dn


def gauss_points(order=3):
    """Tensor-product Gauss-Legendre rule on the cube [-1, 1]^3.

    Parameters
    ----------
    order : int, optional
        Number of points per direction (default 3, exact for degree 2*order-1 per direction).

    Returns
    -------
    points : ndarray, shape (order**3, 3)
        Natural coordinates of the integration points.
    weights : ndarray, shape (order**3,)
        Weights (they sum to 8, the volume of the reference cube).
    """
    if int(order) != order or order < 1:
        raise ValueError(f"order must be a positive integer, got {order!r}")
    g, w = np.polynomial.legendre.leggauss(int(order))
    xi, eta, zeta = np.meshgrid(g, g, g, indexing="ij")
    wx, wy, wz = np.meshgrid(w, w, w, indexing="ij")
    points = np.column_stack([xi.ravel(), eta.ravel(), zeta.ravel()])
    weights = (wx * wy * wz).ravel()
    return points, weights


def _check_mesh(nodes, cells):
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells)
    if nodes.ndim != 2 or nodes.shape[1] != 3:
        raise InputError("mesh.nodes", f"must have shape (N, 3), got {nodes.shape}")
    if cells.ndim != 2 or cells.shape[1] != 20 or not np.issubdtype(cells.dtype, np.integer):
        raise InputError("mesh.cells", f"must be an integer array of shape (E, 20), got {cells.shape}")
    if cells.size and (cells.min() < 0 or cells.max() >= nodes.shape[0]):
        raise InputError("mesh.cells", f"node indices must lie in [0, {nodes.shape[0] - 1}]")
    return nodes, cells


def _jacobians(xe, dn, first_element):
    """Jacobians J[e, g, i, j] = d x_j / d xi_i, their determinants and inverses."""
    jac = np.einsum("gai,eaj->egij", dn, xe)
    det = np.linalg.det(jac)
    bad = np.nonzero(det <= 0.0)
    if bad[0].size:
        e = int(bad[0][0])
        raise InputError(
            "mesh.cells",
            f"element {first_element + e} is inverted or degenerate: Jacobian determinant "
            f"{det[bad][0]:.3e} <= 0 at Gauss point {int(bad[1][0])} (must be > 0 everywhere; "
            f"{np.unique(bad[0]).size} bad element(s) in this chunk)",
        )
    return jac, det, np.linalg.inv(jac)


def _strain_displacement(dndx):
    """B matrices (E, G, 6, 60) from physical shape derivatives dndx (E, G, 20, 3)."""
    e, g = dndx.shape[:2]
    b = np.zeros((e, g, 6, 20, 3))
    dx, dy, dz = dndx[..., 0], dndx[..., 1], dndx[..., 2]
    b[:, :, 0, :, 0] = dx
    b[:, :, 1, :, 1] = dy
    b[:, :, 2, :, 2] = dz
    b[:, :, 3, :, 1] = dz  # gamma_yz
    b[:, :, 3, :, 2] = dy
    b[:, :, 4, :, 0] = dz  # gamma_xz
    b[:, :, 4, :, 2] = dx
    b[:, :, 5, :, 0] = dy  # gamma_xy
    b[:, :, 5, :, 1] = dx
    return b.reshape(e, g, 6, 60)


def element_matrices(nodes, cells, D, density, *, chunk_size=512, order=3):
    """Stiffness and consistent mass matrices of 20-node hexahedra, vectorised over elements.

    Parameters
    ----------
    nodes : array_like, shape (N, 3)
        Node coordinates in m.
    cells : array_like of int, shape (E, 20)
        Node indices of each element in VTK / C3D20 order.
    D : array_like, shape (6, 6)
        Elasticity matrix in Pa, Voigt order (xx, yy, zz, yz, xz, xy), engineering shear.
    density : float or array_like, shape (E,)
        Mass density in kg/m^3 (scalar or one value per element).
    chunk_size : int, optional
        Number of elements processed at once (bounds the temporary memory, about
        ``chunk_size * 0.2 MB``).
    order : int, optional
        Gauss points per direction (default 3, i.e. 27 points).

    Returns
    -------
    Ke : ndarray, shape (E, 60, 60)
        Element stiffness matrices in N/m, DOF order ``3 * local_node + component``.
    Me : ndarray, shape (E, 60, 60)
        Element consistent mass matrices in kg.

    Raises
    ------
    squealcore.errors.InputError
        If the mesh arrays are malformed or an element has a Jacobian determinant <= 0 at a
        Gauss point (inverted or degenerate element; the message gives the element index).
    """
    nodes, cells = _check_mesh(nodes, cells)
    D = np.asarray(D, dtype=float)
    if D.shape != (6, 6):
        raise InputError("material.D", f"must have shape (6, 6), got {D.shape}")
    n_el = cells.shape[0]
    rho = np.broadcast_to(np.asarray(density, dtype=float), (n_el,))
    if np.any(~np.isfinite(rho)) or np.any(rho <= 0.0):
        raise InputError("material.density", "must be > 0 kg/m^3 and finite")
    pts, wts = gauss_points(order)
    n = shape_functions(pts)  # (G, 20)
    dn = shape_derivatives(pts)  # (G, 20, 3)
    ke = np.empty((n_el, 60, 60))
    me = np.empty((n_el, 60, 60))
    eye3 = np.eye(3)
    for start in range(0, n_el, chunk_size):
        stop = min(start + chunk_size, n_el)
        xe = nodes[cells[start:stop]]  # (e, 20, 3)
        _, det, inv = _jacobians(xe, dn, start)
        dndx = np.einsum("egji,gai->egaj", inv, dn)  # dN_a/dx_j
        b = _strain_displacement(dndx)  # (e, G, 6, 60)
        wdet = det * wts[None, :]  # (e, G)
        db = np.einsum("kl,eglj->egkj", D, b)
        ne = stop - start
        bw = (b * wdet[:, :, None, None]).reshape(ne, -1, 60)
        ke[start:stop] = np.matmul(bw.transpose(0, 2, 1), db.reshape(ne, -1, 60))
        m20 = np.einsum("ga,gb,eg->eab", n, n, wdet * rho[start:stop, None])  # (e, 20, 20)
        me[start:stop] = (m20[:, :, None, :, None] * eye3[None, None, :, None, :]).reshape(ne, 60, 60)
    logger.debug("hex20 element matrices: %d elements, %d Gauss points", n_el, pts.shape[0])
    return ke, me


def element_volumes(nodes, cells, *, order=3):
    """Volumes of 20-node hexahedra by Gauss integration of the Jacobian determinant.

    Parameters
    ----------
    nodes : array_like, shape (N, 3)
        Node coordinates in m.
    cells : array_like of int, shape (E, 20)
        Node indices in VTK / C3D20 order.
    order : int, optional
        Gauss points per direction (default 3: exact for parallelepipeds, quadrature accuracy
        for distorted or curved elements).

    Returns
    -------
    ndarray, shape (E,)
        Element volumes in m^3.
    """
    nodes, cells = _check_mesh(nodes, cells)
    pts, wts = gauss_points(order)
    dn = shape_derivatives(pts)
    jac = np.einsum("gai,eaj->egij", dn, nodes[cells])
    return np.linalg.det(jac) @ wts


def element_strains(nodes, cells, u, points=None):
    """Strains inside 20-node hexahedra from nodal displacements.

    Parameters
    ----------
    nodes : array_like, shape (N, 3)
        Node coordinates in m.
    cells : array_like of int, shape (E, 20)
        Node indices in VTK / C3D20 order.
    u : array_like, shape (3N,)
        Nodal displacements in m, DOF order ``3 * node + component``.
    points : array_like, shape (npts, 3), optional
        Natural coordinates of the evaluation points (default: the 27 Gauss points).

    Returns
    -------
    ndarray, shape (E, npts, 6)
        Strains (dimensionless) in Voigt order (xx, yy, zz, yz, xz, xy), engineering shear.
    """
    nodes, cells = _check_mesh(nodes, cells)
    if points is None:
        points, _ = gauss_points(3)
    dn = shape_derivatives(points)
    _, _, inv = _jacobians(nodes[cells], dn, 0)
    b = _strain_displacement(np.einsum("egji,gai->egaj", inv, dn))
    ue = np.asarray(u, dtype=float).reshape(-1, 3)[cells].reshape(cells.shape[0], 60)
    return np.einsum("egkj,ej->egk", b, ue)
