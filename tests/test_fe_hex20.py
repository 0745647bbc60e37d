"""Tests of the 20-node hexahedron, the material law, the assembly and the structured meshes."""

import numpy as np
import pytest

from fe import hex20
from fe.assembly import (apply_dirichlet, assemble, assemble_hex20, expand, nodal_dofmap,
                         rigid_body_vectors, total_mass)
from fe.eigen import solve_modes
from fe.material import isotropic_elasticity
from mesh.structured import annulus_hex20, boundary_nodes, box_hex20, distort_nodes
from squealcore.errors import InputError

E, NU, RHO = 210e9, 0.3, 7850.0
G = E / (2 * (1 + NU))
D = isotropic_elasticity(E, NU)


def _points(n=50, seed=1):
    return np.random.default_rng(seed).uniform(-1, 1, size=(n, 3))


# --- material -----------------------------------------------------------------------------

def test_elasticity_matches_engineering_constants():
    # Independent check: the compliance of an isotropic solid is known in closed form.
    c = np.linalg.inv(D)
    assert c[0, 0] == pytest.approx(1 / E, rel=1e-13)  # round-off only
    assert c[0, 1] == pytest.approx(-NU / E, rel=1e-13)
    assert c[3, 3] == pytest.approx(1 / G, rel=1e-13)
    assert np.allclose(D, D.T, rtol=0, atol=0)


@pytest.mark.parametrize("e, nu, field", [(0.0, 0.3, "youngs_modulus"), (-1.0, 0.3, "youngs_modulus"),
                                          (E, 0.5, "poisson_ratio"), (E, -1.0, "poisson_ratio")])
def test_elasticity_rejects_bad_input(e, nu, field):
    with pytest.raises(InputError) as info:
        isotropic_elasticity(e, nu, prefix="wheel.fe.")
    assert info.value.field == "wheel.fe." + field


# --- shape functions and quadrature -------------------------------------------------------

def test_partition_of_unity_and_kronecker():
    pts = _points()
    n = hex20.shape_functions(pts)
    assert np.abs(n.sum(axis=1) - 1).max() < 1e-14  # exact identity up to round-off
    assert np.abs(hex20.shape_derivatives(pts).sum(axis=1)).max() < 1e-13
    assert np.abs(hex20.shape_functions(hex20.NODE_COORDS) - np.eye(20)).max() < 1e-15


def test_shape_functions_reproduce_quadratic_serendipity_fields():
    # The serendipity space contains 1, x, y, z, x^2, xy, ..., x^2 y, ... : interpolating the
    # nodal values of such a function must reproduce it exactly (round-off).
    pts = _points()
    f = lambda p: 1 + p[:, 0] - 2 * p[:, 1] ** 2 + 3 * p[:, 0] * p[:, 2] + p[:, 0] ** 2 * p[:, 1] - p[:, 0] * p[:, 1] * p[:, 2]
    interp = hex20.shape_functions(pts) @ f(hex20.NODE_COORDS)
    assert np.abs(interp - f(pts)).max() < 1e-13


def test_derivatives_match_central_differences():
    pts = _points()
    h = 1e-5
    fd = np.stack([(hex20.shape_functions(pts + h * e) - hex20.shape_functions(pts - h * e)) / (2 * h)
                   for e in np.eye(3)], axis=-1)
    # central differences of a cubic: truncation error h^2/6 |f'''| ~ 1e-10, round-off ~1e-11
    assert np.abs(fd - hex20.shape_derivatives(pts)).max() < 1e-8


def test_gauss_rule():
    pts, w = hex20.gauss_points(3)
    assert pts.shape == (27, 3) and w.shape == (27,)
    assert w.sum() == pytest.approx(8.0, rel=1e-14)
    f5 = lambda p: np.prod((1 + p) ** 5 * np.array([1.0, 2.0, 0.5]) + p, axis=1)
    # exact: prod over directions of  int (c (1+s)^5 + s) ds = c 2^6 / 6
    exact = np.prod(np.array([1.0, 2.0, 0.5]) * 64 / 6)
    assert w @ f5(pts) == pytest.approx(exact, rel=1e-13)  # degree 5 per direction: exact
    # degree 6 is not integrated exactly by 3 points: the check above can fail
    assert abs(w @ np.prod((1 + pts) ** 6, axis=1) - (128 / 7) ** 3) > 1e-3


