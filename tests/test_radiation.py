"""The fast radiation model (radiation/): each part against something independent.

A-weighting against the IEC 61672-1 table, band sums and spectra against Parseval, the surface
integrals against the areas of a plate and a box, the per-pole vibration against the closed-form
steady-state response and the interaction's own recursion, the rail efficiency against the
cylinder's asymptotes, the line integral against the exponential's integral, and the energy
bookkeeping (radiated ≤ input power, with the ratio ζ_rad / ζ predicted per mode).
"""

import numpy as np
import pytest
from scipy.special import jn_zeros

from fe.greens import modal_poles_residues, receptance
from radiation.acoustics import AIR_DENSITY, SOUND_SPEED
from radiation.bands import a_weighting_db, band_sum, nominal_label, third_octave_centres
from radiation.efficiency import (cylinder_dipole_efficiency, rail_efficiency, wheel_axial_efficiency,
                                  wheel_radial_efficiency)
from radiation.grouping import case_key
from radiation.rail_power import line_integral
from radiation.receiver import GROUND_HEIGHT, RECEIVER_DISTANCE, RECEIVER_HEIGHT, geometric_factor
from stages.radiation_report import loudest_points
from radiation.spectra import one_sided_spectrum, window_slice
from radiation.surface import ModeSurfaces, hex_mode_surfaces, section_mode_surfaces
from radiation.thin_disc import baffled_piston_efficiency, piston_normal_velocity, thin_disc_triangles
from radiation.wheel_power import wheel_power
from radiation.wheel_vibration import contact_response, match_poles, mode_pairs, wheel_vibration
from squealcore.errors import InputError

# IEC 61672-1:2013 Table 3, A-weighting (dB) at nominal frequencies (exact base-10 mid-bands).
IEC_A = {31.62: -39.4, 100.0: -19.1, 1000.0: 0.0, 3981.0: 1.0, 10000.0: -2.5, 19950.0: -9.3}


def test_a_weighting_matches_the_iec_61672_table():
    for f, a in IEC_A.items():
        assert a_weighting_db(f) == pytest.approx(a, abs=0.06)  # table values rounded to 0.1 dB


def test_third_octave_bands_span_20_hz_to_12_5_khz_and_sum_like_parseval():
    centres = third_octave_centres()
    assert [nominal_label(f) for f in centres[[0, 17, -1]]] == ["20", "1k", "12.5k"]
    f = np.linspace(0.0, 20000.0, 20001)
    values = np.ones_like(f)
    inside = (f >= centres[0] * 10 ** -0.05) & (f < centres[-1] * 10 ** 0.05)
    assert band_sum(f, values, centres).sum() == pytest.approx(values[inside].sum())


def test_one_sided_spectrum_conserves_the_mean_square():
    dt, n = 1e-4, 4000
    t = np.arange(n) * dt
    sine = 3.0 * np.sin(2 * np.pi * 1250.0 * t)  # on a bin: the Hann estimate is exact
    _, a = one_sided_spectrum(sine, dt)
    assert np.sum(np.abs(a) ** 2) == pytest.approx(4.5, rel=1e-9)
    noise = np.random.default_rng(1).standard_normal(n)
    _, a = one_sided_spectrum(noise, dt)
    assert np.sum(np.abs(a) ** 2) == pytest.approx(np.var(noise), rel=0.05)  # estimate of a random signal


def _quad8_annulus(r1, r2, t):
    corners = np.array([[r1, 0.0], [r2, 0.0], [r2, t], [r1, t]])
    mids = 0.5 * (corners + np.roll(corners, -1, axis=0))
    return np.vstack([corners, mids]), np.arange(8)[None, :]


def test_section_surface_integrals_of_rigid_motions_are_the_areas():
    r1, r2, t = 0.1, 0.4, 0.02
    nodes, cells = _quad8_annulus(r1, r2, t)
    axial = np.zeros((1, 8, 3))
    axial[0, :, 1] = 1.0  # U_z = 1
    radial = np.zeros((1, 8, 3))
    radial[0, :, 0] = 1.0  # U_r = 1 (the bore does not radiate)
    for n, around in ((0, 1.0), (2, 0.5)):  # cos² nθ averages to 1/2 for n >= 1
        s = section_mode_surfaces(nodes, cells, np.concatenate([axial, radial]), [n, n])
        face = np.pi * (r2**2 - r1**2)
        assert s.axial[0] == pytest.approx(2 * face * around, rel=1e-12)
        assert s.radial[1] == pytest.approx(2 * np.pi * r2 * t * around, rel=1e-12)
        assert s.radial[0] == pytest.approx(0.0, abs=1e-15) and s.axial[1] == pytest.approx(0.0, abs=1e-15)
    assert s.area_axial == pytest.approx(2 * face) and s.area_radial == pytest.approx(2 * np.pi * r2 * t)


