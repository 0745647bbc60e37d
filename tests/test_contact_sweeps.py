"""The transient Gauss-Seidel sweeps (contact/halfspace/tangential_kernels.py) against the discrete friction law.

The converged sweeps are checked against the discrete friction law itself (stick: no slip within the static
bound; slip: traction on the kinetic bound opposite to the slip), with and without Anderson
mixing (the mixing may change the path, not the solution beyond the tolerance).
"""

import numpy as np
import pytest

from contact.halfspace.anderson_kernels import anderson_history, carried_anderson_history, continue_history
from contact.halfspace.bundles import SweepCompliance, TangentialProblem, Tractions, dense_cache
from contact.friction_kernels import _local_slip
from contact.friction_law import CONSTANT_LAW
from contact.halfspace.influence import rectangle_kernels
from contact.halfspace.influence_kernels import (build_upstream_rows, contact_rows, flat_tangential, no_dense_rows,
                                                   same_list)
from contact.kernels_linalg import inner_product
from contact.halfspace.local_sweep_kernels import coarse_correction, coarse_level, coarse_matrix, local_updates
from contact.halfspace.rolling_kernels import _tangential_displacement_at
from contact.halfspace.tangential_kernels import (gather_tangential_problem, gauss_seidel_with_memory,
                                                    tangential_gauss_seidel)
from contact.halfspace.transient_fft import SWEEPS_PER_PRODUCT, transient_sweeps_fft


def _problem(nx=16, ny=13, eta=-3e-3, mu=0.3):
    """A transient step from rest of an elliptic Hertz-like pressure: the contact elements, rigid slip, bounds."""
    dx, dy = 5.5e-3 / nx * 2, 4.4e-3 / ny * 2
    k = rectangle_kernels(nx, ny, dx, dy, 80e9, 0.3)
    x = (np.arange(nx) - (nx - 1) / 2) * dx
    y = (np.arange(ny) - (ny - 1) / 2) * dy
    X, Y = np.meshgrid(x, y, indexing="ij")
    pz = 1e9 * np.sqrt(np.clip(1 - (X / 5e-3) ** 2 - (Y / 4e-3) ** 2, 0, None))
    ix, iy = np.nonzero(pz > 0)
    order = np.lexsort((iy, -ix))
    ix, iy = ix[order].astype(np.int64), iy[order].astype(np.int64)
    n = ix.size
    rng = np.random.default_rng(3)
    problem = TangentialProblem(ix, iy, np.zeros(n), np.full(n, eta * dx), 1e-9 * rng.standard_normal(n),
                                1e-9 * rng.standard_normal(n), mu * pz[ix, iy], mu * pz[ix, iy], CONSTANT_LAW)
    return k, problem, mu * pz.max()


def _rows(k, problem, dense):
    """Dense influence rows of the problem's contact list, or none (the indexed products)."""
    if not dense:
        return no_dense_rows()
    return contact_rows(flat_tangential(k.bundle()), problem.ix, problem.iy, dense_cache(problem.ix.size))