# --- meshes ---------------------------------------------------------------------------------

def test_box_mesh_counts_and_volume():
    nodes, cells = box_hex20(0.3, 0.2, 0.1, 3, 2, 1)
    # serendipity lattice: 4*3*2 corners + 3*3*2 + 4*2*2 + 4*3*1 mid-edge nodes
    assert nodes.shape == (24 + 18 + 16 + 12, 3) and cells.shape == (6, 20)
    assert np.unique(cells).size == nodes.shape[0]
    vol = hex20.element_volumes(nodes, cells)
    assert np.allclose(vol, 0.3 * 0.2 * 0.1 / 6, rtol=1e-13)
    # all nodes are on the boundary except the mid-edge nodes of the (3-1)*(2-1) interior
    # vertical edges (their ends are on the top/bottom faces, their midpoints are not)
    assert boundary_nodes(cells).size == nodes.shape[0] - 2


def test_annulus_mesh_geometry():
    r_in, r_out, t = 0.1, 0.3, 0.02
    nodes, cells = annulus_hex20(r_in, r_out, t, 2, 1, 12)
    r = np.hypot(nodes[:, 0], nodes[:, 2])
    # all nodes, mid-edge nodes included, lie on the lattice circles
    levels = r_in + np.arange(5) * (r_out - r_in) / 4
    assert np.abs(r[:, None] - levels[None, :]).min(axis=1).max() < 1e-15
    # circumferential mid-edge nodes (16-19, zeta = theta direction) at the mid angle
    th = np.arctan2(nodes[:, 0], -nodes[:, 2])  # conventions: (r sin t, z, -r cos t)
    mid = np.angle(np.exp(1j * th[cells[:, 0]]) + np.exp(1j * th[cells[:, 4]]))
    assert np.abs(np.angle(np.exp(1j * (th[cells[:, 16]] - mid)))).max() < 1e-14
    # theta = 0 is the bottom: the node with the smallest Z is at X = 0
    assert np.isclose(nodes[np.argmin(nodes[:, 2]), 0], 0.0, atol=1e-15)
    vol = hex20.element_volumes(nodes, cells)
    assert vol.min() > 0
    # Second method: the mesh is the prism over the region bounded by quadratic (Lagrange) arcs
    # through 3 points of each circle; its area is n_theta (r_out^2 - r_in^2) A1, with
    # A1 = 1/2 int (P x P') ds for the unit-radius arc, integrated exactly by 5-point Gauss.
    s, w = np.polynomial.legendre.leggauss(5)
    a = np.pi / 12 * np.array([-1.0, 0.0, 1.0])
    pts = np.column_stack([np.sin(a), -np.cos(a)])
    lag = np.column_stack([s * (s - 1) / 2, 1 - s**2, s * (s + 1) / 2])
    dlag = np.column_stack([s - 0.5, -2 * s, s + 0.5])
    p, dp = lag @ pts, dlag @ pts
    a1 = 0.5 * w @ (p[:, 0] * dp[:, 1] - p[:, 1] * dp[:, 0])
    assert vol.sum() == pytest.approx(12 * (r_out**2 - r_in**2) * t * abs(a1), rel=1e-13)
    # and the arcs are close to the circle: area within 2e-4 (30-degree quadratic arcs)
    assert vol.sum() == pytest.approx(np.pi * (r_out**2 - r_in**2) * t, rel=2e-4)


def test_mesh_input_errors():
    with pytest.raises(InputError) as info:
        box_hex20(-1.0, 1.0, 1.0, 1, 1, 1)
    assert info.value.field == "lx"
    with pytest.raises(InputError) as info:
        annulus_hex20(0.3, 0.2, 0.02, 1, 1, 8)
    assert info.value.field == "r_out"
    with pytest.raises(InputError):
        annulus_hex20(0.1, 0.2, 0.02, 1, 1, 2)


def test_inverted_element_is_reported():
    nodes, cells = box_hex20(1.0, 1.0, 1.0, 2, 1, 1)
    bad = cells.copy()
    bad[1, :4], bad[1, 4:8] = cells[1, 4:8], cells[1, :4]  # mirror element 1 through its mid plane
    bad[1, 8:12], bad[1, 12:16] = cells[1, 12:16], cells[1, 8:12]
    with pytest.raises(InputError, match="element 1 "):
        hex20.element_matrices(nodes, bad, D, RHO)


