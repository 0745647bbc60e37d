"""Friction characteristics of the sliding speed (issue 35 item 4): contact/friction_law.py and its
use in the point and half-space contact laws, their linearisations and the stability screen.

References: the closed forms of the characteristics, the negative-damping threshold of a single
oscillator on a moving belt (steady sliding is unstable iff ``c + N dμ/dv < 0``, growth rate
``-(c + N μ')/(2m)``), and Coulomb friction (the constant characteristic) as the models had it."""

import math

import numpy as np
import pytest

from contact.friction_kernels import element_law, element_law_characteristic, sliding_factor, sliding_factor_slope
from contact import friction_law
from contact.friction_law import CONSTANT_LAW, EXPONENTIAL, LINEAR, FrictionLaw, scaled
from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_semi_axes
from contact.params import CASE_SECTIONS, ContactParams, Friction, FrictionTable, Material
from contact.point.model import PointContact, linearise_point_contact
from squealcore.errors import InputError
from squealcore.schema import build
from stability.linearised_contact import LinearisedContact, with_friction_slope
from stability.rational import RationalModel
from stability.screen import closed_loop_eigen, screen

MATERIAL = Material(80e9, 0.25)
N = 50e3  # normal load, N
SPEED = 10.0  # rolling speed V, m/s
ETA = -0.05  # lateral creepage: full sliding at v = V |η| = 0.5 m/s
FALLING = Friction(0.4, 0.3, "exponential", 0.5)  # μ_s, μ_k, v_ref = 0.5 m/s
RISING = Friction(0.2, characteristic="linear", slope=0.4)  # μ_0 = 0.2, +40 % per m/s


def _point(friction, kind="steady"):
    hz = hertz_from_semi_axes(6e-3, 4e-3, N, MATERIAL.contact_modulus)
    return PointContact(material=MATERIAL, friction=friction, hertz=hz, kind=kind, speed=SPEED,
                        time_step=5e-4 / SPEED)


# ---- the characteristics and their parameters


def test_characteristics_closed_forms():
    v = np.array([0.0, 0.1, 0.5, 2.0])
    assert FALLING.coefficient(v) == pytest.approx(0.3 + 0.1 * np.exp(-v / 0.5), rel=1e-15)
    assert FALLING.coefficient_slope(v) == pytest.approx(-0.1 / 0.5 * np.exp(-v / 0.5), rel=1e-15)
    assert RISING.coefficient(v) == pytest.approx(0.2 * (1 + 0.4 * v), rel=1e-15)
    assert RISING.coefficient_slope(v) == pytest.approx(np.full(4, 0.2 * 0.4), rel=1e-15)
    clipped = Friction(0.2, characteristic="linear", slope=-1.0)
    assert clipped.coefficient(np.array([0.5, 1.5])) == pytest.approx([0.1, 0.0], abs=1e-16)
    assert clipped.coefficient_slope(np.array([0.5, 1.5])) == pytest.approx([-0.2, 0.0], abs=1e-16)
    # the compiled factor equals the numpy one
    for law in (FALLING.law(), RISING.law(), clipped.law(), CONSTANT_LAW):
        for x in (0.0, 0.3, 1.7):
            assert sliding_factor(law, x) == pytest.approx(float(friction_law.sliding_factor(law, x)), rel=1e-15)
            assert sliding_factor_slope(law, x) == pytest.approx(float(friction_law.sliding_factor_slope(law, x)),
                                                                 rel=1e-15, abs=0.0)
    # constant: Coulomb with the kinetic coefficient at every speed, no slope
    coulomb = Friction(0.4, 0.3)
    assert coulomb.law() == CONSTANT_LAW and coulomb.coefficient(3.0) == 0.3 and coulomb.coefficient_slope(3.0) == 0.0
    assert scaled(FALLING.law(), 2.0).rate == pytest.approx(2.0 / 0.5)


