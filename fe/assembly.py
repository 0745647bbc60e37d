"""Sparse assembly of element matrices, Dirichlet constraints and global helpers.

The assembly works on any element type given its element matrices (E, nd, nd) and per-element
DOF maps (E, nd) into the global DOF vector, so the 3D hexahedron and the axisymmetric element
share it. Global DOF numbering: ``dof = 3 * node + component``.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp

from fe.hex20 import element_matrices
from squealcore.errors import InputError

logger = logging.getLogger(__name__)


def nodal_dofmap(cells, dofs_per_node=3):
    """Element DOF maps for elements whose nodes all carry the same DOFs.

    Parameters
    ----------
    cells : array_like of int, shape (E, n)
        Node indices of each element.
    dofs_per_node : int, optional
        DOFs per node (default 3).

    Returns
    -------
    ndarray of int64, shape (E, n * dofs_per_node)
        ``dofmap[e, dofs_per_node * a + c] = dofs_per_node * cells[e, a] + c``.
    """
    cells = np.asarray(cells, dtype=np.int64)
    k = int(dofs_per_node)
    return (k * cells[:, :, None] + np.arange(k)[None, None, :]).reshape(cells.shape[0], -1)


def _assemble_one(ae, rows, cols, ndof):
    mat = sp.coo_matrix((ae.ravel(), (rows, cols)), shape=(ndof, ndof))
    return mat.tocsr()  # sums duplicate entries


def assemble(Ke, Me, dofmap, ndof=None):
    """Assemble element matrices into global sparse matrices.

    Parameters
    ----------
    Ke, Me : ndarray, shape (E, nd, nd)
        Element stiffness (N/m) and mass (kg) matrices; ``Me`` may be None.
    dofmap : array_like of int, shape (E, nd)
        Global DOF index of each element DOF (see :func:`nodal_dofmap`).
    ndof : int, optional
        Number of global DOFs (default ``dofmap.max() + 1``).

    Returns
    -------
    K, M : scipy.sparse.csr_matrix, shape (ndof, ndof)
        Global stiffness and mass matrices (``M`` is None if ``Me`` is None).
    """
    dofmap = np.asarray(dofmap)
    Ke = np.asarray(Ke)
    n_el, nd = dofmap.shape
    if Ke.shape != (n_el, nd, nd) or (Me is not None and np.shape(Me) != (n_el, nd, nd)):
        raise ValueError(f"element matrices must have shape {(n_el, nd, nd)} to match dofmap")
    if ndof is None:
        ndof = int(dofmap.max()) + 1 if dofmap.size else 0
    if dofmap.size and (dofmap.min() < 0 or dofmap.max() >= ndof):
        raise ValueError(f"dofmap entries must lie in [0, {ndof - 1}]")
    idx = np.int32 if ndof < 2**31 - 1 else np.int64
    dm = dofmap.astype(idx, copy=False)
    rows = np.repeat(dm, nd, axis=1).ravel()
    cols = np.tile(dm, (1, nd)).ravel()
    K = _assemble_one(Ke, rows, cols, ndof)
    M = None if Me is None else _assemble_one(np.asarray(Me), rows, cols, ndof)
    logger.debug("assembled %d elements x %d DOFs into %d global DOFs (nnz %d)", n_el, nd, ndof, K.nnz)
    return K, M


def assemble_hex20(nodes, cells, D, density, *, chunk_size=512):
    """Element matrices of a 20-node hexahedron mesh and their global assembly.

    Parameters
    ----------
    nodes : array_like, shape (N, 3)
        Node coordinates in m.
    cells : array_like of int, shape (E, 20)
        Node indices in VTK / C3D20 order.
    D : array_like, shape (6, 6)
        Elasticity matrix in Pa (see :func:`fe.material.isotropic_elasticity`).
    density : float or array_like, shape (E,)
        Density in kg/m^3.
    chunk_size : int, optional
        Elements per vectorised chunk.

    Returns
    -------
    K, M : scipy.sparse.csr_matrix, shape (3N, 3N)
        Global stiffness (N/m) and consistent mass (kg) matrices.
    """
    nodes = np.asarray(nodes, dtype=float)
    ke, me = element_matrices(nodes, cells, D, density, chunk_size=chunk_size)
    return assemble(ke, me, nodal_dofmap(cells, 3), 3 * nodes.shape[0])


def apply_dirichlet(K, M, fixed_dofs):
    """Remove fixed (zero-displacement) DOFs from K and M.

    Parameters
    ----------
    K, M : scipy.sparse matrix, shape (ndof, ndof)
        Global stiffness and mass matrices.
    fixed_dofs : array_like of int
        Global indices of the DOFs held at zero (duplicates allowed).

    Returns
    -------
    K_ff, M_ff : scipy.sparse.csr_matrix, shape (nfree, nfree)
        Matrices restricted to the free DOFs.
    free_dofs : ndarray of int64, shape (nfree,)
        Global indices of the free DOFs, ascending.
    """
    ndof = K.shape[0]
    fixed = np.asarray(fixed_dofs, dtype=np.int64).ravel()
    if fixed.size and (fixed.min() < 0 or fixed.max() >= ndof):
        raise InputError("fixed_dofs", f"DOF indices must lie in [0, {ndof - 1}]")
    mask = np.ones(ndof, dtype=bool)
    mask[fixed] = False
    free = np.nonzero(mask)[0]
    K = sp.csr_matrix(K)
    M = sp.csr_matrix(M)
    return K[free][:, free], M[free][:, free], free


def expand(shapes_free, free_dofs, ndof):
    """Put vectors on the free DOFs back into full-length vectors (zeros at fixed DOFs).

    Parameters
    ----------
    shapes_free : ndarray, shape (nfree,) or (nfree, m)
        Vectors (e.g. mode shapes) on the free DOFs.
    free_dofs : array_like of int, shape (nfree,)
        Global indices of the free DOFs.
    ndof : int
        Total number of DOFs.

    Returns
    -------
    ndarray, shape (ndof,) or (ndof, m)
        Full vectors, zero at the fixed DOFs.
    """
    shapes_free = np.asarray(shapes_free)
    out = np.zeros((ndof,) + shapes_free.shape[1:], dtype=shapes_free.dtype)
    out[np.asarray(free_dofs)] = shapes_free
    return out


def rigid_body_vectors(nodes):
    """The six rigid-body displacement fields of a 3D node set.

    Parameters
    ----------
    nodes : array_like, shape (N, 3)
        Node coordinates in m.

    Returns
    -------
    ndarray, shape (3N, 6)
        Columns: unit translations along X, Y, Z (m), then small rotations about X, Y, Z
        through the origin (m per rad), DOF order ``3 * node + component``.
    """
    x = np.asarray(nodes, dtype=float)
    n = x.shape[0]
    r = np.zeros((n, 3, 6))
    r[:, [0, 1, 2], [0, 1, 2]] = 1.0
    # rotation theta about axis k: u = theta e_k x r
    r[:, 1, 3], r[:, 2, 3] = -x[:, 2], x[:, 1]
    r[:, 0, 4], r[:, 2, 4] = x[:, 2], -x[:, 0]
    r[:, 0, 5], r[:, 1, 5] = -x[:, 1], x[:, 0]
    return r.reshape(3 * n, 6)


def total_mass(M, dofs_per_node=3):
    """Total mass represented by a consistent mass matrix.

    Computed as ``u.T @ M @ u`` for a unit rigid translation ``u`` along each component.

    Parameters
    ----------
    M : scipy.sparse matrix or ndarray, shape (ndof, ndof)
        Global mass matrix in kg (full, before constraints).
    dofs_per_node : int, optional
        DOFs per node (default 3).

    Returns
    -------
    ndarray, shape (dofs_per_node,)
        Mass in kg seen by a translation along each component (all equal for a 3D solid).
    """
    ndof = M.shape[0]
    out = np.empty(dofs_per_node)
    for c in range(dofs_per_node):
        u = np.zeros(ndof)
        u[c::dofs_per_node] = 1.0
        out[c] = u @ (M @ u)
    return out
