"""The screen's structured eigenvalues (stability/screen.py ``_structured_eigenvalues``,
stability/kernels.py ``aberth_rational_roots``): the closed loop's eigenvalues as the roots of
``det(s I - P) det(I - Rᵀ (s I - P)^{-1} L)`` by the Aberth–Ehrlich iteration instead of the
dense QR algorithm.

References: the quadratic formula (a two-pole scalar loop); the dense eigenvalues of the loop
matrix (scipy.linalg.eigvals: LAPACK's QR, an independent method) and the screen on the dense
path, on stationary and rotating wheel models (rank-1 and full-rank residues), with and without
the creep relaxation (coupling of rank 3 and 6), in full sliding (a rank-1 contact that leaves
some open-loop poles in place) and below saturation; and the fallback to the dense path when a
check fails (forced)."""

import numpy as np
import pytest
import scipy.linalg
from scipy.optimize import linear_sum_assignment
from test_stability_fast import CONTACTS, SPEED, _rail, _wheel

from fe.greens import modal_poles_residues
from stability import screen as screen_module
from stability.kernels import aberth_rational_roots
from stability.screen import _loop, _structured_eigenvalues, screen

#: relative agreement demanded of every eigenvalue (the brief: growing and margin poles to 1e-9)
TOLERANCE = 1e-9
#: ... and absolute, of the loop's largest eigenvalue |λ|max (1/s): both methods' round-off
#: (LAPACK's backward error ~ ε ‖A‖ of the balanced matrix; measured 1e-9 1/s on a real
#: eigenvalue of -0.18 1/s beside |λ|max = 1.8e6 1/s, 6e-16 of it); the eigenvalues that
#: matter lie at 1e3 - 1e5 1/s, where the relative 1e-9 is the binding one
ROUND_OFF = 1e-14


def _big_wheel(seed, rotating):
    """80 wheel modes from 60 Hz to 9 kHz (some close pairs), damping 1e-4 to 1e-2;
    ``rotating``: full-rank non-symmetric residues, as the rotating models."""
    rng = np.random.default_rng(seed)
    f = np.sort(np.concatenate([np.geomspace(60.0, 9000.0, 70), 1.01 * np.geomspace(300.0, 5000.0, 10)]))
    poles, residues = modal_poles_residues(f, np.geomspace(1e-4, 1e-2, f.size), rng.normal(size=(f.size, 3)) * 0.3)
    if rotating:
        residues = residues + 0.2 * np.abs(residues).max() * (rng.normal(size=residues.shape)
                                                              + 1j * rng.normal(size=residues.shape))
    return poles, residues


def _paired_match(reference, values, floor=0.0):
    """Largest error of a one-to-one matching of ``values`` to ``reference`` (the assignment of
    least total distance: multiple eigenvalues are matched one each), relative to
    ``|reference| + floor / TOLERANCE`` (``floor``: an absolute accuracy, 1/s)."""
    distance = np.abs(reference[:, None] - values[None, :])
    rows, cols = linear_sum_assignment(distance)
    return np.max(distance[rows, cols] / (np.abs(reference[rows]) + floor / TOLERANCE))


def test_two_pole_scalar_loop_against_the_quadratic_formula():
    """k = 1, two poles: ``(s - μ1)(s - μ2) - g1 (s - μ2) - g2 (s - μ1) = 0``, a quadratic."""
    mu = np.array([-3.0 + 40.0j, -50.0 - 5.0j])
    g = np.array([7.0 - 2.0j, -30.0 + 11.0j])
    b = -(mu.sum() + g.sum())
    c = mu[0] * mu[1] + g[0] * mu[1] + g[1] * mu[0]
    exact = (-b + np.array([1, -1]) * np.sqrt(b * b - 4 * c)) / 2
    z = mu + np.array([1.0 + 1.0j, -1.0 + 0.5j])
    newton = np.zeros(2)
    sweeps = aberth_rational_roots(mu, g.reshape(2, 1, 1), np.zeros(2, np.int64), np.ones(2, np.int64),
                                   np.ones(2, np.int64), np.ones((1, 1), complex), np.ones(2), z,
                                   np.zeros(2, bool), np.array([2]), np.ones(2, bool), 1e-14, 50, newton,
                                   np.zeros(2, np.int64))
    assert sweeps > 0
    assert _paired_match(exact, z) < 1e-13


