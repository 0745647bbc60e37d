"""The contact frame inclined by the contact angle, and the wheel at the computed contact point."""

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from fe.greens import modal_poles_residues, ramp_invariant_kernel, static_compliance
from fe.rotation import EulerianModel, RotationMatrices
from fe.wheel_modes import (WheelModes, contact_shapes_at, edge3_shape_functions, running_surface_point)
from contact.hertz import hertz_from_curvatures
from contact.params import Friction, Material, contact_curvatures
from contact.point.model import PointContact
from interaction.frame import contact_rotation, static_normal_force, to_body_frame, to_contact_frame
from interaction.simulate import simulate
from interaction.structures import ConvolutionStructure, ModalStructure
from stages.cases import contact_hertz, imposed_creepage, manual_contact
from stages.config import load_study
from stages.wheel import WheelContact, rotating_at

DT = 3.6e-5
SPEED = 50 / 3.6
LOAD = 50e3
MATERIAL = Material.from_young(210e9, 0.3)

# wheel and rail with vertical/lateral coupling at the contact (shapes in m/sqrt(kg), body frames)
WHEEL = ([410.0, 1120.0, 2010.0], [1e-3, 1e-4, 1e-4],
         np.array([[0.0, 0.12, 0.01], [0.002, 0.11, -0.02], [0.0, 0.09, 0.03]]))
RAIL = ([330.0, 900.0], [0.15, 0.2], np.array([[0.0, 0.05, 0.0], [0.0, 0.0, 0.17]]))


def _point_contact(normal_force, mu=0.3):
    hertz = hertz_from_curvatures(1 / 0.78, 1 / 0.6, normal_force, MATERIAL.contact_modulus)
    return PointContact(material=MATERIAL, friction=Friction(mu), hertz=hertz, kind="transient", speed=SPEED,
                        time_step=DT)


def _structures(angle, wheel=WHEEL, rail=RAIL, n_rail=800):
    """Wheel recursion and rail convolution turned into the contact frame inclined by ``angle``."""
    poles, residues = modal_poles_residues(*wheel)
    kernel = ramp_invariant_kernel(*modal_poles_residues(*rail), DT, n_rail)
    return (ModalStructure(poles, to_contact_frame(residues, angle), DT),
            ConvolutionStructure(to_contact_frame(kernel, angle), DT))


# ---- rotation ----

def test_zero_angle_reproduces_the_upright_run_bit_for_bit():
    # The upright model of today (structures and preload as the interaction always took them)
    # against the same run through the contact frame with angle 0: every history identical (==).
    n = 2000
    poles, residues = modal_poles_residues(*WHEEL)
    kernel = ramp_invariant_kernel(*modal_poles_residues(*RAIL), DT, 800)
    for compiled in (True, False):
        upright = simulate(ModalStructure(poles, residues, DT), ConvolutionStructure(kernel, DT), _point_contact(LOAD),
                           speed=SPEED, wheel_load=LOAD, creepage=(0.0, -0.01, 0.0), n_steps=n, compiled=compiled)
        wheel, rail = _structures(0.0)
        normal = static_normal_force(LOAD, 0.0)
        framed = simulate(wheel, rail, _point_contact(normal), speed=SPEED, wheel_load=normal,
                          creepage=(0.0, -0.01, 0.0), n_steps=n, compiled=compiled)
        for name in ("force", "creepage", "wheel_displacement", "rail_displacement", "wheel_velocity",
                     "rail_velocity", "slip_fraction", "iterations"):
            assert np.array_equal(getattr(upright, name), getattr(framed, name)), name
        assert np.abs(upright.force[:, 1]).max() > 0.1 * LOAD  # a run that does something


def test_manual_contact_at_zero_angle_is_todays_hertz_contact():
    # contact.geometry = "manual" with the default contact angle 0: Hertz from the hand-set
    # curvatures at the wheel load exactly as before the contact frame, spin = contact.spin.
    study = load_study(quick=True, assignments=["contact.geometry=manual", "contact.spin=0.25"])
    _, hertz = contact_hertz(study, manual_contact(study))
    curvatures = contact_curvatures(study["wheel"]["rolling_radius"], study["contact"]["wheel_transverse_curvature"],
                                    study["contact"]["rail_head_radius"])
    before = hertz_from_curvatures(*curvatures, study["operating"]["wheel_load"], MATERIAL.contact_modulus)
    assert hertz == before
    point = manual_contact(study)
    assert point.normal_force == study["operating"]["wheel_load"]
    assert imposed_creepage(study, point) == (study["contact"]["longitudinal_creepage"],
                                              study["contact"]["lateral_creepage"], 0.25)


