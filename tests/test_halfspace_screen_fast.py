"""The fast half-space linearisation of the screen (issue 35 item 3) against the reference it replaced.

(1) The steady Gauss-Seidel sweeps on a box of lines give the point-by-point sweeps' result to the
bit (a Python transcription of the earlier kernel is the reference); (2) the prescribed-approach
normal problem with FFT products gives the direct products' force to the solver's tolerance.
"""

import numpy as np
import pytest

from contact.friction_kernels import element_law
from contact.halfspace.anderson_kernels import anderson_history, anderson_input, anderson_mix
from contact.halfspace.model import Grid, HalfspaceContact
from contact.halfspace.steady import steady_gauss_seidel, steady_points
from contact.halfspace.normal import solve_normal
from contact.hertz import hertz_from_semi_axes
from contact.params import Friction, Material


def _point_by_point(K11, K12, K22, ix, iy, up, wx, wy, gs, gk, px, py, ux, uy, dxx, dyy, tol, max_sweeps, depth):
    """The steady sweeps as they were before the box (each evaluation point updated in turn), in Python."""
    nc, ne = px.size, ux.size
    my = K11.shape[1]
    ox, oy = (K11.shape[0] + 1) // 2 - 1, (K11.shape[1] + 1) // 2 - 1
    coef = np.zeros((K11.size, 4))
    coef[:, 0], coef[:, 1], coef[:, 2] = K11.ravel(), K12.ravel(), K22.ravel()
    flat = ix * my + iy
    shift = ox * my + oy
    status = np.ones(nc, np.int8)
    skip = 1e-3 * tol
    history = anderson_history(depth, nc, ne)
    sweeps, change = 0, 0.0
    for sweep in range(max_sweeps):
        anderson_input(history, px, py)
        change = 0.0
        for c in range(nc):
            j = up[c]
            sx = wx[c] + ux[c] - ux[j]
            sy = wy[c] + uy[c] - uy[j]
            qx, qy, sliding = element_law(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c])
            status[c] = 2 if sliding else 1
            if sliding:
                gs[c] = gk[c]
            dpx, dpy = qx - px[c], qy - py[c]
            if abs(dpx) > skip or abs(dpy) > skip:
                px[c], py[c] = qx, qy
                k = flat + shift - flat[c]
                k12 = coef[k, 1]
                ux += coef[k, 0] * dpx + k12 * dpy
                uy += k12 * dpx + coef[k, 2] * dpy
                change = max(change, abs(dpx), abs(dpy))
        sweeps = sweep + 1
        if change <= tol:
            break
        anderson_mix(history, change, px, py, ux, uy)
    return sweeps, change, status


def _steady_problem(creepage, nx=16, ny=12):
    """The arrays of steady_gauss_seidel for a Hertzian contact on an nx x ny grid (zero start)."""
    material = Material(shear_modulus=8e10, poisson_ratio=0.28)
    hertz = hertz_from_semi_axes(4e-3, 3e-3, 20e3, material.contact_modulus)
    grid = Grid.covering(hertz.a, hertz.b, nx=nx, ny=ny, margin=0.2)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid,
                             gap=hertz.A * x**2 + hertz.B * y**2, kind="steady")
    pz = solve_normal(model.kernels, model.gap, normal_force=20e3).pressure
    cix, ciy = np.nonzero(pz > 0)
    order = np.lexsort((-cix, ciy))
    cix, ciy = cix[order].astype(np.int64), ciy[order].astype(np.int64)
    points = steady_points(cix, ciy, nx, ny)
    xi, eta, phi = creepage
    k = model.kernels
    nc, ne = cix.size, points.ix.size
    scale = 0.3 * pz.max()
    return [k.K11, k.K12, k.K22, points.ix, points.iy, points.upstream,
            (xi - phi * y[cix, ciy]) * grid.dx, (eta + phi * x[cix, ciy]) * grid.dx,
            0.3 * pz[cix, ciy], 0.3 * pz[cix, ciy], np.zeros(nc), np.zeros(nc), np.zeros(ne), np.zeros(ne),
            float(k.K11[nx - 1, ny - 1]), float(k.K22[nx - 1, ny - 1]), 1e-9 * scale, 500, 8]


@pytest.mark.parametrize("creepage", [(1e-3, -2e-3, -3.0), (0.0, -1e-3, 0.0), (2e-4, -4e-3, 1.0)])
def test_steady_box_sweeps_equal_the_point_by_point_sweeps_to_the_bit(creepage):
    fast = _steady_problem(creepage)
    reference = [a.copy() if isinstance(a, np.ndarray) else a for a in fast]
    sweeps, change, status = steady_gauss_seidel(*fast)
    ref_sweeps, ref_change, ref_status = _point_by_point(*reference)
    assert sweeps == ref_sweeps and sweeps < 500
    assert change == ref_change
    np.testing.assert_array_equal(status, ref_status)
    for i in (10, 11, 12, 13):  # tractions and displacements
        np.testing.assert_array_equal(fast[i], reference[i])
    assert (status == 2).any() and (status == 1).any()  # partial slip: both laws of the element met


