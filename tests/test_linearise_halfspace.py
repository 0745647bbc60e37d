"""The half-space contact linearised for the stability screen (contact/halfspace/linearise.py).

References: Hertz's normal stiffness 3Q/(2δ), Kalker's creep coefficients (no slip), the full
sliding limits, Hertz's similarity of the half-space problem (on grids scaled with the load),
and the relaxation fitted to the transient half-space (no slip)."""

import math

import numpy as np
import pytest

from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_semi_axes
from contact.kalker import creep_coefficients
from contact.halfspace.linearise import (
    cached_linearisation,
    check_hertzian,
    linearise_halfspace_contact,
    no_slip_slopes,
    normal_stiffness,
    steady_jacobian,
    stick_scaled_relaxation,
    transient_creep_response,
)
from contact.params import Friction, Material
from contact.point.model import linearise_point_contact, load_relaxation_table, relaxation_coefficients
from squealcore.errors import InputError
from stages.cases import case_contact, contact_model, imposed_creepage
from stages.config import load_study
from stages.screen import linear_contact

G, NU, Q = 80e9, 0.25, 50e3
MATERIAL = Material(G, NU)
A = 5e-3  # semi-axis of the circular test contact, m


def _model(mu, n=None, scale=1.0, kind="steady", dx=None, semi_axes=(A, A)):
    """The Hertz contact of semi-axes ``semi_axes`` at Q on an n x n grid (or dx = dx, dy = b / 12),
    with the grid's element sizes times ``scale``."""
    hz = hertz_from_semi_axes(*semi_axes, Q, MATERIAL.contact_modulus)
    grid = Grid.covering(hz.a, hz.b, nx=n, ny=n) if dx is None else Grid.covering(hz.a, hz.b, dx=dx, dy=hz.b / 12)
    grid = Grid(grid.nx, grid.ny, grid.dx * scale, grid.dy * scale)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=MATERIAL, friction=Friction(mu), grid=grid, gap=hz.A * x**2 + hz.B * y**2,
                             kind=kind, speed=10.0)
    return hz, model


def test_normal_stiffness_is_hertz():
    # the solver's dF/dδ against Hertz's 3Q/(2δ): measured -0.7 %, +0.7 %, -0.3 % on 20, 30 and
    # 40 elements per side (the grid's error of the approach's slope; the approach itself is
    # within 0.04 % of Hertz's)
    hz, model = _model(1e3, n=30)
    k, delta = normal_stiffness(model, Q)
    assert k == pytest.approx(1.5 * Q / hz.approach, rel=0.015)
    assert delta == pytest.approx(hz.approach, rel=0.002)


def test_no_slip_slopes_are_kalkers():
    # no slip (friction 1e3): the creep slopes are Kalker's G a b C11, G a b C22 within the
    # 40 x 40 grid's error (measured +1.2 %, +1.4 %; tests/test_contact_rolling.py's 3 %), and the
    # load slope is that of a force proportional to a b ~ Q^(2/3): (2/3) F / Q
    hz, model = _model(1e3, n=40)
    c11, c22, _ = creep_coefficients(1.0, NU)
    gab = G * hz.a * hz.b
    creepage = (1e-4, -2e-4, 0.0)
    lin = linearise_halfspace_contact(model, Q, creepage)
    np.testing.assert_allclose(lin.creep_stiffness, (gab * c11, gab * c22), rtol=0.03)
    jac = steady_jacobian(model, Q, creepage)
    assert jac.slip_fraction == 0.0
    np.testing.assert_allclose(jac.load_slope, 2.0 / 3.0 * jac.force[:2] / Q, rtol=1e-6)
    assert lin.sliding_coefficient == jac.load_slope[1]
    # the no-slip slopes the relaxation is scaled with are the same ones
    np.testing.assert_allclose(no_slip_slopes(_model(0.3, n=40)[1], Q), lin.creep_stiffness, rtol=1e-6)
    assert lin.saturation < 0.01 and lin.relaxation is None