def test_rotation_of_a_diagonal_receptance_matches_the_closed_form():
    # H = diag(hx, hy, hz) seen in the frame with normal n = (0, -sin a, cos a):
    # H'zz = n.H.n = hy sin^2 a + hz cos^2 a, H'yy = hy cos^2 a + hz sin^2 a, H'yz = (hz - hy) sin a cos a.
    a = 0.37
    hx, hy, hz = 1.0e-9 + 2e-10j, 3.0e-9 - 1e-10j, 0.7e-9 + 5e-11j
    h = to_contact_frame(np.diag([hx, hy, hz]), a)
    s, c = math.sin(a), math.cos(a)
    expected = np.array([[hx, 0, 0], [0, hy * c * c + hz * s * s, (hz - hy) * s * c],
                         [0, (hz - hy) * s * c, hy * s * s + hz * c * c]])
    assert np.abs(h - expected).max() <= 1e-15 * abs(hy)


def test_rotation_leaves_isotropic_receptances_unchanged_and_inverts():
    rng = np.random.default_rng(3)
    a = -0.61
    isotropic = (2.0e-9 - 3e-10j) * np.eye(3)
    assert np.abs(to_contact_frame(isotropic, a) - isotropic).max() <= 1e-15 * 2e-9
    # lateral/vertical isotropy: diag(hx, h, h) is unchanged by any turn about x
    transverse = np.diag([1.0, 4.0, 4.0])
    assert np.abs(to_contact_frame(transverse, a) - transverse).max() <= 1e-15 * 4.0
    stack = rng.normal(size=(5, 3, 3))
    back = to_contact_frame(to_contact_frame(stack, a), -a)
    assert np.abs(back - stack).max() <= 1e-14
    rotation = contact_rotation(a)
    assert np.abs(rotation @ rotation.T - np.eye(3)).max() <= 1e-15
    assert np.abs(np.linalg.det(rotation) - 1.0) <= 1e-15
    vectors = rng.normal(size=(4, 3))
    assert np.abs(to_body_frame(np.einsum("ij,nj->ni", rotation, vectors), a) - vectors).max() <= 1e-15


@pytest.mark.parametrize("angle", [0.3, -0.2])
def test_inclined_contact_static_equilibrium(angle):
    # The preload N = Q / cos(angle) along the inclined normal has the vertical component Q, and
    # its lateral one -Q tan(angle) (towards the gauge side for angle > 0).
    normal = static_normal_force(LOAD, angle)
    track = to_body_frame(np.array([0.0, 0.0, normal]), angle)
    assert abs(track[2] - LOAD) <= 1e-12 * LOAD
    assert abs(track[1] + LOAD * math.tan(angle)) <= 1e-12 * LOAD
    assert track[0] == 0.0
    # Quasi-static state of the coupled run under a constant extra approach e: without creepage
    # the tangential forces vanish and the normal force solves the Hertz law with the structures'
    # static compliance along the inclined normal, c = n.(Hw(0) + Hr(0)).n, computed here from
    # the upright structures and n directly:
    #   delta_s (N / N_s)^(2/3) = delta_s + e - c (N - N_s).
    wheel_modes = (WHEEL[0], [0.05, 0.05, 0.05], WHEEL[2])  # damped: the transient is gone after 0.4 s
    n_rail = 3000
    wheel, rail = _structures(angle, wheel=wheel_modes, n_rail=n_rail)
    contact = _point_contact(normal)
    n = int(round(0.4 / DT))
    e = 2e-6
    result = simulate(wheel, rail, contact, speed=SPEED, wheel_load=normal, creepage=(0.0, 0.0, 0.0), n_steps=n,
                      excitation=np.full(n, e))
    n_vec = np.array([0.0, -math.sin(angle), math.cos(angle)])
    compliance = (static_compliance(*modal_poles_residues(*wheel_modes))
                  + ramp_invariant_kernel(*modal_poles_residues(*RAIL), DT, n_rail).sum(axis=0))
    c = n_vec @ compliance @ n_vec
    delta_s = result.static_approach
    final = brentq(lambda f: delta_s * (f / normal) ** (2 / 3) - delta_s - e + c * (f - normal), normal, 2 * normal,
                   xtol=1e-9, rtol=1e-14)
    assert final > normal * (1 + 1e-3)  # the test moves the force measurably
    # 1e-7: the transients (slowest decay 1/(0.05 * 2 pi 410 Hz) = 7.8 ms) are down to e^-51 after 0.4 s;
    # what remains is the coupling tolerance (1e-9 Q) and the rail kernel's truncation (e^-150).
    assert abs(result.force[-1, 2] - final) <= 1e-7 * normal
    assert np.abs(result.force[-1, :2]).max() <= 1e-7 * normal