# --- element matrices, assembly ---------------------------------------------------------------

def _distorted_cube():
    nodes, cells = box_hex20(1.0, 0.8, 0.6, 2, 2, 2)
    nodes = distort_nodes(nodes, cells, 0.08, seed=3)  # interior nodes; h/2 = 0.15..0.25 m
    return nodes, cells


def test_distorted_mesh_volume_and_mass():
    nodes, cells = _distorted_cube()
    assert np.abs(nodes - box_hex20(1.0, 0.8, 0.6, 2, 2, 2)[0]).max() > 0.05  # really moved
    # det J of a serendipity hex20 is of degree <= 5 per direction, so 3x3x3 Gauss integrates
    # it exactly and the distorted elements still fill the box exactly (round-off).
    assert hex20.element_volumes(nodes, cells).sum() == pytest.approx(0.48, rel=1e-13)
    K, M = assemble_hex20(nodes, cells, D, RHO)
    assert np.allclose(total_mass(M), RHO * 0.48, rtol=1e-13)
    # rigid-body motions are in the null space of K (round-off relative to |K|)
    assert np.abs(K @ rigid_body_vectors(nodes)).max() < 1e-9 * abs(K).max()
    assert abs(K - K.T).max() < 1e-12 * abs(K).max()


def test_patch_test_constant_strain_on_distorted_mesh():
    nodes, cells = _distorted_cube()
    K, _ = assemble_hex20(nodes, cells, D, RHO)
    rng = np.random.default_rng(7)
    grad = rng.normal(size=(3, 3)) * 1e-3  # du_i/dx_j
    u0 = np.array([1e-3, -2e-3, 5e-4])
    exact = (u0[None, :] + nodes @ grad.T).ravel()
    bnd = boundary_nodes(cells)
    assert 0 < bnd.size < nodes.shape[0]
    fixed = (3 * bnd[:, None] + np.arange(3)).ravel()
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    u = exact.copy()
    u[free] = 0.0
    import scipy.sparse.linalg as spla
    K = K.tocsr()
    u[free] = spla.spsolve(K[free][:, free].tocsc(), -(K[free][:, fixed] @ exact[fixed]))
    # the isoparametric element reproduces linear fields exactly: round-off only
    assert np.abs(u - exact).max() < 1e-10 * np.abs(exact).max()
    eps = hex20.element_strains(nodes, cells, u)
    eps_exact = np.array([grad[0, 0], grad[1, 1], grad[2, 2], grad[1, 2] + grad[2, 1],
                          grad[0, 2] + grad[2, 0], grad[0, 1] + grad[1, 0]])
    sig = eps @ D
    assert np.abs(sig - D @ eps_exact).max() < 1e-9 * np.abs(D @ eps_exact).max()


def test_assemble_generic_dofmap_matches_dense_loop():
    nodes, cells = box_hex20(0.2, 0.1, 0.1, 2, 1, 1)
    ke, me = hex20.element_matrices(nodes, cells, D, RHO)
    dm = nodal_dofmap(cells)
    K, M = assemble(ke, me, dm, 3 * nodes.shape[0])
    kd = np.zeros(K.shape)
    for e in range(cells.shape[0]):  # independent, obvious dense scatter
        kd[np.ix_(dm[e], dm[e])] += ke[e]
    # same sums in a possibly different order: round-off only
    assert np.abs(K.toarray() - kd).max() <= 1e-14 * np.abs(kd).max()
    Kf, Mf, free = apply_dirichlet(K, M, [0, 1, 2, 2])
    assert Kf.shape == (K.shape[0] - 3,) * 2 and free[0] == 3
    full = expand(np.ones((free.size, 2)), free, K.shape[0])
    assert full.shape == (K.shape[0], 2) and full[:3].sum() == 0 and full[3:].min() == 1