@pytest.mark.parametrize("keys, field", [
    ({"friction_characteristic": "exponential", "friction_reference_speed": 0.5}, "contact.kinetic_friction"),
    ({"friction_characteristic": "exponential", "kinetic_friction": 0.2}, "contact.friction_reference_speed"),
    ({"kinetic_friction": 0.5}, "contact.kinetic_friction"),
    ({"friction_characteristic": "linear", "kinetic_friction": 0.2}, "contact.kinetic_friction"),
    ({"friction_slope": 0.3}, "contact.friction_slope"),
    ({"friction_reference_speed": 0.3}, "contact.friction_reference_speed"),
    ({"friction_characteristic": "falling"}, "contact.friction_characteristic"),
    ({"friction_characteristic": "linear", "friction_slope": 200.0}, "contact.friction_slope"),
    ({"friction_characteristic": "exponential", "kinetic_friction": 0.2, "friction_reference_speed": 0.0},
     "contact.friction_reference_speed"),
])
def test_bad_friction_keys_name_the_field(keys, field):
    with pytest.raises(InputError) as err:
        build(ContactParams, keys, "contact")
    assert err.value.field == field


def test_friction_keys_build_the_characteristic():
    study = build(ContactParams, {"friction": 0.4, "friction_characteristic": "exponential", "kinetic_friction": 0.3,
                                  "friction_reference_speed": 0.5}, "contact")
    assert study.to_friction() == FALLING
    assert build(ContactParams, {}, "contact").to_friction() == Friction(0.3)  # today's default, unchanged
    case = build(FrictionTable, {"coefficient": 0.2, "characteristic": "linear", "slope": 0.4}, "friction")
    assert case.to_friction() == RISING
    assert FrictionTable in CASE_SECTIONS
    with pytest.raises(InputError) as err:
        build(FrictionTable, {"coefficient": 0.3, "kinetic": 0.4}, "friction")
    assert err.value.field == "friction.kinetic"


# ---- (b) the constant characteristic is Coulomb friction as before


def test_constant_characteristic_is_coulomb_exactly():
    # the point law's bundle and the half-space's coefficients carry the constant law, whose
    # factor is exactly 1: the same forces bit for bit as Friction(μ) always gave
    a = _point(Friction(0.3), kind="transient")
    b = _point(build(ContactParams, {"friction": 0.3}, "contact").to_friction(), kind="transient")
    assert a.law.friction_law == CONSTANT_LAW
    assert all(np.array_equal(x, y) for x, y in zip(a.law, b.law))
    state_a, state_b = a.initial_state(), b.initial_state()
    for _ in range(30):
        ra = a.solve(state_a, normal_force=N, creepage=(0.001, -0.004, 0.2))
        rb = b.solve(state_b, normal_force=N, creepage=(0.001, -0.004, 0.2))
        assert np.array_equal(ra.force, rb.force)
        state_a, state_b = ra.new_state, rb.new_state
    # the element law: a characteristic with no dependence on the slip (linear, slope 0) is
    # Coulomb with μ_s = μ_k, to round-off (the same local equation, solved by other Newton steps),
    # in stick and in slip
    flat = FrictionLaw(LINEAR, 0.0, 0.0)
    for sx, sy, slides in ((3e-7, -2e-7, False), (3e-6, -2e-6, True), (1e-5, 4e-6, True)):
        q0 = element_law(sx, sy, 1e3, -2e3, 6e-15, 7e-15, 2e8, 2e8)
        q1 = element_law_characteristic(sx, sy, 1e3, -2e3, 6e-15, 7e-15, 2e8, 2e8, flat)
        assert q1[2] == q0[2] == slides
        assert q1[:2] == pytest.approx(q0[:2], rel=1e-13)


# ---- (c) the laws' sliding bound is μ(v) at the sliding speed


@pytest.mark.parametrize("friction", [FALLING, RISING])
def test_point_law_saturates_at_mu_of_the_sliding_speed(friction):
    for kind in ("steady", "transient"):
        model = _point(friction, kind)
        for eta in (-0.02, -0.05, -0.2):
            v = SPEED * abs(eta)
            if kind == "steady":
                force = model.steady_force(N, (0.0, eta, 0.0))
            else:  # the strip model, rolled through its patch (full slip once the material is through)
                state = model.initial_state()
                for _ in range(60):
                    result = model.solve(state, normal_force=N, creepage=(0.0, eta, 0.0))
                    state = result.new_state
                force = result.force[:2]
            assert np.hypot(*force) / N == pytest.approx(friction.coefficient(v), rel=1e-9), (kind, eta)