def test_contact_angle_out_of_range_is_refused():
    from squealcore.errors import InputError

    with pytest.raises(InputError, match="contact.contact_angle"):
        contact_rotation(1.6)


# ---- the wheel at the computed contact ----

def _section_mesh():
    """Two quad8 columns r in [0.30, 0.35] and [0.35, 0.40], two rows z in [0, 0.06], [0.06, 0.12] (m)."""
    r_lines, z_lines = np.linspace(0.30, 0.40, 5), np.linspace(0.0, 0.12, 5)
    index = {}
    nodes = []

    def node(i, j):
        if (i, j) not in index:
            index[(i, j)] = len(nodes)
            nodes.append((r_lines[i], z_lines[j]))
        return index[(i, j)]

    cells = []
    for i in (0, 2):
        for j in (0, 2):
            corners = [node(i, j), node(i + 2, j), node(i + 2, j + 2), node(i, j + 2)]
            mids = [node(i + 1, j), node(i + 2, j + 1), node(i + 1, j + 2), node(i, j + 1)]
            cells.append(corners + mids)
    return np.array(nodes), np.array(cells)


def _quadratic(z):
    """A field quadratic along the tread (three components, m/sqrt(kg))."""
    return np.stack([0.3 - 2.0 * z + 7.0 * z**2, 1.1 + 0.5 * z - 3.0 * z**2, -0.2 + 4.0 * z**2], axis=-1)


def _hex20_modes(section_nodes):
    """A fake hex20 model: the section nodes at theta = 0, (0, z, -r), among other nodes; one mode per
    scale of the quadratic field."""
    theta0 = np.column_stack([np.zeros(len(section_nodes)), section_nodes[:, 1], -section_nodes[:, 0]])
    others = theta0 + np.array([0.05, 0.0, 0.0])
    hex_nodes = np.vstack([others, theta0])
    field = _quadratic(hex_nodes[:, 1])
    shapes = np.stack([field, -2.5 * field])
    modes = WheelModes(np.array([500.0, 900.0]), np.array([2, 3]), np.zeros(2, int), np.array(["axial"] * 2),
                       np.array(["", ""]), np.zeros((2, 3)), shapes, "hex20")
    return modes, hex_nodes


def test_surface_point_is_on_the_outermost_edge():
    nodes, cells = _section_mesh()
    point = running_surface_point(nodes, cells, 0.083, rolling_radius=0.40)
    assert abs(point.position[0] - 0.40) <= 1e-15
    assert abs(point.position[1] - 0.083) <= 1e-15
    assert abs(point.weights.sum() - 1.0) <= 1e-15


def test_interpolation_at_a_node_equals_the_nodal_value():
    nodes, cells = _section_mesh()
    modes, hex_nodes = _hex20_modes(nodes)
    for z in (0.03, 0.06, 0.12):
        point = running_surface_point(nodes, cells, z)
        got = contact_shapes_at(point, modes, nodes, hex_nodes)
        assert np.abs(got - np.stack([_quadratic(z), -2.5 * _quadratic(z)])).max() <= 1e-12


def test_interpolation_between_nodes_reproduces_a_quadratic_exactly():
    # edge3 shape functions are exact for quadratics in the edge coordinate (straight edge, mid
    # node at the middle: the coordinate is linear in z)
    nodes, cells = _section_mesh()
    modes, hex_nodes = _hex20_modes(nodes)
    for z in (0.0071, 0.0449, 0.0777, 0.1163):
        point = running_surface_point(nodes, cells, z)
        got = contact_shapes_at(point, modes, nodes, hex_nodes)
        assert np.abs(got - np.stack([_quadratic(z), -2.5 * _quadratic(z)])).max() <= 1e-12
    xi = 0.3
    assert np.abs(edge3_shape_functions(xi) @ np.array([-1.0, 0.0, 1.0]) ** 2 - xi**2) <= 1e-15