@pytest.mark.parametrize("eta", [-3e-3, -1e-2, -1e-1])
@pytest.mark.parametrize("depth", [0, 8])
@pytest.mark.parametrize("dense", [False, True])
def test_converged_sweeps_satisfy_the_friction_law(eta, depth, dense):
    k, problem, scale = _problem(eta=eta)
    n = problem.ix.size
    tractions = Tractions(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
    tol = 1e-10 * scale
    sweeps, change, status = tangential_gauss_seidel(k.bundle(), problem, tractions, tol, 5000, (0.0, 0.0), depth,
                                                        _rows(k, problem, dense))
    assert change <= tol
    px, py = tractions.px, tractions.py
    # the displacements carried by the sweeps are those of the tractions (direct product)
    ox, oy = k.nx - 1, k.ny - 1
    di = problem.ix[:, None] - problem.ix[None, :] + ox
    dj = problem.iy[:, None] - problem.iy[None, :] + oy
    ux = k.K11[di, dj] @ px + k.K12[di, dj] @ py
    uy = k.K12[di, dj] @ px + k.K22[di, dj] @ py
    # the carried displacements drift only by the unpropagated changes (< 1e-3 tol each)
    u_scale = k.K11[ox, oy] * scale
    assert np.abs(ux - tractions.ux).max() < 1e-9 * u_scale
    sx = problem.slip_x + ux - problem.previous_x
    sy = problem.slip_y + uy - problem.previous_y
    slip = np.hypot(sx, sy)
    g = problem.kinetic_bound
    stick = status == 1
    # stick: the slip vanishes (to the tolerance times the own compliance) within the bound
    assert slip[stick].max(initial=0.0) < 10 * tol * k.K11[ox, oy]
    assert np.all(np.hypot(px, py)[stick] <= g[stick] * (1 + 1e-12))
    # slip: on the bound, opposite to the slip
    assert np.allclose(np.hypot(px, py)[~stick], g[~stick], rtol=1e-9)
    cosine = -(px * sx + py * sy)[~stick] / (np.hypot(px, py)[~stick] * slip[~stick])
    assert np.all(cosine > 1 - 1e-6)
    # a first step from rest: full stick, partial slip (34 of 130 measured), full slip
    expected = {-3e-3: (n, n), -1e-2: (1, n - 1), -1e-1: (0, 0)}[eta]
    assert expected[0] <= stick.sum() <= expected[1]


@pytest.mark.parametrize("eta", [-3e-3, -1e-2])
def test_dense_rows_give_the_indexed_products_bit_for_bit(eta):
    """The dense rows hold the same coefficients, so the sweeps do the same arithmetic: identical results."""
    k, problem, scale = _problem(eta=eta)
    n = problem.ix.size
    out = []
    for dense in (False, True):
        p = problem._replace(static_bound=problem.static_bound.copy())  # lowered in place where sliding
        tractions = Tractions(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
        out.append((tangential_gauss_seidel(k.bundle(), p, tractions, 1e-10 * scale, 5000, (1e-13, 2e-13), 8,
                                               _rows(k, p, dense))[:2], tractions))
    (run_indexed, t_indexed), (run_dense, t_dense) = out
    assert run_indexed == run_dense
    for a, b in zip(t_indexed, t_dense):
        assert np.array_equal(a, b)


def test_contact_rows_are_rebuilt_when_the_list_changes():
    """The cache keeps the rows of one list; a different list (or order) rebuilds them, a longer one is refused."""
    k, problem, _ = _problem()
    operator = flat_tangential(k.bundle())
    ix, iy = problem.ix, problem.iy
    n = ix.size
    cache = dense_cache(n)

    def reference(cix, ciy):
        """m11 between the list's elements straight from the 2D kernel: K11[ix_t - ix_c + ox, iy_t - iy_c + oy]."""
        return k.K11[cix[None, :] - cix[:, None] + k.nx - 1, ciy[None, :] - ciy[:, None] + k.ny - 1]

    rows = contact_rows(operator, ix, iy, cache)
    assert rows.count == n and cache.count[0] == n
    assert np.array_equal(rows.m11[:n * n].reshape(n, n), reference(ix, iy))
    cache.m11[1] = 7.0  # a marker: a cache hit returns the stored rows untouched
    assert contact_rows(operator, ix, iy, cache).m11[1] == 7.0
    sub_ix, sub_iy = ix[::-1][: n - 5].copy(), iy[::-1][: n - 5].copy()  # another list: rebuilt
    rows = contact_rows(operator, sub_ix, sub_iy, cache)
    m = n - 5
    assert rows.count == m and cache.count[0] == m
    assert np.array_equal(rows.m11[:m * m].reshape(m, m), reference(sub_ix, sub_iy))
    lags = (sub_ix[None, :] - sub_ix[:, None] + k.nx - 1, sub_iy[None, :] - sub_iy[:, None] + k.ny - 1)
    assert np.array_equal(rows.m12[:m * m].reshape(m, m), k.K12[lags])
    small = dense_cache(n - 1)
    contact_rows(operator, sub_ix, sub_iy, small)
    assert same_list(small, sub_ix, sub_iy)
    assert contact_rows(operator, ix, iy, small).count == 0  # beyond the capacity: no rows,
    assert not same_list(small, sub_ix, sub_iy)  # and the cache no longer claims the earlier list


def _transient_from_rest(steps, monkeypatch, min_contact, eta=-3e-3, extrapolate=True):
    """Tractions, stick/slip, result and local-sweep calls of a 44 x 36 transient from rest.

    Each call of the local sweeps is recorded as (step, sweeps, every element sliding).
    ``extrapolate``: the warm start of each step extrapolated from the last two states (the
    model's default, halfspace.EXTRAPOLATED_WARM_START) or the last state itself.
    """
    from contact.halfspace import model as halfspace, tangential
    from contact.halfspace.model import Grid, HalfspaceContact
    from contact.hertz import hertz_from_semi_axes
    from contact.params import Friction, Material

    monkeypatch.setattr(tangential, "TRANSIENT_FFT_MIN_CONTACT", min_contact)
    monkeypatch.setattr(halfspace, "EXTRAPOLATED_WARM_START", extrapolate)
    calls = []  # (step, sweeps, every element sliding) of each call of the local sweeps

    def spy(*args, **kwargs):
        out = transient_sweeps_fft(*args, **kwargs)
        calls.append((step, out[0], bool(np.all(out[4] == 2))))
        return out

    monkeypatch.setattr(tangential, "transient_sweeps_fft", spy)
    material = Material(80e9, 0.3)
    hz = hertz_from_semi_axes(5e-3, 4e-3, 50e3, material.contact_modulus)
    grid = Grid.covering(5e-3, 4e-3, nx=44, ny=36)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                             kind="transient", speed=20.0)
    state = model.initial_state()
    for step in range(steps):
        res = model.solve(state, normal_force=50e3, creepage=(0.0, eta, 0.0))
        state = res.new_state
    return np.asarray(state.traction), res.fields.status, res, calls


def test_full_slip_steps_are_left_to_the_exact_sweeps(monkeypatch):
    """In full slip the local sweeps hand over to the exact ones after one product, and stop being called.

    (tangential.TRANSIENT_EXACT_FIRST.) From rest at eta = -3 % every step is in full slip, but
    for about one contact length (24 steps) the warm start (the last step's tractions) is below
    the friction bound somewhere: those steps start with the local sweeps, whose first product
    finds every element sliding, and the exact sweeps finish. Then the warm start slides
    everywhere and the exact sweeps start at once: no more local sweeps. (The warm start is the
    last state itself here, as this describes: extrapolated, it lies further from the solution
    in the first steps, and the local sweeps then run a few rounds before the hand-over.)
    """
    _, status, res, calls = _transient_from_rest(40, monkeypatch, 0, eta=-3e-2, extrapolate=False)
    assert res.diagnostics.n_slip == res.diagnostics.n_contact == 1036
    steps = [step for step, _, _ in calls]
    assert 0 in steps and max(steps) < 30
    assert all(sweeps == SWEEPS_PER_PRODUCT and full_slip for _, sweeps, full_slip in calls)


@pytest.mark.parametrize("coarse", [False, True])
def test_local_sweeps_with_fft_products_agree_with_exact_sweeps(monkeypatch, coarse):
    """The FFT-product path (transient_fft), with and without its coarse level, and the exact sweeps reach the same
    steps to the tolerance."""
    from contact.halfspace import transient_fft
    monkeypatch.setattr(transient_fft, "COARSE_MIN_CONTACT", 0 if coarse else 10 ** 9)
    exact, status_exact, res_exact, calls_exact = _transient_from_rest(6, monkeypatch, 10 ** 9)
    fft, status_fft, res_fft, calls_fft = _transient_from_rest(6, monkeypatch, 0)
    assert not calls_exact and calls_fft  # the local sweeps ran on the partial-slip steps
    assert all(sweeps > SWEEPS_PER_PRODUCT and not full_slip for _, sweeps, full_slip in calls_fft)
    scale = 0.3 * res_exact.diagnostics.pmax
    # both stop on the same test (an exact sweep changing no traction by more than 1e-9 of the
    # scale); the solutions then differ by a few tolerances at most (measured below 1e-9 of the scale)
    assert np.abs(fft - exact).max() < 1e-8 * scale
    assert np.array_equal(status_fft, status_exact)
    assert 0 < (status_exact == 2).sum() < (status_exact > 0).sum()  # partial slip


@pytest.mark.parametrize("coarse", [False, True])
@pytest.mark.parametrize("kind", ["shift", "transient"])
def test_local_sweeps_agree_with_exact_sweeps_with_series_springs(monkeypatch, kind, coarse):
    """The FFT-product path against the exact sweeps in shift and with series compliances (spin in rolling).

    Six steps on the 44 x 36 grid (1036 in contact), series springs of 1e-9 and 2e-9 m/N along
    x and y (the global term of every sweep); both paths stop on the same exact-sweep test, so
    the tractions agree to a few tolerances (measured 2e-9 and 4e-9 of mu p_max).
    """
    from contact.halfspace import tangential, transient_fft
    from contact.halfspace.model import Grid, HalfspaceContact
    from contact.hertz import hertz_from_semi_axes
    from contact.params import Friction, Material

    monkeypatch.setattr(transient_fft, "COARSE_MIN_CONTACT", 0 if coarse else 10 ** 9)
    material = Material(80e9, 0.3)
    hz = hertz_from_semi_axes(5e-3, 4e-3, 50e3, material.contact_modulus)
    grid = Grid.covering(5e-3, 4e-3, nx=44, ny=36)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")

    def run(min_contact):
        monkeypatch.setattr(tangential, "TRANSIENT_FFT_MIN_CONTACT", min_contact)
        model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid,
                                 gap=hz.A * X ** 2 + hz.B * Y ** 2, kind=kind, speed=20.0)
        state = model.initial_state()
        for n in range(6):
            load = (dict(shift=(0.0, -2e-7 * (1 + n % 3), 0.0)) if kind == "shift"
                    else dict(creepage=(1e-3, -3e-3, 2.0)))
            res = model.solve(state, normal_force=50e3, compliance=(1e-9, 2e-9, 0.0), **load)
            state = res.new_state
        return np.asarray(state.traction), res

    exact, res_exact = run(10 ** 9)
    local, res_local = run(0)
    scale = 0.3 * res_exact.diagnostics.pmax
    assert np.abs(local - exact).max() < 1e-8 * scale
    assert res_local.diagnostics.n_slip == res_exact.diagnostics.n_slip
    assert 0 < res_exact.diagnostics.n_slip < res_exact.diagnostics.n_contact == 1036  # partial slip