@pytest.mark.parametrize("law", [FrictionLaw(EXPONENTIAL, 1.0 / 3.0, 2e5), FrictionLaw(LINEAR, 0.0, 1.5e5),
                                 FrictionLaw(LINEAR, 0.0, -0.3e5), FrictionLaw(EXPONENTIAL, 2.0, 3e6),
                                 FrictionLaw(LINEAR, 0.0, -2e5)])
def test_element_law_slides_on_the_bound_at_its_own_slip(law):
    # the sliding traction's size is kinetic_bound φ(σ) with σ the element's slip after the update
    # (rates per metre of slip: 2e5 /m is v_ref = 0.5 m/s at a time step of 1e-5 s; the last two
    # laws are steep, |dg/dσ| times the compliance up to 14 and 2: a fixed-point iteration on σ
    # would not converge, the bracketed Newton steps do)
    dxx, dyy, gk = 6e-15, 8e-15, 3e8
    for sx, sy in ((5e-6, -3e-6), (-8e-6, 6e-6), (1e-5, 2e-5)):
        gs = gk * sliding_factor(law, 0.0)
        qx, qy, sliding = element_law_characteristic(sx, sy, 0.0, 0.0, dxx, dyy, gs, gk, law)
        assert sliding
        wx, wy = sx + dxx * qx, sy + dyy * qy  # the slip with the new traction
        sigma = math.hypot(wx, wy)
        assert math.hypot(qx, qy) == pytest.approx(gk * sliding_factor(law, sigma), rel=1e-12, abs=1e-6)
        if math.hypot(qx, qy) > 0.0:  # the traction opposes the slip
            assert (qx * wx + qy * wy) / (math.hypot(qx, qy) * sigma) == pytest.approx(-1.0, abs=1e-9)


def test_halfspace_transient_slides_at_mu_of_the_sliding_speed():
    # full sliding at V |η|: the elements' slip speeds differ from the rigid one by the elastic
    # gradient (a few per cent here), so the force lies between μ at 0.9 v and at 1.1 v, and the
    # falling law gives less than μ_s, more than μ_k
    hz = hertz_from_semi_axes(5e-3, 5e-3, N, MATERIAL.contact_modulus)
    grid = Grid.covering(hz.a, hz.b, nx=16, ny=16)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    forces = {}
    for name, friction in (("falling", FALLING), ("rising", RISING)):
        model = HalfspaceContact(material=MATERIAL, friction=friction, grid=grid, gap=hz.A * x**2 + hz.B * y**2,
                                 kind="transient", speed=SPEED)
        state = model.initial_state()
        for _ in range(40):
            result = model.solve(state, normal_force=N, creepage=(0.0, ETA, 0.0))
            state = result.new_state
        forces[name] = abs(result.force[1]) / N
        v = SPEED * abs(ETA)
        lo, hi = sorted((friction.coefficient(0.9 * v), friction.coefficient(1.1 * v)))
        assert lo <= forces[name] <= hi, (name, forces[name], lo, hi)
        # steady rolling: one coefficient, μ at the contact's sliding speed V |η|
        steady = HalfspaceContact(material=MATERIAL, friction=friction, grid=grid, gap=hz.A * x**2 + hz.B * y**2,
                                  kind="steady", speed=SPEED)
        result = steady.solve(steady.initial_state(), normal_force=N, creepage=(0.0, ETA, 0.0))
        assert abs(result.force[1]) / N == pytest.approx(friction.coefficient(v), rel=2e-5)


# ---- (a) the negative-damping threshold of one oscillator


def _belt_growth(damping, mass, stiffness, model, duration=0.25, dt=5e-5):
    """Growth rate (1/s) of a mass on a spring and damper, driven by the point law's lateral force
    at the creepage ``ETA + ẏ / V`` (the sliding speed moves with the oscillator's velocity), by
    RK4 steps and a fit of the logarithm of its velocity's peaks."""
    static = model.steady_force(N, (0.0, ETA, 0.0))[1]

    def rate(state):
        y, u = state
        force = model.steady_force(N, (0.0, ETA + u / SPEED, 0.0))[1] - static
        return np.array([u, (force - damping * u - stiffness * y) / mass])

    state = np.array([0.0, 1e-4])
    speeds = []
    for _ in range(int(duration / dt)):
        k1 = rate(state)
        k2 = rate(state + 0.5 * dt * k1)
        k3 = rate(state + 0.5 * dt * k2)
        k4 = rate(state + dt * k3)
        state = state + dt / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        speeds.append(state[1])
    u = np.asarray(speeds)
    peaks = np.flatnonzero((u[1:-1] > u[:-2]) & (u[1:-1] >= u[2:])) + 1
    return np.polyfit(peaks * dt, np.log(u[peaks]), 1)[0]


