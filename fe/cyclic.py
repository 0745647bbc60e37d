r"""Modes of a revolved hex20 mesh by cyclic symmetry: the same 3D model, solved sector by sector.

A mesh made by revolving a section through ``N`` equal steps (mesh/wheel_mesh.py) consists of
``N`` identical sectors, each the previous one turned by ``Δ = 2π/N`` about the axle. Its
stiffness and mass matrices are then block-circulant, and every mode is a travelling-wave
(Bloch) mode of one harmonic ``n`` (0 ≤ n ≤ N/2):

.. math::

    u(\theta + \Delta) = e^{i n \Delta} R(\Delta)\, u(\theta),

where ``R(Δ)`` turns Cartesian vectors by ``Δ`` about the axle (Cartesian components turn with
the sector). With the DOFs of one sector split into interior ``I``, left face ``L`` (θ = 0) and
right face ``R`` (θ = Δ, shared with the next sector), ``u_R = e^{inΔ} R u_L`` and the sector's
matrices reduce to the Hermitian pair ``P^H K_s P``, ``P^H M_s P`` with
``P = [[1, 0], [0, 1], [0, e^{inΔ} R]]``. Each reduced problem is small and is solved
by :func:`fe.eigen.solve_modes` (Sturm count check: no mode in the band is missed). The eigenvalues are exactly those of the full
3D problem of the same mesh (tested against :func:`fe.eigen.solve_modes` on the full matrices).

Real mode shapes: for ``0 < n < N/2`` each complex mode gives the degenerate pair
``Re U`` and ``Im U``; for ``n = 0`` and ``n = N/2`` the modes are real. Shapes are
mass-normalised over the whole wheel.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fe.assembly import assemble, nodal_dofmap
from fe.eigen import solve_modes
from fe.hex20 import element_matrices

logger = logging.getLogger(__name__)


def rotation(angle):
    """Matrix turning Cartesian vectors by ``angle`` (rad) about the axle (Y), θ increasing.

    With a point at ``(r sin θ, z, −r cos θ)`` (docs/conventions.md), ``R e_r(θ) = e_r(θ + angle)``.
    """
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])


def sector_layout(nodes, cells, n_sectors, tolerance=1e-9):
    """Find the first sector of a revolved mesh and how every node maps onto it.

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m, axle = Y, θ = atan2(X, −Z).
    cells : (E, 20) int ndarray
    n_sectors : int
        Number of revolve steps.
    tolerance : float
        Relative tolerance on angles and positions.

    Returns
    -------
    dict
        ``cells`` (Es, 20) cells of sector 0; ``left`` / ``right`` node ids of its faces
        (``right[k]`` is ``left[k]`` turned by Δ); ``interior`` its other node ids;
        ``node_sector`` (N,) sector index k and ``node_base`` (N,) the sector-0 node that
        turned by ``kΔ`` gives each node.
    """
    delta = 2 * np.pi / n_sectors
    theta = np.mod(np.arctan2(nodes[:, 0], -nodes[:, 2]) + tolerance, 2 * np.pi) - tolerance
    position = theta / delta
    sector = np.floor(position + tolerance).astype(int) % n_sectors
    first = np.all((position[cells] > -tolerance) & (position[cells] < 1 + tolerance), axis=1)
    sector_cells = cells[first]
    if len(sector_cells) * n_sectors != len(cells):
        raise ValueError(f"mesh is not {n_sectors} identical sectors ({len(sector_cells)} cells in sector 0 "
                         f"of {len(cells)})")
    sector_nodes = np.unique(sector_cells)
    pos = position[sector_nodes]
    left = sector_nodes[np.abs(pos) < tolerance]
    right_all = sector_nodes[np.abs(pos - 1) < tolerance]
    interior = np.setdiff1d(sector_nodes, np.concatenate([left, right_all]))
    # base node of every node: turn it back by its sector's angle and find the sector-0 node
    turned = np.einsum("nij,nj->ni", np.stack([rotation(-k * delta) for k in range(n_sectors)])[sector], nodes)
    candidates = np.concatenate([left, interior])
    scale = np.abs(nodes).max()
    key = lambda xyz: np.round(xyz / (tolerance * 1e3 * scale)).astype(np.int64)  # noqa: E731
    lookup = {tuple(k): n for k, n in zip(key(nodes[candidates]), candidates)}
    try:
        base = np.array([lookup[tuple(k)] for k in key(turned)])
    except KeyError:
        raise ValueError("mesh nodes are not the revolution of one sector") from None
    # pair right-face nodes with left-face nodes: right node turned back by Δ is a left node
    back = key((rotation(-delta) @ nodes[right_all].T).T)
    left_of_right = np.array([lookup[tuple(k)] for k in back])
    order = np.argsort(left_of_right)
    left_sorted = left_of_right[order]
    if not np.array_equal(np.sort(left), left_sorted):
        raise ValueError("left and right faces of the sector do not match")
    return {"cells": sector_cells, "left": left_sorted, "right": right_all[order], "interior": interior,
            "node_sector": sector, "node_base": base, "n_sectors": n_sectors}


def _sector_system(nodes, layout, clamped_nodes, elasticity, density):
    """Sector matrices and the DOF partition of the cyclic reduction.

    Returns
    -------
    K, M : sparse matrices over all DOFs (only sector 0's cells assembled).
    every : (n,) int ndarray
        Free sector DOFs ordered interior, left face, right face.
    n_interior, n_left : int
        Lengths of the first two groups.
    rotation_blocks : scipy.sparse matrix
        ``R(Δ)`` for every right-face node (the constraint ``u_R = e^{inΔ} R u_L``).
    """
    ke, me = element_matrices(nodes, layout["cells"], elasticity, density)
    K, M = assemble(ke, me, nodal_dofmap(layout["cells"], 3), 3 * len(nodes))
    clamped = set(np.asarray(clamped_nodes).tolist())
    keep_i = np.array([n for n in layout["interior"] if n not in clamped], dtype=int)
    pairs = [(left, right) for left, right in zip(layout["left"], layout["right"]) if left not in clamped]
    keep_l = np.array([p[0] for p in pairs], dtype=int)
    keep_r = np.array([p[1] for p in pairs], dtype=int)

    def dofs(ids):
        return (3 * ids[:, None] + np.arange(3)).ravel()

    every = np.concatenate([dofs(keep_i), dofs(keep_l), dofs(keep_r)])
    n_sectors = layout["n_sectors"]
    rotation_blocks = sp.block_diag([rotation(2 * np.pi / n_sectors)] * len(keep_r))
    return K, M, every, 3 * len(keep_i), 3 * len(keep_l), rotation_blocks


def _bloch_projection(n_interior, n_left, rotation_blocks, phase):
    """``P = [[1, 0], [0, 1], [0, phase R]]`` mapping (interior, left) DOFs to (interior, left, right)."""
    n_right = rotation_blocks.shape[0]
    n_ind = n_interior + n_left
    return sp.bmat([[sp.identity(n_ind, dtype=complex)],
                    [sp.hstack([sp.csr_matrix((n_right, n_interior)), phase * rotation_blocks])]]).tocsr()


def solve_cyclic(nodes, cells, clamped_nodes, n_sectors, elasticity, density, f_max, n_max=None):
    """All modes below ``f_max`` of a revolved hex20 mesh, harmonic by harmonic.

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m.
    cells : (E, 20) int ndarray
        VTK hex20 order.
    clamped_nodes : (c,) int ndarray
        Nodes with all displacements fixed (must be a revolved set).
    n_sectors : int
        Revolve steps of the mesh (``elements_around``).
    elasticity : (6, 6) ndarray
        Pa.
    density : float
        kg/m³.
    f_max : float
        Hz.
    n_max : int, optional
        Highest harmonic; default: stop after three consecutive harmonics (from n = 2 on)
        without a mode below ``f_max``.

    Returns
    -------
    frequency : (m,) ndarray
        Hz, ascending.
    shapes : (m, N, 3) ndarray
        Cartesian, mass-normalised over the whole mesh, m/√kg.
    harmonic : (m,) int ndarray
    """
    layout = sector_layout(nodes, cells, n_sectors)
    K, M, every, n_interior, n_left, R = _sector_system(nodes, layout, clamped_nodes, elasticity, density)
    Ks = K[every][:, every].tocsr()
    Ms = M[every][:, every].tocsr()
    delta = 2 * np.pi / n_sectors
    top = n_sectors // 2 if n_max is None else min(n_max, n_sectors // 2)
    results = []
    empty_run = 0
    for n in range(top + 1):
        P = _bloch_projection(n_interior, n_left, R, np.exp(1j * n * delta))
        Kn = (P.conj().T @ Ks @ P).tocsc()
        Mn = (P.conj().T @ Ms @ P).tocsc()
        lam_hz, vec = solve_modes(0.5 * (Kn + Kn.conj().T), 0.5 * (Mn + Mn.conj().T), f_max)
        logger.debug("harmonic %d: %d modes below %.0f Hz", n, lam_hz.size, f_max)
        if lam_hz.size:
            results.append((n, (2 * np.pi * lam_hz) ** 2, P @ vec))
            empty_run = 0
        elif n >= 2:
            empty_run += 1
            if n_max is None and empty_run >= 3:
                break
    logger.info("cyclic hex20: %d sector DOF, harmonics 0..%d", n_interior + n_left, n)
    return _expand(nodes, layout, every, results, n_sectors)


def _expand(nodes, layout, every, results, n_sectors):
    """Full real mass-normalised shapes from the sector's complex Bloch modes."""
    delta = 2 * np.pi / n_sectors
    n_nodes = len(nodes)
    # sector-0 complex displacement on every node of sector 0, then turned copies
    index = np.full(3 * n_nodes, -1)
    index[every] = np.arange(len(every))
    sector = layout["node_sector"]
    base = layout["node_base"]
    turns = np.stack([rotation(k * delta) for k in range(n_sectors)])[sector]  # (N, 3, 3)
    freqs, shapes, harmonics = [], [], []
    for n, lam, vectors in results:
        phase = np.exp(1j * n * delta * sector)  # (N,)
        for j in range(lam.size):
            v = np.zeros(3 * n_nodes, dtype=complex)
            v[every] = vectors[:, j]
            local = v.reshape(-1, 3)[base]  # displacement of the base node (sector 0 frame)
            full = phase[:, None] * np.einsum("nij,nj->ni", turns, local)
            f = np.sqrt(max(lam[j], 0.0)) / (2 * np.pi)
            if n == 0 or 2 * n == n_sectors:
                real = full.real if np.abs(full.real).max() >= np.abs(full.imag).max() else full.imag
                norm = np.sqrt(_mass_ratio(real, full, n_sectors))
                shapes.append(real / norm)
                freqs.append(f)
                harmonics.append(n)
            else:
                for part in (full.real, full.imag):
                    shapes.append(part * np.sqrt(2.0 / n_sectors))
                    freqs.append(f)
                    harmonics.append(n)
    order = np.argsort(freqs, kind="stable")
    return np.asarray(freqs)[order], np.asarray(shapes)[order], np.asarray(harmonics)[order]


def _mass_ratio(real, full, n_sectors):
    """Mass of the real part relative to a unit-mass sector mode (n = 0 or N/2: real modes).

    The complex mode has mass 1 per sector, i.e. N in all; its real part carries
    ``N |Re|² / (|Re|² + |Im|²)`` of it.
    """
    re2 = np.sum(full.real**2)
    im2 = np.sum(full.imag**2)
    chosen = np.sum(real**2)
    return n_sectors * chosen / (re2 + im2)


def solve_cyclic_static(nodes, cells, clamped_nodes, n_sectors, elasticity, sector_loads):
    """Static displacement of a revolved hex20 mesh under a load that is the same in every sector.

    Such a load (e.g. the centrifugal body force) excites only harmonic 0, so the solution is
    the revolution of one sector's: ``(P^H K_s P) q = P^H f_s`` with the n = 0 constraint of
    :func:`solve_cyclic`. Equal to the full solve of the same matrices (tested).

    Parameters
    ----------
    nodes, cells, clamped_nodes, n_sectors, elasticity
        As :func:`solve_cyclic`.
    sector_loads : (Es, 20, 3) ndarray
        Consistent nodal loads (N) of the cells of sector 0, in the order of
        ``sector_layout(...)["cells"]``.

    Returns
    -------
    (N, 3) ndarray
        Displacement, m.
    """
    layout = sector_layout(nodes, cells, n_sectors)
    K, _, every, n_interior, n_left, R = _sector_system(nodes, layout, clamped_nodes, elasticity, 1.0)
    load = np.zeros(3 * len(nodes))
    np.add.at(load, (3 * layout["cells"][:, :, None] + np.arange(3)).ravel(), np.asarray(sector_loads).ravel())
    P = _bloch_projection(n_interior, n_left, R, 1.0).real
    Ks = K[every][:, every]
    q = spla.spsolve((P.T @ Ks @ P).tocsc(), P.T @ load[every])
    sector_u = np.zeros(3 * len(nodes))
    sector_u[every] = P @ q
    base = sector_u.reshape(-1, 3)[layout["node_base"]]
    turns = np.stack([rotation(k * 2 * np.pi / n_sectors) for k in range(n_sectors)])[layout["node_sector"]]
    return np.einsum("nij,nj->ni", turns, base)