def _hex20_box(x0, x1, y0, y1, z0, z1):
    corners = np.array([[x0, y0, z0], [x1, y0, z0], [x1, y1, z0], [x0, y1, z0],
                        [x0, y0, z1], [x1, y0, z1], [x1, y1, z1], [x0, y1, z1]])
    edges = [(0, 1), (1, 2), (2, 3), (3, 0), (4, 5), (5, 6), (6, 7), (7, 4), (0, 4), (1, 5), (2, 6), (3, 7)]
    mids = np.array([0.5 * (corners[a] + corners[b]) for a, b in edges])
    return np.vstack([corners, mids]), np.arange(20)[None, :]


def test_hex_surface_integrals_of_rigid_motions_are_the_face_areas():
    # a box beside the axle (Y axis) at X in [1, 1.2]: its ±Y faces are axial, the outer X face and the
    # ±Z faces radial-facing, the inner X face is the "bore" (smallest radius) and does not radiate
    nodes, cells = _hex20_box(1.0, 1.2, 0.0, 0.1, -0.05, 0.05)
    shapes = np.zeros((2, 20, 3))
    shapes[0, :, 1] = 1.0  # along the axle
    shapes[1, :, 0] = 1.0  # along X (radial at θ = 90°)
    s = hex_mode_surfaces(nodes, cells, shapes)
    assert s.axial[0] == pytest.approx(2 * 0.2 * 0.1, rel=1e-12)
    assert s.radial[1] == pytest.approx(0.1 * 0.1, rel=1e-12)  # the outer face only
    assert s.radial[0] == pytest.approx(0.0, abs=1e-15)


def _single_mode(f0=1000.0, zeta=0.02, shape=(0.0, 0.08, -0.02)):
    return {"frequency": np.array([f0]), "damping_ratio": np.array([zeta]), "nodal_diameters": np.array([3]),
            "contact_shape": np.array([shape])}


def _harmonic_force(f, amplitude, dt, n):
    t = np.arange(n) * dt
    force = np.zeros((n, 3))
    force[:, 1] = amplitude * np.sin(2 * np.pi * f * t)
    return force


def test_modal_velocity_matches_the_closed_form_steady_state():
    modes = _single_mode()
    poles, residues = modal_poles_residues(modes["frequency"], modes["damping_ratio"], modes["contact_shape"])
    surfaces = ModeSurfaces(np.array([0.01]), np.array([0.002]), 1.0, 0.5, 0.45, 0.13)
    dt, n, f = 2e-5, 60000, 930.0  # 1.2 s: the transient (time constant 8 ms) has died out
    force = _harmonic_force(f, 100.0, dt, n)
    window = slice(n - 10000, n)
    vib = wheel_vibration(poles, residues, modes, surfaces, force, dt, travelling=False, window=window)
    omega, omega0 = 2 * np.pi * f, 2 * np.pi * modes["frequency"][0]
    phi_y = modes["contact_shape"][0, 1]
    amplitude = omega * phi_y * 100.0 / abs(omega0**2 - omega**2 + 2j * 0.02 * omega0 * omega)
    assert np.sqrt(np.mean(vib.velocity[0, window] ** 2)) == pytest.approx(amplitude / np.sqrt(2), rel=2e-3)
    # the sum over poles is the contact velocity of the closed-form receptance
    v = contact_response(poles, residues, force, dt)[window, 1]
    h = receptance(poles, residues, np.array([f]))[0, 1, 1]
    assert np.sqrt(np.mean(v**2)) == pytest.approx(omega * abs(h) * 100.0 / np.sqrt(2), rel=2e-3)
    # and the power the force puts in is ½ |F|² Re(i ω H)
    assert vib.input_power[0] == pytest.approx(0.5 * 100.0**2 * np.real(1j * omega * h), rel=2e-3)


def test_pole_displacements_reproduce_the_interaction_recursion():
    from interaction.structures import ModalStructure

    modes = _single_mode()
    poles, residues = modal_poles_residues([500.0, 1700.0], [0.01, 0.003], [[0.0, 0.05, 0.01], [0.01, -0.02, 0.07]])
    dt, n = 3e-5, 3000
    force = np.random.default_rng(3).standard_normal((n, 3)) * 50.0
    structure = ModalStructure(poles, residues, dt)
    expected = np.empty((n, 3))
    for k in range(n):
        expected[k] = structure.displacement(structure.history(), force[k])
        structure.commit(force[k])
    got = contact_response(poles, residues, force, dt, quantity="displacement")
    assert np.max(np.abs(got - expected)) <= 1e-12 * np.max(np.abs(expected))
    del modes


