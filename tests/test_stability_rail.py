"""Linear stability with the flexible rail: the vector fit of the rail's receptance
(stability/rational.py) and the closed wheel-contact-rail loop (stability/screen.py).

References: a known rational function (the fit must recover its poles); the rail's receptance
by the wave sum on samples the fit never saw, and the moving receptance's wavenumber integral
against the wave sum as v -> 0; the rigid-rail eigenvalues of
stability.linear.pole_residue_eigenvalues; the closed-form characteristic polynomial of a
one-mode wheel on a one-mode rail."""

import numpy as np
import pytest

from fe.greens import modal_poles_residues
from mesh.rail_mesh import mesh_rail_section
from profiles.rail_section import RailParams
from stability.linear import pole_residue_eigenvalues
from stability.rational import (RationalModel, evaluate, passivity_violations, rail_moving_receptance,
                                vector_fit)
from stability.screen import closed_loop_eigenvalues, growing_poles_with_rail
from squealcore.errors import InputError
from waveguide.params import TrackParams
from waveguide.waves import RailWaveguide

BAND = (20.0, 8000.0)  # Hz


def _match(reference, values):
    """Largest relative distance from each reference eigenvalue to its nearest value."""
    values = np.asarray(values)
    return max(np.min(np.abs(values - r)) / abs(r) for r in reference)


def test_vector_fit_recovers_a_rational_function():
    """Samples of a known 3x3 model with 6 pole pairs and a direct term: the fit (started from
    its own log-spaced poles) must find the poles and reproduce H to round-off."""
    rng = np.random.default_rng(3)
    f0 = np.array([60.0, 300.0, 900.0, 2100.0, 4000.0, 6500.0])
    poles, _ = modal_poles_residues(f0, np.full(6, 0.02), np.ones((6, 3)))
    res = rng.normal(size=(6, 3, 3)) + 1j * rng.normal(size=(6, 3, 3))
    res = (res + np.swapaxes(res, 1, 2)) * 1e-6
    true = RationalModel(poles, res, 1e-10 * np.eye(3), np.zeros((3, 3)))
    f = np.geomspace(*BAND, 300)
    fit = vector_fit(f, evaluate(true, f), n_pairs=8, n_iterations=10)
    # every true pole is found (to 1e-6 relative: a noise-free rational function of lower order
    # than the fit; the spare poles get negligible residues)
    assert _match(poles, fit.poles) < 1e-6
    fm = np.sqrt(f[1:] * f[:-1])
    h, hf = evaluate(true, fm), evaluate(fit, fm)
    assert np.abs(hf - h).max() < 1e-6 * np.abs(h).max()


@pytest.fixture(scope="module")
def rail():
    """Coarse rail section (as tests/test_waveguide_greens.py) with its 3 kHz reduced basis; the
    band to 8 kHz uses the model's continuation (as the quick study does)."""
    mesh = mesh_rail_section(RailParams(element_size=0.02))
    track = TrackParams(max_frequency=3000.0, contact_lateral_position=0.015)
    return RailWaveguide(mesh, track, basis_frequency=1.25 * track.max_frequency)


def test_moving_receptance_tends_to_point_receptance(rail):
    """The wavenumber integral at Doppler-shifted frequencies (v > 0) against the wave sum
    (v = 0): at v = 1 mm/s only the quadrature error remains (measured 3e-4 at 1 kHz)."""
    f = [150.0, 1000.0]
    slow = rail_moving_receptance(rail, 1e-3, f)
    point = rail_moving_receptance(rail, 0.0, f)
    for k in range(2):
        assert np.abs(slow[k] - point[k]).max() < 2e-3 * np.abs(point[k]).max()


