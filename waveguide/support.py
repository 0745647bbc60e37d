"""Continuous two-layer track support (pad - sleeper mass - ballast) acting on the rail foot,
and the load patch on the rail head.

The pad is a distributed spring layer under the foot bottom (traction per unit area =
pad stiffness per metre / foot width x (u - u_sleeper)); the sleeper layer is a rigid mass
per metre on the ballast spring. Eliminating the sleeper displacement gives the
frequency-dependent stiffness matrix per metre

    Ks(omega) = kp / b * Mb - kp^2 / (kp + kb - omega^2 ms) / b^2 * c c^T

for each of the lateral (y) and vertical (z) directions, with ``Mb = int N^T N ds`` and
``c = int N ds`` over the foot bottom of width ``b``. For a rigid foot this is the familiar
series stiffness kp (kb - omega^2 ms) / (kp + kb - omega^2 ms).
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import scipy.sparse as sp

from squealcore.errors import InputError
from waveguide.shape import edge_rule, element_geometry

logger = logging.getLogger(__name__)

__all__ = ["FootSupport", "foot_support", "equivalent_stiffness", "patch_weights",
           "section_weights"]


def equivalent_stiffness(omega, pad, ballast, pad_loss, ballast_loss, sleeper_mass, damping=None):
    """Dynamic stiffness per metre (N/m per m) of pad + sleeper mass + ballast in series.

    Parameters
    ----------
    omega : float or ndarray
        Angular frequency (rad/s).
    pad, ballast : float
        Stiffnesses per metre (N/m per m).
    pad_loss, ballast_loss : float
        Loss factors (-).
    sleeper_mass : float
        kg/m.
    damping : waveguide.damping.TrackDamping, optional
        Complex factors of pad and ballast (then ``pad_loss`` and ``ballast_loss`` are not
        used); default hysteretic ``1 + i eta``.

    Returns
    -------
    complex or ndarray
    """
    if damping is None:
        fp, fb = 1 + 1j * pad_loss, 1 + 1j * ballast_loss
    else:
        fp, fb = damping.factor("pad", omega), damping.factor("ballast", omega)
    kp = pad * fp
    kb = ballast * fb - np.asarray(omega) ** 2 * sleeper_mass
    return kp * kb / (kp + kb)


@dataclasses.dataclass(frozen=True)
class FootSupport:
    """Support matrices on the foot bottom (DOF space of the full mesh).

    ``mb[c]`` (sparse, m): int N^T N ds on the DOFs of component c (0 x, 1 y, 2 z);
    ``c[c]`` (N_dof,) (m): int N ds; ``width`` (m) foot-bottom width.
    """

    mb: tuple
    c: tuple
    width: float


def _edge_integrals(nodes, edges, n_points=8):
    """Per-edge quadrature: shape values (q, 3), weights*|J| (B, q), points (B, q, 2)."""
    s, w, n, dn = edge_rule(n_points)
    xe = nodes[edges]  # (B, 3, 2)
    xq = np.einsum("qa,bak->bqk", n, xe)
    tq = np.einsum("qa,bak->bqk", dn, xe)
    jac = np.linalg.norm(tq, axis=2)
    return n, w[None, :] * jac, xq, tq / jac[..., None]


def foot_support(mesh, tol: float = 1e-6) -> FootSupport:
    """Support matrices on the boundary edges lying on the foot bottom (z = min z).

    Parameters
    ----------
    mesh : mesh.rail_mesh.RailMesh
    tol : float
        Tolerance (m) on z for an edge to belong to the foot bottom.

    Returns
    -------
    FootSupport
    """
    zmin = mesh.nodes[:, 1].min()
    e = mesh.boundary_edges
    on = np.all(np.abs(mesh.nodes[e, 1] - zmin) < tol, axis=1)
    edges = e[on]
    if len(edges) == 0:
        raise InputError("rail.profile", "the outline has no flat foot bottom to support")
    n, wj, _, _ = _edge_integrals(mesh.nodes, edges)
    ndof = 3 * mesh.n_nodes
    mats = []
    vecs = []
    for comp in (0, 1, 2):
        dofs = 3 * edges + comp
        blocks = np.einsum("qa,qb,eq->eab", n, n, wj)
        rows = np.repeat(dofs, 3, axis=1).ravel()
        cols = np.tile(dofs, (1, 3)).ravel()
        mats.append(sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(ndof, ndof)))
        vecs.append(np.bincount(dofs.ravel(), np.einsum("qa,eq->ea", n, wj).ravel(), minlength=ndof))
    width = float(wj.sum())
    logger.info("foot support on %d edges, width %.4f m", len(edges), width)
    return FootSupport(tuple(mats), tuple(vecs), width)


def patch_weights(mesh, lateral_position: float, width: float, n_points: int = 64):
    """Nodal weights of a uniform unit load over ``|y - lateral_position| < width / 2`` on the
    upward-facing boundary of the head.

    Parameters
    ----------
    mesh : mesh.rail_mesh.RailMesh
    lateral_position : float
        y of the patch centre (m).
    width : float
        Patch width (m).
    n_points : int
        Quadrature points per edge (the patch edge cuts through elements).

    Returns
    -------
    ndarray (N_dof, 3)
        Column j: consistent nodal forces (sum 1) for a unit force in direction j
        (x, y, z) spread uniformly over the patch; also the weights of the patch-averaged
        displacement.
    """
    e = mesh.boundary_edges
    height = mesh.height
    n, wj, xq, tq = _edge_integrals(mesh.nodes, e, n_points)
    # outward normal of a counter-clockwise boundary: tangent rotated by -90 degrees
    nz = -tq[..., 0]
    top = (nz > 0.5) & (xq[..., 1] > 0.5 * height)
    inside = np.abs(xq[..., 0] - lateral_position) < width / 2
    wq = wj * top * inside
    total = wq.sum()
    if total <= 0:
        raise InputError("track.contact_lateral_position",
                         f"no head-top surface within +-{width / 2:g} m of y = {lateral_position:g} m")
    nodal = np.bincount(e.ravel(), np.einsum("qa,eq->ea", n, wq).ravel(), minlength=mesh.n_nodes) / total
    p = np.zeros((3 * mesh.n_nodes, 3))
    for c in range(3):
        p[c::3, c] = nodal
    return p


def section_weights(mesh, n_order: int = 3):
    """Weights of a load distributed over the whole section in proportion to the area (like
    a body force) and of the area-averaged displacement (the displacement of beam theory).

    Returns
    -------
    ndarray (N_dof, 3)
    """
    n, _, wdet, _ = element_geometry(mesh.nodes, mesh.cells, mesh.element_type, n_order)
    nodal = np.bincount(mesh.cells.ravel(), np.einsum("qa,eq->ea", n, wdet).ravel(),
                        minlength=mesh.n_nodes)
    nodal /= nodal.sum()
    p = np.zeros((3 * mesh.n_nodes, 3))
    for c in range(3):
        p[c::3, c] = nodal
    return p
