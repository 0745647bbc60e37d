"""The mechanism of the low-frequency (137 Hz / 203 Hz) instabilities of the computed contact.

In the contact frame inclined by the contact angle α, a wheel mode whose contact-point shape is
mostly lateral, ``φ = (0, φ_y, φ_z)`` with ``r = φ_z / φ_y`` small (the n = 0 and n = 1 axial
modes), has the normal component ``φ_z' = φ_z cos α - φ_y sin α``. In full sliding the lateral
friction force follows the normal force (``F_y' = μ_s F_z'``), so the mode feeds itself through
the contact with the modal "stiffness" ``κ K(s)``, ``κ = φ_z' (φ_z' + μ_s φ_y')``, where
``K = 1 / (1/k_n + h_r(s))`` is the contact spring in series with the rail's normal receptance.
To first order the pole moves by ``δλ = i κ K(iω) / (2ω)``: its growth rate is

    σ ≈ -ζ ω - κ Im K(iω) / (2 ω),

and a passive, damped rail (``Im h_r < 0``, so ``Im K > 0``) makes the mode grow when
``κ < 0``, i.e. when α exceeds r (for μ_s > 0): the upright contact (α = 0) damps it, the
inclined one feeds it. A rigid rail (K real) only shifts the frequency. These tests check the
screen (:func:`stability.screen.screen`) against the exact characteristic polynomial of a
one-mode wheel on a one-pole rail and against the first-order formula, and the switches that
make the pole grow or decay (docs/results.md, *The default study*; the study's own numbers are printed by
``python benchmarks/lowfreq_first_order.py OUT`` and ``python benchmarks/lowfreq_switches.py OUT``).
"""

import math

import numpy as np
import pytest

from interaction.frame import contact_rotation
from stability.linearised_contact import LinearisedContact
from stability.rational import RationalModel
from stability.screen import closed_loop_eigen, closed_loop_eigenvalues, screen

# The study's n = 0 axial mode at the computed contact (stationary wheel; benchmarks/lowfreq_first_order.py
# prints its decay and shape, benchmarks/lowfreq_switches.py the contact's k_n):
# 203.9 Hz, Re p = -1.28 1/s, mass-normalised shape at the tread with φ_y² = 6.84e-3 1/kg and
# r = φ_z / φ_y = 7.6e-3; the contact angle 0.025 rad, k_n = 1.11e9 N/m, μ = 0.6.
WHEEL_HZ, WHEEL_DECAY = 203.9, 1.28
PHI_Y = math.sqrt(6.84e-3)
RATIO = 7.6e-3
ANGLE = 0.025
K_N = 1.11e9
MU = 0.6
# A rail on its pad for the normal direction: mass m on k with damping c (resonance 225 Hz,
# damping ratio 0.3); its receptance at 204 Hz, (2.7 - 8.3i) nm/N, is of the order of the study's
# rail fit's (2.4 - 2.7i) nm/N.
RAIL_MASS = 100.0
RAIL_K = RAIL_MASS * (2 * math.pi * 225.0) ** 2
RAIL_C = 2 * 0.3 * math.sqrt(RAIL_K * RAIL_MASS)


def wheel_mode(angle):
    """Pole (rad/s) and residue (1, 3, 3) of the one-mode wheel, contact frame inclined by ``angle``,
    and its contact-frame shape φ' (1/sqrt(kg))."""
    omega = 2 * math.pi * WHEEL_HZ
    pole = complex(-WHEEL_DECAY, math.sqrt(omega**2 - WHEEL_DECAY**2))
    phi = contact_rotation(angle) @ np.array([0.0, PHI_Y, RATIO * PHI_Y])
    # φφᵀ / (s² + 2ζωs + ω²) = φφᵀ / ((s - p)(s - p̄)): residue φφᵀ / (p - p̄) at p
    return np.array([pole]), (np.outer(phi, phi) / (pole - pole.conjugate()))[None], phi