def _direct_coarse_matrix(k, problem, level, series):
    """The coarse matrix summed pair by pair from the kernels (the definition), series terms added."""
    m = level.size.size
    ix, iy = problem.ix, problem.iy
    di = ix[:, None] - ix[None, :] + k.nx - 1
    dj = iy[:, None] - iy[None, :] + k.ny - 1
    one = np.zeros((ix.size, m))
    one[np.arange(ix.size), level.group] = 1.0
    blocks = [[one.T @ k.K11[di, dj] @ one, one.T @ k.K12[di, dj] @ one],
              [one.T @ k.K12[di, dj] @ one, one.T @ k.K22[di, dj] @ one]]
    blocks[0][0] += series[0] * np.outer(level.size, level.size)
    blocks[1][1] += series[1] * np.outer(level.size, level.size)
    return np.block(blocks)


@pytest.mark.parametrize("block", [1, 2, 3, 5])
def test_coarse_matrix_sums_the_influence_over_pairs_of_blocks(block):
    """local_sweep_kernels.coarse_matrix (prefix sums over runs of sources) equals the pair-by-pair sum, series springs
    included; local_sweep_kernels.coarse_level groups the elements by squares of grid lines and keeps its inverse.

    Exact up to the order of the additions (measured 2e-16 of the largest entry); block 1 is the
    dense influence matrix of the contact list itself.
    """
    k, problem, _ = _problem()
    series = (1e-16, 2e-16)  # m/Pa
    flat = flat_tangential(k.bundle())
    level = coarse_level(flat, problem.ix, problem.iy, block, *series)
    matrix = coarse_matrix(flat, problem.ix, problem.iy, level.group, level.size, *series)
    expected = _direct_coarse_matrix(k, problem, level, series)
    assert level.size.sum() == problem.ix.size
    assert np.array_equal(np.sort(np.unique(level.group)), np.arange(level.size.size))
    assert np.array_equal(np.bincount(level.group), level.size)
    # the elements of one block share their block of grid lines
    for b in range(level.size.size):
        members = level.group == b
        assert np.unique(problem.ix[members] // block).size == 1 == np.unique(problem.iy[members] // block).size
    assert np.abs(matrix - expected).max() < 1e-13 * np.abs(expected).max()
    assert np.allclose(level.inverse @ expected, np.eye(2 * level.size.size), atol=1e-10)


def test_coarse_correction_cancels_the_block_slip_and_gives_the_block_mean_displacements():
    """local_sweep_kernels.coarse_correction: afterwards the sticking elements' slip sums to zero over every block, and
    the displacements it updates have the block means of the exact product's.

    All elements sticking, tractions and displacements of a random start (exact), series springs
    along x and y. The slip sums are a linear solve of the coarse matrix (zero to its conditioning,
    measured 1e-13 of the start's sums); the block means are the coarse matrix's product, exact
    to rounding. The pointwise displacements differ from the exact ones (the correction's
    detail within a block is left to the next product).
    """
    k, problem, scale = _problem()
    n = problem.ix.size
    series = (3e-16, 1e-16)  # m/Pa: springs of about 5e-9 m/N on these elements
    flat = flat_tangential(k.bundle())
    level = coarse_level(flat, problem.ix, problem.iy, 3, *series)
    rng = np.random.default_rng(5)
    px, py = 0.1 * scale * rng.standard_normal(n), 0.1 * scale * rng.standard_normal(n)

    def exact(px, py):
        field = np.zeros((k.nx, k.ny, 2))
        field[problem.ix, problem.iy, 0], field[problem.ix, problem.iy, 1] = px, py
        u = k.tangential_displacement(field)
        return u[problem.ix, problem.iy, 0].copy(), u[problem.ix, problem.iy, 1].copy()

    def block_sums(values):
        return np.bincount(level.group, values, minlength=level.size.size)

    def slip(px, py, ux, uy):
        return (problem.slip_x + ux - problem.previous_x + series[0] * px.sum(),
                problem.slip_y + uy - problem.previous_y + series[1] * py.sum())

    ux, uy = exact(px, py)
    before = [block_sums(s) for s in slip(px, py, ux, uy)]
    total = np.array([px.sum(), py.sum()])
    compliance = SweepCompliance(float(k.K11[k.nx - 1, k.ny - 1]) + series[0],
                                 float(k.K22[k.nx - 1, k.ny - 1]) + series[1], *series)
    coarse_correction(level, problem, Tractions(px, py, ux, uy), compliance, total, np.ones(n, np.int8))
    # the running sum against a fresh one, to the rounding of sums of terms of either sign
    assert np.abs(total - [px.sum(), py.sum()]).max() < 1e-12 * np.abs(np.concatenate([px, py])).sum()
    ex, ey = exact(px, py)
    after = [block_sums(s) for s in slip(px, py, ex, ey)]
    for b, a in zip(before, after):
        assert np.abs(a).max() < 1e-10 * np.abs(b).max()
    for u, e in ((ux, ex), (uy, ey)):
        assert np.abs(block_sums(u) - block_sums(e)).max() < 1e-12 * np.abs(block_sums(e)).max()
        assert not np.allclose(u, e, rtol=1e-3)  # the detail within the blocks is not there


def test_coarse_level_saves_rounds_on_a_finer_grid(monkeypatch):
    """On a 66 x 54 transient from rest (2332 in contact, eta = -0.3 %) the coarse level takes fewer local sweeps.

    Measured over the first 8 steps (normal iterations and sweeps): 622 without, 564 with, 0.91
    (medians of 60 steps: 65 and 57 a step, docs/benchmarks.md); asserted below 0.95 of it. The
    steps agree to the tolerance.
    """
    from contact.halfspace import tangential, transient_fft
    from contact.halfspace.model import Grid, HalfspaceContact
    from contact.hertz import hertz_from_semi_axes
    from contact.params import Friction, Material

    material = Material(80e9, 0.3)
    hz = hertz_from_semi_axes(5e-3, 4e-3, 50e3, material.contact_modulus)
    grid = Grid.covering(5e-3, 4e-3, nx=66, ny=54)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    blocks = []

    def spy(*args, **kwargs):
        out = transient_fft.transient_sweeps_fft(*args, **kwargs)
        blocks.append(transient_fft.coarse_block_size(args[1].ix.size))
        return out

    monkeypatch.setattr(tangential, "transient_sweeps_fft", spy)

    def run(min_contact):
        monkeypatch.setattr(transient_fft, "COARSE_MIN_CONTACT", min_contact)
        model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid,
                                 gap=hz.A * X ** 2 + hz.B * Y ** 2, kind="transient", speed=20.0)
        state, sweeps = model.initial_state(), 0
        for _ in range(8):
            res = model.solve(state, normal_force=50e3, creepage=(0.0, -3e-3, 0.0))
            state, sweeps = res.new_state, sweeps + res.diagnostics.iterations
        return np.asarray(state.traction), res, sweeps

    default = transient_fft.COARSE_MIN_CONTACT
    without, res, sweeps_without = run(10 ** 9)
    assert set(blocks) == {0}
    blocks.clear()
    with_coarse, _, sweeps_with = run(default)
    assert res.diagnostics.n_contact == 2332 and set(blocks) == {6}
    assert sweeps_with < 0.95 * sweeps_without
    assert np.abs(with_coarse - without).max() < 1e-8 * 0.3 * res.diagnostics.pmax


