"""Tangential half-space problems: Carter (2D), Kalker's creep coefficients, saturation,
transient -> steady, and the Cattaneo-Mindlin shift."""

import math

import numpy as np
import pytest

from contact.factory import create_model
from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_semi_axes
from contact.halfspace.influence import plane_strain_kernels, rectangle_kernels
from contact.kalker import load_table
from contact.halfspace.normal import solve_normal
from contact.params import Friction, Material
from contact.halfspace.tangential import SLIP, STICK, solve_tangential
from squealcore.errors import InputError


# --------------------------------------------------------------------------- Carter (2D)
@pytest.mark.parametrize("ratio", [0.2, 0.5, 0.8])
def test_carter_two_dimensional_rolling(ratio):
    """Carter (1926), two identical cylinders, plane strain (Johnson 1985, sec. 8.2):
    q(x) = -sgn(xi) mu [p(x) - (c/a) p0 sqrt(1 - (x - d)^2/c^2)] in the stick zone at the
    leading edge (d = a - c), Fx = -sgn(xi) mu Fn (1 - (c/a)^2),
    |xi| = 2 (1 - nu) mu p0 (1 - c/a) / G."""
    G, nu, mu, a, p0, n = 80e9, 0.3, 0.3, 5e-3, 1e9, 200
    dx = 2.2 * a / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    k = plane_strain_kernels(n, dx, G, nu)
    pz = (p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None)))[:, None]
    fn = pz.sum() * dx
    xi = ratio * 2 * (1 - nu) * mu * p0 / G  # ratio = 1 - c/a
    w = np.zeros((n, 1, 2))
    w[..., 0] = xi * dx
    sol = solve_tangential(k, pz, w, mode="steady", friction=Friction(mu))
    c = a * (1 - ratio)
    d = a - c
    exact = -mu * (pz[:, 0] - (c / a) * p0 * np.sqrt(np.clip(1 - ((x - d) / c) ** 2, 0, None)))
    fx = sol.traction[:, 0, 0].sum() * dx
    # force: discretisation error measured 0.1-0.2 % at 200 strips; issue asks 2 %
    assert fx / (mu * fn) == pytest.approx(-(1 - (c / a) ** 2), abs=0.02 * (1 - (c / a) ** 2))
    err = np.abs(sol.traction[:, 0, 0] - exact) / (mu * p0)
    # traction within 2 % of mu p0 everywhere except within one element of the points where
    # the exact traction behaves like a square root (contact edges x = +-a and the stick/slip
    # boundary x = a - 2c): there a half-element shift alone gives ~ sqrt(dx/c) ~ 3-5 %
    near = np.min(np.abs(x[:, None] - np.array([-a, a, a - 2 * c])[None, :]), axis=1) <= 1.0 * dx
    assert err[~near].max() < 0.02
    # rms over the contact: measured 0.1-0.3 %
    assert np.sqrt(np.mean(err[pz[:, 0] > 0] ** 2)) < 0.005
    # stick at the leading edge, slip at the trailing edge
    inside = pz[:, 0] > 0
    assert sol.status[inside][-1] == STICK and sol.status[inside][0] == SLIP


# ------------------------------------------------------------ Kalker's creep coefficients
def _table(a_over_b, nu):
    t = load_table()
    m = np.isclose(t["a_over_b"], a_over_b) & np.isclose(t["nu"], nu)
    return t["C11"][m][0], t["C22"][m][0], t["C23"][m][0]


def _creep_coefficients(a_over_b, n):
    """C11, C22, C23 of the steady no-slip (linear) problem on an n x n grid, nu = 0.25."""
    G, nu = 80e9, 0.25
    b = 5e-3
    a = a_over_b * b
    hz = hertz_from_semi_axes(a, b, 50e3, G / (1 - nu))
    grid = Grid.covering(a, b, nx=n, ny=n)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    k = rectangle_kernels(n, n, grid.dx, grid.dy, G, nu)
    pz = solve_normal(k, hz.A * X ** 2 + hz.B * Y ** 2, normal_force=50e3).pressure
    out = []
    no_slip = Friction(1e4)  # linear theory: friction bound never reached at 1e-5 creepage
    for xi, eta, phi, comp, norm in [(1e-5, 0, 0, 0, G * a * b * 1e-5), (0, 1e-5, 0, 1, G * a * b * 1e-5),
                                     (0, 0, 1e-3, 1, G * (a * b) ** 1.5 * 1e-3)]:
        w = np.stack([xi - phi * Y, eta + phi * X], axis=-1) * grid.dx
        sol = solve_tangential(k, pz, w, mode="steady", friction=no_slip)
        assert (sol.status[pz > 0] == STICK).all()
        out.append(-sol.traction[..., comp].sum() * grid.dx * grid.dy / norm)
    return np.array(out)