def test_rational_rail_model(rail):
    """Vector fit of the rail's receptance over 20 Hz - 8 kHz (200 log-spaced samples, 30 pole
    pairs): within 2 % in magnitude at the 199 geometric midpoints (which the fit never saw) for
    every component above 1e-3 of the largest (xx, yy, zz, yz; measured <= 0.6 %); the poles
    stable; passive (Y + Y^H >= 0, Y = iωH) on a dense grid."""
    f = np.geomspace(*BAND, 200)
    h = rail_moving_receptance(rail, 0.0, f)
    model = vector_fit(f, h, n_pairs=30, n_iterations=20, symmetric=True)
    assert np.all(model.poles.real < 0)
    fm = np.sqrt(f[1:] * f[:-1])
    ref = rail_moving_receptance(rail, 0.0, fm)
    fit = evaluate(model, fm)
    big = np.abs(ref).max()
    checked = 0
    for i in range(3):
        for j in range(3):
            if np.abs(ref[:, i, j]).max() < 1e-3 * big:
                continue
            err = np.abs(np.abs(fit[:, i, j]) - np.abs(ref[:, i, j])) / np.abs(ref[:, i, j])
            assert err.max() < 0.02, (i, j, err.max())
            checked += 1
    assert checked >= 5  # xx, yy, zz, yz, zy
    viol = passivity_violations(model, np.geomspace(*BAND, 4000))
    assert viol["frequency"].size == 0, viol["relative"].min()
    assert model.band == BAND
    # the direct term is a compliance (the patch's, ~4e-10 m/N), not a negative spring
    assert np.linalg.eigvalsh(0.5 * (model.direct + model.direct.T)).min() > 0
    # passive rail, passive wheel, frictionless contact: nothing may grow (also out of band)
    poles, res = _wheel()
    lam = closed_loop_eigenvalues(poles, res, model, 1.2e9, 0.0)
    assert lam.real.max() < 0


def _wheel(n=8, seed=1):
    rng = np.random.default_rng(seed)
    f = np.sort(rng.uniform(300.0, 6000.0, n))
    shapes = rng.normal(size=(n, 3)) * 0.3
    return modal_poles_residues(f, np.full(n, 1e-3), shapes)


@pytest.mark.parametrize("mu", [0.6, -0.3])
def test_rigid_rail_gives_pole_residue_eigenvalues(mu):
    """Rail with no poles and D = 0: the loop is pole_residue_eigenvalues' to 1e-9 relative."""
    poles, res = _wheel()
    k_n = 1.2e9
    ref = pole_residue_eigenvalues(poles, res, k_n, mu)
    lam = closed_loop_eigenvalues(poles, res, RationalModel.rigid(), k_n, mu)
    assert lam.size == ref.size
    assert _match(ref, lam) < 1e-9 and _match(lam, ref) < 1e-9


def test_rigid_rail_general_residues():
    """Full-rank, non-symmetric residues (a rotating-wheel-like model): the loop has 3 states
    per pole; the eigenvalues of pole_residue_eigenvalues are among them, and the others stay at
    the open-loop poles (the sliding contact acts through one direction only)."""
    rng = np.random.default_rng(5)
    poles, _ = _wheel(4)
    res = (rng.normal(size=(4, 3, 3)) + 1j * rng.normal(size=(4, 3, 3))) * 1e-5
    ref = pole_residue_eigenvalues(poles, res, 1e9, 0.6)
    lam = closed_loop_eigenvalues(poles, res, RationalModel.rigid(), 1e9, 0.6)
    assert lam.size == 3 * ref.size
    assert _match(ref, lam) < 1e-9
    open_loop = np.concatenate([poles, np.conj(poles)])
    rest = [x for x in lam if np.min(np.abs(ref - x)) > 1e-9 * abs(x)]
    assert len(rest) == 2 * ref.size and _match(rest, open_loop) < 1e-9


def _one_mode(f, zeta, shape):
    p, r = modal_poles_residues([f], [zeta], [shape])
    return p, r