@pytest.mark.parametrize("relative_step", [0.01, -0.01, 0.2])
def test_prescribed_approach_with_fft_products_equals_the_direct_products(relative_step):
    material = Material(shear_modulus=8e10, poisson_ratio=0.28)
    hertz = hertz_from_semi_axes(5e-3, 3e-3, 30e3, material.contact_modulus)
    grid = Grid.covering(1.5 * hertz.a, 1.5 * hertz.b, dx=2e-4, dy=5e-4)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid, gap=hertz.A * x**2 + hertz.B * y**2)
    at_load = solve_normal(model.kernels, model.gap, normal_force=30e3, tol=1e-9, full_displacement=False)
    approach = at_load.approach * (1.0 + relative_step)
    fft, direct = (solve_normal(model.kernels, model.gap, approach=approach, p_init=at_load.pressure, tol=1e-9,
                                full_displacement=False, fft=flag) for flag in (True, False))
    assert fft.normal_force == pytest.approx(direct.normal_force, rel=1e-8)
    np.testing.assert_allclose(fft.pressure, direct.pressure, rtol=0, atol=1e-7 * direct.pressure.max())
    # and Hertz's force at that approach, to the grid's discretisation error
    assert fft.normal_force == pytest.approx(30e3 * (1.0 + relative_step) ** 1.5, rel=0.02)


@pytest.fixture(scope="module")
def quick_halfspace(copy_quick_structures, tmp_path_factory):
    """The quick study with the half-space contact and its structures (a copy of the session's)."""
    from stages.config import load_study
    from stages.screen import read_structures

    out = copy_quick_structures(tmp_path_factory.mktemp("halfspace_screen_fast"))
    study = load_study(quick=True, assignments=["contact.model=halfspace"])
    return study, read_structures(study, out)


def _reference_linearisation(monkeypatch):
    """The linearisation as before issue 35 item 3: direct products for the prescribed approach, nothing
    kept between configurations (the steady sweeps are the same to the bit, tested above)."""
    from contact.halfspace import linearise

    direct = linearise.solve_normal
    monkeypatch.setattr(linearise, "solve_normal", lambda *a, **k: direct(*a, **{**k, "fft": False}))
    monkeypatch.setattr(linearise, "_load_cached", lambda kind, model, load, step, compute, tol=None: compute())
    linearise._CACHE.clear()


#: Configurations (speed m/s, friction, lateral creepage) in partial slip, near and in saturation.
CONFIGURATIONS = [(13.9, 0.3, -0.003), (8.0, 0.6, -0.003), (8.0, 0.3, -0.01), (13.9, 0.6, -0.01),
                  (13.9, 0.3, -0.015)]


def test_fast_screen_equals_the_reference_screen(quick_halfspace, monkeypatch):
    # the half-space screen of several configurations (linearisation and the three wheel models on
    # the flexible rail): growth rates within 1e-6 1/s and frequencies within 1e-6 Hz of the path
    # it replaced, the slopes within 1e-6 of themselves (the only difference: the approach-controlled
    # normal solves to their tolerance 1e-9)
    from contact.halfspace import linearise
    from stages.cases import case_study
    from stages.screen import linear_contact, screen_study

    study, (models, rail, point) = quick_halfspace
    configs = [case_study(study, {"operating.speed": v, "contact.friction": mu, "contact.lateral_creepage": eta})
               for v, mu, eta in CONFIGURATIONS]
    linearise._CACHE.clear()
    linearise._LOAD_CACHE.clear()
    fast = []
    for config in configs:
        contact = linear_contact(config, point)
        fast.append((contact, screen_study(config, models, rail, point=point, contact=contact, pole_modes=False)))
    _reference_linearisation(monkeypatch)
    growing = 0
    for config, (contact, results) in zip(configs, fast):
        ref = linear_contact(config, point)
        assert contact.normal_stiffness == pytest.approx(ref.normal_stiffness, rel=1e-6)
        assert contact.sliding_coefficient == pytest.approx(ref.sliding_coefficient, rel=1e-6, abs=1e-9)
        np.testing.assert_allclose(contact.creep_stiffness, ref.creep_stiffness, rtol=1e-6)
        np.testing.assert_allclose(contact.relaxation, ref.relaxation, rtol=1e-6)
        reference = screen_study(config, models, rail, point=point, contact=ref, pole_modes=False)
        for name, result in results.items():
            assert result["margin"] == pytest.approx(reference[name]["margin"], abs=1e-6)
            assert result["margin_frequency"] == pytest.approx(reference[name]["margin_frequency"], abs=1e-6)
            assert len(result["poles"]) == len(reference[name]["poles"])
            growing += result["margin"] > 0
    assert growing > 0  # some configurations squeal, some do not
    assert growing < 3 * len(CONFIGURATIONS)


def test_steady_solutions_from_the_shared_normal_solution_equal_those_from_rest():
    # the linearisation solves the normal problem at the load once and starts every steady solution
    # from it (_loaded_start): the same forces to the bit as solving it from the unloaded state
    from contact.halfspace import linearise

    material = Material(shear_modulus=8e10, poisson_ratio=0.28)
    hertz = hertz_from_semi_axes(4e-3, 3e-3, 20e3, material.contact_modulus)
    grid = Grid.covering(1.3 * hertz.a, 1.3 * hertz.b, nx=24, ny=18)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = linearise.steady_twin(HalfspaceContact(material=material, friction=Friction(0.3), grid=grid,
                                                   gap=hertz.A * x**2 + hertz.B * y**2, kind="transient"))
    linearise._LOAD_CACHE.clear()
    for creepage in [(0.0, -2e-3, 0.0), (1e-3, 3e-3, -2.0)]:
        shared = model.solve(linearise._loaded_start(model, 20e3), normal_force=20e3, creepage=creepage)
        rest = model.solve(model.initial_state(), normal_force=20e3, creepage=creepage)
        np.testing.assert_array_equal(shared.force, rest.force)
        np.testing.assert_array_equal(shared.new_state.traction, rest.new_state.traction)
        assert shared.diagnostics.n_slip == rest.diagnostics.n_slip > 0