def test_negative_damping_threshold_of_one_oscillator():
    # m ÿ + c ẏ + k y = F_y(η + ẏ/V) with F_y = μ(V|η|) N in full sliding: the linearisation is
    # m ÿ + (c + N μ'(v)) ẏ + k y = 0, unstable iff c + N μ' < 0, growth -(c + N μ')/(2m)
    model = _point(FALLING)
    v = SPEED * abs(ETA)
    slope = float(FALLING.coefficient_slope(v))
    threshold = -N * slope  # c at which steady sliding turns unstable, N s/m
    assert threshold == pytest.approx(N * 0.1 / 0.5 * math.exp(-1.0))
    mass = 10.0
    stiffness = mass * (2 * math.pi * 100.0) ** 2
    for factor in (0.8, 1.2):
        c = factor * threshold
        expected = -(c + N * slope) / (2 * mass)
        measured = _belt_growth(c, mass, stiffness, model)
        assert np.sign(measured) == np.sign(expected) == (1 if factor < 1 else -1)
        assert measured == pytest.approx(expected, rel=0.02)
    # the linearisation's damping is N μ'(v), for the steady law and the strip model alike
    for kind in ("steady", "transient"):
        lin = linearise_point_contact(_point(FALLING, kind), N, (0.0, ETA, 0.0))
        assert lin.friction_damping[1] == pytest.approx(N * slope, rel=1e-6)
        assert lin.friction_damping[0] == 0.0
        assert lin.saturation == pytest.approx(1.0, abs=1e-12)
        assert lin.sliding_coefficient == pytest.approx(FALLING.coefficient(v), rel=1e-6)  # μ(v) at the operating point
    rising = linearise_point_contact(_point(RISING), N, (0.0, ETA, 0.0))
    assert rising.friction_damping[1] == pytest.approx(N * 0.2 * 0.4, rel=1e-6)  # a modifier damps
    assert linearise_point_contact(_point(Friction(0.3)), N, (0.0, ETA, 0.0)).friction_damping == (0.0, 0.0)


def test_halfspace_linearisation_damping_in_full_sliding():
    # the steady half-space at μ(v), plus the slope term F/μ μ'(v): N μ'(v) in full sliding
    from contact.halfspace.linearise import linearise_halfspace_contact  # lazy: the half-space linearisation is heavy

    hz = hertz_from_semi_axes(5e-3, 5e-3, N, MATERIAL.contact_modulus)
    grid = Grid.covering(hz.a, hz.b, nx=16, ny=16)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=MATERIAL, friction=FALLING, grid=grid, gap=hz.A * x**2 + hz.B * y**2,
                             kind="transient", speed=SPEED)
    lin = linearise_halfspace_contact(model, N, (0.0, ETA, 0.0))
    v = SPEED * abs(ETA)
    # the steady solution's |F_t| is μ Q to the solver's tolerance on the grid (measured 1 - 6e-6)
    assert lin.saturation == pytest.approx(1.0, abs=2e-5)
    assert lin.friction_damping[1] == pytest.approx(N * float(FALLING.coefficient_slope(v)), rel=2e-5)
    assert lin.sliding_coefficient == pytest.approx(FALLING.coefficient(v), rel=2e-5)


# ---- (d) the screen's growth rate changes sign at the threshold