@pytest.mark.parametrize("a_over_b", [0.5, 1.0, 2.0])
def test_creep_coefficients_match_kalker_table(a_over_b):
    # 40 x 40 elements over the Hertz patch + 10 %: measured deviation from Table E.3
    # +1.2..+1.8 % (C11, C22) and -0.9..-1.3 % (C23); the discretisation error decreases
    # roughly like 1/n with scatter from the staircase boundary (n = 20: +3..+5 %)
    got = _creep_coefficients(a_over_b, 40)
    ref = np.array(_table(a_over_b, 0.25))
    np.testing.assert_allclose(got, ref, rtol=0.03)


@pytest.mark.slow
@pytest.mark.parametrize("a_over_b", [0.5, 1.0, 2.0])
def test_creep_coefficients_fine_grid(a_over_b):
    # 50 x 50 elements (dense steady matrix ~ 2 GB flops): still within 3 % of Kalker
    got = _creep_coefficients(a_over_b, 50)
    np.testing.assert_allclose(got, np.array(_table(a_over_b, 0.25)), rtol=0.03)


# ------------------------------------------------------------------ half-space models
MAT = Material(80e9, 0.3)


def _model(kind, mu=0.3, a=5e-3, b=4e-3, n=(22, 18), F=50e3, mu_k=None):
    hz = hertz_from_semi_axes(a, b, F, MAT.contact_modulus)
    grid = Grid.covering(a, b, nx=n[0], ny=n[1])
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    return HalfspaceContact(material=MAT, friction=Friction(mu, mu_k), grid=grid,
                            gap=hz.A * X ** 2 + hz.B * Y ** 2, kind=kind, speed=20.0), hz


def test_full_slip_saturates_at_mu_fn():
    model, _ = _model("steady")
    res = model.solve(model.initial_state(), normal_force=50e3, creepage=(0.002, -0.02, 0.0))
    ft = math.hypot(res.force[0], res.force[1])
    # all elements slip, each with |p_t| = mu p_z (exact up to round-off)
    assert res.diagnostics.n_slip == res.diagnostics.n_contact
    f = res.fields
    g = model.grid
    assert np.hypot(f.traction[..., 0], f.traction[..., 1]).sum() * g.dx * g.dy == pytest.approx(
        0.3 * res.force[2], rel=1e-12)
    # the slip directions differ slightly (elastic deformation), so |F| is a little below
    # mu Fn: at 3x the saturation creepage the measured deficit is 0.005 %
    assert 0.999 * 0.3 * res.force[2] < ft <= 0.3 * res.force[2]
    # direction of the force opposes the creepage (Kalker's sign convention)
    assert res.force[0] < 0 < res.force[1]


def test_kinetic_friction_bounds_sliding_traction():
    # mu_s = 0.4 > mu_k = 0.3: in full slip every element carries mu_k p_z, so the summed
    # traction magnitude is mu_k Fn exactly (round-off)
    model, _ = _model("transient", mu=0.4, mu_k=0.3)
    st = model.initial_state()
    for _ in range(40):  # roll until the material has crossed the contact (full slip)
        res = model.solve(st, normal_force=50e3, creepage=(0.0, -0.03, 0.0))
        st = res.new_state
    t = res.fields.traction
    g = model.grid
    assert res.diagnostics.n_slip == res.diagnostics.n_contact
    assert np.hypot(t[..., 0], t[..., 1]).sum() * g.dx * g.dy == pytest.approx(0.3 * 50e3, rel=1e-12)