@pytest.mark.parametrize("mu, creep", [(0.6, (0.0, 0.0)), (0.0, (3e5, 4e5))])
def test_one_mode_wheel_on_one_mode_rail(mu, creep):
    """Closed form: with G = φφᵀ/D_w(s) + ψψᵀ/D_r(s) (D = s² + 2ζωs + ω²) and the contact
    W(s) = k_n d e_zᵀ + s C / v, det(I + W G) D_w D_r = det(diag(D_w, D_r) + [φ ψ]ᵀ W [φ ψ])
    (determinant lemma), a quartic in s whose roots are the loop's eigenvalues (1e-9)."""
    v = 13.89
    k_n = 1.0e9
    phi = np.array([0.01, 0.2, 0.35])
    psi = np.array([0.002, 0.05, 0.12])
    wheel = _one_mode(2500.0, 0.002, phi)
    rail = RationalModel(*_one_mode(1100.0, 0.05, psi), np.zeros((3, 3)), np.zeros((3, 3)))
    d = np.array([0.0, mu, 1.0])
    c = np.diag([creep[0], creep[1], 0.0]) / v
    P = np.polynomial.Polynomial
    dw = P([(2 * np.pi * 2500.0) ** 2, 2 * 0.002 * 2 * np.pi * 2500.0, 1.0])
    dr = P([(2 * np.pi * 1100.0) ** 2, 2 * 0.05 * 2 * np.pi * 1100.0, 1.0])

    def w(a, b):  # a^T W(s) b as a polynomial in s
        return P([k_n * (a @ d) * b[2], a @ c @ b])

    m = [[dw + w(phi, phi), w(phi, psi)], [w(psi, phi), dr + w(psi, psi)]]
    # the rail receives -F and Δu = u_w - u_r = (H_w + H_r) F: both enter with a plus sign
    char = m[0][0] * m[1][1] - m[0][1] * m[1][0]
    ref = char.roots()
    lam = closed_loop_eigenvalues(*wheel, rail, k_n, mu, creep, speed=v)
    assert lam.size == 4
    assert _match(ref, lam) < 1e-9 and _match(lam, ref) < 1e-9


def test_growing_poles_and_participation():
    """Two close wheel modes coupled by sliding friction (mode coupling) on a soft one-mode rail:
    the growing pole is reported with both wheel modes, each with a real share, and it is an
    eigenvalue of the loop; with the rail's direct term and creep the descriptor form (QZ)
    gives the same eigenvalues as the rail with that compliance moved into a stiff mode."""
    wheel = modal_poles_residues([5000.0, 4900.0], [1e-4, 1e-4], [[0.0, 0.3, 0.05], [0.0, -0.1, 0.2]])
    rail = RationalModel(*_one_mode(900.0, 0.1, [0.0, 0.05, 0.1]), np.zeros((3, 3)), np.zeros((3, 3)))
    # measured: one pole at 5009 Hz growing at 245 1/s (rigid rail: 245 1/s), shares 0.65 / 0.35
    poles = growing_poles_with_rail(*wheel, rail, 1e9, -0.6)
    assert poles, "the coupled pair must go unstable"
    top = poles[0]
    assert 4900 < top["frequency"] < 5100 and top["growth_rate"] > 0
    assert sorted(top["wheel_modes"]) == [0, 1]
    assert sum(top["participation"]) == pytest.approx(1.0, abs=1e-12)
    assert top["in_band"]  # a modal rail model has no band limit
    lam = closed_loop_eigenvalues(*wheel, rail, 1e9, -0.6)
    assert min(top["participation"]) > 0.2
    assert np.min(np.abs(lam - top["eigenvalue"])) == 0.0
    # a direct term D (a massless spring) equals a mode far above the band with D = φφᵀ/ω²
    direct = np.diag([1e-10, 2e-10, 3e-10])
    with_d = RationalModel(rail.poles, rail.residues, direct, np.zeros((3, 3)))
    stiff_f = 2e6  # Hz
    # the diagonal D as three orthogonal stiff modes, D_ii = φ_i² / ω_s²
    ps, rs = [], []
    for i in range(3):
        shape = np.zeros(3)
        shape[i] = np.sqrt(direct[i, i]) * 2 * np.pi * stiff_f
        pp, rr = modal_poles_residues([stiff_f], [0.0], [shape])
        ps.append(pp)
        rs.append(rr)
    stiff = RationalModel(np.concatenate([rail.poles] + ps), np.concatenate([rail.residues] + rs),
                          np.zeros((3, 3)), np.zeros((3, 3)))
    creep = (2e5, 3e5)
    lam_d = closed_loop_eigenvalues(*wheel, with_d, 1e9, 0.2, creep, speed=13.89)
    lam_s = closed_loop_eigenvalues(*wheel, stiff, 1e9, 0.2, creep, speed=13.89)
    # below 50 kHz: the wheel, the rail mode and the creep force's lag (F_y: -2.3e5 1/s; that
    # of F_x, -6.9e5 1/s, lies among the stiff modes' eigenvalues)
    low_d = lam_d[np.abs(lam_d) < 2 * np.pi * 5e4]
    low_s = lam_s[np.abs(lam_s) < 2 * np.pi * 5e4]
    assert low_s.size == low_d.size == 7
    # 1e-3: the stiff modes' own dynamics is what differs (ω²/ω_s² ~ 1e-5 at 5 kHz, measured
    # 3e-4 for the creep lag at 2.3e5 1/s = 0.02 ω_s)
    assert _match(low_d, low_s) < 1e-3