def test_full_sliding_limits():
    # full sliding: F_y = -μ Q sign(η), so μ_s = μ (η < 0), c_y = 0 and the saturation 1 (less by
    # the spread of the slip direction over the contact: measured 5e-6); c_x = μ Q / |η| (the
    # sliding force turned by ξ) within the elastic slip's share, measured 0.09-0.12 % on 20-40
    # elements per side
    mu, eta = 0.3, -0.05
    hz, model = _model(mu, n=30)
    lin = linearise_halfspace_contact(model, Q, (0.0, eta, 0.0))
    assert lin.sliding_coefficient == pytest.approx(mu, rel=1e-4)
    assert 0.0 <= lin.creep_stiffness[1] < 1e-5 * G * hz.a * hz.b
    assert 1.0 - 1e-4 < lin.saturation <= 1.0 + 1e-9
    assert lin.creep_stiffness[0] == pytest.approx(mu * Q / abs(eta), rel=0.003)


@pytest.mark.parametrize("creepage", [(5e-4, -2e-3, 0.0), (0.0, -1e-3, 0.5)])
def test_load_slope_by_similarity_matches_load_steps_on_scaled_grids(creepage):
    # the discrete problem at Q' on the grid scaled by s = (Q'/Q)^(1/3) is the problem at Q scaled
    # (the contact's edge crosses no element): the force there is (Q'/Q) F(Q, ξ/s, η/s, φ) to the
    # solver's tolerance, and the central difference over Q (1 ± 1 %) on such grids is the load
    # slope of steady_jacobian (partial slip, slip fractions 0.52 and 0.45; they differ by the
    # creepage steps' own stick/slip switching: measured 0.05 % and 0.001 %)
    mu = 0.3
    _, base = _model(mu, n=30)
    jac = steady_jacobian(base, Q, creepage)
    assert 0.2 < jac.slip_fraction < 0.9
    xi, eta, phi = creepage
    forces = []
    for factor in (1.01, 0.99):
        s = factor ** (1.0 / 3.0)
        _, scaled = _model(mu, n=30, scale=s)
        got = scaled.solve(scaled.initial_state(), normal_force=factor * Q, creepage=creepage).force
        ref = base.solve(base.initial_state(), normal_force=Q, creepage=(xi / s, eta / s, phi)).force
        np.testing.assert_allclose(got, factor * ref, rtol=0, atol=1e-6 * mu * Q)
        forces.append(got[:2])
    slope = (forces[0] - forces[1]) / (0.02 * Q)
    np.testing.assert_allclose(jac.load_slope, slope, rtol=0.005, atol=1e-6)


def test_transient_response_without_slip_matches_the_fitted_relaxation():
    # on the fit's own grid (dx = a/12, dy = b/12), the transient half-space's lateral creep
    # force at Ω = ω a / V = 1 against -c_y0 H(iΩ) of the fitted relaxation: the log amplitude
    # ratio and the phase difference within the fit's largest error (the table's err_y, 0.074;
    # measured 0.004 and 0.026): a frequency response instead of the fit's step responses
    hz, model = _model(1e3, kind="transient", dx=A / 12)
    omega = 1.0
    frequency = omega * model.speed / (2 * math.pi * hz.a)
    measured = transient_creep_response(model, Q, (0.0, -1e-4, 0.0), frequency, periods=4)
    beta, a1, a2 = relaxation_coefficients(1.0, NU)[1]
    h = (1 + beta * 1j * omega) / (1 + a1 * 1j * omega + a2 * (1j * omega) ** 2)
    ratio = np.log(measured / (-no_slip_slopes(model, Q)[1] * h))
    table = load_relaxation_table()
    err = float(table["err_y"][np.isclose(table["a_over_b"], 1.0) & np.isclose(table["nu"], NU)][0])
    assert abs(ratio.real) <= err and abs(ratio.imag) <= err


