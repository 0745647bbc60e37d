"""Structured 20-node hexahedron meshes (boxes, annular discs) for tests and benchmarks.

Cells are in VTK / Abaqus C3D20 node order (docs/conventions.md).
"""

from __future__ import annotations

import numpy as np

from fe.hex20 import FACES, NODE_COORDS
from squealcore.errors import InputError, require_range


def _require_count(field, value, low):
    if isinstance(value, bool) or int(value) != value or value < low:
        raise InputError(field, f"must be an integer >= {low}, got {value!r}")
    return int(value)


def _structured_hex20(nx, ny, nz, periodic_z=False):
    """Topology of an nx x ny x nz block of hex20 elements on a half-spacing lattice.

    Returns the lattice indices (N, 3) of the nodes (each in [0, 2n], or [0, 2nz) if periodic
    in z) and the cells (E, 20) in VTK order. Lattice points with two or three odd indices
    (face and cell centres) are not nodes of the serendipity element.
    """
    mz = 2 * nz if periodic_z else 2 * nz + 1
    i, j, k = np.meshgrid(np.arange(2 * nx + 1), np.arange(2 * ny + 1), np.arange(mz), indexing="ij")
    lattice = np.column_stack([i.ravel(), j.ravel(), k.ravel()])
    keep = (lattice % 2).sum(axis=1) <= 1
    number = -np.ones(lattice.shape[0], dtype=np.int64)
    number[keep] = np.arange(keep.sum())
    ex, ey, ez = np.meshgrid(np.arange(nx), np.arange(ny), np.arange(nz), indexing="ij")
    base = 2 * np.column_stack([ex.ravel(), ey.ravel(), ez.ravel()])  # (E, 3)
    off = (NODE_COORDS + 1).astype(np.int64)  # (20, 3) in {0, 1, 2}
    idx = base[:, None, :] + off[None, :, :]  # (E, 20, 3)
    if periodic_z:
        idx[..., 2] %= mz
    flat = (idx[..., 0] * (2 * ny + 1) + idx[..., 1]) * mz + idx[..., 2]
    cells = number[flat]
    return lattice[keep], cells


def box_hex20(lx, ly, lz, nx, ny, nz, origin=(0.0, 0.0, 0.0)):
    """Structured mesh of a rectangular box with 20-node hexahedra.

    Parameters
    ----------
    lx, ly, lz : float
        Edge lengths along X, Y, Z in m (> 0).
    nx, ny, nz : int
        Number of elements along X, Y, Z (>= 1).
    origin : sequence of 3 floats, optional
        Corner with the smallest coordinates, in m.

    Returns
    -------
    nodes : ndarray, shape (N, 3)
        Node coordinates in m.
    cells : ndarray of int64, shape (nx*ny*nz, 20)
        Node indices in VTK / C3D20 order; the natural axes (xi, eta, zeta) are along (X, Y, Z).
    """
    lengths = np.array([require_range(f, v, 0.0, None, low_open=True, unit="m")
                        for f, v in (("lx", lx), ("ly", ly), ("lz", lz))])
    counts = [_require_count(f, v, 1) for f, v in (("nx", nx), ("ny", ny), ("nz", nz))]
    lattice, cells = _structured_hex20(*counts)
    h = lengths / (2 * np.array(counts))
    nodes = np.asarray(origin, dtype=float)[None, :] + lattice * h[None, :]
    return nodes, cells


def annulus_hex20(r_in, r_out, thickness, n_r, n_z, n_theta):
    """Structured mesh of an annular disc around the Y axis with 20-node hexahedra.

    A section point (r, z) at angle theta sits at (r sin theta, z, -r cos theta)
    (docs/conventions.md); z runs from 0 to ``thickness``. All nodes, including the mid-edge
    nodes, lie exactly on circles about the Y axis (the mid-edge nodes of circumferential edges
    are at the mid angle).

    Parameters
    ----------
    r_in, r_out : float
        Inner and outer radius in m (0 < r_in < r_out).
    thickness : float
        Axial thickness in m (> 0).
    n_r, n_z : int
        Elements through the radial depth and the thickness (>= 1).
    n_theta : int
        Elements around the circumference (>= 3).

    Returns
    -------
    nodes : ndarray, shape (N, 3)
        Node coordinates in m.
    cells : ndarray of int64, shape (n_r*n_z*n_theta, 20)
        Node indices in VTK / C3D20 order; natural axes (xi, eta, zeta) along (r, z, theta),
        which is right-handed, so Jacobians are positive.
    """
    r_in = require_range("r_in", r_in, 0.0, None, low_open=True, unit="m")
    r_out = require_range("r_out", r_out, r_in, None, low_open=True, unit="m")
    thickness = require_range("thickness", thickness, 0.0, None, low_open=True, unit="m")
    n_r = _require_count("n_r", n_r, 1)
    n_z = _require_count("n_z", n_z, 1)
    n_theta = _require_count("n_theta", n_theta, 3)
    lattice, cells = _structured_hex20(n_r, n_z, n_theta, periodic_z=True)
    r = r_in + lattice[:, 0] * (r_out - r_in) / (2 * n_r)
    z = lattice[:, 1] * thickness / (2 * n_z)
    theta = lattice[:, 2] * (2.0 * np.pi) / (2 * n_theta)
    nodes = np.column_stack([r * np.sin(theta), z, -r * np.cos(theta)])
    return nodes, cells


def boundary_nodes(cells):
    """Nodes on the boundary of a hex20 mesh (on faces that belong to one element only).

    Parameters
    ----------
    cells : array_like of int, shape (E, 20)
        Node indices in VTK / C3D20 order.

    Returns
    -------
    ndarray of int64
        Sorted indices of the boundary nodes.
    """
    cells = np.asarray(cells, dtype=np.int64)
    faces = cells[:, FACES].reshape(-1, 8)  # (6E, 8)
    key = np.sort(faces[:, :4], axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    outer = counts[inverse.ravel()] == 1
    return np.unique(faces[outer])


def distort_nodes(nodes, cells, amplitude, *, seed=0, interior_only=True):
    """Move nodes by random offsets (for patch tests on distorted meshes).

    Parameters
    ----------
    nodes : array_like, shape (N, 3)
        Node coordinates in m.
    cells : array_like of int, shape (E, 20)
        Node indices in VTK / C3D20 order.
    amplitude : float
        Largest offset per component in m (offsets uniform in [-amplitude, amplitude]).
    seed : int, optional
        Seed of the random generator (the result is reproducible).
    interior_only : bool, optional
        If True (default), boundary nodes (see :func:`boundary_nodes`) are not moved.

    Returns
    -------
    ndarray, shape (N, 3)
        The moved node coordinates in m. The caller must check that Jacobians stay positive
        (``fe.hex20.element_matrices`` raises if not).
    """
    amplitude = require_range("amplitude", amplitude, 0.0, None, unit="m")
    nodes = np.array(nodes, dtype=float)
    rng = np.random.default_rng(seed)
    move = np.ones(nodes.shape[0], dtype=bool)
    if interior_only:
        move[boundary_nodes(cells)] = False
    nodes[move] += rng.uniform(-amplitude, amplitude, size=(int(move.sum()), 3))
    return nodes