def test_coarse_level_is_built_when_a_contact_list_comes_again(monkeypatch):
    """transient_fft: a new contact list is solved without a coarse level, the second solution in a row builds it
    (once), a changed list drops it until it comes again."""
    from contact.halfspace import transient_fft
    k, problem, scale = _problem()
    builds = []
    build = coarse_level

    def counted(*args):
        builds.append(args[1].size)
        return build(*args)

    monkeypatch.setattr(transient_fft, "coarse_level", counted)
    smaller = problem._replace(**{name: np.asarray(field)[:-3] for name, field in zip(problem._fields, problem)
                                  if name != "law"})

    def solve(p, block=3):
        n = p.ix.size
        return transient_sweeps_fft(k, p, Tractions(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)), (0.0, 0.0),
                                    1e-9 * scale, 2000, 16, coarse_block=block)

    first = solve(problem)
    assert builds == []
    without = solve(smaller, block=0), solve(problem, block=0)  # no coarse level: nothing recorded
    assert builds == [] and np.array_equal(first[2], without[1][2])  # the first solution had none
    solve(problem)
    solve(problem)
    assert builds == [problem.ix.size]  # built at the second solution in a row, then kept
    solve(smaller)
    solve(problem)
    assert builds == [problem.ix.size]  # each a new list: no build
    solve(problem)
    assert builds == [problem.ix.size] * 2