def test_transient_rolling_converges_to_steady():
    # constant creepage with partial slip: after the material has passed the contact a few
    # times the transient state is the steady state (same discrete equations; only the
    # solver tolerances 1e-9 differ)
    creep = (1e-3, -2e-3, -3.0)
    steady, _ = _model("steady")
    ref = steady.solve(steady.initial_state(), normal_force=50e3, creepage=creep)
    trans, _ = _model("transient")
    st = trans.initial_state()
    forces = []
    for _ in range(80):
        r = trans.solve(st, normal_force=50e3, creepage=creep)
        st = r.new_state
        forces.append(r.force)
    assert 0 < ref.diagnostics.n_slip < ref.diagnostics.n_contact  # genuinely partial slip
    np.testing.assert_allclose(forces[-1], ref.force, rtol=0, atol=1e-6 * 0.3 * 50e3)
    assert r.diagnostics.n_slip == ref.diagnostics.n_slip
    # and the first step is not steady yet (the test could fail)
    assert abs(forces[0][1] - ref.force[1]) > 0.05 * abs(ref.force[1])


def test_solve_is_pure_and_state_immutable():
    model, _ = _model("transient")
    st = model.initial_state()
    r1 = model.solve(st, normal_force=50e3, creepage=(0, -1e-3, 0))
    r1b = model.solve(st, normal_force=50e3, creepage=(0, -1e-3, 0))
    np.testing.assert_array_equal(r1.force, r1b.force)
    r2 = model.solve(r1.new_state, normal_force=50e3, creepage=(0, -1e-3, 0))
    r2b = model.solve(r1.new_state, normal_force=50e3, creepage=(0, -1e-3, 0))
    np.testing.assert_array_equal(r2.force, r2b.force)
    with pytest.raises(ValueError):
        r2.new_state.traction[0, 0, 0] = 1.0
    lift = model.solve(r2.new_state, approach=-1e-6, creepage=(0, -1e-3, 0))
    assert np.all(lift.force == 0) and lift.diagnostics.n_contact == 0


@pytest.mark.parametrize("fraction", [0.3, 0.7])
def test_cattaneo_mindlin_shift(fraction):
    """Circular contact under a tangential shift delta (Mindlin 1949; Johnson eq. 7.42 for
    two identical bodies): delta = 3 mu P (2 - nu) / (8 G a) [1 - (1 - Q/(mu P))^(2/3)],
    stick radius c = a (1 - Q/(mu P))^(1/3)."""
    mu, P, a = 0.3, 20e3, 4e-3
    model, hz = _model("shift", mu=mu, a=a, b=a, n=(48, 48), F=P)
    G, nu = MAT.shear_modulus, MAT.poisson_ratio
    q_ratio = fraction
    delta = 3 * mu * P * (2 - nu) / (8 * G * a) * (1 - (1 - q_ratio) ** (2 / 3))
    res = model.solve(model.initial_state(), normal_force=P, shift=(delta, 0.0, 0.0))
    # force: measured 0.04-0.05 % off on 48 x 48 elements; 0.5 % allows for the staircase
    # boundary of the discretised contact
    assert -res.force[0] / (mu * P) == pytest.approx(q_ratio, rel=0.005)
    assert abs(res.force[1]) < 1e-6 * P
    # stick radius from the stick area, pi c^2 = n_stick dx dy: measured +0.5..+1.0 %;
    # 2 % is about half an element ring at this resolution (dx = a / 22)
    g = model.grid
    c = math.sqrt(res.diagnostics.n_stick * g.dx * g.dy / math.pi)
    assert c / a == pytest.approx((1 - q_ratio) ** (1 / 3), rel=0.02)


def test_create_model_and_approach_control():

    model, hz = _model("transient")
    same = create_model("halfspace", material=MAT, friction=Friction(0.3), grid=model.grid,
                        gap=model.gap, kind="transient", speed=20.0)
    assert same.time_step == pytest.approx(model.grid.dx / 20.0)
    # prescribed approach: the normal force follows the grid's own force/approach relation
    r1 = same.solve(same.initial_state(), normal_force=50e3, creepage=(0, 0, 0))
    r2 = same.solve(same.initial_state(), approach=r1.diagnostics.approach, creepage=(0, 0, 0))
    assert r2.force[2] == pytest.approx(50e3, rel=1e-6)  # solver tolerance
    with pytest.raises(InputError) as exc:
        create_model("fem")
    assert exc.value.field == "model"
    with pytest.raises(InputError):
        same.solve(same.initial_state(), normal_force=1.0, approach=1e-6)


