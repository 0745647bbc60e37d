r"""Centrifugal prestress of a spinning wheel and the modal geometric stiffness it causes.

A wheel spinning at Ω about its axle (the Y axis, docs/conventions.md) carries the body force
``ρ Ω² r e_r = ρ Ω² (X, 0, Z)`` (N/m³). With the hub bore clamped, the static linear solution
``K u⁰ = f`` gives the prestress ``σ⁰ = C : ε(u⁰)``, proportional to Ω². All functions here
work at **Ω = 1 rad/s**; the caller scales by Ω².

The geometric (initial-stress) stiffness of mode shapes Φ_k under σ⁰ is

.. math::  K_{\sigma,kl} = \int \sigma^0_{ij}\, \frac{\partial \Phi_{k,m}}{\partial x_i}
           \frac{\partial \Phi_{l,m}}{\partial x_j}\, dV ,

the second variation of the work of σ⁰ on the Green–Lagrange strain. It is invariant under a
rotation of the basis, so it is evaluated in Cartesian components for the hex20 mesh and in
the local cylindrical basis (e_r, e_z, e_θ) for the axisymmetric section.

Quadrature: 3×3×3 Gauss points per hex20 and 3×3 per quad8 (the same points the modal
integrals of :mod:`fe.rotation` use, from :mod:`fe.quadrature`); stresses are evaluated at the points,
not smoothed.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.sparse.linalg as spla

from fe import hex20
from fe.assembly import apply_dirichlet, assemble_hex20, expand
from fe.axisymmetric import harmonic_matrices
from fe.cyclic import sector_layout, solve_cyclic_static
from fe.material import isotropic_elasticity
from fe.quadrature import hex20_quadrature_chunks, section_quadrature
from squealcore.errors import InputError, require_range

logger = logging.getLogger(__name__)


@dataclass(frozen=True)
class Prestress:
    """Centrifugal prestress at Ω = 1 rad/s.

    Attributes
    ----------
    stress : (E, G, 3, 3) ndarray
        Cauchy stress at the Gauss points (Pa per (rad/s)²): Cartesian (X, Y, Z) for hex20,
        (r, z, θ) for the axisymmetric section.
    displacement : (N, 3) ndarray
        Static nodal displacement (m per (rad/s)²): (X, Y, Z) or (U_r, U_z, U_θ).
    """

    stress: np.ndarray
    displacement: np.ndarray


def _lame(youngs_modulus, poisson_ratio):
    e = require_range("wheel.fe.youngs_modulus", youngs_modulus, 0.0, None, low_open=True, unit="Pa")
    nu = require_range("wheel.fe.poisson_ratio", poisson_ratio, -1.0, 0.5, low_open=True, high_open=True)
    return e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))


def _clamped(clamped_nodes, n_nodes):
    clamped = np.asarray(clamped_nodes, dtype=np.int64).ravel()
    if clamped.size == 0:
        raise InputError("wheel.fe.clamped_nodes", "the centrifugal static solve needs at least one clamped node")
    if clamped.min() < 0 or clamped.max() >= n_nodes:
        raise InputError("wheel.fe.clamped_nodes", f"node indices must lie in [0, {n_nodes - 1}]")
    return clamped


def _stress_from_gradient(grad, lam, mu):
    eps = 0.5 * (grad + np.swapaxes(grad, -1, -2))
    tr = np.trace(eps, axis1=-2, axis2=-1)
    return lam * tr[..., None, None] * np.eye(3) + 2.0 * mu * eps


def prestress_hex20(nodes, cells, clamped_nodes, youngs_modulus, poisson_ratio, density, chunk_size=256,
                    n_sectors=None):
    """Centrifugal prestress of a hex20 mesh at Ω = 1 rad/s (hub clamped).

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m.
    cells : (E, 20) int ndarray
        VTK hex20 order.
    clamped_nodes : (c,) int ndarray
        Nodes with all displacements fixed (non-empty).
    youngs_modulus, poisson_ratio, density : float
        Pa, -, kg/m³.
    chunk_size : int
        Elements per vectorised chunk.
    n_sectors : int, optional
        Revolve steps of the mesh: solve the static problem on one sector by cyclic symmetry
        (fe/cyclic.py; the load is the same in every sector) instead of the full matrices.

    Returns
    -------
    Prestress
        Stress (E, 27, 3, 3) Cartesian, displacement (N, 3).
    """
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells)
    rho = require_range("wheel.fe.density", density, 0.0, None, low_open=True, unit="kg/m^3")
    lam, mu = _lame(youngs_modulus, poisson_ratio)
    clamped = _clamped(clamped_nodes, nodes.shape[0])
    d = isotropic_elasticity(youngs_modulus, poisson_ratio, prefix="wheel.fe.")
    pts, wts = hex20.gauss_points(3)
    n_shape = hex20.shape_functions(pts)

    def element_loads(load_cells):
        xe = nodes[load_cells]
        jac = np.einsum("gai,eaj->egij", hex20.shape_derivatives(pts), xe)
        wdet = np.linalg.det(jac) * wts[None, :]
        pos = np.einsum("ga,eaj->egj", n_shape, xe)
        body = rho * pos * np.array([1.0, 0.0, 1.0])  # ρ r e_r at Ω = 1 rad/s, N/m³
        return np.einsum("ga,eg,egc->eac", n_shape, wdet, body)

    if n_sectors:
        sector_cells = sector_layout(nodes, cells, n_sectors)["cells"]
        u = solve_cyclic_static(nodes, cells, clamped, n_sectors, d, element_loads(sector_cells))
    else:
        k, m = assemble_hex20(nodes, cells, d, rho)
        load = np.zeros(3 * nodes.shape[0])
        np.add.at(load, (3 * cells[:, :, None] + np.arange(3)).ravel(), element_loads(cells).ravel())
        fixed = (3 * clamped[:, None] + np.arange(3)).ravel()
        k_ff, _, free = apply_dirichlet(k, m, fixed)
        u = expand(spla.spsolve(k_ff.tocsc(), load[free], permc_spec="MMD_AT_PLUS_A"), free,
                   load.size).reshape(-1, 3)
    stress = np.empty((cells.shape[0], pts.shape[0], 3, 3))
    for start, stop, _, _, _, grad in hex20_quadrature_chunks(nodes, cells, u[None], chunk_size):
        stress[start:stop] = _stress_from_gradient(grad[0], lam, mu)
    logger.info("centrifugal prestress (hex20, 1 rad/s): max |u| %.3e m, max |sigma| %.3e Pa",
                np.abs(u).max(), np.abs(stress).max())
    return Prestress(stress, u)


def prestress_axisymmetric(section_nodes, section_cells, clamped_nodes, youngs_modulus, poisson_ratio, density):
    """Centrifugal prestress of a body of revolution at Ω = 1 rad/s (harmonic n = 0, hub clamped).

    Parameters
    ----------
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    section_cells : (Es, 8) int ndarray
        VTK quad8 order.
    clamped_nodes : (c,) int ndarray
        Section nodes fixed all around (non-empty).
    youngs_modulus, poisson_ratio, density : float
        Pa, -, kg/m³.

    Returns
    -------
    Prestress
        Stress (Es, 9, 3, 3) in the basis (e_r, e_z, e_θ) (σ_rθ = σ_zθ = 0), displacement
        (Ns, 3) as (U_r, U_z, U_θ = 0).
    """
    nodes = np.asarray(section_nodes, dtype=float)
    cells = np.asarray(section_cells)
    rho = require_range("wheel.fe.density", density, 0.0, None, low_open=True, unit="kg/m^3")
    lam, mu = _lame(youngs_modulus, poisson_ratio)
    clamped = _clamped(clamped_nodes, nodes.shape[0])
    k, _ = harmonic_matrices(nodes, cells, 0, youngs_modulus, poisson_ratio, density)
    n_shape, dn_dx, radius, w_rda = section_quadrature(nodes, cells)
    # U_r load: ∫ ρ r N_a dV = 2π ∫ ρ r N_a r dA
    f_e = 2.0 * np.pi * rho * np.einsum("ga,eg->ea", n_shape, w_rda * radius)
    load = np.zeros(3 * nodes.shape[0])
    np.add.at(load, 3 * cells.ravel(), f_e.ravel())
    comp = np.arange(load.size) % 3
    fixed = np.zeros(load.size, dtype=bool)
    fixed[(3 * clamped[:, None] + np.arange(3)).ravel()] = True
    free = np.nonzero(~fixed & (comp < 2))[0]
    k = k.tocsr()
    u = np.zeros(load.size)
    u[free] = spla.spsolve(k[free][:, free].tocsc(), load[free])
    u = u.reshape(-1, 3)
    ue = u[cells]  # (E, 8, 3)
    ur = np.einsum("ga,ea->eg", n_shape, ue[..., 0])
    d_u = np.einsum("egaj,eac->egcj", dn_dx, ue)  # (E, G, 3, 2): ∂(U_r, U_z, U_θ)/∂(r, z)
    grad = np.zeros(ur.shape + (3, 3))
    grad[..., 0, 0] = d_u[..., 0, 0]
    grad[..., 0, 1] = d_u[..., 0, 1]
    grad[..., 1, 0] = d_u[..., 1, 0]
    grad[..., 1, 1] = d_u[..., 1, 1]
    grad[..., 2, 2] = ur / radius
    stress = _stress_from_gradient(grad, lam, mu)
    logger.info("centrifugal prestress (axisymmetric, 1 rad/s): max |u_r| %.3e m, max |sigma| %.3e Pa",
                np.abs(u[:, 0]).max(), np.abs(stress).max())
    return Prestress(stress, u)


def geometric_stiffness(gradient, stress, weight):
    """Modal geometric stiffness ``Σ_points w σ_ij G_k[m, i] G_l[m, j]``.

    Parameters
    ----------
    gradient : (k, e, G, 3, 3) ndarray
        Mode gradients ``G[..., m, i] = ∂Φ_m/∂x_i`` at the points (1/√kg).
    stress : (e, G, 3, 3) ndarray
        Prestress in the same basis (Pa).
    weight : (e, G) ndarray
        Integration weights (m³).

    Returns
    -------
    (k, k) ndarray
        K_σ contribution (N/m · m²/kg = 1/s² per (rad/s)² of spin).
    """
    k = gradient.shape[0]
    t = np.einsum("kegmi,egij->kegmj", gradient, stress * weight[..., None, None], optimize=True)
    return t.reshape(k, -1) @ gradient.reshape(k, -1).T