def rail_normal():
    """The rail's normal receptance ``1 / (m s² + c s + k)`` (contact-frame zz only) as a RationalModel."""
    pole = np.roots([RAIL_MASS, RAIL_C, RAIL_K])
    pole = pole[pole.imag > 0][0]
    residue = np.zeros((1, 3, 3), complex)
    residue[0, 2, 2] = 1.0 / (RAIL_MASS * (pole - pole.conjugate()))
    return RationalModel(np.array([pole]), residue, np.zeros((3, 3)), np.zeros((3, 3)), None)


def sliding(mu=MU):
    """The contact in full sliding: no creep terms, the lateral force ``μ_s`` times the normal force."""
    return LinearisedContact(K_N, mu, (0.0, 0.0), None, 1.0)


def exact_roots(angle, mu=MU, rigid=False):
    """Roots of the loop's characteristic polynomial, from ``1 + k_n e_zᵀ (H_w + H_r) d = 0``:
    ``w(s) r(s) + k_n (κ r(s) + w(s)) = 0`` with ``w = s² + 2ζωs + ω²``, ``r = m s² + c s + k``
    (rigid rail: ``w + k_n κ = 0``)."""
    pole, _, phi = wheel_mode(angle)
    w = np.array([1.0, -2 * pole[0].real, abs(pole[0]) ** 2])
    kappa = phi[2] * (phi[2] + mu * phi[1])
    if rigid:
        return np.roots(w + np.array([0.0, 0.0, K_N * kappa]))
    r = np.array([RAIL_MASS, RAIL_C, RAIL_K])
    return np.roots(np.polyadd(np.polymul(w, r), K_N * np.polyadd(kappa * r, w)))


def wheel_pole(eigenvalues):
    """The closed-loop eigenvalue nearest the wheel mode (upper half plane)."""
    lam = np.asarray(eigenvalues)
    return lam[np.argmin(np.abs(lam - 2j * math.pi * WHEEL_HZ))]


def screened(angle, mu=MU, rigid=False):
    poles, residues, _ = wheel_mode(angle)
    rail = RationalModel.rigid() if rigid else rail_normal()
    return wheel_pole(closed_loop_eigenvalues(poles, residues, rail, K_N, mu)), \
        screen(poles, residues, rail, sliding(mu), speed=10.0)


@pytest.mark.parametrize("angle", [0.0, ANGLE])
def test_screen_matches_the_characteristic_polynomial(angle):
    # both are exact for this system: only round-off differs (eigenvalues of a 4x4 loop)
    lam, _ = screened(angle)
    exact = wheel_pole(exact_roots(angle))
    assert lam == pytest.approx(exact, rel=1e-9, abs=1e-6)


def test_the_inclined_contact_makes_the_lateral_mode_grow():
    upright, upright_screen = screened(0.0)
    inclined, inclined_screen = screened(ANGLE)
    assert upright.real < -WHEEL_DECAY  # the rail's damping adds to the wheel's
    assert upright_screen["poles"] == []
    assert inclined.real > 1.0  # the study's pole grows at 2.4 1/s
    grown = [p for p in inclined_screen["poles"] if abs(p["frequency"] - WHEEL_HZ) < 5.0]
    assert len(grown) == 1 and grown[0]["growth_rate"] == pytest.approx(inclined.real, rel=1e-9)


def test_growth_needs_the_friction_and_the_flexible_rail():
    # without the sliding friction (μ_s = 0) κ = φ_z'² > 0 and without a damped rail K is real
    no_friction, _ = screened(ANGLE, mu=0.0)
    rigid, rigid_screen = screened(ANGLE, rigid=True)
    assert no_friction.real < -WHEEL_DECAY
    assert rigid.real == pytest.approx(-WHEEL_DECAY, rel=1e-6)  # a pure stiffness: the decay is untouched
    assert rigid_screen["poles"] == []