# ------------------------------------------------- steady solver (issue 16): direct convergence
def _issue_model(kind, n, a=8e-3, b=4e-3, F=50e3):
    """The issue-16 steady case: a = 8, b = 4 mm, n x n elements over the patch + 10 %."""
    hz = hertz_from_semi_axes(a, b, F, MAT.contact_modulus)
    grid = Grid.covering(a, b, nx=n, ny=n)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    return HalfspaceContact(material=MAT, friction=Friction(0.3), grid=grid, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                            kind=kind, speed=20.0)


@pytest.mark.parametrize("creep", [(1e-3, -2e-3, -3.0), (0.0, 0.0, -10.0), (1e-4, 1e-4, 1.0)])
def test_steady_agrees_with_transient_run_to_steady_state(creep, caplog):
    # the steady sweeps and the transient steps repeated until nothing changes solve the same
    # discrete equations; both stop at a traction change of 1e-9 mu p_max per sweep, and the
    # measured differences are <= 5e-10 mu p_max (tractions) and 5e-12 mu Fn (forces)
    steady = _issue_model("steady", 20)
    with caplog.at_level("WARNING", logger="contact"):
        ref = steady.solve(steady.initial_state(), normal_force=50e3, creepage=creep)
    assert not [r for r in caplog.records if r.levelname == "WARNING"]  # no fallback to rolling
    trans = _issue_model("transient", 20)
    st = trans.initial_state()
    bound = 0.3 * ref.new_state.pressure.max()
    for step in range(600):
        r = trans.solve(st, normal_force=50e3, creepage=creep)
        change = np.abs(r.new_state.traction - st.traction).max()
        st = r.new_state
        if step > 2 and change < 1e-10 * bound:
            break
    assert step > 10  # the transient needed many steps: the comparison is not trivial
    np.testing.assert_allclose(ref.new_state.traction, st.traction, rtol=0, atol=1e-8 * bound)
    np.testing.assert_allclose(ref.force, r.force, rtol=0, atol=1e-9 * 0.3 * 50e3)
    assert ref.diagnostics.n_slip == r.diagnostics.n_slip
    assert ref.diagnostics.n_stick == r.diagnostics.n_stick


@pytest.mark.parametrize("creep", [(1e-3, -2e-3, -3.0), (0.0, -1e-3, 0.0), (1e-4, 1e-4, 1.0)])
def test_steady_sweeps_satisfy_the_discrete_equations(creep, caplog):
    # issue 16's 40 x 40 spin case (and a stick-dominated one without spin): the sweeps
    # converge directly (no rolling fallback) and the result satisfies the steady equations,
    # checked independently with the FFT displacement on the whole grid:
    # S = W + u(i) - u(i + 1); stick: |S| ~ 0 and |p| <= mu p_z; slip: |p| = mu p_z, p || -S
    model = _issue_model("steady", 40)
    pz = solve_normal(model.kernels, model.gap, normal_force=50e3).pressure
    g = model.grid
    X, Y = np.meshgrid(g.x, g.y, indexing="ij")
    xi, eta, phi = creep
    w = np.stack([xi - phi * Y, eta + phi * X], axis=-1) * g.dx
    with caplog.at_level("WARNING", logger="contact"):
        sol = solve_tangential(model.kernels, pz, w, mode="steady", friction=Friction(0.3))
    assert not [r for r in caplog.records if r.levelname == "WARNING"]
    assert sol.sweeps < 200
    u = model.kernels.tangential_displacement(sol.traction)
    s = w[:-1] + u[:-1] - u[1:]
    p = sol.traction[:-1]
    stick = sol.status[:-1] == STICK
    slip = sol.status[:-1] == SLIP
    assert stick.any() and slip.any()
    bound = 0.3 * pz[:-1]
    # slip of a stick element: the tractions are accurate to 1e-9 mu p_max per element; the
    # slip that such an error leaves is about the local compliance times it
    tol_s = 1e-7 * 0.3 * pz.max() * model.kernels.K11[g.nx - 1, g.ny - 1]
    assert np.abs(s[stick]).max() < tol_s
    assert (np.hypot(p[stick, 0], p[stick, 1]) <= bound[stick] * (1 + 1e-9)).all()
    pm = np.hypot(p[slip, 0], p[slip, 1])
    np.testing.assert_allclose(pm, bound[slip], rtol=1e-12)
    sm = np.hypot(s[slip, 0], s[slip, 1])
    cos = -(p[slip] * s[slip]).sum(axis=1) / (pm * sm)
    assert cos.min() > 1 - 1e-6


