"""Axisymmetric harmonic (Fourier) finite element of a body of revolution and its modal solver.

The body is the revolution of a cross-section in the (r, z) half plane about the z axis (the
axle). The section is meshed with 8-node serendipity quadrilaterals (:mod:`fe.quad8`). For
the harmonic ``n`` the displacement is (``docs/conventions.md``)

* family ``"cos"``: ``u_r = U_r cos n th``, ``u_z = U_z cos n th``, ``u_th = U_th sin n th``;
* family ``"sin"``: ``u_r = U_r sin n th``, ``u_z = U_z sin n th``, ``u_th = -U_th cos n th``,

with nodal amplitudes ``(U_r, U_z, U_th)`` (3 DOF per node, ``dof = 3 * node + component``).
Both families give the same stiffness and mass matrices. The strains of linear elasticity in
cylindrical coordinates, ordered ``(e_rr, e_zz, e_thth, g_rz, g_rth, g_zth)`` (engineering
shears), become for the ``"cos"`` family

* ``e_rr = U_r,r cos``, ``e_zz = U_z,z cos``, ``e_thth = (U_r + n U_th) / r cos``,
  ``g_rz = (U_r,z + U_z,r) cos``,
* ``g_rth = (-n U_r / r + U_th,r - U_th / r) sin``, ``g_zth = (-n U_z / r + U_th,z) sin``.

The circumferential integral is done analytically: ``int cos^2 = int sin^2 = pi`` for
``n >= 1``. For ``n = 0`` the matrices are those of the fields ``(U_r, U_z, U_th)`` constant
around the circumference (factor ``2 pi``): the (r, z) part (family ``"cos"``) and the
torsional ``U_th`` part (family ``"sin"``, ``u_th = -U_th``) are then decoupled. With this
factor ``K`` and ``M`` are the stiffness and mass of the whole 3D body for that harmonic,
so ``phi^T M phi = 1`` means ``int rho |u|^2 dV = 1`` over the 3D body.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from fe.material import isotropic_elasticity
from squealcore.errors import InputError, require_range

from . import quad8

logger = logging.getLogger(__name__)

#: Free-DOF count up to which the dense generalised eigensolver is used.
DENSE_LIMIT = 1200
#: Highest harmonic the automatic choice of ``n_max`` may reach.
N_MAX_CAP = 400

_FAMILIES = ("cos", "sin")


@dataclass(frozen=True)
class AxisymmetricModes:
    """Modes of a body of revolution from the harmonic element.

    Attributes
    ----------
    frequency : ndarray, shape (m,)
        Natural frequencies (Hz), ascending.
    harmonic : ndarray of int, shape (m,)
        Harmonic number ``n`` (number of nodal diameters) of each mode.
    family : ndarray of str, shape (m,)
        ``"cos"`` or ``"sin"``. For ``n >= 1`` both members of each degenerate pair are listed
        (identical frequency and amplitudes). For ``n = 0`` each mode is listed once:
        ``"cos"`` for the (r, z) modes, ``"sin"`` for the torsional ``u_th`` modes.
    shapes : ndarray, shape (m, N, 3)
        Nodal amplitudes ``(U_r, U_z, U_th)`` (m per sqrt(kg)), mass-normalised over the whole
        3D body; zero at clamped nodes.
    n_max : int
        Highest harmonic that was solved.
    """

    frequency: np.ndarray
    harmonic: np.ndarray
    family: np.ndarray
    shapes: np.ndarray
    n_max: int


# --------------------------------------------------------------------------- input checks


def _check_mesh(nodes_rz, cells):
    nodes = np.asarray(nodes_rz, dtype=float)
    if nodes.ndim != 2 or nodes.shape[1] != 2 or nodes.shape[0] < 8:
        raise InputError("fe.nodes_rz", f"must have shape (N >= 8, 2), got {nodes.shape}")
    if not np.all(np.isfinite(nodes)):
        raise InputError("fe.nodes_rz", "must be finite")
    if np.any(nodes[:, 0] <= 0.0):
        raise InputError(
            "fe.nodes_rz",
            f"radii must lie in (0, inf) m (sections touching the axis are not supported), "
            f"got min r = {nodes[:, 0].min():g}",
        )
    cells_arr = np.asarray(cells)
    if cells_arr.ndim != 2 or cells_arr.shape[1] != 8 or cells_arr.shape[0] < 1:
        raise InputError("fe.cells", f"must have shape (E >= 1, 8), got {cells_arr.shape}")
    if not np.issubdtype(cells_arr.dtype, np.integer):
        raise InputError("fe.cells", f"must be integer node indices, got dtype {cells_arr.dtype}")
    if cells_arr.min() < 0 or cells_arr.max() >= nodes.shape[0]:
        raise InputError(
            "fe.cells", f"node indices must lie in [0, {nodes.shape[0] - 1}]"
        )
    return nodes, cells_arr.astype(np.int64)


def _check_harmonic(n, field="fe.harmonic"):
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
        raise InputError(field, f"must be an integer in [0, inf), got {n!r}")
    return int(n)


def _check_material(youngs_modulus, poisson_ratio, density):
    e = require_range("material.youngs_modulus", youngs_modulus, 0.0, low_open=True, unit="Pa")
    nu = require_range("material.poisson_ratio", poisson_ratio, -1.0, 0.5,
                       low_open=True, high_open=True)
    rho = require_range("material.density", density, 0.0, low_open=True, unit="kg/m^3")
    return e, nu, rho


# --------------------------------------------------------------------------- element matrices


def circumferential_factor(n):
    """Integral of cos^2(n theta) over one revolution: ``pi`` for n >= 1, ``2 pi`` for n = 0."""
    return 2.0 * np.pi if n == 0 else np.pi


def _gauss_data(nodes, cells, order=3):
    """Shape functions, global derivatives, radius and r dA weights at the Gauss points.

    Returns
    -------
    n_shape : ndarray (G, 8)
    dn_dx : ndarray (E, G, 8, 2)
        Derivatives d/dr, d/dz of the shape functions.
    radius : ndarray (E, G)
        Radius at the Gauss points (m).
    w_rda : ndarray (E, G)
        Gauss weight * det J * r (m^3), so that sum f * w_rda = int f r dr dz.
    """
    pts, wts = quad8.gauss_points(order)
    n_shape = quad8.shape_functions(pts)  # (G, 8)
    dn = quad8.shape_derivatives(pts)  # (G, 8, 2)
    x = nodes[cells]  # (E, 8, 2)
    jac = np.einsum("eia,gib->egab", x, dn)  # J[a, b] = d x_a / d xi_b
    det = jac[..., 0, 0] * jac[..., 1, 1] - jac[..., 0, 1] * jac[..., 1, 0]
    if np.any(det <= 0.0):
        bad = np.unique(np.nonzero(det <= 0.0)[0])
        raise InputError(
            "fe.cells",
            f"elements must be counter-clockwise in (r, z) with det J in (0, inf); "
            f"{bad.size} element(s) fail, first {bad[:5].tolist()}",
        )
    inv = np.empty_like(jac)
    inv[..., 0, 0] = jac[..., 1, 1] / det
    inv[..., 1, 1] = jac[..., 0, 0] / det
    inv[..., 0, 1] = -jac[..., 0, 1] / det
    inv[..., 1, 0] = -jac[..., 1, 0] / det
    dn_dx = np.einsum("gib,egba->egia", dn, inv)
    radius = np.einsum("gi,ei->eg", n_shape, x[..., 0])
    w_rda = wts[None, :] * det * radius
    return n_shape, dn_dx, radius, w_rda


def _strain_matrix(n_shape, dn_dx, radius, n):
    """Strain-displacement matrices B (E, G, 6, 24) of harmonic n (amplitudes of the strains)."""
    n_e, n_g = radius.shape
    shp = np.broadcast_to(n_shape, (n_e, n_g, 8))
    n_r = shp / radius[..., None]  # N / r
    d_r, d_z = dn_dx[..., 0], dn_dx[..., 1]
    b = np.zeros((n_e, n_g, 6, 8, 3))
    b[:, :, 0, :, 0] = d_r
    b[:, :, 1, :, 1] = d_z
    b[:, :, 2, :, 0] = n_r
    b[:, :, 2, :, 2] = n * n_r
    b[:, :, 3, :, 0] = d_z
    b[:, :, 3, :, 1] = d_r
    b[:, :, 4, :, 0] = -n * n_r
    b[:, :, 4, :, 2] = d_r - n_r
    b[:, :, 5, :, 1] = -n * n_r
    b[:, :, 5, :, 2] = d_z
    return b.reshape(n_e, n_g, 6, 24)


def element_matrices(nodes_rz, cells, n, youngs_modulus, poisson_ratio, density):
    """Element stiffness and consistent mass matrices of harmonic ``n``.

    Parameters
    ----------
    nodes_rz : array_like, shape (N, 2)
        Section node coordinates (r, z) (m), r > 0.
    cells : array_like of int, shape (E, 8)
        Node indices of the 8-node quadrilaterals (VTK order, counter-clockwise in (r, z)).
    n : int
        Harmonic number (>= 0).
    youngs_modulus : float
        Young's modulus (Pa).
    poisson_ratio : float
        Poisson's ratio (-), in (-1, 0.5).
    density : float
        Mass density (kg/m^3).

    Returns
    -------
    k_e : ndarray, shape (E, 24, 24)
        Element stiffness matrices (N/m), local DOF ``3 * i + component``.
    m_e : ndarray, shape (E, 24, 24)
        Element consistent mass matrices (kg).
    """
    nodes, cells = _check_mesh(nodes_rz, cells)
    n = _check_harmonic(n)
    e, nu, rho = _check_material(youngs_modulus, poisson_ratio, density)
    # Isotropic D is the same for any strain order with the three normal strains first:
    # here (rr, zz, thth, rz, rth, zth), engineering shears.
    d = isotropic_elasticity(e, nu)
    n_shape, dn_dx, radius, w_rda = _gauss_data(nodes, cells)
    b = _strain_matrix(n_shape, dn_dx, radius, n)
    c = circumferential_factor(n)
    k_e = c * np.einsum("egki,kl,eglj,eg->eij", b, d, b, w_rda, optimize=True)
    nn = np.einsum("gi,gj,eg->eij", n_shape, n_shape, w_rda)  # int N_i N_j r dA
    m_e = np.zeros_like(k_e)
    for comp in range(3):
        m_e[:, comp::3, comp::3] = c * rho * nn
    return k_e, m_e


def harmonic_matrices(nodes_rz, cells, n, youngs_modulus, poisson_ratio, density):
    """Global stiffness and mass matrices of harmonic ``n`` of the body of revolution.

    Parameters
    ----------
    nodes_rz : array_like, shape (N, 2)
        Section node coordinates (r, z) (m), r > 0.
    cells : array_like of int, shape (E, 8)
        8-node quadrilaterals (VTK order, counter-clockwise in (r, z)).
    n : int
        Harmonic number (>= 0).
    youngs_modulus : float
        Young's modulus (Pa).
    poisson_ratio : float
        Poisson's ratio (-).
    density : float
        Mass density (kg/m^3).

    Returns
    -------
    K : scipy.sparse.csr_matrix, shape (3N, 3N)
        Stiffness (N/m) of the whole 3D body for this harmonic; DOF ``3 * node + c`` with
        components (U_r, U_z, U_th).
    M : scipy.sparse.csr_matrix, shape (3N, 3N)
        Consistent mass (kg), same DOF order; the circumferential factor (pi, or 2 pi for
        n = 0) is included.
    """
    nodes, cells_arr = _check_mesh(nodes_rz, cells)
    k_e, m_e = element_matrices(nodes, cells_arr, n, youngs_modulus, poisson_ratio, density)
    ndof = 3 * nodes.shape[0]
    dofs = (3 * cells_arr[:, :, None] + np.arange(3)).reshape(-1, 24)
    rows = np.repeat(dofs, 24, axis=1).ravel()
    cols = np.tile(dofs, (1, 24)).ravel()
    k = sp.coo_matrix((k_e.ravel(), (rows, cols)), shape=(ndof, ndof)).tocsr()
    m = sp.coo_matrix((m_e.ravel(), (rows, cols)), shape=(ndof, ndof)).tocsr()
    return k, m


# --------------------------------------------------------------------------- eigen solution


def count_eigenvalues_below(k, m, lam):
    """Number of eigenvalues of ``K phi = lambda M phi`` below ``lam`` (Sylvester's law).

    Uses the inertia of ``K - lam M`` from a sparse LU factorisation with diagonal pivoting
    only (a symmetric ``L D L^T`` in disguise).

    Parameters
    ----------
    k, m : scipy.sparse matrix, shape (n, n)
        Symmetric stiffness and positive definite mass.
    lam : float
        Shift (rad^2/s^2).

    Returns
    -------
    int
        Count of eigenvalues strictly below ``lam``.
    """
    a = (k - lam * m).tocsc()
    try:
        lu = spla.splu(a, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0,
                       options={"SymmetricMode": True})
    except RuntimeError:  # zero pivot without pivoting
        lu = None
    if lu is None or not np.array_equal(lu.perm_r, lu.perm_c):
        # fall back to a dense symmetric (Bunch-Kaufman) factorisation
        logger.debug("sparse inertia failed; dense LDL^T of %d DOF", a.shape[0])
        _, dblk, _ = scipy.linalg.ldl(a.toarray())
        return int(np.sum(np.linalg.eigvalsh(dblk) < 0.0))
    return int(np.sum(lu.U.diagonal() < 0.0))


def _solve_band(k, m, lam_max):
    """All eigenpairs of ``K phi = lambda M phi`` with ``lambda <= lam_max``.

    Returns ascending eigenvalues (rad^2/s^2) and M-normalised vectors (columns).
    """
    ndof = k.shape[0]
    count = count_eigenvalues_below(k, m, lam_max)
    if count == 0:
        return np.zeros(0), np.zeros((ndof, 0))
    n_req = count + 4
    if ndof <= DENSE_LIMIT or n_req >= ndof // 3:
        lam, vec = scipy.linalg.eigh(k.toarray(), m.toarray(),
                                     subset_by_value=(-np.inf, lam_max))
    else:
        # shift below the spectrum so that K - sigma M is positive definite (free bodies)
        sigma = -1e-3 * lam_max
        lam, vec = spla.eigsh(k.tocsc(), k=n_req, M=m.tocsc(), sigma=sigma, which="LM")
        order = np.argsort(lam)
        lam, vec = lam[order], vec[:, order]
        keep = lam <= lam_max
        lam, vec = lam[keep], vec[:, keep]
    if lam.size != count:
        logger.warning("eigensolver found %d modes below the limit, Sylvester count %d; "
                       "using the dense solver", lam.size, count)
        lam, vec = scipy.linalg.eigh(k.toarray(), m.toarray(),
                                     subset_by_value=(-np.inf, lam_max))
        if lam.size != count:
            raise RuntimeError(f"mode count mismatch: {lam.size} found, {count} expected")
    norms = np.sqrt(np.einsum("ij,ij->j", vec, m @ vec))
    return lam, vec / norms


def _harmonic_modes(k, m, free, n, lam_max):
    """Eigenpairs of one harmonic: list of (lambda, full vector, family) groups."""
    groups = []
    if n == 0:
        comp = free % 3
        parts = [(free[comp < 2], "cos"), (free[comp == 2], "sin")]
    else:
        parts = [(free, "cos")]
    for dofs, family in parts:
        if dofs.size == 0:
            continue
        lam, vec = _solve_band(k[dofs][:, dofs], m[dofs][:, dofs], lam_max)
        full = np.zeros((k.shape[0], lam.size))
        full[dofs] = vec
        groups.append((lam, full, family))
    return groups


def solve_axisymmetric_modes(nodes_rz, cells, clamped_nodes, youngs_modulus, poisson_ratio,
                             density, f_max, n_max=None):
    """All modes of the body of revolution below ``f_max``, harmonic by harmonic.

    Parameters
    ----------
    nodes_rz : array_like, shape (N, 2)
        Section node coordinates (r, z) (m), r > 0.
    cells : array_like of int, shape (E, 8)
        8-node quadrilaterals (VTK order, counter-clockwise in (r, z)).
    clamped_nodes : array_like of int, shape (c,)
        Section nodes whose three DOF are fixed (all around the circumference). May be empty
        (free body: rigid-body modes at 0 Hz appear in n = 0 and n = 1).
    youngs_modulus : float
        Young's modulus (Pa).
    poisson_ratio : float
        Poisson's ratio (-).
    density : float
        Mass density (kg/m^3).
    f_max : float
        Upper frequency of the band (Hz), > 0.
    n_max : int or None, optional
        Highest harmonic. ``None``: increase ``n`` until three consecutive harmonics
        (starting at n >= 2) have no mode below ``f_max``; the choice is logged.

    Returns
    -------
    AxisymmetricModes
        Frequencies (Hz), harmonics, families and mass-normalised amplitudes (m, N, 3),
        sorted by frequency (then harmonic, then family ``"cos"`` before ``"sin"``).
    """
    nodes, cells_arr = _check_mesh(nodes_rz, cells)
    f_max = require_range("fe.f_max", f_max, 0.0, low_open=True, unit="Hz")
    if n_max is not None:
        n_max = _check_harmonic(n_max, "fe.n_max")
    clamped = np.asarray(clamped_nodes, dtype=np.int64).ravel()
    if clamped.size and (clamped.min() < 0 or clamped.max() >= nodes.shape[0]):
        raise InputError("fe.clamped_nodes",
                         f"node indices must lie in [0, {nodes.shape[0] - 1}]")
    n_nodes = nodes.shape[0]
    fixed = np.zeros(3 * n_nodes, dtype=bool)
    fixed[(3 * clamped[:, None] + np.arange(3)).ravel()] = True
    free = np.nonzero(~fixed)[0]
    lam_max = (2.0 * np.pi * f_max) ** 2

    lams, vecs, harms, fams = [], [], [], []
    n, empty_run = 0, 0
    while True:
        if n_max is not None and n > n_max:
            break
        k, m = harmonic_matrices(nodes, cells_arr, n, youngs_modulus, poisson_ratio, density)
        groups = _harmonic_modes(k, m, free, n, lam_max)
        n_found = sum(g[0].size for g in groups)
        logger.debug("harmonic %d: %d mode(s) below %g Hz", n, n_found, f_max)
        families = _FAMILIES if n >= 1 else (None,)
        for lam, vec, fam in groups:
            for family in families:
                lams.append(lam)
                vecs.append(vec)
                harms.append(np.full(lam.size, n))
                fams.append(np.full(lam.size, family or fam, dtype="<U3"))
        if n_max is None:
            empty_run = empty_run + 1 if (n_found == 0 and n >= 2) else 0
            if empty_run == 3:
                n_max = n
                logger.info("n_max = %d chosen automatically: harmonics %d-%d have no mode "
                            "below %g Hz", n, n - 2, n, f_max)
                break
            if n >= N_MAX_CAP:
                logger.warning("automatic n_max stopped at the cap %d", N_MAX_CAP)
                n_max = n
                break
        n += 1

    lam = np.concatenate(lams) if lams else np.zeros(0)
    vec = np.concatenate(vecs, axis=1) if vecs else np.zeros((3 * n_nodes, 0))
    harm = np.concatenate(harms) if harms else np.zeros(0, dtype=int)
    fam = np.concatenate(fams) if fams else np.zeros(0, dtype="<U3")
    freq = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * np.pi)
    order = np.lexsort((fam != "cos", harm, freq))
    shapes = vec[:, order].T.reshape(-1, n_nodes, 3)
    logger.info("%d axisymmetric modes below %g Hz (n = 0..%d)", order.size, f_max, n_max)
    return AxisymmetricModes(frequency=freq[order], harmonic=harm[order].astype(int),
                             family=fam[order], shapes=shapes, n_max=int(n_max))


# --------------------------------------------------------------------------- 3D reconstruction


def reconstruct(shape, n, family, nodes_rz, theta):
    """Cartesian displacement of the revolved section nodes for one harmonic mode.

    Parameters
    ----------
    shape : array_like, shape (N, 3)
        Nodal amplitudes (U_r, U_z, U_th).
    n : int
        Harmonic number (>= 0).
    family : {"cos", "sin"}
        Circumferential family (``docs/conventions.md``).
    nodes_rz : array_like, shape (N, 2)
        Section node coordinates (r, z) (m); used for checking the node count.
    theta : array_like, shape (T,)
        Circumferential angles (rad); theta = 0 is the bottom of the wheel.

    Returns
    -------
    ndarray, shape (T, N, 3)
        Displacement (X, Y, Z) in the wheel frame, where the section point (r, z) at angle
        theta sits at ``(r sin theta, z, -r cos theta)``; same units as ``shape``.
    """
    amp = np.asarray(shape, dtype=float)
    nodes = np.asarray(nodes_rz, dtype=float)
    if amp.ndim != 2 or amp.shape[1] != 3 or amp.shape[0] != nodes.shape[0]:
        raise InputError("shape", f"must have shape ({nodes.shape[0]}, 3), got {amp.shape}")
    n = _check_harmonic(n)
    if family not in _FAMILIES:
        raise InputError("family", f"must be one of {_FAMILIES}, got {family!r}")
    th = np.atleast_1d(np.asarray(theta, dtype=float))[:, None]  # (T, 1)
    c, s = np.cos(n * th), np.sin(n * th)
    if family == "cos":
        u_r, u_z, u_t = amp[:, 0] * c, amp[:, 1] * c, amp[:, 2] * s
    else:
        u_r, u_z, u_t = amp[:, 0] * s, amp[:, 1] * s, -amp[:, 2] * c
    st, ct = np.sin(th), np.cos(th)
    out = np.empty((th.shape[0], amp.shape[0], 3))
    out[..., 0] = u_r * st + u_t * ct
    out[..., 1] = u_z
    out[..., 2] = -u_r * ct + u_t * st
    return out
