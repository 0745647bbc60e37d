"""Time-domain interaction against independent references: direct convolution, the coupled
frequency-domain solution, static equilibrium and a complex-eigenvalue stability analysis."""

import numpy as np
import pytest

import interaction.simulate as sim
from fe.greens import kernel_dtft, modal_poles_residues, ramp_invariant_kernel
from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_curvatures
from contact.params import Friction, Material
from contact.point.model import PointContact
from interaction.loop_steps import PREDICTION_ORDER, PREDICTION_WINDOW, fit_prediction, predicted
from interaction.linear_contact import LinearContact, coupled_response
from interaction.metrics import squeal_metrics
from interaction.simulate import simulate
from interaction.structures import ConvolutionStructure, ModalStructure
from squealcore.errors import InputError
from stability.linear import (growing_poles, pole_residue_eigenvalues, sliding_instabilities,
                              stability_eigenvalues)

DT = 3.6e-5
SPEED = 50 / 3.6
LOAD = 50e3

# A small wheel (three modes with vertical/lateral coupling at the contact) and a rail (two
# heavily damped modes); mass-normalised shapes in m/sqrt(kg), contact frame.
WHEEL = ([410.0, 1120.0, 2010.0], [1e-3, 1e-4, 1e-4],
         np.array([[0.0, 0.12, 0.01], [0.002, 0.11, -0.02], [0.0, 0.09, 0.03]]))
RAIL = ([330.0, 900.0], [0.15, 0.2], np.array([[0.0, 0.05, 0.0], [0.0, 0.0, 0.17]]))


def _point_contact(mu, kind="transient", tangential="strip"):
    material = Material.from_young(210e9, 0.3)
    hertz = hertz_from_curvatures(1 / 0.78, 1 / 0.6, LOAD, material.contact_modulus)
    return PointContact(material=material, friction=Friction(mu), hertz=hertz, kind=kind, speed=SPEED, time_step=DT,
                        tangential=tangential)


def _modal(modes):
    return ModalStructure(*modal_poles_residues(*modes), DT)


def _convolution(modes, n):
    return ConvolutionStructure(ramp_invariant_kernel(*modal_poles_residues(*modes), DT, n), DT)


def test_modal_recursion_equals_direct_convolution():
    # The same nonlinear run with the wheel advanced by its exact recursion and by a direct
    # convolution with its (untruncated) kernel: displacements equal to 1e-10 relative.
    n = 1500
    a = simulate(_modal(WHEEL), _convolution(RAIL, n), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.01, 0.0), n_steps=n)
    b = simulate(_convolution(WHEEL, n), _convolution(RAIL, n), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.01, 0.0), n_steps=n)
    scale = np.abs(a.wheel_displacement).max()
    assert scale > 0
    assert np.abs(a.wheel_displacement - b.wheel_displacement).max() <= 1e-10 * scale
    assert np.abs(a.force - b.force).max() <= 1e-8 * LOAD


@pytest.mark.parametrize("frequency", [250.0, 1000.0, 2500.0])
def test_linearised_contact_matches_frequency_domain(frequency):
    # Linear contact (normal spring + linear creep, creepages fed back from the structures' velocities)
    # under a harmonic approach excitation: the steady force amplitude and phase of the time
    # stepping equal the coupled frequency-domain solution. Tolerance 1 % (issue); the residual
    # is the decay of the start transient, below 1e-4 after 1 s for these damping ratios.
    contact = LinearContact(1.1e9, (4e6, 3.5e6), 0.0, LOAD, DT)
    n = int(round(1.0 / DT))
    t = np.arange(n) * DT
    amplitude = 1e-7  # m, small against the static approach (~68 um)
    excitation = amplitude * np.cos(2 * np.pi * frequency * t)
    wheel = ((np.array(WHEEL[0]), np.maximum(WHEEL[1], 0.01), WHEEL[2]))
    result = simulate(_modal(wheel), _modal(RAIL), contact, speed=SPEED, wheel_load=LOAD,
                      creepage=(0.0, 0.0, 0.0), n_steps=n, excitation=excitation)
    periods = int(0.1 * frequency)
    m = int(round(periods / frequency / DT))
    tail = slice(n - m, n)
    basis = np.exp(1j * 2 * np.pi * frequency * t[tail])
    dF = result.force[tail] - np.array([0.0, 0.0, LOAD])
    measured = 2 * (basis.conj() @ dF) / m
    expected = amplitude * coupled_response(kernel_dtft(*modal_poles_residues(*wheel), DT, [frequency]),
                                            kernel_dtft(*modal_poles_residues(*RAIL), DT, [frequency]),
                                            contact, SPEED, [frequency])[0]
    for i in (1, 2):
        assert abs(measured[i] - expected[i]) <= 0.01 * abs(expected[i])