def test_axisymmetric_interpolation_at_a_node_equals_the_reconstructed_shape():
    from fe.axisymmetric import reconstruct

    nodes, cells = _section_mesh()
    rng = np.random.default_rng(5)
    amplitudes = rng.normal(size=(2, len(nodes), 3))
    modes = WheelModes(np.array([500.0, 900.0]), np.array([0, 2]), np.zeros(2, int), np.array(["axial"] * 2),
                       np.array(["cos", "sin"]), np.zeros((2, 3)), amplitudes, "axisymmetric")
    point = running_surface_point(nodes, cells, 0.09)
    node = point.nodes[np.argmax(point.weights)]
    got = contact_shapes_at(point, modes, nodes)
    for k, (n, fam) in enumerate(zip(modes.nodal_diameters, modes.orientation)):
        expected = reconstruct(amplitudes[k][[node]], n, fam, nodes[[node]], np.array([0.0]))[0, 0]
        assert np.abs(got[k] - expected).max() <= 1e-12


def test_rotating_models_spin_at_the_geometry_rolling_radius():
    nodes, cells = _section_mesh()
    m = 2
    axi = WheelModes(np.array([500.0, 900.0]), np.array([2, 3]), np.zeros(m, int), np.array(["axial"] * m),
                     np.array(["cos", "cos"]), np.zeros((m, 3)), np.ones((m, len(nodes), 3)), "axisymmetric")
    model = EulerianModel(axi.frequency, np.full(m, 0.01), np.ones((m, 3)),
                          RotationMatrices(np.zeros((m, m)), np.zeros((m, m)), None))
    mesh = {"contact_position": np.array([0.0, 0.07, -0.40]), "contact_section_node": 0, "contact_hex_node": 0}
    base = {"modes": axi, "zeta": np.full(m, 0.01), "model": model, "switches": {"centrifugal": False}, "axi": axi,
            "axi_zeta": np.full(m, 0.01), "mesh": mesh, "rotation": {"moving_load_path": "harmonic"}}
    point = running_surface_point(nodes, cells, 0.05)
    shapes = np.array([[0.1, 0.2, 0.3], [0.4, 0.5, 0.6]])
    out = rotating_at(base, SPEED, WheelContact(point, shapes, 0.385, -1))
    assert out["spin"] == SPEED / 0.385
    assert np.array_equal(out["model"].contact_shape, shapes)
    node = rotating_at(base, SPEED)
    assert node["spin"] == SPEED / 0.40


def test_vectors_and_matrices_turn_alike():
    # a mode shape phi gives the residue phi phi^T: turning the shape (R phi) and turning the
    # residue (R phi phi^T R^T) agree
    from interaction.frame import vectors_to_contact_frame

    phi = np.array([0.01, 0.12, -0.03])
    a = 0.21
    turned = vectors_to_contact_frame(phi, a)
    assert np.abs(np.outer(turned, turned) - to_contact_frame(np.outer(phi, phi), a)).max() <= 1e-16
    assert np.abs(to_body_frame(turned, a) - phi).max() <= 1e-16


def test_computed_contact_is_the_one_source_of_the_case():
    # contact.geometry = "profiles": the Hertz patch, the static normal force and the spin of a
    # case all come from the ContactPoint (not from wheel.rolling_radius or contact.spin)
    from contact_geometry.contact_point import ContactPoint

    study = load_study(quick=True, assignments=["contact.spin=0.5", "wheel.rolling_radius=0.45"])
    assert study["contact"]["geometry"] == "profiles"
    load = study["operating"]["wheel_load"]
    angle, radius = 0.05, 0.38
    normal = load / math.cos(angle)
    expected = hertz_from_curvatures(0.5 * math.cos(angle) / radius, 1.5, normal, MATERIAL.contact_modulus)
    point = ContactPoint(lateral_displacement=0.0, wheel_lateral=0.072, rail_lateral=0.001, rail_section_lateral=0.002,
                         rail_section_height=0.155, rolling_radius=radius, contact_angle=angle,
                         rail_section_angle=angle - math.atan(1 / 30), curvature_long=math.cos(angle) / radius,
                         curvature_lat=3.0, semi_axis_a=expected.a, semi_axis_b=expected.b, normal_force=normal,
                         spin=math.sin(angle) / radius, n_contacts=1)
    _, hertz = contact_hertz(study, point)
    assert hertz == expected
    assert imposed_creepage(study, point) == (study["contact"]["longitudinal_creepage"],
                                              study["contact"]["lateral_creepage"], -math.sin(angle) / radius)