@pytest.mark.parametrize("zeta", [0.02, 1e-4])
def test_radiated_power_over_input_power_is_the_radiation_damping_over_the_damping(zeta):
    """Energy bookkeeping: in steady state a mode dissipates all the power the force puts in
    (``P_in = 2 ζ ω_r <q̇²>``, time domain) and radiates ``ρ c σ I <q̇²>`` (frequency domain), so
    ``W / P_in = ζ_rad / ζ`` with ``ζ_rad = ρ c σ I / (2 ω_r)``; W ≤ P_in exactly when ζ ≥ ζ_rad."""
    f0 = 1000.0
    modes = _single_mode(f0, zeta)
    poles, residues = modal_poles_residues(modes["frequency"], modes["damping_ratio"], modes["contact_shape"])
    surfaces = ModeSurfaces(np.array([2e-4]), np.array([0.0]), 1.0, 0.5, 0.45, 0.13)
    dt = 2e-5
    n_window = 5000  # 0.1 s: 100 periods at 1000 Hz, on a bin of the window
    n = 1 + int(6.0 / (2 * np.pi * f0 * zeta) / dt) if zeta > 1e-3 else 80000
    force = _harmonic_force(f0, 100.0, dt, n + n_window)
    window = slice(n, n + n_window)
    vib = wheel_vibration(poles, residues, modes, surfaces, force, dt, travelling=False, window=window)
    radiated = wheel_power(vib, window, dt, 0.45, 0.13).total
    supplied = vib.input_power.sum()
    sigma = wheel_axial_efficiency(f0, 3, 0.45)
    zeta_rad = AIR_DENSITY * SOUND_SPEED * sigma * 2e-4 / (2 * 2 * np.pi * f0)
    if zeta > 1e-3:  # steady state reached: the identity holds
        assert radiated / supplied == pytest.approx(zeta_rad / zeta, rel=1e-2)
        assert radiated <= supplied
    else:  # 1e-4 > ζ_rad: still building up, input > dissipation > radiation
        assert zeta_rad < zeta
        assert radiated <= supplied


def test_a_pole_listed_twice_radiates_like_the_pole_once():
    """The same system written with one pole split in two (residues 3R and -2R, as a model may list
    a travelling wave once per partner of its pair): the contact velocity is the same, and so
    must be the radiated power and the input power (summed before squaring, not after)."""
    modes = _single_mode(1000.0, 0.01)
    poles, residues = modal_poles_residues(modes["frequency"], modes["damping_ratio"], modes["contact_shape"])
    surfaces = ModeSurfaces(np.array([2e-4]), np.array([1e-4]), 1.0, 0.5, 0.45, 0.13)
    dt, n = 2e-5, 20000
    force = _harmonic_force(1000.0, 100.0, dt, n)
    window = slice(n - 5000, n)
    split_poles = np.concatenate([poles, poles])
    split_residues = np.concatenate([3.0 * residues, -2.0 * residues])
    assert np.allclose(contact_response(split_poles, split_residues, force, dt), contact_response(poles, residues, force, dt),
                       rtol=0.0, atol=1e-12 * np.abs(contact_response(poles, residues, force, dt)).max())
    one = wheel_vibration(poles, residues, modes, surfaces, force, dt, travelling=True, window=window)
    two = wheel_vibration(split_poles, split_residues, modes, surfaces, force, dt, travelling=True, window=window)
    assert len(two.frequency) == 1
    assert wheel_power(two, window, dt, 0.45, 0.13).total == pytest.approx(wheel_power(one, window, dt, 0.45, 0.13).total,
                                                                           rel=1e-9)
    assert two.input_power.sum() == pytest.approx(one.input_power.sum(), rel=1e-9)