def test_screen_growth_rate_changes_sign_at_the_threshold():
    # one lateral wheel mode (modal mass m, 800 Hz, damping c) on a rigid rail, in full sliding
    # with the slope term d = N μ': its pole's Re λ = -(c + d)/(2m) exactly
    mass, freq = 5.0, 800.0
    omega = 2 * math.pi * freq
    d = N * float(FALLING.coefficient_slope(SPEED * abs(ETA)))
    phi = np.array([0.0, 1.0 / math.sqrt(mass), 0.0])
    for factor in (0.5, 0.99, 1.01, 2.0):
        c = -factor * d
        zeta = c / (2 * mass * omega)
        pole = complex(-zeta * omega, omega * math.sqrt(1 - zeta**2))
        residue = np.outer(phi, phi) / (2j * pole.imag)
        contact = LinearisedContact(1e9, 0.35, (0.0, 0.0), None, 1.0, (0.0, d))
        result = screen([pole], [residue], RationalModel.rigid(), contact, SPEED)
        expected = -(c + d) / (2 * mass)
        assert result["margin"] == pytest.approx(expected, rel=1e-8, abs=1e-9 * omega)
        assert (result["margin"] > 0) == (factor < 1)
        assert result["margin_frequency"] == pytest.approx(math.sqrt(omega**2 - ((c + d) / (2 * mass)) ** 2) / (2 * math.pi),
                                                           rel=1e-9)
    # without the slope term the same loop is the one the screen always solved
    lam, _ = closed_loop_eigen([pole], [residue], RationalModel.rigid(), 1e9, 0.35)
    lam0, _ = closed_loop_eigen([pole], [residue], RationalModel.rigid(), 1e9, 0.35, friction_damping=(0.0, 0.0))
    assert np.array_equal(np.sort_complex(lam), np.sort_complex(lam0))


def test_with_friction_slope_leaves_coulomb_alone():
    lin = LinearisedContact(1e9, 0.3, (1e5, 2e5), None, 0.5)
    assert with_friction_slope(lin, Friction(0.3), SPEED, (0.0, ETA, 0.0), (0.0, N)) is lin
    assert with_friction_slope(lin, FALLING, SPEED, (0.0, 0.0, 0.0), (0.0, N)) is lin


# ---- steady curving's creep law


def test_curving_creep_law_saturates_at_mu_of_the_sliding_speed():
    from curving.creep import CreepLaw  # lazy: the curving package is only needed here
    from curving.geometry import ContactGeometry

    tread = ContactGeometry("tread", 0.39, 0.0, 0.0, 1.0 / 0.39, 1.0 / 0.3)
    law = CreepLaw(speed=SPEED)
    for eta in (-0.02, -0.1):
        force = law.force(tread, FALLING, N, (0.0, eta, 0.0))
        assert np.hypot(*force) / N == pytest.approx(FALLING.coefficient(SPEED * abs(eta)), rel=1e-9)
    # a coefficient is Coulomb friction, as before
    assert np.array_equal(law.force(tread, 0.3, N, (0.0, -0.02, 0.0)), CreepLaw().force(tread, 0.3, N, (0.0, -0.02, 0.0)))


def _receptance(poles, residues, s):
    return sum(r / (s - p) + np.conj(r) / (s - np.conj(p)) for p, r in zip(poles, residues))


@pytest.mark.parametrize("relaxed", [False, True])
def test_screen_with_friction_damping_solves_its_loop(relaxed):
    # two wheel modes and one rail mode (no direct compliance: the damping acts on the whole
    # relative velocity), a partly sliding contact with creep, optional relaxation and the slope
    # term: every eigenvalue is a root of det(I + Z(s) (H_w(s) + H_r(s))), Z the contact's
    # impedance k_n d e_zᵀ + diag(W_x, W_y, 0) + s diag(d_x, d_y, 0), W the (relaxed) creep law
    rng = np.random.default_rng(3)
    speed = 20.0
    wheel_poles = np.array([complex(-3.0, 2 * math.pi * 900), complex(-5.0, 2 * math.pi * 2600)])
    shapes = rng.standard_normal((2, 3)) * 0.3
    wheel_residues = np.array([np.outer(v, v) / (2j * p.imag) for v, p in zip(shapes, wheel_poles)])
    rail_pole = complex(-400.0, 2 * math.pi * 1500)
    rail_shape = np.array([0.05, 0.2, 0.1])
    rail = RationalModel(np.array([rail_pole]), np.array([np.outer(rail_shape, rail_shape) / (2j * rail_pole.imag)]),
                         np.zeros((3, 3)), np.zeros((3, 3)))
    relaxation = np.array([[3e-3, 1.0e-2, 2.9e-5], [2.9e-3, 0.9e-2, 2.5e-5]]) if relaxed else None
    contact = LinearisedContact(1e9, 0.3, (2e5, 1e5), relaxation, 0.6, (-300.0, -2000.0))
    lam, _ = closed_loop_eigen(wheel_poles, wheel_residues, rail, contact.normal_stiffness,
                               contact.sliding_coefficient, contact.creep_stiffness, speed,
                               relaxation=contact.relaxation, friction_damping=contact.friction_damping)
    d = np.array([0.0, contact.sliding_coefficient, 1.0])
    assert lam.size >= 6
    for s in lam:
        z = contact.normal_stiffness * np.outer(d, [0.0, 0.0, 1.0]).astype(complex)
        for j in range(2):
            tau = s / speed
            c = contact.creep_stiffness[j]
            if relaxed:
                b, a1, a2 = relaxation[j]
                z[j, j] += c * tau * (1 + b * tau) / (1 + a1 * tau + a2 * tau**2)
            else:
                z[j, j] += c * tau
            z[j, j] += s * contact.friction_damping[j]
        m = np.eye(3) + z @ (_receptance(wheel_poles, wheel_residues, s) + _receptance(rail.poles, rail.residues, s))
        singular = np.linalg.svd(m, compute_uv=False)
        assert singular[-1] < 1e-8 * singular[0], s