@pytest.mark.parametrize("eta", [-2e-3, -4.5e-3])
def test_stick_scaled_relaxation_matches_the_transient_in_partial_slip(eta):
    # partial slip (μ = 0.3; saturation 0.72 and 0.994): the transient half-space's lateral creep
    # force at Ω = 3 against the linearised law -c_y W(iΩ) with the relaxation shortened to the
    # stick area. Measured |ln ratio| (amplitude, phase): 0.084, 0.006 and 0.003, 0.074, as close
    # as the no-slip fit itself (0.074): within 0.12. The no-slip relaxation as it is misses by
    # 0.53 and 1.38 in log amplitude (the creep damping), so the shortening is needed: > 0.3.
    hz, model = _model(0.3, kind="transient", dx=A / 12)
    relaxation = relaxation_coefficients(1.0, NU) * np.array([hz.a, hz.a, hz.a**2])
    creepage = (0.0, eta, 0.0)
    omega = 3.0
    frequency = omega * model.speed / (2 * math.pi * hz.a)
    measured = transient_creep_response(model, Q, creepage, frequency, periods=4)

    def law(lin):
        b, a1, a2 = lin.relaxation[1]
        tau = 1j * omega / hz.a
        return -lin.creep_stiffness[1] * (1 + b * tau) / (1 + a1 * tau + a2 * tau**2)

    short = linearise_halfspace_contact(model, Q, creepage, relaxation)
    assert 0.5 < short.saturation < 1.0
    ratio = np.log(measured / law(short))
    assert abs(ratio.real) <= 0.12 and abs(ratio.imag) <= 0.12
    no_slip = linearise_halfspace_contact(model, Q, creepage, relaxation, stick_relaxation=False)
    assert abs(np.log(measured / law(no_slip)).real) > 0.3


def test_stick_scaled_relaxation_limits():
    relaxation = np.array([[3e-3, 1e-2, 3e-5], [2.9e-3, 9e-3, 2.4e-5]])
    # no slip: unchanged; a slope a quarter of the no-slip one: lengths halved, a2 quartered
    np.testing.assert_array_equal(stick_scaled_relaxation(relaxation, (7e6, 6e6), (7e6, 6e6)), relaxation)
    half = stick_scaled_relaxation(relaxation, (7e6 / 4, 6e6 / 4), (7e6, 6e6))
    np.testing.assert_allclose(half, relaxation * np.array([0.5, 0.5, 0.25]), rtol=1e-12)
    # full sliding: lengths at the floor, still a2 > 0 (the loop's realisation needs it)
    gone = stick_scaled_relaxation(relaxation, (0.0, 0.0), (7e6, 6e6))
    assert np.all(gone > 0) and np.all(gone <= 1e-3 * relaxation)


def test_gap_must_be_hertzian():
    _, model = _model(0.3, n=10)
    check_hertzian(model)
    bumpy = HalfspaceContact(material=MATERIAL, friction=Friction(0.3), grid=model.grid,
                             gap=np.asarray(model.gap) + 1e-7 * np.cos(np.arange(model.grid.nx))[:, None], kind="steady")
    with pytest.raises(InputError) as info:
        steady_jacobian(bumpy, Q, (0.0, -1e-3, 0.0))
    assert info.value.field == "contact.gap"


def test_screen_linearises_the_study_contact_model():
    # the hook in stages.screen.linear_contact: "point" stays the point law's linearisation,
    # "halfspace" is the half-space's on the case's grid with the point model's relaxation shortened
    # to the stick area, computed once per distinct contact
    study = load_study(None, True, ["contact.geometry = \"manual\"", "contact.lateral_creepage = -0.003"])
    point = case_contact(study)
    creepage = imposed_creepage(study, point)
    point_lin = linear_contact(study, point)
    model = contact_model(study, point)
    expected = linearise_point_contact(model, point.normal_force, creepage)
    for field in ("normal_stiffness", "sliding_coefficient", "creep_stiffness", "saturation"):
        assert getattr(point_lin, field) == getattr(expected, field)
    np.testing.assert_array_equal(point_lin.relaxation, expected.relaxation)
    half_study = load_study(None, True, ["contact.geometry = \"manual\"", "contact.lateral_creepage = -0.003",
                                         "contact.model = \"halfspace\""])
    half = linear_contact(half_study, point)
    assert half is linear_contact(half_study, point)  # cached
    ref = linearise_halfspace_contact(contact_model(half_study, point), point.normal_force, creepage,
                                      model.relaxation_constants(point.normal_force))
    assert half.normal_stiffness == ref.normal_stiffness and half.creep_stiffness == ref.creep_stiffness
    np.testing.assert_array_equal(half.relaxation, ref.relaxation)
    assert half is cached_linearisation(contact_model(half_study, point), point.normal_force, creepage,
                                        model.relaxation_constants(point.normal_force))
    # the two laws differ by design (partial slip): same order, not the same numbers
    assert 0.0 < half.saturation < 1.0 and half.creep_stiffness[1] > 0.0