def test_an_iterate_exactly_at_a_root_is_a_converged_root():
    """``q(s) = (s - μ) (1 - g / (s - μ)) = s - μ - g`` with μ = -1, g = 1: its root s = 0 makes
    ``M = 1 - g / (s - μ)`` exactly zero. An iterate that lands exactly on a root (which one does
    depends on the last bits of the arithmetic) stays there as a converged root with a zero
    Newton step, instead of a NaN from the singular M that spoiled every other root."""
    mu = np.array([-1.0 + 0.0j])
    for start in (0.0 + 0.0j, 0.3 - 0.2j):  # exactly at the root, and near it (must converge to it)
        z = np.array([start])
        newton = np.full(1, np.nan)
        sweeps = aberth_rational_roots(mu, np.ones((1, 1, 1), complex), np.zeros(1, np.int64), np.ones(1, np.int64),
                                       np.ones(1, np.int64), np.ones((1, 1), complex), np.ones(1), z,
                                       np.zeros(1, bool), np.array([1]), np.ones(1, bool), 1e-14, 50, newton,
                                       np.zeros(1, np.int64))
        assert sweeps > 0 and abs(z[0]) <= 1e-14 and np.isfinite(newton[0])
        if start == 0:
            assert z[0] == 0 and newton[0] == 0 and sweeps == 1


CASES = [(name, rotating, big) for name in sorted(CONTACTS) for rotating in (False, True) for big in (False, True)]


@pytest.mark.parametrize("name, rotating, big", CASES)
def test_structured_eigenvalues_are_the_dense_ones(name, rotating, big):
    """Every eigenvalue of the loop matrix, one to one, to 1e-9 relative (or 1e-14 of the
    largest; measured <= 1e-12 relative above 10 1/s); the real ones real."""
    contact = CONTACTS[name]
    poles, residues = (_big_wheel if big else _wheel)(3, rotating)
    rail = _rail(4, 0.0 if name == "creep" else 1e-11)
    a, e, low_rank, _, _ = _loop(poles, residues, rail, contact.normal_stiffness, contact.sliding_coefficient,
                                 contact.creep_stiffness, SPEED, None, contact.relaxation)
    assert e is None and low_rank is not None
    lam = _structured_eigenvalues(low_rank)
    assert lam is not None, "a check failed on a regular loop"
    dense = scipy.linalg.eigvals(a)
    assert lam.size == dense.size
    assert _paired_match(dense, lam, ROUND_OFF * np.abs(dense).max()) < TOLERANCE
    # the real ones real (LAPACK's may be a pair ±1e-11 i where a real eigenvalue is double)
    assert np.count_nonzero(lam.imag == 0) >= np.count_nonzero(dense.imag == 0)
    near_real = np.abs(dense.imag) <= 1e-12 * np.abs(dense)
    assert np.count_nonzero(lam.imag == 0) == np.count_nonzero(near_real)


def test_full_sliding_leaves_open_loop_poles_in_place():
    """Full sliding couples through the normal direction alone (rank 1): of a rotating wheel's
    pole with a rank-3 residue two eigenvalues stay at the pole, exactly in the structured path
    (the dense one has them to round-off); the screen must also give their wheel modes (the
    eigenvector at an exact open-loop pole)."""
    contact = CONTACTS["sliding"]
    poles, residues = _wheel(5, True)
    rail = _rail(6)
    _, _, low_rank, _, _ = _loop(poles, residues, rail, contact.normal_stiffness, contact.sliding_coefficient,
                                 contact.creep_stiffness, SPEED, None, contact.relaxation)
    lam = _structured_eigenvalues(low_rank)
    # two per wheel pole (the pole as the diagonalised 2x2 block gives it: to 1 ulp)
    kept = [np.count_nonzero(np.abs(lam - p) <= 1e-15 * abs(p)) for p in poles]
    assert kept == [2] * poles.size
    fast = screen(poles, residues, rail, contact, SPEED, min_share=0.0)
    assert fast["margin_modes"] and np.isclose(sum(fast["margin_shares"]), 1.0, atol=1e-12)