def test_coarse_block_size_grows_with_the_contact_and_refuses_a_negative_block():
    from squealcore.errors import InputError

    from contact.halfspace import transient_fft
    assert transient_fft.coarse_block_size(transient_fft.COARSE_MIN_CONTACT - 1) == 0
    assert transient_fft.coarse_block_size(transient_fft.COARSE_MIN_CONTACT) >= 2
    assert transient_fft.coarse_block_size(4144) == 8 and transient_fft.coarse_block_size(16520) == 16
    k, problem, scale = _problem()
    n = problem.ix.size
    with pytest.raises(InputError, match="coarse_block"):
        transient_sweeps_fft(k, problem, Tractions(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)), (0.0, 0.0),
                             1e-9 * scale, 100, 8, coarse_block=-1)


def test_anderson_memory_is_carried_only_for_the_same_contact_list():
    """continue_history keeps the stored differences for the same list and forgets them otherwise."""
    k, problem, scale = _problem()
    n = problem.ix.size
    cache = dense_cache(n)
    contact_rows(flat_tangential(k.bundle()), problem.ix, problem.iy, cache)  # the list the memory is for
    history = carried_anderson_history(8, n, n)
    p = problem._replace(static_bound=problem.static_bound.copy())
    tractions = Tractions(np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n))
    gauss_seidel_with_memory(k.bundle(), p, tractions, 1e-10 * scale, 5000, (0.0, 0.0), _rows(k, p, True),
                                history, 8)
    stored = history.counters[0]
    assert stored > 0 and history.counters[2] == 1
    continue_history(history, same_list(cache, problem.ix, problem.iy))
    assert history.counters[0] == stored and history.counters[2] == 0 and history.last_change[0] == np.inf
    continue_history(history, same_list(cache, problem.ix[1:].copy(), problem.iy[1:].copy()))
    assert history.counters[0] == 0  # another list: forgotten
    history.counters[0] = stored
    history.counters[3] = 0
    continue_history(history, True)
    assert history.counters[0] == 0  # a memory for one solution only: forgotten