@pytest.mark.slow
def test_steady_150_by_150_in_bounded_memory():
    # issue 16: 150 x 150 steady rolling without spin, < 1 GiB (the dense steady matrix was
    # ~7 GB); memory of the Python/numpy allocations measured by tracemalloc (numba's
    # compiled kernels allocate through numpy's allocator too)
    import tracemalloc
    model = _issue_model("steady", 150)
    tracemalloc.start()
    try:
        res = model.solve(model.initial_state(), normal_force=50e3, creepage=(1e-3, -2e-3, 0.0))
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 2 ** 30
    assert 0 < res.diagnostics.n_slip < res.diagnostics.n_contact
    assert res.force[2] == pytest.approx(50e3, rel=1e-6)


def test_contact_at_the_leading_edge_transient_reaches_the_steady_solution(caplog):
    # a grid exactly over the Hertz patch (no margin): the contact reaches the border elements,
    # including the leading edge, where the entering particles come from outside the grid; both
    # solvers then work on the grid plus one exterior line upstream. The transient steps run to
    # steady state must reach the steady solution (tolerances as in the test above), and a
    # WARNING reports the edge contact
    a, b = 5e-3, 4e-3
    hz = hertz_from_semi_axes(a, b, 50e3, MAT.contact_modulus)
    grid = Grid.covering(a, b, nx=20, ny=16, margin=0.0)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")

    def model(kind):
        return HalfspaceContact(material=MAT, friction=Friction(0.3), grid=grid, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                                kind=kind, speed=20.0)

    creep = (1e-3, -2e-3, -3.0)
    steady = model("steady")
    with caplog.at_level("WARNING", logger="contact"):
        ref = steady.solve(steady.initial_state(), normal_force=50e3, creepage=creep)
    assert (ref.new_state.pressure[-1] > 0).any()  # the case is what it claims
    assert any("leading" in r.getMessage() for r in caplog.records if r.levelname == "WARNING")
    trans = model("transient")
    st = trans.initial_state()
    bound = 0.3 * ref.new_state.pressure.max()
    for step in range(600):
        r = trans.solve(st, normal_force=50e3, creepage=creep)
        change = np.abs(r.new_state.traction - st.traction).max()
        st = r.new_state
        if step > 2 and change < 1e-10 * bound:
            break
    assert step > 10
    np.testing.assert_allclose(ref.new_state.traction, st.traction, rtol=0, atol=1e-8 * bound)
    assert ref.diagnostics.n_slip == r.diagnostics.n_slip


def test_steady_fallback_to_rolling_warns_and_agrees(monkeypatch, caplog):
    # the last resort: when the steady sweeps stop short (here forced: one sweep), the solver
    # logs a WARNING and finishes with the fixed point of transient steps, which reaches the
    # same solution (its stopping rule, a step change below 10 tol, leaves ~1e-8 mu p_max: measured
    # 1.3e-8; bound 1e-6)
    import contact.halfspace.tangential as tangential
    model = _issue_model("steady", 16)
    creep = (1e-3, -2e-3, -3.0)
    ref = model.solve(model.initial_state(), normal_force=50e3, creepage=creep)
    real = tangential.steady_gauss_seidel

    def one_sweep(*args):
        return real(*args[:-2], 1, args[-1])

    monkeypatch.setattr(tangential, "steady_gauss_seidel", one_sweep)
    with caplog.at_level("WARNING", logger="contact"):
        res = model.solve(model.initial_state(), normal_force=50e3, creepage=creep)
    assert any("transient-step iteration" in r.getMessage() for r in caplog.records if r.levelname == "WARNING")
    bound = 0.3 * ref.new_state.pressure.max()
    np.testing.assert_allclose(res.new_state.traction, ref.new_state.traction, rtol=0, atol=1e-6 * bound)
    assert res.diagnostics.n_slip == ref.diagnostics.n_slip