def test_a_repeated_pole_with_two_shapes_radiates_its_summed_motion():
    """A pole listed twice with residues of different shapes (their sum of rank two, so the two
    are computed apart and summed): the merged modal velocity is the projection of the model's
    whole contact velocity on the mode's contact shape."""
    modes = _single_mode(1000.0, 0.01)
    poles, residues = modal_poles_residues(modes["frequency"], modes["damping_ratio"], modes["contact_shape"])
    other = np.outer([0.0, 0.01, 0.03], [0.02, 0.0, 0.01]) / (2j * 2 * np.pi * 1000.0)
    split_poles, split_residues = np.concatenate([poles, poles]), np.concatenate([residues, other[None]])
    surfaces = ModeSurfaces(np.array([2e-4]), np.array([1e-4]), 1.0, 0.5, 0.45, 0.13)
    dt, n = 2e-5, 20000
    force = np.random.default_rng(5).standard_normal((n, 3)) * 30.0
    vib = wheel_vibration(split_poles, split_residues, modes, surfaces, force, dt, travelling=True)
    phi = modes["contact_shape"][0]
    expected = contact_response(split_poles, split_residues, force, dt) @ (phi / (phi @ phi))
    assert vib.velocity.shape == (1, n)
    assert np.max(np.abs(np.abs(vib.velocity[0]) - np.abs(expected))) <= 1e-9 * np.max(np.abs(expected))


def test_rotating_poles_take_the_pair_of_their_harmonic_and_twice_its_surface():
    frequency = np.array([400.0, 400.0, 1100.0, 1100.0])
    nd = np.array([2, 2, 3, 3])
    shapes = np.array([[0.0, 0.06, 0.01], [0.0, 0.08, 0.0], [0.0, 0.03, 0.04], [0.02, 0.0, 0.0]])
    group, cos_shape = mode_pairs(frequency, nd, shapes)
    assert list(group) == [0, 0, 1, 1]
    assert np.linalg.norm(cos_shape[0]) ** 2 == pytest.approx(np.linalg.eigvalsh(shapes[:2].T @ shapes[:2])[-1])
    spin = 2 * np.pi * 5.0  # 5 Hz: shifts 10 and 15 Hz
    assert list(match_poles([390.0, 410.0, 1085.0, 1116.0], frequency, nd, spin)) == [0, 0, 2, 2]


def test_cylinder_efficiency_has_its_asymptotes():
    assert cylinder_dipole_efficiency(1e-2) == pytest.approx(np.pi / 2 * 1e-6, rel=1e-3)  # σ → (π/2)(ka)³
    assert cylinder_dipole_efficiency(200.0) == pytest.approx(1.0, rel=5e-3)
    # the rail: efficient (> 0.8) above 2 kHz, weak (< 0.1) at 200 Hz, vertical (foot 0.13 m)
    assert rail_efficiency(2000.0, 0.133) > 0.8 and rail_efficiency(200.0, 0.133) < 0.1


def test_wheel_efficiencies_rise_to_one_and_fall_faster_for_more_nodal_diameters():
    f = np.array([30.0, 20000.0])
    for n in range(8):
        ax = wheel_axial_efficiency(f, n, 0.42)
        rad = wheel_radial_efficiency(f, n, 0.42, 0.135)
        assert ax[1] > 0.95 and rad[1] > 0.95 and ax[0] < 0.1
    assert wheel_axial_efficiency(500.0, 6, 0.42) < wheel_axial_efficiency(500.0, 2, 0.42)


def test_line_integral_of_an_exponential_decay():
    x = np.linspace(0.0, 3.0, 31)
    beta = 1.7
    # trapezoids (relative error (β Δx)² / 12 = 0.24 %) + the exact tail beyond 3 m
    assert line_integral(x, np.exp(-beta * x)) == pytest.approx(2.0 / beta, rel=(beta * 0.1) ** 2 / 12 * 1.05)


def test_receiver_geometry_adds_the_ground_image():
    g = geometric_factor(0.75, 0.5)
    d2 = (RECEIVER_DISTANCE - 0.75) ** 2
    assert g == pytest.approx(1 / (d2 + (RECEIVER_HEIGHT - 0.5) ** 2)
                              + 1 / (d2 + (RECEIVER_HEIGHT + 0.5 - 2 * GROUND_HEIGHT) ** 2))
    assert 2.5 < 10 * np.log10(g * d2) < 3.0  # hard ground: +3 dB less the longer image path


def test_case_key_pairs_the_wheel_models():
    keys = {case_key(f"friction=0.6_lateral_creepage=-0.01_wheel_model={m}-0123abcd")
            for m in ("stationary", "moving_load", "eulerian")}
    assert keys == {"friction=0.6_lateral_creepage=-0.01"}


def test_the_spectra_figure_keeps_the_loudest_operating_points():
    results = [{"case_id": f"friction={mu}_wheel_model={m}-0123abcd", "wheel_model": m, "L_pA": level}
               for mu, level in ((0.1, 50.0), (0.2, 90.0), (0.3, 70.0)) for m in ("stationary", "eulerian")]
    kept = loudest_points(results, limit=2)
    assert sorted({r["case_id"].split("_")[0] for r in kept}) == ["friction=0.2", "friction=0.3"]
    assert len(kept) == 4 and loudest_points(results, limit=3) == results