@pytest.mark.parametrize("eta", [-3e-3, -1e-2])
def test_a_carried_memory_solves_a_sequence_as_accurately_in_fewer_sweeps(eta):
    """Nearby problems warm-started from the last solution, as in the time loop: the memory carried
    from the last solution gives the same accuracy as a fresh one in fewer sweeps.

    The stopping test (a sweep changing no traction by more than tol) leaves an error of up to
    about tol / (1 - rho), rho the sweeps' contraction, so both are compared with solutions
    converged 1e4 times tighter. A zero start (far from the last solution) drops the carried
    memory (tangential_kernels.CARRY_LIMIT): the same result as a fresh memory, bit for bit.
    """
    k, problem, scale = _problem(eta=eta)
    n = problem.ix.size
    tol = 1e-7 * scale  # the first sweeps of the later problems change up to ~1e3 tol (the limit: 1e4)
    history = carried_anderson_history(32, n, n)

    def solve(p, tolerance, start, memory=None):
        q = p._replace(static_bound=problem.static_bound.copy())
        t = Tractions(*[a.copy() for a in start])
        if memory is None:
            out = tangential_gauss_seidel(k.bundle(), q, t, tolerance, 50000, (0.0, 0.0), 8, _rows(k, q, True))
        else:
            out = gauss_seidel_with_memory(k.bundle(), q, t, tolerance, 50000, (0.0, 0.0), _rows(k, q, True),
                                              memory, 32)
        return out[0], np.concatenate([t.px, t.py]), t

    zero = (np.zeros(n),) * 4
    start_carried = start_fresh = zero
    sweeps_carried = sweeps_fresh = 0
    for shift in (0.0, 1e-4, 2e-4, 3e-4, 4e-4):  # the rigid slip changes, the list stays
        p = problem._replace(slip_y=problem.slip_y * (1.0 + shift))
        continue_history(history, True)
        s_c, carried, t_c = solve(p, tol, start_carried, history)
        s_f, fresh, t_f = solve(p, tol, start_fresh)
        reference = solve(p, 1e-4 * tol, zero)[1]
        assert np.abs(carried - reference).max() <= max(3 * np.abs(fresh - reference).max(), 2 * tol)
        sweeps_carried += s_c
        sweeps_fresh += s_f
        start_carried = tuple(t_c)
        start_fresh = tuple(t_f)
    assert sweeps_carried < 0.8 * sweeps_fresh
    # a zero start with the carried memory: dropped after the first sweep, as if fresh
    continue_history(history, True)
    fresh32 = anderson_history(32, n, n)
    assert np.array_equal(solve(p, tol, zero, history)[1], solve(p, tol, zero, fresh32)[1])


@pytest.mark.parametrize("length", [0, 1, 7, 8, 9, 17, 600, 1001])
def test_inner_product_is_the_sum_of_products(length):
    # The mixing's and the rail history's inner products let the compiler reorder the sum (to
    # vectorise it). Against the correctly rounded sum (math.fsum of the products' float64
    # roundings): within the standard bound of a reordered sum, length × eps × the sum of
    # magnitudes, and exact on integers (every partial sum is exact there); entries past
    # ``length`` are ignored.
    import math
    rng = np.random.default_rng(length)
    a = rng.standard_normal(length + 5)
    b = rng.standard_normal(length + 5)
    exact = math.fsum(a[i] * b[i] for i in range(length))
    bound = length * np.finfo(float).eps * np.sum(np.abs(a[:length] * b[:length]))
    assert abs(inner_product(a, b, length) - exact) <= bound
    ints = rng.integers(-1000, 1000, length + 5).astype(float)
    assert inner_product(ints, ints, length) == float(np.sum(ints[:length] ** 2))


def test_upstream_rows_give_the_summed_displacements():
    # The time loop's displacement at the element upstream of each leading-edge element (outside
    # the list) is read from rows built once per list (influence_kernels.build_upstream_rows) instead of
    # summed from the kernels by index (rolling_kernels._tangential_displacement_at). Both for the same
    # tractions: equal to round-off of the sum of magnitudes; one row per list element whose
    # upstream neighbour is outside the list, -1 for the others; a list needing more rows than
    # UPSTREAM_MAX_ROWS gets none.
    from contact.halfspace.bundles import UPSTREAM_MAX_ROWS, upstream_rows_storage
    k, problem, _ = _problem()
    operator = flat_tangential(k.bundle())
    nx, ny = 16, 13
    ix, iy = problem.ix, problem.iy
    nc = ix.size
    lookup = -np.ones(nx * ny, np.int64)
    lookup[ix * ny + iy] = np.arange(nc)
    upstream = upstream_rows_storage(nx * ny)
    build_upstream_rows(operator, ix, iy, lookup, ny, upstream)
    outside = lookup[(ix + 1) * ny + iy] < 0
    assert upstream.count[0] == outside.sum() > 0
    assert np.array_equal(upstream.position[:nc] >= 0, outside)
    rng = np.random.default_rng(5)
    tx, ty = 1e6 * rng.standard_normal(nc), 1e6 * rng.standard_normal(nc)
    every = np.arange(nc)
    for c in np.nonzero(outside)[0]:
        row = upstream.position[c]
        m11, m12, m22 = (m[row * nc:(row + 1) * nc] for m in (upstream.m11, upstream.m12, upstream.m22))
        ux = inner_product(m11, tx, nc) + inner_product(m12, ty, nc)
        uy = inner_product(m12, tx, nc) + inner_product(m22, ty, nc)
        sx, sy = _tangential_displacement_at(operator, ix[c] + 1, iy[c], ix, iy, tx, ty, every)
        scale = np.sum(np.abs(m11 * tx) + np.abs(m12 * ty) + np.abs(m22 * ty))
        assert abs(ux - sx) <= 1e-13 * scale and abs(uy - sy) <= 1e-13 * scale
    # a list with holes on every other line needs more rows than the storage holds
    holes = np.array([(a, b) for a in range(1, nx - 1) for b in range(1, ny - 1) if a % 2 == 0], np.int64)
    lookup = -np.ones(nx * ny, np.int64)
    lookup[holes[:, 0] * ny + holes[:, 1]] = np.arange(len(holes))
    assert len(holes) > UPSTREAM_MAX_ROWS
    build_upstream_rows(operator, holes[:, 0].copy(), holes[:, 1].copy(), lookup, ny, upstream)
    assert upstream.count[0] == -1


