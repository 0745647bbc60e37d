"""Shape functions and quadrature of the 2D cross-section elements (8-node quad, 6-node triangle).

The 8-node quadrilateral is :mod:`fe.quad8`, shared with the wheel's axisymmetric element.

Node orders (docs/conventions.md): quad8 = VTK order, corners 0-3 counter-clockwise, then
mid-side nodes 4 (0-1), 5 (1-2), 6 (2-3), 7 (3-0); tri6 = corners 0-2 counter-clockwise, then
mid-side nodes 3 (0-1), 4 (1-2), 5 (2-0). Coordinates of the section are (y, z) in m.
"""

from __future__ import annotations

import numpy as np

from fe import quad8

__all__ = ["gauss_rule", "shape_functions", "element_geometry", "edge_rule"]

def _tri6(r, s):
    """Quadratic triangle shape functions N (q, 6) and derivatives dN (q, 6, 2)."""
    t = 1 - r - s
    n = np.stack([t * (2 * t - 1), r * (2 * r - 1), s * (2 * s - 1), 4 * r * t, 4 * r * s, 4 * s * t], 1)
    dr = np.stack([1 - 4 * t, 4 * r - 1, 0 * r, 4 * (t - r), 4 * s, -4 * s], 1)
    ds = np.stack([1 - 4 * t, 0 * r, 4 * s - 1, -4 * r, 4 * r, 4 * (t - s)], 1)
    return n, np.stack([dr, ds], 2)


def gauss_rule(element_type: str, order: int = 3):
    """Quadrature points and weights on the reference element.

    Parameters
    ----------
    element_type : {"quad8", "tri6"}
    order : int
        Gauss-Legendre points per direction for quads (3 integrates the quad8 stiffness
        exactly on affine elements); for triangles 3 gives the 6-point degree-4 rule,
        otherwise the 7-point degree-5 rule.

    Returns
    -------
    points : ndarray (q, 2)
    weights : ndarray (q,)
    """
    if element_type == "quad8":
        return quad8.gauss_points(order)
    if element_type == "tri6":
        if order <= 3:  # Strang-Fix 6-point rule, degree 4
            a, b = 0.445948490915965, 0.091576213509771
            wa, wb = 0.223381589678011 / 2, 0.109951743655322 / 2
            pts = [[a, a], [1 - 2 * a, a], [a, 1 - 2 * a], [b, b], [1 - 2 * b, b], [b, 1 - 2 * b]]
            return np.array(pts), np.array([wa] * 3 + [wb] * 3)
        a, b = 0.470142064105115, 0.101286507323456
        wa, wb, w0 = 0.132394152788506 / 2, 0.125939180544827 / 2, 0.225 / 2
        pts = [[1 / 3, 1 / 3], [a, a], [1 - 2 * a, a], [a, 1 - 2 * a], [b, b], [1 - 2 * b, b], [b, 1 - 2 * b]]
        return np.array(pts), np.array([w0] + [wa] * 3 + [wb] * 3)
    raise ValueError(f"unknown element type {element_type!r}")


def shape_functions(element_type: str, points):
    """Shape functions (q, n_nodes) and reference derivatives (q, n_nodes, 2) at ``points``."""
    points = np.asarray(points, dtype=float)
    if element_type == "quad8":  # the same element as the wheel section's (fe/quad8.py)
        return quad8.shape_functions(points), quad8.shape_derivatives(points)
    if element_type == "tri6":
        return _tri6(points[:, 0], points[:, 1])
    raise ValueError(f"unknown element type {element_type!r}")


def element_geometry(nodes, cells, element_type: str, order: int = 3):
    """Physical quadrature data of all elements, vectorised.

    Parameters
    ----------
    nodes : ndarray (N, 2)
        Node coordinates (y, z) in m.
    cells : ndarray (E, n)
        Element connectivity.
    element_type : {"quad8", "tri6"}
    order : int
        Quadrature order, see :func:`gauss_rule`.

    Returns
    -------
    n : ndarray (q, n)
        Shape functions at the quadrature points.
    dn : ndarray (E, q, n, 2)
        Derivatives d/dy, d/dz of the shape functions (1/m).
    wdet : ndarray (E, q)
        Quadrature weight times Jacobian determinant (m^2).
    xq : ndarray (E, q, 2)
        Physical coordinates of the quadrature points (m).
    """
    pts, w = gauss_rule(element_type, order)
    n, dref = shape_functions(element_type, pts)
    xe = np.asarray(nodes)[np.asarray(cells)]  # (E, n, 2)
    jac = np.einsum("qak,eal->eqkl", dref, xe)  # d(y,z)_l / d(xi)_k
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    if np.any(det <= 0):
        raise ValueError("element with non-positive Jacobian (clockwise or distorted)")
    inv = np.empty_like(jac)
    inv[..., 0, 0] = jac[..., 1, 1] / det
    inv[..., 1, 1] = jac[..., 0, 0] / det
    inv[..., 0, 1] = -jac[..., 0, 1] / det
    inv[..., 1, 0] = -jac[..., 1, 0] / det
    dn = np.einsum("qak,eqlk->eqal", dref, inv)
    xq = np.einsum("qa,eal->eql", n, xe)
    return n, dn, det * w, xq


def edge_rule(n_points: int = 40):
    """Shape functions of a 3-node edge (corner, corner, mid) at Gauss points on [-1, 1].

    Returns
    -------
    s : ndarray (q,)
    w : ndarray (q,)
    n : ndarray (q, 3)
    dn : ndarray (q, 3)
    """
    s, w = np.polynomial.legendre.leggauss(n_points)
    n = np.column_stack([0.5 * s * (s - 1), 0.5 * s * (s + 1), 1 - s**2])
    dn = np.column_stack([s - 0.5, s + 0.5, -2 * s])
    return s, w, n, dn