@pytest.mark.parametrize("creep", [(1e-3, -2e-3, -3.0), (0.0, -1e-3, 0.0), (1e-3, -2e-3, 0.0)])
def test_steady_sweeps_with_fft_products_agree_with_exact_updates(creep, monkeypatch, caplog):
    # the large-contact variant (local updates + one FFT product per sweep) forced on the 40 x 40
    # case: the same solution as the sweeps with exact updates, to the solver tolerance (both
    # stop at a sweep change of 1e-9 mu p_max; measured differences ~1e-10), without falling back
    import contact.halfspace.tangential as tangential
    model = _issue_model("steady", 40)
    pz = solve_normal(model.kernels, model.gap, normal_force=50e3).pressure
    g = model.grid
    X, Y = np.meshgrid(g.x, g.y, indexing="ij")
    xi, eta, phi = creep
    w = np.stack([xi - phi * Y, eta + phi * X], axis=-1) * g.dx
    exact = solve_tangential(model.kernels, pz, w, mode="steady", friction=Friction(0.3))
    monkeypatch.setattr(tangential, "STEADY_FFT_MIN_CONTACT", 0)
    with caplog.at_level("INFO", logger="contact"):
        fft = solve_tangential(model.kernels, pz, w, mode="steady", friction=Friction(0.3))
    assert not [r for r in caplog.records if r.levelno >= 20 and "no convergence" in r.getMessage()]
    np.testing.assert_allclose(fft.traction, exact.traction, rtol=0, atol=1e-8 * 0.3 * pz.max())
    np.testing.assert_array_equal(fft.status, exact.status)


def test_transient_step_reuses_the_normal_solution_of_the_same_load(monkeypatch):
    """A step whose state records that its pressure solves the normal problem of the same load
    (``HalfspaceState.normal``) does not solve it again; another load, another series compliance or
    a state without the record does. The reused pressure is the solution to the tolerance: a fresh
    solve from zero agrees to 10 tol of the peak (two solutions within the tolerance, tol = 1e-9).
    The result depends on the state and the inputs only: another model instance gives the same
    numbers bit for bit."""
    import dataclasses

    import contact.halfspace.model as halfspace

    calls = []

    def counted(*args, **kwargs):
        calls.append(kwargs.get("normal_force"))
        return solve_normal(*args, **kwargs)

    monkeypatch.setattr(halfspace, "solve_normal", counted)
    model, _ = _model("transient")
    state = model.initial_state()
    pressures = []
    for _ in range(4):
        result = model.solve(state, normal_force=50e3, creepage=(0, -3e-3, 0))
        state = result.new_state
        pressures.append(state.pressure)
    assert calls == [50e3]  # the first step only
    assert all(np.array_equal(p, pressures[0]) for p in pressures)
    fresh = solve_normal(model.kernels, model.gap, normal_force=50e3, tol=model.tol)
    assert np.abs(fresh.pressure - pressures[-1]).max() <= 10 * model.tol * fresh.pressure.max()

    other_model, _ = _model("transient")
    again = other_model.solve(state, normal_force=50e3, creepage=(0, -3e-3, 0))
    same = model.solve(state, normal_force=50e3, creepage=(0, -3e-3, 0))
    np.testing.assert_array_equal(again.force, same.force)
    np.testing.assert_array_equal(again.new_state.pressure, same.new_state.pressure)
    assert calls == [50e3]

    model.solve(state, normal_force=51e3, creepage=(0, -3e-3, 0))
    model.solve(state, normal_force=50e3, creepage=(0, -3e-3, 0), compliance=(0.0, 0.0, 1e-9))
    model.solve(dataclasses.replace(state, normal=None), normal_force=50e3, creepage=(0, -3e-3, 0))
    assert calls == [50e3, 51e3, 50e3, 50e3]
    approach = result.diagnostics.approach
    step = model.solve(state, approach=approach, creepage=(0, -3e-3, 0))
    model.solve(step.new_state, approach=approach, creepage=(0, -3e-3, 0))
    assert calls == [50e3, 51e3, 50e3, 50e3, None]  # solved once for the approach, then reused

    # the same load on another contact (another gap on the same grid): solved, not taken from the state
    narrower = HalfspaceContact(material=MAT, friction=Friction(0.3), grid=model.grid, gap=1.2 * model.gap,
                                kind="transient", speed=20.0)
    other = narrower.solve(state, normal_force=50e3, creepage=(0, -3e-3, 0))
    assert calls[-1] == 50e3 and len(calls) == 6
    reference = solve_normal(narrower.kernels, narrower.gap, normal_force=50e3, tol=narrower.tol)
    assert np.abs(other.new_state.pressure - reference.pressure).max() <= 10 * narrower.tol * reference.pressure.max()