def test_static_equilibrium_holds_without_creepage():
    n = 3000
    r = simulate(_modal(WHEEL), _modal(RAIL), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, 0.0, 0.0), n_steps=n)
    # Nothing excites the system: F3 stays at the wheel load and no tangential force appears
    # (round-off only).
    assert np.abs(r.force[:, 2] - LOAD).max() <= 1e-9 * LOAD
    assert np.abs(r.force[:, :2]).max() <= 1e-9 * LOAD
    assert np.abs(r.wheel_displacement).max() <= 1e-15


def test_high_friction_gives_no_limit_cycle():
    # mu = 5: the creep force (eta = -0.3 %) is far from saturation, so the structural creepage
    # only damps: the start transient decays and no squeal is flagged.
    n = int(round(0.6 / DT))
    r = simulate(_modal(WHEEL), _modal(RAIL), _point_contact(5.0), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.003, 0.0), n_steps=n)
    early = np.std(r.force[: n // 6, 1])
    late = np.std(r.force[-n // 6:, 1])
    assert late < 1e-2 * early
    assert not squeal_metrics(r.force[:, 1], DT, window=0.1).squeal


# Two wheel modes that couple through sliding friction (flutter), found by the linear analysis.
FLUTTER_WHEEL = ([1026.3, 1498.0], [1e-3, 1e-3], np.array([[0.0, 0.0247, -0.1723], [0.0, 0.1087, -0.0098]]))
FLUTTER_RAIL = ([329.6], [0.1], np.array([[0.0, 0.0, 0.177]]))


def _crossing_frequency(signal):
    x = signal - signal.mean()
    idx = np.nonzero((x[:-1] < 0) & (x[1:] >= 0))[0]
    times = (idx + x[idx] / (x[idx] - x[idx + 1])) * DT
    return (len(times) - 1) / (times[-1] - times[0])


def test_predicted_instability_grows_at_predicted_frequency():
    contact = _point_contact(0.3)
    hertz = contact.hertz
    k_n = 1.5 * LOAD / hertz.approach  # Hertz: dF/dδ = 3F/(2δ)
    ev = stability_eigenvalues(FLUTTER_WHEEL, FLUTTER_RAIL, k_n, +0.3)  # eta < 0: F_y = +mu F_z
    unstable = ev[(ev.real > 0) & (ev.imag > 0)]
    assert unstable.size == 1
    predicted = unstable[0].imag / (2 * np.pi)
    n = int(round(0.05 / DT))
    r = simulate(_modal(FLUTTER_WHEEL), _modal(FLUTTER_RAIL), contact, speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.03, 0.0), n_steps=n)
    fz = r.force[:, 2]
    first = np.std(fz[n // 5: 2 * n // 5])
    last = np.std(fz[3 * n // 5: 4 * n // 5])
    growth = np.log(last / first) / (2 * n // 5 * DT)
    assert growth > 0.5 * unstable[0].real  # it grows, at a rate of the predicted order
    # the frequency of the growth, where the linear analysis applies: over the first 0.02 s (the
    # normal force's deviation grows from 6 % to 25 % of the load in full sliding); later the
    # oscillation lifts the wheel off and its frequency moves by 2-3 % with the contact law
    assert _crossing_frequency(fz[: 2 * n // 5]) == pytest.approx(predicted, rel=0.02)


def test_predicted_stable_case_decays():
    contact = _point_contact(0.3)
    k_n = 1.5 * LOAD / contact.hertz.approach
    ev = stability_eigenvalues(FLUTTER_WHEEL, FLUTTER_RAIL, k_n, -0.3)  # eta > 0: F_y = -mu F_z
    assert np.all(ev.real < 0)
    n = int(round(0.1 / DT))
    r = simulate(_modal(FLUTTER_WHEEL), _modal(FLUTTER_RAIL), contact, speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, 0.03, 0.0), n_steps=n)
    fz = r.force[:, 2]
    assert np.std(fz[-n // 5:]) < 0.1 * np.std(fz[: n // 5])


def test_compiled_loop_equals_python_loop():
    # The compiled point-contact loop (contact/point/loop.py) against the Python reference loop:
    # the same equations, solved differently (the compiled loop by Newton's method with the law's
    # own Jacobian from the first iteration, the Python loop by fixed point and then Newton with a
    # forward-difference Jacobian), so the histories agree to the coupling tolerance (1e-9 Q),
    # and the compiled loop needs fewer evaluations of the law per step.
    n = 3000
    runs = [simulate(_modal(WHEEL), _convolution(RAIL, 800), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                     creepage=(0.0, -0.01, 0.0), n_steps=n, compiled=compiled) for compiled in (True, False)]
    a, b = runs
    assert np.abs(a.force - b.force).max() <= 1e-9 * LOAD
    scale = np.abs(b.wheel_displacement).max()
    assert np.abs(a.wheel_displacement - b.wheel_displacement).max() <= 1e-9 * scale
    assert np.abs(a.creepage - b.creepage).max() <= 1e-9
    assert a.iterations.mean() < b.iterations.mean()
    assert np.allclose(a.slip_fraction, b.slip_fraction, atol=1e-12)


class _WithoutSeriesCompliance:
    """A contact model seen through the plain interface: the interaction then iterates on the
    whole instantaneous compliance (fixed point) instead of handing its diagonal to the model."""

    def __init__(self, model):
        self.model = model
        self.time_step = model.time_step

    def initial_state(self):
        return self.model.initial_state()

    def solve(self, state, **kwargs):
        return self.model.solve(state, **kwargs)


def _halfspace_contact(mu, tol, capacity=1.0):
    """Half-space contact on a grid covering the Hertz patch at ``capacity`` times the load (+ 25 %)."""
    material = Material.from_young(210e9, 0.3)
    hertz = hertz_from_curvatures(1 / 0.78, 1 / 0.6, LOAD, material.contact_modulus)
    peak = hertz.scaled(capacity * LOAD)
    grid = Grid.covering(peak.a, peak.b, dx=SPEED * DT, dy=1e-3, margin=0.25)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    return HalfspaceContact(material=material, friction=Friction(mu), grid=grid, gap=hertz.A * x**2 + hertz.B * y**2,
                            kind="transient", speed=SPEED, tol=tol)


def test_halfspace_series_compliance_equals_fixed_point_coupling():
    # The half-space model takes the diagonal of the structures' instantaneous compliance into its
    # own solution (a rank-one term in its influence coefficients); the plain coupling iterates on
    # all of it. Both solve the same implicit equations, so the histories agree to the solver
    # tolerance (1e-9 of Q per step; 1e-7 Q allows its accumulation over the run). The rail is
    # made soft so that the loop gain (instantaneous compliance x contact stiffness) is ~0.3 and
    # the coupling matters.
    n = 100
    rail = ([330.0, 900.0], [0.15, 0.2], np.array([[0.0, 1.5, 0.0], [0.0, 0.0, 1.2]]))
    runs = []
    for wrap in (lambda c: c, _WithoutSeriesCompliance):
        runs.append(simulate(_modal(WHEEL), _convolution(rail, n), wrap(_halfspace_contact(0.3, 1e-10)), speed=SPEED,
                             wheel_load=LOAD, creepage=(0.0, -0.004, 0.0), n_steps=n, tolerance=1e-9))
    series, plain = runs
    gain = (_modal(WHEEL).k0 + _convolution(rail, n).k0)[2, 2] * 1.5 * LOAD / series.static_approach
    assert gain > 0.2  # the test is meaningful only with a strong coupling
    assert plain.iterations.mean() > 2 * series.iterations.mean()
    assert np.abs(series.force - plain.force).max() <= 1e-7 * LOAD
    # the tangential coupling is exercised: creep forces of ~1 kN, 1e7 times the tolerance
    assert np.abs(series.force[:, 1]).max() > 0.01 * LOAD


def test_sliding_instabilities_lists_the_growing_poles():
    k_n = 1.5 * LOAD / _point_contact(0.3).hertz.approach
    found = sliding_instabilities(FLUTTER_WHEEL, k_n, +0.3, FLUTTER_RAIL)
    ev = stability_eigenvalues(FLUTTER_WHEEL, FLUTTER_RAIL, k_n, +0.3)
    expected = ev[(ev.real > 0) & (ev.imag > 0)]
    assert len(found) == expected.size == 1
    assert found[0]["frequency"] == pytest.approx(expected[0].imag / (2 * np.pi), rel=1e-12)
    assert found[0]["growth_rate"] == pytest.approx(expected[0].real, rel=1e-12)
    nearest = np.argmin(np.abs(np.asarray(FLUTTER_WHEEL[0]) - found[0]["frequency"]))
    assert found[0]["mode"] == nearest
    # without friction coupling the damped system has no growing pole (a check that can fail:
    # the contact spring alone is symmetric and positive)
    assert sliding_instabilities(FLUTTER_WHEEL, k_n, 0.0, FLUTTER_RAIL) == []


def test_pole_residue_stability_equals_the_modal_analysis():
    """Second method: the closed loop of the pole-residue receptance (any wheel model) against
    the modal state-space analysis of stability_eigenvalues, for real modes on a rigid rail."""
    k_n = 1.5 * LOAD / _point_contact(0.3).hertz.approach
    no_rail = (np.zeros(0), np.zeros(0), np.zeros((0, 3)))
    # two close modes that friction can couple (like the default wheel's 5 kHz pair)
    pair = ([5000.0, 5038.0], [1e-4, 1e-4], np.array([[0.0, 0.1, 0.1], [0.0, 0.2, -0.02]]))
    for wheel in (FLUTTER_WHEEL, pair):
        poles, residues = modal_poles_residues(*wheel)
        for mu in (-0.3, 0.0, 0.3, 0.6):
            modal = _by_frequency(stability_eigenvalues(wheel, no_rail, k_n, mu))
            loop = _by_frequency(pole_residue_eigenvalues(poles, residues, k_n, mu))
            assert np.abs(loop - modal).max() <= 1e-9 * np.abs(modal).max()
    # the pair is unstable for one sliding direction only (a check that can fail)
    poles, residues = modal_poles_residues(*pair)
    assert len(growing_poles(pole_residue_eigenvalues(poles, residues, k_n, 0.3))) == 1
    assert growing_poles(pole_residue_eigenvalues(poles, residues, k_n, -0.3)) == []
    assert growing_poles(pole_residue_eigenvalues(poles, residues, k_n, 0.0)) == []


def test_pole_residue_stability_of_one_mode_matches_the_closed_form():
    """One complex pole pair with a non-symmetric residue (as rotation gives): the characteristic
    equation 1 + k_n (r / (s - p) + conj(r) / (s - conj p)) = 0 is the quadratic
    s² - 2 Re(p) s + |p|² + k_n (2 Re(r) s - 2 Re(r conj p)) = 0."""
    p = -40.0 + 2j * np.pi * 2000.0
    residues = np.zeros((1, 3, 3), complex)
    residues[0, 2, 2] = 1e-9 / (2j * 2 * np.pi * 2000.0) * (1.0 + 0.1j)
    residues[0, 2, 1] = 3e-10 * (0.2 - 1.0j) / (2 * np.pi * 2000.0)
    k_n, mu = 1e9, 0.4
    r = residues[0, 2, 2] + mu * residues[0, 2, 1]
    expected = np.roots([1.0, -2 * p.real + 2 * k_n * r.real, abs(p) ** 2 - 2 * k_n * (r * np.conj(p)).real])
    found = pole_residue_eigenvalues([p], residues, k_n, mu)
    assert _by_frequency(found) == pytest.approx(_by_frequency(expected), rel=1e-10)


def _by_frequency(eigenvalues):
    """Eigenvalues sorted by imaginary part (distinct in these tests)."""
    eigenvalues = np.asarray(eigenvalues)
    return eigenvalues[np.argsort(eigenvalues.imag)]


def test_compiled_halfspace_loop_equals_python_loop():
    # The compiled half-space loop (contact/halfspace/loop.py: states as element lists, normal
    # problems warm-started from a table of solutions, the tangential inputs' dependence on the
    # normal force solved within the step) against the Python reference loop (full-grid states,
    # FFT displacements, every off-diagonal compliance iterated). Both solve the same implicit
    # equations to the solver tolerance (1e-10 here), so the histories agree to 1e-6 Q over the
    # run. A 1 kHz roughness of 1.5 times the static approach makes the wheel lift off and land
    # again, so cold starts, changing contact areas and stick/slip changes are all exercised.
    n = 600
    contact = _halfspace_contact(0.3, 1e-10, capacity=3.0)
    static = contact.solve(contact.initial_state(), normal_force=LOAD).diagnostics.approach
    t = np.arange(n) * DT
    excitation = -3.0 * static * np.maximum(np.sin(2 * np.pi * 1000.0 * t), 0.0) * (t > 0.004)
    runs = [simulate(_modal(WHEEL), _convolution(RAIL, 800), _halfspace_contact(0.3, 1e-10, 3.0), speed=SPEED,
                     wheel_load=LOAD, creepage=(0.0, -0.004, 0.0), n_steps=n, tolerance=1e-10,
                     excitation=excitation, compiled=compiled) for compiled in (True, False)]
    a, b = runs
    lift_off = b.force[:, 2] == 0.0
    assert 10 < lift_off.sum() < n // 2  # the run loses and regains contact
    assert np.array_equal(a.force[:, 2] == 0.0, lift_off)
    assert np.abs(a.force - b.force).max() <= 1e-6 * LOAD
    scale = np.abs(b.wheel_displacement).max()
    assert np.abs(a.wheel_displacement - b.wheel_displacement).max() <= 1e-6 * scale
    assert np.abs(a.slip_fraction - b.slip_fraction).max() <= 0.02  # an element or two at the stick/slip border


def test_newton_takes_over_where_the_fixed_point_fails(monkeypatch):
    # A soft spring in series with the rail (2e-9 m/N more lateral instantaneous compliance):
    # in partial slip the point contact's creep stiffness times that compliance per rolled step
    # makes the coupling's loop gain exceed 1, so the plain fixed point diverges at once. The
    # Python loop's Newton steps (forward-difference Jacobian, from iteration NEWTON_AFTER on) and
    # the compiled loop's (the law's own Jacobian) converge it, for the creep law on relaxed
    # creepages and for the strips (whose force is piecewise smooth in the trial force: elements
    # switch between stick and slip), and the two loops agree to the coupling tolerance.
    # Independent check for the creep law: once the start transient has died out the lateral
    # force is its steady creep force at the final normal force and creepage (within 0.2 %; the
    # wheel's lightly damped modes still ring by ~10 N of 12 kN).
    kernel = ramp_invariant_kernel(*modal_poles_residues(*RAIL), DT, 800)
    kernel[0] += np.diag([2e-9, 2e-9, 6e-10])
    kwargs = dict(speed=SPEED, wheel_load=LOAD, creepage=(0.0, -0.002, 0.0), n_steps=3000, max_iterations=60)
    with monkeypatch.context() as m:
        m.setattr(sim, "NEWTON_AFTER", 60)
        with pytest.raises(sim.SimulationDiverged, match="did not converge"):
            simulate(_modal(WHEEL), ConvolutionStructure(kernel, DT), _point_contact(0.6, tangential="relaxation"),
                     compiled=False, **kwargs)
    for tangential in ("relaxation", "strip"):
        a, b = [simulate(_modal(WHEEL), ConvolutionStructure(kernel, DT), _point_contact(0.6, tangential=tangential),
                         compiled=compiled, **kwargs) for compiled in (True, False)]
        assert (b.iterations > sim.NEWTON_AFTER).any()
        assert a.iterations.max() <= 6  # law evaluations per step of the compiled loop
        assert np.abs(a.force - b.force).max() <= 1e-7 * LOAD
    a_relaxed = simulate(_modal(WHEEL), ConvolutionStructure(kernel, DT), _point_contact(0.6, tangential="relaxation"),
                         compiled=True, **kwargs)
    steady = _point_contact(0.6, tangential="relaxation").steady_force(a_relaxed.force[-1, 2], a_relaxed.creepage[-1])
    assert a_relaxed.force[-1, 1] == pytest.approx(steady[1], rel=2e-3)


def test_compiled_halfspace_snapshots_equal_python_loop_fields():
    # The compiled half-space loop run in one-step chunks (its whole state carried between the
    # calls) with contact-field snapshots, against the Python reference loop's fields of the same
    # steps, through lift-off (roughness as in test_compiled_halfspace_loop_equals_python_loop).
    # Independent checks: each snapshot integrates to the force of its step (the loop's own sum,
    # to round-off) and matches the Python loop's full-grid fields to the solver tolerance.
    n = 240
    contact = _halfspace_contact(0.3, 1e-10, capacity=3.0)
    static = contact.solve(contact.initial_state(), normal_force=LOAD).diagnostics.approach
    t = np.arange(n) * DT
    excitation = -3.0 * static * np.maximum(np.sin(2 * np.pi * 1000.0 * t), 0.0) * (t > 0.004)
    steps = (20, 111, 150, n - 1)
    calls = {True: [], False: []}
    runs = [simulate(_modal(WHEEL), _convolution(RAIL, 800), _halfspace_contact(0.3, 1e-10, 3.0), speed=SPEED,
                     wheel_load=LOAD, creepage=(0.0, -0.004, 0.0), n_steps=n, tolerance=1e-10, excitation=excitation,
                     compiled=compiled, snapshot_steps=steps, chunk_seconds=1e-9,
                     progress=lambda done, total, c=compiled: calls[c].append((done, total)))
            for compiled in (True, False)]
    a, b = runs
    lift_off = b.force[:, 2] == 0.0
    assert lift_off[:150].any() and not lift_off[steps[1]]  # snapshots before and after a lift-off
    assert np.abs(a.force - b.force).max() <= 1e-6 * LOAD  # tolerance of the existing comparison
    # a first chunk of up to the first snapshot step, then one-step chunks (1e-9 s each), each reported
    assert [done for done, _ in calls[True]] == list(range(steps[0] + 1, n + 1))
    assert calls[False] == [(done, n) for done in range(1, n + 1)]
    assert sorted(a.extra["snapshots"]) == sorted(b.extra["snapshots"]) == list(steps)
    area = contact.grid.dx * contact.grid.dy
    for step in steps:
        fa, fb = a.extra["snapshots"][step], b.extra["snapshots"][step]
        assert fa.pressure.shape == (contact.grid.nx, contact.grid.ny) and fa.traction.shape[-1] == 2
        assert fa.pressure.sum() * area == pytest.approx(a.force[step, 2], rel=1e-12, abs=1e-9)
        assert fa.traction[..., 0].sum() * area == pytest.approx(a.force[step, 0], rel=1e-12, abs=1e-9)
        assert fa.traction[..., 1].sum() * area == pytest.approx(a.force[step, 1], rel=1e-12, abs=1e-9)
        pmax = max(fb.pressure.max(), 1.0)
        # the histories' 1e-6 of the load, per element of the fields (found: 3e-8)
        assert np.abs(fa.pressure - fb.pressure).max() <= 1e-6 * pmax
        assert np.abs(fa.traction - fb.traction).max() <= 1e-6 * 0.3 * pmax
        assert np.array_equal(fa.status > 0, fb.status > 0)  # the same contact area
        assert np.mean(fa.status != fb.status) <= 0.01  # stick/slip: an element or two at the border
        assert np.array_equal(fa.x, contact.grid.x) and np.array_equal(fa.y, contact.grid.y)


def test_point_contact_has_no_snapshots_and_progress_can_interrupt():
    # The point model has no contact fields: the snapshots are an empty dict. A KeyboardInterrupt
    # raised between chunks (here by the progress callback, as Ctrl-C would be) stops the run.
    r = simulate(_modal(WHEEL), _convolution(RAIL, 800), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.01, 0.0), n_steps=300, snapshot_steps=(10, 299))
    assert r.extra["snapshots"] == {}
    calls = []

    def interrupt(done, total):
        calls.append(done)
        if len(calls) == 2:
            raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        simulate(_modal(WHEEL), _convolution(RAIL, 800), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.01, 0.0), n_steps=3000, chunk_seconds=1e-9, progress=interrupt)
    assert len(calls) == 2 and calls[1] < 3000


def test_snapshot_steps_out_of_range_are_refused():
    with pytest.raises(InputError, match="snapshot_steps"):
        simulate(_modal(WHEEL), _convolution(RAIL, 800), _point_contact(0.3), speed=SPEED, wheel_load=LOAD,
                 creepage=(0.0, -0.01, 0.0), n_steps=100, snapshot_steps=(100,))


def test_force_prediction_is_exact_for_a_few_harmonics():
    # The first coupling pass of the compiled half-space loop starts from a linear prediction of
    # the force (interaction/loop_steps.py). A constant plus h sinusoids obeys a linear recursion of
    # order 2 h + 1, so the fitted order-30 predictor must reproduce the next sample of a 5 kHz
    # limit cycle with two overtones (5.6 steps per period, where linear extrapolation is off by
    # about the amplitude) to round-off of the fit (1e-6 of the amplitude here); a constant
    # direction (nothing to fit) keeps the linear extrapolation.
    n = 400
    phase = 2 * np.pi * 5000.0 * DT * np.arange(n + 1)
    fy = 30e3 + 900.0 * np.sin(phase) + 200.0 * np.sin(2 * phase + 0.3) + 50.0 * np.cos(3 * phase + 1.0)
    force = np.column_stack([np.zeros(n + 1), fy, np.full(n + 1, LOAD)])
    coef, mean, use = np.zeros((3, PREDICTION_ORDER)), np.zeros(3), np.zeros(3, np.int64)
    fit_prediction(force[:n], n, coef, mean, use)
    assert list(use) == [0, 1, 0]
    assert abs(predicted(force, n, 1, coef, mean) - fy[n]) < 1e-6 * 900.0
    assert abs(2 * fy[n - 1] - fy[n - 2] - fy[n]) > 100.0  # what the extrapolation would give


def test_compiled_halfspace_loop_does_not_depend_on_its_chunks():
    # The force prediction is refitted at fixed steps (multiples of PREDICTION_REFIT), so a run
    # split into one-step chunks must give the very same histories as one run in large chunks,
    # past the steps where the prediction starts (a 1 kHz roughness keeps the force moving).
    n = PREDICTION_WINDOW + PREDICTION_ORDER + 100
    contact = _halfspace_contact(0.3, 1e-9)
    static = contact.solve(contact.initial_state(), normal_force=LOAD).diagnostics.approach
    excitation = 0.2 * static * np.sin(2 * np.pi * 1000.0 * np.arange(n) * DT)
    a, b = [simulate(_modal(WHEEL), _convolution(RAIL, 800), _halfspace_contact(0.3, 1e-9), speed=SPEED,
                     wheel_load=LOAD, creepage=(0.0, -0.004, 0.0), n_steps=n, tolerance=1e-9,
                     excitation=excitation, chunk_seconds=seconds) for seconds in (1e-9, 10.0)]
    assert np.array_equal(a.force, b.force)
    assert np.array_equal(a.iterations, b.iterations)


@pytest.mark.parametrize("nk", [1, 6, 7])
def test_compiled_histories_are_the_convolution_and_the_recursion(nk):
    # interaction/loop_steps.py sums the rail's convolution as inner products of the kernel's rows
    # (interaction.structures.rail_rows) with the flat force buffer, and the wheel's modal
    # recursion; against the same sums written with numpy (einsum) on the kernel as stored, to
    # round-off.
    from interaction.bundles import LoopState, Structures
    from interaction.loop_steps import structural_histories
    from interaction.structures import rail_rows
    rng = np.random.default_rng(nk)
    m = 4
    tail = rng.standard_normal((nk, 3, 3)) * 1e-9
    structures = Structures(np.exp(1j * rng.uniform(0, 1, m)), rng.standard_normal((m, 3, 3)) * (1 + 1j) * 1e-9,
                            np.eye(3) * 1e-9, rail_rows(tail), np.eye(3) * 1e-9)
    wheel = rng.standard_normal((m, 3)) + 1j * rng.standard_normal((m, 3))
    buffer = rng.standard_normal((2 * nk, 3)) * 1e3
    head = nk // 2
    far = rng.standard_normal((nk, 3)) * 1e-6  # the far field of the block starting at step 10
    state = LoopState(wheel, buffer, np.array([head]), np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3),
                      np.zeros(1), np.zeros(1, np.int64), np.zeros(6), far, np.array([10]))
    hist_w, hist_r = np.zeros(3), np.zeros(3)
    structural_histories(structures, state, hist_w, hist_r, 10 + nk - 1)
    rail = np.einsum("qij,qj->i", tail, buffer[head:head + nk]) + far[nk - 1]
    wheel_sum = 2 * np.einsum("rij,rj->i", structures.wheel_weights, wheel).real
    assert np.allclose(hist_r, rail, rtol=1e-12, atol=1e-12 * np.abs(rail).max())
    assert np.allclose(hist_w, wheel_sum, rtol=1e-12, atol=1e-12 * np.abs(wheel_sum).max())


@pytest.mark.parametrize("start", [0, 512, 1536])
def test_rail_far_field_equals_the_direct_convolution(start):
    # interaction.structures.RailFarField sums the rail kernel's samples beyond the near part by
    # FFT (overlap-save), a block of steps at a time; against the direct sum over those samples
    # of the force deviations (numpy einsum, an independent formula), to round-off, for a block at
    # the start (forces before step 0 are zero), one partly and one fully inside the kernel.
    from interaction.bundles import LoopState
    from interaction.structures import RailFarField
    rng = np.random.default_rng(start)
    nk, near = 1300, 512
    tail = rng.standard_normal((nk, 3, 3)) * 1e-9
    force = np.column_stack([rng.standard_normal((start, 2)) * 1e3, LOAD + rng.standard_normal(start) * 1e3])
    field = RailFarField(tail, near)
    state = LoopState(*([None] * 10), np.zeros((near, 3)), np.zeros(1, np.int64))
    field.fill(force, LOAD, start, state)
    assert state.far_start[0] == start
    deviation = force - np.array([0.0, 0.0, LOAD])
    expected = np.zeros((near, 3))
    for t in range(near):
        n = start + t
        for q in range(near + 1, nk + 1):  # sample q of the kernel is tail[q - 1]
            if n - q >= 0:
                expected[t] += tail[q - 1] @ deviation[n - q]
    scale = max(np.abs(expected).max(), 1e-30)
    assert np.abs(state.far - expected).max() <= 1e-12 * scale
    if start == 0:
        assert np.all(state.far == 0.0)


def test_force_prediction_fit_equals_least_squares():
    # The predictor's normal equations are built from shifted inner products and a sliding-window
    # recursion (interaction/loop_steps.py); against numpy's least squares on the same lagged matrix
    # (an independent solver, SVD), for a noisy limit cycle: the same one-step predictions to
    # 1e-6 of the amplitude (the fit's regularisation is 1e-12 of the trace).
    rng = np.random.default_rng(3)
    n = 1000
    phase = 2 * np.pi * 5000.0 * DT * np.arange(n + 1)
    fy = 30e3 + 900.0 * np.sin(phase) + 200.0 * np.sin(2 * phase + 0.3) + rng.standard_normal(n + 1)
    force = np.column_stack([np.zeros(n + 1), fy, np.full(n + 1, LOAD)])
    coef, mean, use = np.zeros((3, PREDICTION_ORDER)), np.zeros(3), np.zeros(3, np.int64)
    fit_prediction(force[:n], n, coef, mean, use)
    assert use[1] == 1
    c = fy[n - PREDICTION_WINDOW - PREDICTION_ORDER:n].mean()
    y = fy - c
    rows = np.array([y[k - 1 - np.arange(PREDICTION_ORDER)] for k in range(n - PREDICTION_WINDOW, n)])
    a, *_ = np.linalg.lstsq(rows, y[n - PREDICTION_WINDOW:n], rcond=None)
    reference = c + a @ y[n - 1 - np.arange(PREDICTION_ORDER)]
    assert abs(mean[1] - c) < 1e-9 * 30e3
    assert abs(predicted(force, n, 1, coef, mean) - reference) < 1e-6 * 900.0


def _traction_states(nx, ny, elements, traction, step, operator):
    """Element states of an nx x ny grid whose committed list is ``elements``, whose traction
    history holds ``traction(s, direction, element)`` (Pa) for the TRACTION_HISTORY steps before
    ``step``, and whose dense-row cache holds the list (built from ``operator``)."""
    from contact.halfspace.anderson_kernels import carried_anderson_history
    from contact.halfspace.bundles import COMMITTED, TRACTION_HISTORY, element_states
    from contact.halfspace.influence_kernels import contact_rows
    n = nx * ny
    states = element_states(n, np.zeros(n), carried_anderson_history(8, n, n))
    states.count[COMMITTED] = len(elements)
    for k, (ix, iy) in enumerate(elements):
        states.ix[COMMITTED, k], states.iy[COMMITTED, k] = ix, iy
        states.lookup[COMMITTED, ix * ny + iy] = k
        for s in range(step - TRACTION_HISTORY, step):
            for j in range(2):
                states.history[s % TRACTION_HISTORY, j * n + ix * ny + iy] = traction(s, j, k)
        states.tx[COMMITTED, k] = traction(step - 1, 0, k)
        states.ty[COMMITTED, k] = traction(step - 1, 1, k)
    m = len(elements)
    contact_rows(operator, states.ix[COMMITTED, :m].copy(), states.iy[COMMITTED, :m].copy(), states.rows)
    return states


def test_traction_prediction_is_exact_for_a_few_harmonics_and_only_where_it_pays():
    # In a limit cycle the first coupling pass starts its tangential solution from tractions
    # predicted per element with the force's recursion (contact/halfspace/loop.py, _predicted_start).
    # Tractions that are each element's own constant plus the force's harmonics (own amplitudes
    # and phases) must be predicted to the fit's round-off (1e-6 of the amplitude, as for the
    # force), and the start's displacement differences must be the direct product of the
    # influence coefficients with the predicted tractions (summed here independently, to
    # round-off). No prediction for white noise (which no recursion predicts better than the last
    # value), nor where the last window took few sweeps (a steady contact: the start would cost
    # more than it saves).
    from contact.halfspace.bundles import FlatTangential
    from contact.halfspace.loop import _predicted_start, _traction_prediction_pays
    from interaction.loop_steps import PREDICTION_REFIT
    nx, ny, step = 6, 5, 64
    elements = [(4, 1), (3, 2), (3, 3), (2, 1), (1, 3)]
    m = len(elements)
    rng = np.random.default_rng(1)
    const, amp1, amp2, ph1, ph2 = (rng.uniform(-1, 1, (2, m)) for _ in range(5))
    omega = 2 * np.pi * 5000.0 * DT

    def harmonic(s, j, k):
        return 1e6 * (const[j, k] + amp1[j, k] * np.sin(omega * s + 3 * ph1[j, k])
                      + 0.3 * amp2[j, k] * np.sin(2 * omega * s + 3 * ph2[j, k]))

    n = 400
    phase = omega * np.arange(n)
    fy = 30e3 + 900.0 * np.sin(phase) + 200.0 * np.sin(2 * phase + 0.3)
    force = np.column_stack([-0.5 * fy, fy, np.full(n, LOAD)])
    coef, mean, use = np.zeros((3, PREDICTION_ORDER)), np.zeros(3), np.zeros(3, np.int64)
    fit_prediction(force, n, coef, mean, use)
    assert list(use) == [1, 1, 0]
    kernels = [rng.standard_normal((2 * nx - 1, 2 * ny - 1)) * 1e-12 for _ in range(3)]
    operator = FlatTangential(*(k.ravel() for k in kernels), 2 * ny - 1, nx - 1, ny - 1)
    many_sweeps, few_sweeps = np.full(step, 9.0), np.full(step, 2.3)
    assert few_sweeps[:PREDICTION_REFIT].sum() < 4 * PREDICTION_REFIT
    states = _traction_states(nx, ny, elements, harmonic, step, operator)
    _traction_prediction_pays(states, step, coef, use, ny, few_sweeps)
    assert list(states.prediction[1:]) == [0, 0]
    _traction_prediction_pays(states, step, coef, use, ny, many_sweeps)
    assert list(states.prediction[1:]) == [1, 1]
    assert _predicted_start(states, step, coef, ny, 2)
    assert states.count[2] == m
    last = np.array([[harmonic(step - 1, j, k) for k in range(m)] for j in range(2)])
    for j, field in enumerate((states.tx[2, :m], states.ty[2, :m])):
        exact = np.array([harmonic(step, j, k) for k in range(m)])
        assert np.abs(field - exact).max() < 1e-6 * 1e6
        assert np.abs(field - exact).max() < 1e-3 * np.abs(exact - last[j]).max()  # far closer than the last step's
    k11, k12, k22 = kernels
    for k, (ix, iy) in enumerate(elements):
        lags = [(ix - jx + nx - 1, iy - jy + ny - 1) for jx, jy in elements]
        ux = sum(k11[a] * states.tx[2, q] + k12[a] * states.ty[2, q] for q, a in enumerate(lags))
        uy = sum(k12[a] * states.tx[2, q] + k22[a] * states.ty[2, q] for q, a in enumerate(lags))
        assert abs(states.ux[2, k] - ux) <= 1e-12 * (abs(ux) + 1e-18)
        assert abs(states.uy[2, k] - uy) <= 1e-12 * (abs(uy) + 1e-18)
    noise = rng.standard_normal((step, 2, m))
    states = _traction_states(nx, ny, elements, lambda s, j, k: 1e6 * noise[s, j, k], step, operator)
    _traction_prediction_pays(states, step, coef, use, ny, many_sweeps)
    assert list(states.prediction[1:]) == [0, 0]