def test_the_spectrum_window_is_the_l_f2_window():
    # the last rms_window seconds, or the whole history when it is shorter (as L_F2 takes it)
    assert window_slice(1000, 1e-3, 0.15) == slice(850, 1000)
    assert window_slice(100, 1e-3, 0.15) == slice(0, 100)
    with pytest.raises(InputError, match="simulation.rms_window"):
        window_slice(1000, 1e-3, 0.01)




def test_axial_efficiency_of_n_0_lies_between_the_thin_disc_and_the_rim_corner_and_n_1_below_it():
    """n = 0 axial (corner fitted to the wheel's BEM): at low frequency (ka = 0.1) σ_ax lies above a
    thin rigid disc's closed-form limit 8(ka)⁴/(27π²) (dipole of the entrained mass 8ρa³/3, Lamb
    §108: the thick wheel entrains more) and below the rim-corner law 1/(1 + (1/ka)⁴); the n = 1
    rocking (a dipole through the wheel's asymmetry, weaker) radiates less than n = 0 from
    ka = 0.1 to 10."""
    radius = 0.42
    ka = np.geomspace(0.1, 10.0, 41)
    f = ka * SOUND_SPEED / (2 * np.pi * radius)
    sigma_0 = wheel_axial_efficiency(f, 0, radius)
    assert 8.0 * ka[0] ** 4 / (27.0 * np.pi ** 2) < sigma_0[0] < 1.0 / (1.0 + ka[0] ** -4)
    assert np.all(wheel_axial_efficiency(f, 1, radius) < sigma_0)


def test_baffled_piston_efficiency_has_its_series_and_reaches_one_at_the_first_zero_of_j1():
    """σ = 1 - J₁(2ka)/(ka): (ka)²/2 - (ka)⁴/12 + O((ka)⁶) from the series of J₁ (next term
    (ka)⁶/144, 1e-7 relative at ka = 0.05), and exactly 1 where J₁(2ka) = 0 (2ka = 3.8317)."""
    ka = 0.05
    assert baffled_piston_efficiency(ka) == pytest.approx(ka**2 / 2 - ka**4 / 12, rel=1e-6)
    assert baffled_piston_efficiency(jn_zeros(1, 1)[0] / 2) == pytest.approx(1.0, abs=1e-12)


def test_thin_disc_mesh_is_closed_outward_and_moves_its_two_faces():
    """The gmsh disc (a = 0.5 m, t = 0.05 m): every edge shared by two triangles with opposite
    directions (closed, consistently oriented); the divergence theorem ⅓∮x·n dS gives the volume
    πa²t and ∮n dS = 0; the moving faces' area is 2πa² (inscribed polygon of N sides:
    relative deficit ≈ (2π/N)²/6, under 0.2 % here) and the rim does not move."""
    a, t = 0.5, 0.05
    vertices, triangles = thin_disc_triangles(a, t, face_size=0.1, rim_size=0.025, grading_distance=0.15)
    edges = np.concatenate([triangles[:, [0, 1]], triangles[:, [1, 2]], triangles[:, [2, 0]]])
    directed = {tuple(e) for e in edges}
    assert len(directed) == len(edges)  # no edge twice in the same direction
    assert all((j, i) in directed for i, j in directed)  # each one also in the other direction
    xyz = vertices[triangles]
    cross = np.cross(xyz[:, 1] - xyz[:, 0], xyz[:, 2] - xyz[:, 0])  # 2 × area × unit normal
    volume = np.einsum("ti,ti->", xyz.mean(axis=1), cross) / 6.0
    rim_points = np.hypot(vertices[:, 0], vertices[:, 1]) > a * (1 - 1e-9)
    n_sides = int(np.sum(rim_points & (np.abs(vertices[:, 2] - t / 2) < 1e-12)))  # top edge
    deficit = (2 * np.pi / n_sides) ** 2 / 6
    assert volume == pytest.approx(np.pi * a**2 * t, rel=2 * deficit)
    assert np.abs(cross.sum(axis=0)).max() < 1e-12
    velocity = piston_normal_velocity(vertices, triangles)
    moving_area = 0.5 * np.sum(np.linalg.norm(cross, axis=1) * velocity)
    assert moving_area == pytest.approx(2 * np.pi * a**2, rel=2 * deficit)
    assert deficit < 0.002
    assert np.all(np.abs(xyz[velocity == 0][..., 2]).max(axis=1) <= t / 2 + 1e-12)