def test_bad_input():
    wheel = _one_mode(1000.0, 0.01, [0.0, 0.1, 0.2])
    with pytest.raises(InputError) as e:
        closed_loop_eigenvalues(*wheel, RationalModel.rigid(), -1.0, 0.3)
    assert e.value.field == "contact.normal_stiffness"
    with pytest.raises(InputError) as e:
        closed_loop_eigenvalues(*wheel, RationalModel.rigid(), 1e9, 0.0, (1e5, 1e5))
    assert e.value.field == "operating.speed"
    with pytest.raises(InputError) as e:
        vector_fit([1.0, 2.0], np.zeros((2, 3, 3)))
    assert e.value.field == "frequency_hz"


def test_real_rail_pole_is_one_state_per_term():
    """A rail term on a real pole with a real residue (an overdamped rail, as vector fits give)
    is one real state: with H_r = 2 R/(s - p), R = ψψᵀ/2, the characteristic polynomial of the
    one-mode wheel on it is the cubic det([[D_w + φᵀWφ, φᵀWψ], [ψᵀWφ, (s - p) + ψᵀWψ]]) (determinant
    lemma), whose three roots are the loop's eigenvalues (1e-9), and no state stays at p."""
    k_n, mu = 1.0e9, 0.5
    phi = np.array([0.01, 0.2, 0.35])
    psi = np.array([0.0, 0.004, 0.01])  # static compliance ψψᵀ/|p| ~ 5e-9 m/N, the contact's 1e-9 m/N
    wheel = _one_mode(2500.0, 0.002, phi)
    p = -2.0 * np.pi * 3000.0
    rail = RationalModel(np.array([p + 0j]), np.outer(psi, psi)[None] / 2.0 + 0j, np.zeros((3, 3)),
                         np.zeros((3, 3)))
    d = np.array([0.0, mu, 1.0])
    P = np.polynomial.Polynomial
    dw = P([(2 * np.pi * 2500.0) ** 2, 2 * 0.002 * 2 * np.pi * 2500.0, 1.0])

    def w(a, b):  # a^T W b, W = k_n d e_zᵀ
        return k_n * (a @ d) * b[2]

    char = (dw + w(phi, phi)) * (P([-p, 1.0]) + w(psi, psi)) - w(phi, psi) * w(psi, phi)
    ref = char.roots()
    lam = closed_loop_eigenvalues(*wheel, rail, k_n, mu)
    assert lam.size == 3
    assert _match(ref, lam) < 1e-9 and _match(lam, ref) < 1e-9