def test_growth_rate_follows_the_first_order_formula_and_the_threshold_angle():
    # σ ≈ -ζω - κ Im K(iω) / (2ω), K = 1 / (1/k_n + h_r(iω)); the neglected second-order term is
    # of relative size |δλ| / |λ_wheel - λ_rail| (< 5 1/s over 430 1/s: ~1 %), so 5 % on the shift
    omega = 2 * math.pi * WHEEL_HZ
    h_r = 1.0 / (RAIL_MASS * (1j * omega) ** 2 + RAIL_C * 1j * omega + RAIL_K)
    k_eff = 1.0 / (1.0 / K_N + h_r)
    assert k_eff.imag > 0.0  # a passive rail
    rates = []
    for angle in np.linspace(0.0, 2 * ANGLE, 9):
        _, _, phi = wheel_mode(angle)
        kappa = phi[2] * (phi[2] + MU * phi[1])
        lam, _ = screened(angle)
        predicted = -WHEEL_DECAY - kappa * k_eff.imag / (2 * omega)
        assert lam.real + WHEEL_DECAY == pytest.approx(predicted + WHEEL_DECAY, rel=0.05)
        assert (lam.real > -WHEEL_DECAY) == (kappa < 0)  # fed exactly when κ < 0
        rates.append(lam.real)
    assert np.all(np.diff(rates) > 0)  # the steeper the contact, the faster the growth
    # κ changes sign where φ_z' = 0, tan α = r: below that the contact damps the mode
    threshold = math.atan(RATIO)
    below, _ = screened(0.9 * threshold)
    above, _ = screened(1.1 * threshold)
    assert below.real < -WHEEL_DECAY < above.real


def test_screen_without_relaxation_on_a_rail_with_direct_term():
    # the descriptor (QZ) path of the screen: a creep stiffness without relaxation and a rail with
    # a direct term; its eigenvalues are those of closed_loop_eigenvalues (eigenvectors path)
    poles, residues, _ = wheel_mode(ANGLE)
    rail = rail_normal()
    rail = RationalModel(rail.poles, rail.residues, np.diag([1e-10, 1e-10, 1e-10]), np.zeros((3, 3)), None)
    contact = LinearisedContact(K_N, 0.0, (2e6, 2e6), None, 0.5)
    result = screen(poles, residues, rail, contact, speed=10.0)
    lam = closed_loop_eigenvalues(poles, residues, rail, K_N, 0.0, (2e6, 2e6), 10.0)
    oscillating = lam[lam.imag > 0]
    assert result["margin"] == pytest.approx(oscillating.real.max(), rel=1e-9)


def test_screen_names_the_mode_of_the_full_eigenvector():
    # the screen attributes a pole to wheel modes by inverse iteration; on the badly scaled loop
    # (k_n ~ 1e9 N/m, creep relaxation) one step named a longitudinal 576 Hz mode for the
    # 203 Hz pole (share 0.996); the shares must be those of the full eigenvector
    def mode(hz, shape, zeta=1e-4):
        omega = 2 * math.pi * hz
        pole = complex(-zeta * omega, omega * math.sqrt(1 - zeta**2))
        return pole, np.outer(shape, shape) / (pole - pole.conjugate())

    poles, residues, _ = wheel_mode(ANGLE)
    extra = [mode(576.0, [0.09, 0.0, 0.0]), mode(1411.0, [0.0, 0.05, 0.01]), mode(2000.0, [0.0, 0.02, 0.03])]
    poles = np.concatenate([poles, [p for p, _ in extra]])
    residues = np.concatenate([residues, [r for _, r in extra]])
    relaxation = np.array([[3.03e-3, 1.03e-2, 2.9e-5], [2.91e-3, 9.07e-3, 2.46e-5]])  # the study's, m, m, m²
    contact = LinearisedContact(K_N, MU, (2.2e6, 0.0), relaxation, 1.0)
    lam, shares = closed_loop_eigen(poles, residues, rail_normal(), K_N, MU, contact.creep_stiffness, 13.9,
                                    relaxation=relaxation)
    result = screen(poles, residues, rail_normal(), contact, speed=13.9)
    assert result["poles"], "the inclined contact makes the 203.9 Hz mode grow"
    for pole in result["poles"]:
        full = shares[np.argmin(np.abs(lam - pole["eigenvalue"]))]
        assert pole["wheel_modes"][0] == int(np.argmax(full))
        assert pole["participation"][0] == pytest.approx(full.max(), abs=1e-3)