def test_free_block_has_six_rigid_body_modes():
    nodes, cells = box_hex20(0.4, 0.2, 0.1, 2, 1, 1)
    K, M = assemble_hex20(nodes, cells, D, RHO)
    import scipy.linalg as sla
    lam = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True)
    # six zero eigenvalues (round-off: |K| ~ 1e11 N/m, |M| ~ 1 kg -> ~1e-4 rad^2/s^2 scale)
    assert np.abs(lam[:6]).max() < 1e-8 * lam[6]
    assert lam[6] > 1e5  # then a clear gap to the first elastic mode (~ (2 pi 3 kHz)^2)
    u = np.zeros(K.shape[0])
    u[0::3] = 1.0
    assert u @ (M @ u) == pytest.approx(RHO * 0.4 * 0.2 * 0.1, rel=1e-13)


def _rect_torsion_constant(a, c, terms=200):
    """Saint-Venant torsion constant of an a x c rectangle (a >= c), series solution."""
    n = np.arange(1, 2 * terms, 2)
    return c**3 * a / 3 * (1 - 192 / np.pi**5 * c / a * np.sum(np.tanh(n * np.pi * a / (2 * c)) / n**5))


def test_torsion_constant_series_matches_table():
    # Roark / Timoshenko-Goodier: square J = 0.1406 a^4, 2:1 rectangle J = 0.229 a c^3 (4 digits)
    assert _rect_torsion_constant(1.0, 1.0) == pytest.approx(0.1406, abs=5e-5)
    assert _rect_torsion_constant(2.0, 1.0) / 2.0 == pytest.approx(0.2287, abs=5e-5)


def test_cantilever_bending_and_torsion_frequencies():
    # Slender steel bar along X, b = 40 mm (Y) x h = 20 mm (Z), L = 1 m, clamped at X = 0.
    # Slenderness L/b = 25, L/h = 50: Euler-Bernoulli is adequate (Timoshenko shear and rotary
    # inertia corrections -0.1 % and -0.03 %). Torsion: Saint-Venant, J from the series,
    # polar inertia Ip = b h (b^2 + h^2) / 12. The 3D model differs from both theories by the
    # clamp restraining warping and Poisson contraction (stiffening, ~0.2-0.5 %) plus the
    # discretisation (4 x 4 quadratic elements across, 25 along: < 0.3 %); measured
    # +0.36 % (Z bending), +0.19 % (Y bending), +0.63 % (torsion), so 1 % is a fair bound.
    L, b, h = 1.0, 0.04, 0.02
    nodes, cells = box_hex20(L, b, h, 25, 4, 4, origin=(0.0, -b / 2, -h / 2))
    K, M = assemble_hex20(nodes, cells, D, RHO)
    clamp = np.nonzero(np.isclose(nodes[:, 0], 0.0))[0]
    Kf, Mf, free = apply_dirichlet(K, M, (3 * clamp[:, None] + np.arange(3)).ravel())
    area = b * h
    beta1 = 1.875104068711961  # first root of cos(x) cosh(x) = -1
    f_bend = lambda inertia: beta1**2 / (2 * np.pi) * np.sqrt(E * inertia / (RHO * area * L**4))
    f_y, f_z = f_bend(h * b**3 / 12), f_bend(b * h**3 / 12)
    J = _rect_torsion_constant(b, h)
    f_t = 1 / (4 * L) * np.sqrt(G * J / (RHO * b * h * (b * b + h * h) / 12))
    f, phi = solve_modes(Kf, Mf, 1.1 * f_t)
    u = expand(phi, free, K.shape[0]).reshape(-1, 3, f.size)
    tip = np.isclose(nodes[:, 0], L)
    y, z = nodes[tip, 1], nodes[tip, 2]
    uy = np.abs(u[tip, 1].mean(axis=0))
    uz = np.abs(u[tip, 2].mean(axis=0))
    rot = np.abs(((y[:, None] * u[tip, 2] - z[:, None] * u[tip, 1]).mean(axis=0)) / np.mean(y * y + z * z))
    scale = np.sqrt(uy**2 + uz**2 + (rot * b) ** 2)
    first = lambda m: f[np.nonzero(m > 0.9 * scale)[0][0]]  # first mode dominated by the motion
    assert first(uz) == pytest.approx(f_z, rel=0.01)
    assert first(uy) == pytest.approx(f_y, rel=0.01)
    assert first(rot * b) == pytest.approx(f_t, rel=0.01)
    assert f[0] == first(uz) and f[1] == first(uy)  # ordering: Z bending, Y bending