def test_local_slip_solves_its_equation():
    # One sliding element: s = c + D p with p = -g s/|s| and D = diag(dxx, dyy), i.e. sigma = |s|
    # solves sum_k c_k^2 / (sigma + g d_k)^2 = 1 (friction_kernels._local_slip, Newton from the
    # direction-weighted compliance). Against the root found by bracketing (scipy's brentq, an
    # independent method) over compliances that differ by up to 50 %: the traction to 1e-12 of
    # the bound, on the bound, and opposite to the slip.
    from scipy.optimize import brentq
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(300):
        d = 10 ** rng.uniform(-12, -10)
        dxx, dyy = d * (1 + rng.uniform(-0.5, 0.5) * 10 ** rng.uniform(-4, 0)), d
        g = 10 ** rng.uniform(4, 8)
        cx, cy = (g * d * 10 ** rng.uniform(0.01, 2)) * np.array([np.cos(a := rng.uniform(0, 2 * np.pi)), np.sin(a)])

        def equation(s):
            return cx**2 / (s + g * dxx) ** 2 + cy**2 / (s + g * dyy) ** 2 - 1.0

        if equation(0.0) <= 0.0:
            continue
        sigma = brentq(equation, 0.0, np.hypot(cx, cy), xtol=1e-30, rtol=4 * np.finfo(float).eps)
        px, py = _local_slip(cx, cy, dxx, dyy, g)
        assert abs(px + g * cx / (sigma + g * dxx)) <= 1e-12 * g
        assert abs(py + g * cy / (sigma + g * dyy)) <= 1e-12 * g
        assert abs(np.hypot(px, py) - g) <= 1e-12 * g
        assert px * (cx + dxx * px) + py * (cy + dyy * py) < 0  # opposite to the slip s = c + D p
        checked += 1
    assert checked > 250


@pytest.mark.parametrize("reach", [0, 1, 2])
def test_local_updates_list_every_neighbour_with_its_coefficients(reach):
    """The local sweeps' table of neighbours and stencil against a brute-force search over the list.

    A wrong stencil or a missed neighbour would not make the local sweeps wrong (each round ends
    with an exact product and the exact sweep confirms) but slower, so it is checked here
    directly: for a contact list with holes touching the grid's edges, every element within
    ``reach`` lines appears at its offset's slot with the kernels' coefficients of that offset
    (exactly: the same numbers), and every other slot is -1.
    """
    nx, ny = 9, 7
    k = rectangle_kernels(nx, ny, 0.5e-3, 0.4e-3, 80e9, 0.3)
    rng = np.random.default_rng(5)
    inside = rng.random((nx, ny)) < 0.7
    cix, ciy = (a.astype(np.int64) for a in np.nonzero(inside))
    updates = local_updates(flat_tangential(k.bundle()), cix, ciy, nx, ny, reach)
    width = 2 * reach + 1
    assert updates.neighbours.shape == (cix.size, width * width)
    position = {(i, j): c for c, (i, j) in enumerate(zip(cix, ciy))}
    for c in range(cix.size):
        for q in range(width * width):
            di, dj = divmod(q, width)
            di -= reach
            dj -= reach
            expected = position.get((cix[c] + di, ciy[c] + dj), -1)
            assert updates.neighbours[c, q] == expected
            kernel = (k.K11, k.K12, k.K22)
            for row in range(3):
                assert updates.stencil[row, q] == kernel[row][di + nx - 1, dj + ny - 1]