# ---- the compiled time loops take the characteristic as the Python loops do


def _loop_structures(dt):
    from fe.greens import modal_poles_residues, ramp_invariant_kernel  # lazy: only the loop tests need them
    from interaction.structures import ConvolutionStructure, ModalStructure

    wheel = ([410.0, 1120.0, 2010.0], [1e-3, 1e-4, 1e-4],
             np.array([[0.0, 0.12, 0.01], [0.002, 0.11, -0.02], [0.0, 0.09, 0.03]]))
    rail = ([330.0, 900.0], [0.15, 0.2], np.array([[0.0, 0.05, 0.0], [0.0, 0.0, 0.17]]))
    return (ModalStructure(*modal_poles_residues(*wheel), dt),
            ConvolutionStructure(ramp_invariant_kernel(*modal_poles_residues(*rail), dt, 800), dt))


@pytest.mark.parametrize("model", ["point", "halfspace"])
def test_compiled_loop_equals_python_loop_with_a_falling_characteristic(model):
    # the same equations solved by the compiled loop (the bundles' friction laws) and the Python
    # reference loop (the models' solve): histories equal to the coupling tolerance (1e-10 here),
    # to 1e-6 Q as tests/test_interaction.py checks for Coulomb friction
    from contact.hertz import hertz_from_curvatures  # lazy: only the loop tests need them
    from interaction.simulate import simulate

    dt, speed, load = 3.6e-5, 50 / 3.6, 50e3
    material = Material.from_young(210e9, 0.3)
    hertz = hertz_from_curvatures(1 / 0.78, 1 / 0.6, load, material.contact_modulus)
    falling = Friction(0.4, 0.3, "exponential", 0.05)

    def contact(friction):
        if model == "point":
            return PointContact(material=material, friction=friction, hertz=hertz, kind="transient", speed=speed,
                                time_step=dt)
        peak = hertz.scaled(1.5 * load)
        grid = Grid.covering(peak.a, peak.b, dx=speed * dt, dy=1e-3, margin=0.25)
        x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
        return HalfspaceContact(material=material, friction=friction, grid=grid, gap=hertz.A * x**2 + hertz.B * y**2,
                                kind="transient", speed=speed, tol=1e-10)

    n = 1500 if model == "point" else 300
    runs = {}
    for name, friction, compiled in (("compiled", falling, True), ("python", falling, False),
                                     ("coulomb", Friction(0.3), True)):
        runs[name] = simulate(*_loop_structures(dt), contact(friction), speed=speed, wheel_load=load,
                              creepage=(0.0, -0.01, 0.0), n_steps=n, tolerance=1e-10, compiled=compiled)
    a, b = runs["compiled"], runs["python"]
    assert np.abs(a.force - b.force).max() <= 1e-6 * load
    # the characteristic is used: μ(V |η|) = 0.306 > μ_k at this sliding speed, and its negative
    # damping sets the wheel ringing, so the run differs from Coulomb friction at μ_k
    assert np.abs(a.force - runs["coulomb"].force).max() > 1e-3 * load
