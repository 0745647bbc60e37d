"""Tests of the wheel section, its gmsh meshes (quad8 section, hex20 3D wheel) and plots.

Volumes and masses of the meshes are integrated here with this file's own serendipity shape
functions and Gauss rules, independently of the FE package and of the outline code.
"""

import math
from pathlib import Path

import gmsh
import meshio
import numpy as np
import pytest
from scipy.spatial import cKDTree

from mesh.wheel_mesh import GMSH_HEX20_TO_VTK, GMSH_HEX20, mesh_wheel, write_vtu
from mesh.plots import plot_section_mesh, plot_wheel_3d
from mesh.wheel_section import (WheelParams, outline_area_moment, outline_mass, read_profile,
                                section_outline)
from profiles.s1002 import s1002_height
from squealcore.errors import InputError

DATA = Path(__file__).parent / "data"
TARGET_MASS = 213.0  # kg, the paper's C20 wheel
COARSE = {"section_element_size": 0.03, "elements_around": 12}

# VTK natural coordinates of the quad8 and hex20 nodes (docs/conventions.md).
QUAD8_XI = np.array([[-1, -1], [1, -1], [1, 1], [-1, 1], [0, -1], [1, 0], [0, 1], [-1, 0]], float)
HEX20_XI = np.array([
    [-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
    [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1],
    [0, -1, -1], [1, 0, -1], [0, 1, -1], [-1, 0, -1],
    [0, -1, 1], [1, 0, 1], [0, 1, 1], [-1, 0, 1],
    [-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
# VTK hex20 mid-edge node -> the two corners of its edge.
HEX20_EDGES = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
                        [0, 4], [1, 5], [2, 6], [3, 7]])


# ----------------------------------------------------------------------------------------------
# Independent serendipity shape functions and Gauss rules
# ----------------------------------------------------------------------------------------------
def gauss_3():
    """3-point Gauss-Legendre rule on [-1, 1]."""
    x = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
    w = np.array([5.0, 8.0, 5.0]) / 9.0
    return x, w


def serendipity_grad(xi, nodes_xi):
    """Shape functions (G, n) and natural derivatives (G, n, d) of the serendipity element.

    Corner nodes: prod(1 + x_j x_ij) (sum x_j x_ij - d + 1) / 2^d; mid-edge nodes (one zero
    natural coordinate k): (1 - x_k^2) prod_{j != k} (1 + x_j x_ij) / 2^(d-1).
    """
    d = nodes_xi.shape[1]
    G, n = len(xi), len(nodes_xi)
    N = np.zeros((G, n))
    dN = np.zeros((G, n, d))
    for a, xa in enumerate(nodes_xi):
        zero = np.flatnonzero(xa == 0)
        if len(zero) == 0:
            lin = 1.0 + xi * xa                                # (G, d)
            s = (xi * xa).sum(axis=1) - d + 1
            prod = lin.prod(axis=1)
            N[:, a] = prod * s / 2 ** d
            for k in range(d):
                others = np.prod(np.delete(lin, k, axis=1), axis=1)
                dN[:, a, k] = (xa[k] * others * s + prod * xa[k]) / 2 ** d
        else:
            k0 = zero[0]
            lin = 1.0 + xi * xa
            lin[:, k0] = 1.0 - xi[:, k0] ** 2
            N[:, a] = lin.prod(axis=1) / 2 ** (d - 1)
            for k in range(d):
                others = np.prod(np.delete(lin, k, axis=1), axis=1)
                deriv = -2.0 * xi[:, k0] if k == k0 else xa[k]
                dN[:, a, k] = deriv * others / 2 ** (d - 1)
    return N, dN


def quad8_rule():
    x, w = gauss_3()
    xi = np.array([[a, b] for a in x for b in x])
    wt = np.array([wa * wb for wa in w for wb in w])
    return xi, wt


def hex20_rule():
    x, w = gauss_3()
    xi = np.array([[a, b, c] for a in x for b in x for c in x])
    wt = np.array([wa * wb * wc for wa in w for wb in w for wc in w])
    return xi, wt


def section_jacobians(nodes, cells):
    """det J (E, 9) and r (E, 9) at the 3x3 Gauss points of quad8 elements, plus weights."""
    xi, wt = quad8_rule()
    N, dN = serendipity_grad(xi, QUAD8_XI)
    X = nodes[cells]                                   # (E, 8, 2)
    J = np.einsum("gak,eai->egik", dN, X)              # dx_i / dxi_k
    detJ = J[..., 0, 0] * J[..., 1, 1] - J[..., 0, 1] * J[..., 1, 0]
    r = np.einsum("ga,ea->eg", N, X[..., 0])
    return detJ, r, wt


def hex_jacobians(nodes, cells):
    """det J (E, 27) at the 3x3x3 Gauss points of hex20 elements, plus weights."""
    xi, wt = hex20_rule()
    _, dN = serendipity_grad(xi, HEX20_XI)
    J = np.einsum("gak,eai->egik", dN, nodes[cells])
    return np.linalg.det(J), wt


def section_mass(mesh):
    """Mass of the solid of revolution of the quad8 section mesh: rho int 2 pi r dA (kg)."""
    detJ, r, wt = section_jacobians(mesh.section_nodes, mesh.section_cells)
    return mesh.params.density * 2.0 * math.pi * np.sum(detJ * r * wt)


def hex_mass(mesh):
    detJ, wt = hex_jacobians(mesh.hex_nodes, mesh.hex_cells)
    return mesh.params.density * np.sum(detJ * wt)


def test_shape_functions_are_interpolating():
    # Kronecker delta at the nodes and partition of unity (derivatives sum to 0): exact to
    # round-off, so 1e-12.
    for nodes_xi in (QUAD8_XI, HEX20_XI):
        N, dN = serendipity_grad(nodes_xi, nodes_xi)
        assert np.allclose(N, np.eye(len(nodes_xi)), atol=1e-12)
        assert np.allclose(dN.sum(axis=1), 0.0, atol=1e-12)
    # Derivatives against central differences (step 1e-6: error ~1e-12 for these cubics).
    rng = np.random.default_rng(0)
    xi = rng.uniform(-1, 1, (5, 3))
    _, dN = serendipity_grad(xi, HEX20_XI)
    for k in range(3):
        e = np.zeros(3)
        e[k] = 1e-6
        fd = (serendipity_grad(xi + e, HEX20_XI)[0] - serendipity_grad(xi - e, HEX20_XI)[0]) / 2e-6
        assert np.allclose(dN[:, :, k], fd, atol=1e-8)


# ----------------------------------------------------------------------------------------------
# Meshes shared by several tests
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def default_mesh():
    return mesh_wheel(WheelParams())


@pytest.fixture(scope="module")
def coarse_mesh():
    return mesh_wheel(WheelParams.from_mapping(COARSE))


# ----------------------------------------------------------------------------------------------
# Mass
# ----------------------------------------------------------------------------------------------
def test_pappus_against_closed_form_annuli():
    # The stepped profile is three rectangles; its solid of revolution is three annular
    # cylinders: V = pi sum (b^2 - a^2) w. Exact polygon formula, so only round-off: 1e-12.
    pts = read_profile(DATA / "stepped_profile.txt")
    exact = math.pi * ((0.09**2 - 0.05**2) * 0.10 + (0.25**2 - 0.09**2) * 0.02
                       + (0.30**2 - 0.25**2) * 0.10)
    area, moment = outline_area_moment(pts)
    assert area == pytest.approx(0.04 * 0.1 + 0.16 * 0.02 + 0.05 * 0.1, rel=1e-12)
    assert 2 * math.pi * moment == pytest.approx(exact, rel=1e-12)


def test_outline_labels_and_orientation():
    p = WheelParams()
    points, labels = section_outline(p)
    area, _ = outline_area_moment(points)
    assert area > 0  # counter-clockwise in (r, z)
    bore = points[labels["bore"]]
    assert np.allclose(bore[:, 0], p.hub_bore_radius, atol=1e-15)
    centre = 0.5 * p.rim_width + p.hub_offset
    assert np.allclose(np.sort(bore[:, 1]), centre + np.array([-0.5, 0.5]) * p.hub_length, atol=1e-15)
    assert np.allclose(points[labels["contact"]], [p.rolling_radius, p.contact_offset], atol=1e-15)
    # Tread: r(z) = r0 - conicity (z - z_c) at the field face.
    field_top = points[np.argmin(np.hypot(points[:, 0] - 0.39, points[:, 1] - p.rim_width))]
    r_expected = p.rolling_radius - p.tread_conicity * (p.rim_width - p.contact_offset)
    assert np.allclose(field_top, [r_expected, p.rim_width], atol=1e-15)
    # The outline spans the rim width axially and reaches the flange tip radially.
    assert points[:, 0].max() == pytest.approx(p.rolling_radius + p.flange_height, abs=1e-12)
    assert points[:, 1].max() == pytest.approx(max(p.rim_width, centre + 0.5 * p.hub_length))


def test_default_wheel_mass_is_213_kg(default_mesh):
    m_outline = outline_mass(WheelParams())
    # Brief: within 1 % of the paper's 213 kg; the default hub_length was tuned to 0.3 %.
    assert abs(m_outline / TARGET_MASS - 1) < 0.003
    # Mesh masses: quadratic elements approximate the fillet and flange arcs, so allow 0.5 %
    # (measured: section -1.8e-6, hex +4.2e-6).
    m_section = section_mass(default_mesh)
    m_hex = hex_mass(default_mesh)
    assert abs(m_section / m_outline - 1) < 0.005
    assert abs(m_hex / m_outline - 1) < 0.005
    # 3D vs revolved section: the nodes coincide, but (a) circles are interpolated by
    # parabolas over 5 deg (relative volume error -a^4/30 = -1.2e-7, a = half angle) and
    # (b) on curved section edges the hex20 face centre sits (1 - cos a) x (edge sagitta) off
    # the surface of revolution (~1e-5 for the fillets here). Measured 6.0e-6; allow 5e-5.
    assert abs(m_hex / m_section - 1) < 5e-5
    assert default_mesh.mass == pytest.approx(m_outline, rel=1e-12)


def test_default_mesh_size_is_paper_like(default_mesh):
    # The paper: about 110 section elements x 72 = 7920 hexahedra, 37800 nodes.
    n_sec = len(default_mesh.section_cells)
    assert 95 <= n_sec <= 125
    assert len(default_mesh.hex_cells) == 72 * n_sec


# ----------------------------------------------------------------------------------------------
# Node orders and element validity
# ----------------------------------------------------------------------------------------------
def test_hex20_permutation_on_a_gmsh_box():
    # A single 20-node hexahedron meshed by gmsh on a 1 x 2 x 3 box. After the permutation the
    # nodes must sit at the VTK natural coordinates mapped through the corners (trilinear map,
    # exact for a box: tolerance 1e-12 m).
    gmsh.initialize(readConfigFiles=False, interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("box")
        gmsh.model.occ.addBox(0.1, -0.2, 0.3, 1.0, 2.0, 3.0)
        gmsh.model.occ.synchronize()
        for _, c in gmsh.model.getEntities(1):
            gmsh.model.mesh.setTransfiniteCurve(c, 2)
        for _, s in gmsh.model.getEntities(2):
            gmsh.model.mesh.setTransfiniteSurface(s)
            gmsh.model.mesh.setRecombine(2, s)
        gmsh.model.mesh.setTransfiniteVolume(1)
        gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
        gmsh.model.mesh.generate(3)
        gmsh.model.mesh.setOrder(2)
        _, node_tags = gmsh.model.mesh.getElementsByType(GMSH_HEX20)
        xyz = np.array([gmsh.model.mesh.getNode(t)[0] for t in node_tags])
    finally:
        gmsh.finalize()
    assert xyz.shape == (20, 3)
    vtk = xyz[GMSH_HEX20_TO_VTK]
    lin = np.prod(1.0 + HEX20_XI[:, None, :] * HEX20_XI[None, :8, :], axis=2) / 8.0  # (20, 8)
    assert np.allclose(lin @ vtk[:8], vtk, atol=1e-12)


def test_hex20_order_in_wheel_mesh(coarse_mesh):
    # Every mid-edge node is nearest to the midpoint of its own VTK edge among the 12 edges.
    # Midpoints are taken in cylindrical coordinates (mean r, z and theta), which is the chord
    # midpoint for in-plane edges and the arc midpoint for circumferential ones; only the
    # sagitta of curved in-plane edges (fillets) remains, far less than the element size.
    X = coarse_mesh.hex_nodes[coarse_mesh.hex_cells]                     # (E, 20, 3)
    r, z = np.hypot(X[..., 0], X[..., 2]), X[..., 1]
    t = np.arctan2(X[..., 0], -X[..., 2])
    a, b = HEX20_EDGES[:, 0], HEX20_EDGES[:, 1]
    tm = t[:, a] + 0.5 * np.angle(np.exp(1j * (t[:, b] - t[:, a])))
    rm, zm = 0.5 * (r[:, a] + r[:, b]), 0.5 * (z[:, a] + z[:, b])
    mids = np.stack([rm * np.sin(tm), zm, -rm * np.cos(tm)], axis=-1)  # (E, 12, 3)
    dist = np.linalg.norm(X[:, 8:, None, :] - mids[:, None, :, :], axis=-1)
    assert np.all(np.argmin(dist, axis=2) == np.arange(12))


def test_hex_jacobian_positive_everywhere(default_mesh):
    detJ, _ = hex_jacobians(default_mesh.hex_nodes, default_mesh.hex_cells)
    assert detJ.min() > 0.0
    # Corner-node signed volume (trilinear map at the centre) also positive.
    sign = HEX20_XI[:8]
    J = np.einsum("eai,aj->eij", default_mesh.hex_nodes[default_mesh.hex_cells[:, :8]], sign) / 8
    assert np.linalg.det(J).min() > 0.0
    # Every node used, none twice within a cell.
    cells = default_mesh.hex_cells
    assert np.array_equal(np.unique(cells), np.arange(len(default_mesh.hex_nodes)))
    assert all(len(set(c)) == 20 for c in cells[:: max(1, len(cells) // 500)])


def test_section_elements_counter_clockwise(default_mesh):
    detJ, _, _ = section_jacobians(default_mesh.section_nodes, default_mesh.section_cells)
    assert detJ.min() > 0.0  # positive in (r, z) = counter-clockwise at every Gauss point
    cells = default_mesh.section_cells
    assert cells.shape[1] == 8
    assert np.array_equal(np.unique(cells), np.arange(len(default_mesh.section_nodes)))
    assert all(len(set(c)) == 8 for c in cells)


# ----------------------------------------------------------------------------------------------
# Revolution consistency
# ----------------------------------------------------------------------------------------------
def check_revolution(mesh):
    n_around = mesh.params.elements_around
    sec, cells = mesh.section_nodes, mesh.section_cells
    corners = np.unique(cells[:, :4])
    X = mesh.hex_nodes
    rz = np.column_stack([np.hypot(X[:, 0], X[:, 2]), X[:, 1]])
    theta = np.arctan2(X[:, 0], -X[:, 2]) % (2 * math.pi)   # (r sin t, z, -r cos t)
    tol = 1e-9  # m; gmsh rotates coordinates in double precision
    # Every 3D node on the circle of a section node.
    dist, idx = cKDTree(sec).query(rz)
    assert dist.max() < tol
    # Angles: corner and in-plane nodes at k 2 pi / N, circumferential mid-edge nodes halfway.
    step = 2 * math.pi / n_around
    in_plane = np.unique(mesh.hex_cells[:, :16])
    circ = np.unique(mesh.hex_cells[:, 16:])
    assert np.intersect1d(in_plane, circ).size == 0
    frac_in = theta[in_plane] / step
    frac_circ = theta[circ] / step - 0.5
    assert np.abs(frac_in - np.round(frac_in)).max() < 1e-8
    assert np.abs(frac_circ - np.round(frac_circ)).max() < 1e-8
    # Circumferential mid-edge nodes sit on circles of section corner nodes.
    assert np.all(np.isin(idx[circ], corners))
    # Counts: a closed ring has N layers of every section node and of every corner mid-edge.
    assert len(mesh.hex_cells) == n_around * len(cells)
    assert len(X) == n_around * (len(sec) + len(corners))
    assert len(in_plane) == n_around * len(sec)
    # No two 3D nodes coincide (the seams are merged).
    pairs = cKDTree(X).query_pairs(1e-7)
    assert not pairs


def test_revolution_consistency_default(default_mesh):
    check_revolution(default_mesh)


def test_revolution_consistency_odd_count():
    # 13 around: four revolution pieces of unequal size (4, 3, 3, 3 elements).
    check_revolution(mesh_wheel(WheelParams.from_mapping({**COARSE, "elements_around": 13})))


# ----------------------------------------------------------------------------------------------
# Contact and clamped nodes
# ----------------------------------------------------------------------------------------------
def test_contact_and_clamped_nodes(default_mesh):
    p = default_mesh.params
    # The contact node is a geometry point of the tread: exact to round-off (1e-12 m).
    c = default_mesh.section_nodes[default_mesh.contact_section_node]
    assert np.allclose(c, [p.rolling_radius, p.contact_offset], atol=1e-12)
    expected = np.array([0.0, p.contact_offset, -p.rolling_radius])
    assert np.allclose(default_mesh.contact_position, expected, atol=1e-12)
    assert np.allclose(default_mesh.hex_nodes[default_mesh.contact_hex_node], expected, atol=1e-12)
    # Clamped section nodes: exactly the nodes at the bore radius.
    sec = default_mesh.section_nodes
    at_bore = np.flatnonzero(np.abs(sec[:, 0] - p.hub_bore_radius) < 1e-12)
    assert np.array_equal(np.sort(default_mesh.section_clamped_nodes), at_bore)
    z = sec[at_bore, 1]
    half = 0.5 * p.hub_length
    centre = 0.5 * p.rim_width + p.hub_offset
    assert z.min() == pytest.approx(centre - half, abs=1e-12)
    assert z.max() == pytest.approx(centre + half, abs=1e-12)
    # Clamped 3D nodes: all nodes on the bore cylinder (radius to 1e-9 m), N per section
    # bore node plus N per bore corner node.
    X = default_mesh.hex_nodes
    on_bore = np.flatnonzero(np.abs(np.hypot(X[:, 0], X[:, 2]) - p.hub_bore_radius) < 1e-9)
    assert np.array_equal(np.sort(default_mesh.hex_clamped_nodes), on_bore)
    n_corner = len(np.intersect1d(at_bore, default_mesh.section_cells[:, :4]))
    assert len(on_bore) == p.elements_around * (len(at_bore) + n_corner)


def test_contact_offset_moves_contact_node():
    mesh = mesh_wheel(WheelParams.from_mapping({**COARSE, "contact_offset": 0.09}))
    p = mesh.params
    r_c = p.rolling_radius  # the tread formula gives r0 at z = contact_offset
    assert np.allclose(mesh.section_nodes[mesh.contact_section_node], [r_c, 0.09], atol=1e-12)
    assert np.allclose(mesh.hex_nodes[mesh.contact_hex_node], [0.0, 0.09, -r_c], atol=1e-12)


def test_meshing_is_deterministic(coarse_mesh):
    again = mesh_wheel(coarse_mesh.params)
    assert np.array_equal(again.hex_cells, coarse_mesh.hex_cells)
    assert np.array_equal(again.hex_nodes, coarse_mesh.hex_nodes)
    assert np.array_equal(again.section_cells, coarse_mesh.section_cells)


# ----------------------------------------------------------------------------------------------
# Validation
# ----------------------------------------------------------------------------------------------
def write_profile(path, points, close=True):
    pts = np.vstack([points, points[:1]]) if close else points
    np.savetxt(path, pts, header="r z (m)")
    return str(path)


@pytest.mark.parametrize("mapping, field", [
    ({"web_thickness": -0.01}, "wheel.web_thickness"),
    ({"web_thickness": 0.0}, "wheel.web_thickness"),
    ({"rim_inner_radius": 0.39}, "wheel.rim_inner_radius"),
    ({"rim_inner_radius": 0.40}, "wheel.rim_inner_radius"),
    ({"web_thickness": 0.14}, "wheel.web_thickness"),        # wider than the 0.135 m rim
    ({"rim_width": 0.0}, "wheel.rim_width"),
    ({"hub_outer_radius": 0.35}, "wheel.hub_outer_radius"),   # >= rim_inner_radius
    ({"hub_bore_radius": 0.13}, "wheel.hub_bore_radius"),     # >= hub_outer_radius
    ({"contact_offset": 0.02}, "wheel.contact_offset"),       # on the flange
    ({"contact_offset": 0.14}, "wheel.contact_offset"),       # beyond the field face
    ({"flange_root_radius": 0.05}, "wheel.flange_root_radius"),
    ({"fillet_radius": 0.06}, "wheel.fillet_radius"),          # 2 x 0.06 + web > rim width
    ({"fillet_radius": 0.05, "hub_length": 0.11}, "wheel.fillet_radius"),  # > hub - web
    ({"flange_tip_radius": 0.02}, "wheel.flange_tip_radius"),
    ({"web_offset": 0.05}, "wheel.web_offset"),
    ({"hub_length": 0.015}, "wheel.hub_length"),              # shorter than the web
    ({"colour": "red"}, "wheel.colour"),                      # unknown key
    ({"rim_width": "wide"}, "wheel.rim_width"),               # not a number
    ({"density": True}, "wheel.density"),
    ({"elements_around": 7.5}, "wheel.elements_around"),
    ({"elements_around": 2}, "wheel.elements_around"),
    ({"profile_file": 3}, "wheel.profile_file"),
])
def test_invalid_parameters_are_refused(mapping, field):
    with pytest.raises(InputError) as err:
        WheelParams.from_mapping(mapping)
    assert err.value.field == field
    assert "must" in err.value.message  # each message states what is allowed


def test_self_intersecting_or_open_profile_is_refused(tmp_path):
    bow_tie = np.array([[0.1, 0.0], [0.3, 0.1], [0.3, 0.0], [0.1, 0.1]])
    for path in (write_profile(tmp_path / "bow.txt", bow_tie),
                 write_profile(tmp_path / "open.txt", read_profile(DATA / "stepped_profile.txt"),
                               close=False),
                 write_profile(tmp_path / "axis.txt", np.array([[0.0, 0.0], [0.2, 0.0], [0.2, 0.1]])),
                 str(tmp_path / "missing.txt")):
        with pytest.raises(InputError) as err:
            WheelParams.from_mapping({"profile_file": path})
        assert err.value.field == "wheel.profile_file"
    with pytest.raises(InputError) as err:
        WheelParams.from_mapping({"profile_file": str(DATA / "stepped_profile.txt"),
                                  "contact_offset": 0.2})
    assert err.value.field == "wheel.contact_offset"


# ----------------------------------------------------------------------------------------------
# Profiles from files
# ----------------------------------------------------------------------------------------------
def test_stepped_profile_file_meshes_exactly():
    params = WheelParams.from_mapping({"profile_file": str(DATA / "stepped_profile.txt"),
                                       "section_element_size": 0.02, "elements_around": 12})
    mesh = mesh_wheel(params)
    exact = params.density * math.pi * ((0.09**2 - 0.05**2) * 0.10 + (0.25**2 - 0.09**2) * 0.02
                                        + (0.30**2 - 0.25**2) * 0.10)
    assert mesh.mass == pytest.approx(exact, rel=1e-12)
    # Straight edges: the quad8 map is exact and 3x3 Gauss integrates r det J exactly (1e-10).
    assert section_mass(mesh) == pytest.approx(exact, rel=1e-10)
    # 3D: every hex is (bilinear section map) x (parabola through three points of a circle
    # over 2a = 30 deg), which hex20 represents exactly, so the volume ratio is the parabolic
    # to circular sector area ratio, [sin a cos a + 4/3 sin a (1 - cos a)] / a = 1 - 1.553e-4.
    a = math.pi / params.elements_around
    ratio = (math.sin(a) * math.cos(a) + 4 / 3 * math.sin(a) * (1 - math.cos(a))) / a
    assert hex_mass(mesh) == pytest.approx(exact * ratio, rel=1e-10)
    # Contact at the outermost crossing of z = 0.07 (the rim outer face r = 0.30).
    assert np.allclose(mesh.section_nodes[mesh.contact_section_node], [0.30, 0.07], atol=1e-12)
    assert np.allclose(mesh.section_nodes[mesh.section_clamped_nodes, 0], 0.05, atol=1e-12)
    check_revolution(mesh)


def test_curved_profile_file_gives_its_pappus_mass(tmp_path):
    # A different wheel written as a finely sampled outline (arcs every 2 deg) and read back:
    # the file path uses splines between corners.
    other = WheelParams.from_mapping({"rolling_radius": 0.36, "rim_inner_radius": 0.315,
                                      "web_offset": 0.012, "hub_length": 0.14})
    points, _ = section_outline(other)
    path = write_profile(tmp_path / "wheel.txt", points)
    params = WheelParams.from_mapping({"profile_file": path, "section_element_size": 0.02,
                                       "elements_around": 12})
    pappus = params.density * 2 * math.pi * outline_area_moment(read_profile(path))[1]
    assert outline_mass(params) == pytest.approx(pappus, rel=1e-12)
    assert outline_mass(params) == pytest.approx(outline_mass(other), rel=1e-12)
    mesh = mesh_wheel(params)
    # Splines through 2-deg samples and quadratic elements: allow 0.5 % as for the default.
    assert abs(section_mass(mesh) / pappus - 1) < 0.005
    assert abs(hex_mass(mesh) / pappus - 1) < 0.005
    detJ, _, _ = section_jacobians(mesh.section_nodes, mesh.section_cells)
    assert detJ.min() > 0
    assert np.allclose(mesh.section_nodes[mesh.contact_section_node], [0.36, 0.07], atol=1e-9)
    check_revolution(mesh)


# ----------------------------------------------------------------------------------------------
# Output files
# ----------------------------------------------------------------------------------------------
def test_vtu_and_msh_output(coarse_mesh, tmp_path):
    vtu = tmp_path / "wheel.vtu"
    write_vtu(coarse_mesh, vtu)
    back = meshio.read(vtu)
    assert np.allclose(back.points, coarse_mesh.hex_nodes)
    assert np.array_equal(back.cells_dict["hexahedron20"], coarse_mesh.hex_cells)
    # Second method for the gmsh -> VTK permutation: meshio's own conversion of the .msh.
    msh = tmp_path / "wheel.msh"
    mesh = mesh_wheel(coarse_mesh.params, msh_path=msh)
    m = meshio.read(msh)
    hexes = m.cells_dict["hexahedron20"]
    _, to_ours = cKDTree(mesh.hex_nodes).query(m.points)
    converted = to_ours[hexes]
    ours = {tuple(c) for c in mesh.hex_cells}
    mirrored = {tuple(c) for c in mesh.hex_cells[:, [4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15,
                                                      8, 9, 10, 11, 16, 17, 18, 19]]}
    # Each meshio cell equals ours, or ours mirrored if we flipped it to positive volume.
    assert len(hexes) == len(mesh.hex_cells)
    assert all(tuple(c) in ours or tuple(c) in mirrored for c in converted)


def test_plots(coarse_mesh, tmp_path):
    for func, name in ((plot_section_mesh, "section.png"), (plot_wheel_3d, "wheel.png")):
        path = tmp_path / name
        func(coarse_mesh, path)
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert path.stat().st_size > 10_000


# ----------------------------------------------------------------------------------------------
# Tread profile (S1002) as the running surface
# ----------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def s1002_mesh():
    return mesh_wheel(WheelParams.from_mapping({"tread_profile": "S1002", "section_element_size": 0.02,
                                                "elements_around": 24}))


def _boundary_nodes(cells):
    """Corner and mid-side section nodes on boundary edges of quad8 cells."""
    pairs = cells[:, [[0, 1], [1, 2], [2, 3], [3, 0]]].reshape(-1, 2)
    mids = cells[:, 4:].reshape(-1)
    _, inverse, counts = np.unique(np.sort(pairs, axis=1), axis=0, return_inverse=True, return_counts=True)
    boundary = counts[inverse.reshape(-1)] == 1
    return np.unique(pairs[boundary].ravel()), np.unique(mids[boundary])


def test_s1002_mesh_outer_surface_follows_the_profile(s1002_mesh):
    p = s1002_mesh.params
    y0, y1 = 0.0005, 0.130  # extent of the shipped samples (m from the flange back)

    def height(y):  # the S1002 closed form, m
        return s1002_height((y - 0.070) * 1e3) * 1e-3

    corners, mids = _boundary_nodes(s1002_mesh.section_cells)
    nodes = s1002_mesh.section_nodes
    on = lambda idx: idx[(nodes[idx, 1] >= y0) & (nodes[idx, 1] <= y1)  # noqa: E731
                         & (nodes[idx, 0] > p.rim_inner_radius + 1e-6)]
    corners, mids = on(corners), on(mids)
    assert len(corners) >= 8 and len(mids) >= 8
    # Corner nodes lie on gmsh's spline through the 0.05 mm samples, mid-side nodes on their
    # polyline: both within the chord sagitta h^2 kappa / 8 of the exact curve (h <= 0.22 mm
    # along the steep flange back, kappa <= 1/12 mm: 0.5 um normal, 2.3 um vertically at the
    # slope 4.4 there), plus the 1.2e-4 mm rounding of the published coefficients: 3 um.
    for idx in (corners, mids):
        r, y = nodes[idx, 0], nodes[idx, 1]
        assert np.abs(r - p.rolling_radius - height(y)).max() < 3e-6
    # hex20: every node of the 3D wheel stays inside the running surface, and the rotated
    # tread nodes are on it (each corner node's circle carries 2 N nodes, each mid-side 1 N)
    X = s1002_mesh.hex_nodes
    r, y = np.hypot(X[:, 0], X[:, 2]), X[:, 1]
    inside = (y >= y0) & (y <= y1)
    gap = r[inside] - p.rolling_radius - height(y[inside])
    assert gap.max() < 3e-6
    assert np.sum(np.abs(gap) < 3e-6) == p.elements_around * (2 * len(corners) + len(mids))
    assert np.allclose(nodes[s1002_mesh.contact_section_node], [p.rolling_radius, p.contact_offset], atol=1e-12)


def test_s1002_mesh_mass_and_elements(s1002_mesh):
    m_outline = outline_mass(s1002_mesh.params)
    assert s1002_mesh.mass == pytest.approx(m_outline, rel=1e-12)
    # quadratic elements on the curved flange (radii 12-20.5 mm, element edges ~20 mm) and the
    # fillets: 0.5 % as for the default wheel
    assert abs(section_mass(s1002_mesh) / m_outline - 1) < 0.005
    assert abs(hex_mass(s1002_mesh) / m_outline - 1) < 0.005
    detJ, _, _ = section_jacobians(s1002_mesh.section_nodes, s1002_mesh.section_cells)
    assert detJ.min() > 0
    hexJ, _ = hex_jacobians(s1002_mesh.hex_nodes, s1002_mesh.hex_cells)
    assert hexJ.min() > 0
    check_revolution(s1002_mesh)


def test_turned_s1002_wheel_meshes_at_the_quick_size():
    # turned to 0.36 m (12 mm of rim left under the field-side chamfer) at the quick preset's
    # size: the revolved model once recombined the section differently from the trial mesh
    params = WheelParams.from_mapping({"tread_profile": "S1002", "rolling_radius": 0.36,
                                       "section_element_size": 0.02, "elements_around": 24})
    mesh = mesh_wheel(params)
    detJ, _, _ = section_jacobians(mesh.section_nodes, mesh.section_cells)
    assert detJ.min() > 0
    assert abs(section_mass(mesh) / outline_mass(params) - 1) < 0.005
    assert np.allclose(mesh.section_nodes[mesh.contact_section_node], [0.36, 0.07], atol=1e-12)
    check_revolution(mesh)