def test_extrapolated_warm_start_changes_only_the_iterations(monkeypatch):
    """The transient model's extrapolated warm start against the last state as warm start.

    halfspace.EXTRAPOLATED_WARM_START: the same solutions (to the solver's tolerance: forces to
    1e-8 of the normal force, tractions to 1e-8 mu p_max, as the solver paths are compared
    elsewhere; tolerance 1e-9 per traction, summed over at most 260 elements) in fewer sweeps
    over the first 100 steps from rest (22 x 18, partial slip; measured 1896 against 2109).
    """
    from contact.halfspace import model as halfspace
    from contact.halfspace.model import Grid, HalfspaceContact
    from contact.hertz import hertz_from_semi_axes
    from contact.params import Friction, Material

    material = Material(80e9, 0.3)
    hz = hertz_from_semi_axes(5e-3, 4e-3, 50e3, material.contact_modulus)
    grid = Grid.covering(5e-3, 4e-3, nx=22, ny=18)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    runs = {}
    for extrapolate in (False, True):
        monkeypatch.setattr(halfspace, "EXTRAPOLATED_WARM_START", extrapolate)
        model = HalfspaceContact(material=material, friction=Friction(0.3), grid=grid,
                                 gap=hz.A * X ** 2 + hz.B * Y ** 2, kind="transient", speed=20.0)
        state = model.initial_state()
        forces, tractions, iterations = [], [], 0
        for _ in range(100):
            res = model.solve(state, normal_force=50e3, creepage=(0.0, -3e-3, 0.0))
            state = res.new_state
            forces.append(res.force)
            tractions.append(np.asarray(state.traction))
            iterations += res.diagnostics.iterations
        runs[extrapolate] = (np.array(forces), np.array(tractions), iterations, res)
    plain, extrapolated = runs[False], runs[True]
    assert 0 < extrapolated[3].diagnostics.n_stick < extrapolated[3].diagnostics.n_contact  # partial slip
    assert np.abs(extrapolated[0] - plain[0]).max() <= 1e-8 * 50e3
    assert np.abs(extrapolated[1] - plain[1]).max() <= 1e-8 * 0.3 * plain[3].diagnostics.pmax
    assert extrapolated[2] < 0.95 * plain[2]


@pytest.mark.parametrize("mode", ["transient", "shift"])
def test_gathered_problem_equals_the_array_gather(mode):
    """The compiled gather of a tangential problem against numpy's fancy indexing (the way it was built before).

    Sweep order (lines of constant x from the leading edge, each along y: lexsort), rigid slip,
    previous displacement of the particle (upstream in transient rolling, in place for a shift),
    friction bounds and warm start, on a contact with holes; the warm start's displacement is
    taken only when the warm tractions vanish outside the contact.
    """
    rng = np.random.default_rng(8)
    nx, ny = 11, 9
    pressure = np.where(rng.random((nx, ny)) < 0.6, rng.random((nx, ny)) * 1e9, 0.0)
    pressure[-1] = 0.0  # transient rolling needs an element upstream
    slip, previous, warm, warm_u = rng.standard_normal((4, nx, ny, 2))
    warm[pressure <= 0] = 0.0
    problem, start, status = gather_tangential_problem(pressure, slip, previous, 1 if mode == "transient" else 0,
                                                          warm, warm_u, 0.4, 0.3, CONSTANT_LAW)
    cix, ciy = np.nonzero(pressure > 0)
    order = np.lexsort((ciy, -cix))
    cix, ciy = cix[order], ciy[order]
    src = cix + 1 if mode == "transient" else cix
    assert status == 0
    np.testing.assert_array_equal(problem.ix, cix)
    np.testing.assert_array_equal(problem.iy, ciy)
    for got, want in ((problem.slip_x, slip[cix, ciy, 0]), (problem.slip_y, slip[cix, ciy, 1]),
                      (problem.previous_x, previous[src, ciy, 0]), (problem.previous_y, previous[src, ciy, 1]),
                      (problem.static_bound, 0.4 * pressure[cix, ciy]), (problem.kinetic_bound, 0.3 * pressure[cix, ciy]),
                      (start.px, warm[cix, ciy, 0]), (start.py, warm[cix, ciy, 1]),
                      (start.ux, warm_u[cix, ciy, 0]), (start.uy, warm_u[cix, ciy, 1])):
        np.testing.assert_array_equal(got, want)
    outside = warm.copy()
    outside[np.nonzero(pressure <= 0)[0][0], np.nonzero(pressure <= 0)[1][0], 0] = 1.0
    assert gather_tangential_problem(pressure, slip, previous, 0, outside, warm_u, 0.4, 0.3, CONSTANT_LAW)[2] == 2
    if mode == "transient":
        pressure[-1, 3] = 1e8
        assert gather_tangential_problem(pressure, slip, previous, 1, warm, warm_u, 0.4, 0.3, CONSTANT_LAW)[2] == 1


def test_tangential_problem_refuses_fields_of_another_grid_and_a_contact_at_the_leading_line():
    """solve_tangential names the field of a wrong shape, and refuses transient rolling without an element upstream."""
    from squealcore.errors import InputError
    from contact.params import Friction
    from contact.halfspace.tangential import solve_tangential

    k = rectangle_kernels(8, 6, 1e-3, 1e-3, 80e9, 0.3)
    pressure = np.zeros((8, 6))
    pressure[3:5, 2:4] = 1e8
    slip = np.full((8, 6, 2), 1e-7)
    with pytest.raises(InputError, match="u_prev"):
        solve_tangential(k, pressure, slip, mode="transient", friction=Friction(0.3), u_prev=np.zeros((8, 5, 2)))
    with pytest.raises(InputError, match="rigid_slip"):
        solve_tangential(k, pressure, slip[:, :, :1], mode="transient", friction=Friction(0.3))
    pressure[7, 2] = 1e8
    with pytest.raises(InputError, match="grid.nx"):
        solve_tangential(k, pressure, slip, mode="transient", friction=Friction(0.3))
    assert solve_tangential(k, pressure, slip, mode="shift", friction=Friction(0.3)).traction.shape == (8, 6, 2)
