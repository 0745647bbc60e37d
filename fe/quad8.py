"""8-node serendipity quadrilateral (isoparametric reference element).

Node order is VTK's (see ``docs/conventions.md``): corners 0-3 counter-clockwise, then the
mid-side nodes 4 (edge 0-1), 5 (edge 1-2), 6 (edge 2-3), 7 (edge 3-0). Natural coordinates
(xi, eta) lie in [-1, 1]^2; they are dimensionless.
"""

from __future__ import annotations

import numpy as np

#: Natural coordinates (xi, eta) of the eight nodes, shape (8, 2).
NODE_COORDS = np.array(
    [
        [-1.0, -1.0],
        [1.0, -1.0],
        [1.0, 1.0],
        [-1.0, 1.0],
        [0.0, -1.0],
        [1.0, 0.0],
        [0.0, 1.0],
        [-1.0, 0.0],
    ]
)

_CORNERS = slice(0, 4)
_MID_XI = np.array([4, 6])  # mid-side nodes with xi_i = 0 (edges 0-1 and 2-3)
_MID_ETA = np.array([5, 7])  # mid-side nodes with eta_i = 0 (edges 1-2 and 3-0)


def _as_points(points):
    pts = np.asarray(points, dtype=float)
    if pts.ndim == 1:
        pts = pts[None, :]
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise ValueError(f"points must have shape (P, 2), got {np.shape(points)}")
    return pts[:, 0:1], pts[:, 1:2]


def shape_functions(points):
    """Evaluate the eight shape functions.

    Parameters
    ----------
    points : array_like, shape (P, 2)
        Natural coordinates (xi, eta) of the evaluation points (dimensionless).

    Returns
    -------
    ndarray, shape (P, 8)
        ``N[p, i]``: shape function of node ``i`` at point ``p``.
    """
    xi, eta = _as_points(points)
    xn, en = NODE_COORDS[:, 0], NODE_COORDS[:, 1]
    n = np.empty((xi.shape[0], 8))
    c = _CORNERS
    n[:, c] = 0.25 * (1 + xi * xn[c]) * (1 + eta * en[c]) * (xi * xn[c] + eta * en[c] - 1)
    n[:, _MID_XI] = 0.5 * (1 - xi**2) * (1 + eta * en[_MID_XI])
    n[:, _MID_ETA] = 0.5 * (1 + xi * xn[_MID_ETA]) * (1 - eta**2)
    return n


def shape_derivatives(points):
    """Derivatives of the shape functions with respect to the natural coordinates.

    Parameters
    ----------
    points : array_like, shape (P, 2)
        Natural coordinates (xi, eta) of the evaluation points (dimensionless).

    Returns
    -------
    ndarray, shape (P, 8, 2)
        ``dN[p, i, 0] = dN_i/dxi`` and ``dN[p, i, 1] = dN_i/deta`` at point ``p``.
    """
    xi, eta = _as_points(points)
    xn, en = NODE_COORDS[:, 0], NODE_COORDS[:, 1]
    d = np.empty((xi.shape[0], 8, 2))
    c = _CORNERS
    d[:, c, 0] = 0.25 * xn[c] * (1 + eta * en[c]) * (2 * xi * xn[c] + eta * en[c])
    d[:, c, 1] = 0.25 * en[c] * (1 + xi * xn[c]) * (xi * xn[c] + 2 * eta * en[c])
    m = _MID_XI
    d[:, m, 0] = -xi * (1 + eta * en[m])
    d[:, m, 1] = 0.5 * en[m] * (1 - xi**2)
    m = _MID_ETA
    d[:, m, 0] = 0.5 * xn[m] * (1 - eta**2)
    d[:, m, 1] = -eta * (1 + xi * xn[m])
    return d


def gauss_points(order=3):
    """Tensor-product Gauss-Legendre rule on the reference square [-1, 1]^2.

    Parameters
    ----------
    order : int, optional
        Number of points per direction (default 3, exact for polynomials of degree 5 in each
        natural coordinate).

    Returns
    -------
    points : ndarray, shape (order**2, 2)
        Natural coordinates (xi, eta) of the points, xi varying fastest.
    weights : ndarray, shape (order**2,)
        Weights; they sum to 4 (the area of the reference square).
    """
    if int(order) != order or order < 1:
        raise ValueError(f"order must be a positive integer, got {order!r}")
    x, w = np.polynomial.legendre.leggauss(int(order))
    xi, eta = np.meshgrid(x, x, indexing="xy")
    wx, we = np.meshgrid(w, w, indexing="xy")
    points = np.column_stack([xi.ravel(), eta.ravel()])
    return points, (wx * we).ravel()
