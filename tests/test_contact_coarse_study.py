"""The coarse-correction study of the transient solver (benchmarks/contact_coarse.py): its parts checked.

The study's conclusions (docs/benchmarks.md) rest on three operators; each is compared here with
an independent construction on a small grid.
"""

import importlib.util
from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def study():
    spec = importlib.util.spec_from_file_location("contact_coarse", REPO / "benchmarks" / "contact_coarse.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.fixture(scope="module")
def problem(study):
    return study.StickProblem(12, 10)


def _dense(problem):
    """The influence matrix on the contact set from the kernels, element pair by element pair."""
    k, cells, n = problem.kernels, problem.cells, problem.n
    d = cells[:, None, :] - cells[None, :, :]
    o = (d[..., 0] + k.nx - 1, d[..., 1] + k.ny - 1)
    return np.block([[k.K11[o], k.K12[o]], [k.K12[o], k.K22[o]]])


def test_product_is_the_dense_influence_matrix(problem):
    t = np.random.default_rng(1).standard_normal(2 * problem.n)
    dense = _dense(problem) @ t
    assert np.allclose(problem.apply(t), dense, rtol=0, atol=1e-12 * np.abs(dense).max())


def test_local_sweeps_are_gauss_seidel_on_the_near_coupling(problem):
    """Two sweeps element by element (both components of an element together, forward order) on the
    dense matrix cut to the 3 x 3 neighbourhood."""
    a = _dense(problem)
    n, cells = problem.n, problem.cells
    near = np.abs(cells[:, None, :] - cells[None, :, :]).max(axis=2) <= 1
    a_near = a * np.tile(near, (2, 2))
    r = np.random.default_rng(2).standard_normal(2 * n)
    t = np.zeros(2 * n)
    for _ in range(2):
        for i in range(n):
            for c in (0, 1):  # x then y of element i, each with the latest values
                row = c * n + i
                t[row] += (r[row] - a_near[row] @ t) / a_near[row, row]
    assert np.allclose(problem.local_sweeps(r), t, rtol=1e-12, atol=1e-12 * np.abs(t).max())


def test_one_element_aggregates_make_the_coarse_correction_the_exact_inverse(study, problem):
    coarse, unknowns = problem.coarse_correction(1)
    assert unknowns == 2 * problem.n
    iterations, residual = study.gmres_iterations(problem, study.two_level(problem, coarse))
    assert iterations <= 2 and residual < study.TOLERANCE


def test_a_start_at_the_solution_needs_no_iteration(study, problem):
    """The study's coarse start enters GMRES as its initial guess: started from the exact solution (the
    coarse correction of one-element aggregates), no iteration is needed; from zero, some are."""
    coarse, _ = problem.coarse_correction(1)
    exact = coarse(problem.rigid_slip)
    iterations, residual = study.gmres_iterations(problem, problem.local_sweeps, exact)
    assert iterations == 0 and residual < study.TOLERANCE
    assert study.gmres_iterations(problem, problem.local_sweeps)[0] > 5


def test_near_field_product_is_the_dense_matrix_cut_to_the_neighbourhood(problem):
    a = _dense(problem)
    cells = problem.cells
    near = np.abs(cells[:, None, :] - cells[None, :, :]).max(axis=2) <= 1
    t = np.random.default_rng(3).standard_normal(2 * problem.n)
    expected = (a * np.tile(near, (2, 2))) @ t
    assert np.allclose(problem.near_apply(t), expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_block_mean_effect_of_a_correction_is_the_block_mean_of_its_product(problem):
    """The solver's view of a coarse correction ``t = P c``: the block means of ``A t``, constant on each block."""
    coarse, _, effect = problem.coarse_correction(3, block_means=True)
    t = coarse(np.random.default_rng(4).standard_normal(2 * problem.n))  # a correction: constant on the blocks
    exact = _dense(problem) @ t
    key = (problem.cells[:, 0] // 3) * (problem.kernels.ny + 1) + problem.cells[:, 1] // 3
    _, group = np.unique(key, return_inverse=True)
    seen = effect(t)
    for component in (slice(0, problem.n), slice(problem.n, 2 * problem.n)):
        for b in range(group.max() + 1):
            members = group == b
            block = seen[component][members]
            assert np.allclose(block, block[0], rtol=1e-12, atol=0)
            assert np.isclose(block[0], exact[component][members].mean(), rtol=1e-10, atol=1e-12 * np.abs(exact).max())
