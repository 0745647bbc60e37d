"""Waveguide (2.5D, SAFE) matrices of the rail cross-section.

Displacement ``u(x, y, z, t) = U(y, z) exp(i (omega t - kappa x))`` with 3 DOF per node
(u_x, u_y, u_z; ``dof = 3 * node + component``). The stiffness is
``K(kappa) = K0 + i kappa K1 + kappa^2 K2`` with K1 skew-symmetric. Multiplying the axial DOF
by i (``U = T V``, ``T = diag(i, 1, 1)``) and the equations by ``T^H`` gives the real symmetric
form ``K0 + kappa K1s + kappa^2 K2`` with ``K1s = K1 S`` (``S`` flips the sign of the x
columns); :func:`assemble` returns that form.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import scipy.sparse as sp

from fe.material import isotropic_elasticity

from waveguide.shape import element_geometry

logger = logging.getLogger(__name__)

__all__ = ["WaveguideMatrices", "assemble"]


@dataclasses.dataclass(frozen=True)
class WaveguideMatrices:
    """Sparse real matrices (N = 3 n_nodes) of the rail without support and without damping.

    ``K0`` (N/m per m), ``K1s`` (N per m, symmetric form), ``K2`` (N), ``M`` (kg/m). The rail
    damping enters as the factor (1 + i loss_factor) on K0, K1s, K2.
    """

    K0: sp.csr_matrix
    K1s: sp.csr_matrix
    K2: sp.csr_matrix
    M: sp.csr_matrix


def _assemble_blocks(cells, blocks, n_dof):
    e, m, _ = blocks.shape
    dofs = (3 * cells[:, :, None] + np.arange(3)).reshape(e, -1)
    rows = np.repeat(dofs, m, axis=1).ravel()
    cols = np.tile(dofs, (1, m)).ravel()
    return sp.csr_matrix((blocks.ravel(), (rows, cols)), shape=(n_dof, n_dof))


def assemble(mesh, youngs_modulus: float, poisson_ratio: float, density: float | None = None):
    """Assemble the waveguide matrices of a meshed section, vectorised over elements.

    Parameters
    ----------
    mesh : mesh.rail_mesh.RailMesh
    youngs_modulus : float
        E (Pa), real; the loss factor is applied by the caller.
    poisson_ratio : float
    density : float, optional
        kg/m^3, defaults to ``mesh.density``.

    Returns
    -------
    WaveguideMatrices
    """
    rho = mesh.density if density is None else density
    n, dn, wdet, _ = element_geometry(mesh.nodes, mesh.cells, mesh.element_type, order=3)
    e, q, nn, _ = dn.shape
    d = isotropic_elasticity(youngs_modulus, poisson_ratio, prefix="track.")
    b1 = np.zeros((e, q, 6, nn, 3))
    dy, dz = dn[..., 0], dn[..., 1]
    b1[:, :, 1, :, 1] = dy  # eps_yy
    b1[:, :, 2, :, 2] = dz  # eps_zz
    b1[:, :, 3, :, 1] = dz  # gamma_yz
    b1[:, :, 3, :, 2] = dy
    b1[:, :, 4, :, 0] = dz  # gamma_xz (d/dz part)
    b1[:, :, 5, :, 0] = dy  # gamma_xy (d/dy part)
    b1 = b1.reshape(e, q, 6, 3 * nn)
    b2 = np.zeros((q, 6, nn, 3))  # coefficients of d/dx
    b2[:, 0, :, 0] = n
    b2[:, 4, :, 2] = n
    b2[:, 5, :, 1] = n
    b2 = b2.reshape(q, 6, 3 * nn)
    db1 = np.einsum("ij,eqjk->eqik", d, b1)
    k0 = np.einsum("eqik,eqil,eq->ekl", b1, db1, wdet)
    k1 = np.einsum("qik,eqil,eq->ekl", b2, db1, wdet)
    k1 = k1 - np.transpose(k1, (0, 2, 1))  # B2^T D B1 - B1^T D B2
    k2 = np.einsum("qik,ij,qjl,eq->ekl", b2, d, b2, wdet)
    nm = np.einsum("qa,qb,eq->eab", n, n, wdet) * rho
    m = np.zeros((e, nn, 3, nn, 3))
    for c in range(3):
        m[:, :, c, :, c] = nm
    m = m.reshape(e, 3 * nn, 3 * nn)
    # symmetric form: flip the sign of the x columns of K1
    sx = np.tile([-1.0, 1.0, 1.0], nn)
    k1s = k1 * sx[None, None, :]
    ndof = 3 * mesh.n_nodes
    mats = WaveguideMatrices(*(_assemble_blocks(mesh.cells, b, ndof) for b in (k0, k1s, k2, m)))
    logger.info("waveguide matrices: %d DOF", ndof)
    return mats