def _same_screen(fast, dense):
    """The two screens' results agree: poles, margin (eigenvalue to 1e-9 relative or 1e-14 of the
    loops' largest eigenvalues, ~1e7 1/s here), verdict, wheel
    modes and shares (to 1e-8: near an exact open-loop pole the dense eigenvector is off by the
    dense eigenvalue's round-off)."""
    assert len(fast["poles"]) == len(dense["poles"])
    assert fast["out_of_band"] == dense["out_of_band"]
    pairs = list(zip(fast["poles"], dense["poles"]))
    pairs.append(({"eigenvalue": complex(fast["margin"], 2 * np.pi * fast["margin_frequency"]),
                   "wheel_modes": fast["margin_modes"], "participation": fast["margin_shares"]},
                  {"eigenvalue": complex(dense["margin"], 2 * np.pi * dense["margin_frequency"]),
                   "wheel_modes": dense["margin_modes"], "participation": dense["margin_shares"]}))
    for p, q in pairs:
        assert abs(p["eigenvalue"] - q["eigenvalue"]) <= TOLERANCE * abs(q["eigenvalue"]) + ROUND_OFF * 1e7
        assert p["wheel_modes"] == q["wheel_modes"]
        assert np.allclose(p["participation"], q["participation"], rtol=0.0, atol=1e-8)
    assert (fast["margin"] > 0) == (dense["margin"] > 0)


@pytest.mark.parametrize("name", sorted(CONTACTS))
@pytest.mark.parametrize("rotating", [False, True])
def test_screen_structured_equals_dense(name, rotating):
    contact = CONTACTS[name]
    poles, residues = _big_wheel(11, rotating)
    rail = _rail(12, 0.0 if name == "creep" else 1e-11)
    fast = screen(poles, residues, rail, contact, SPEED)
    dense = screen(poles, residues, rail, contact, SPEED, structured=False)
    _same_screen(fast, dense)


def test_forced_fallback_gives_the_dense_result(monkeypatch):
    """No sweep allowed: the iteration reports no convergence, the screen takes the dense
    eigenvalues (and says so by returning the dense path's result)."""
    contact = CONTACTS["creep with relaxation"]
    poles, residues = _big_wheel(13, True)
    rail = _rail(14)
    dense = screen(poles, residues, rail, contact, SPEED, structured=False)
    monkeypatch.setattr(screen_module, "ABERTH_MAX_SWEEPS", 0)
    _, _, low_rank, _, _ = _loop(poles, residues, rail, contact.normal_stiffness, contact.sliding_coefficient,
                                 contact.creep_stiffness, SPEED, None, contact.relaxation)
    assert _structured_eigenvalues(low_rank) is None
    _same_screen(screen(poles, residues, rail, contact, SPEED), dense)


def test_a_missing_root_is_detected(monkeypatch):
    """The completeness check can fail: with one root too few started (a pole's order taken one
    lower), the converged roots miss trace(A) and the structured path declines."""
    contact = CONTACTS["creep"]
    poles, residues = _wheel(15, False)
    _, _, low_rank, _, _ = _loop(poles, residues, _rail(16, 0.0), contact.normal_stiffness,
                                 contact.sliding_coefficient, contact.creep_stiffness, SPEED, None, None)
    assert _structured_eigenvalues(low_rank) is not None
    orders = screen_module._pole_orders

    def one_fewer(*args):
        rank = orders(*args).copy()
        rank[np.argmax(rank)] -= 1
        return rank

    monkeypatch.setattr(screen_module, "_pole_orders", one_fewer)
    assert _structured_eigenvalues(low_rank) is None
