"""The screen's fast wheel-mode shares (stability/screen.py, ``_LowRank``): the eigenvector of
a pole from the null vector of the small contact matrix must be the eigenvector of the dense
eigen-solution (scipy.linalg.eig with right vectors, the path of ``closed_loop_eigen``).

References: the full eigenvectors of the dense loop matrix (an independent LAPACK solution), and
the eigen-equation ``A x = λ x`` itself."""

import numpy as np
import pytest

from fe.greens import modal_poles_residues
from stability.linearised_contact import LinearisedContact
from stability.rational import RationalModel
from stability.screen import _loop, closed_loop_eigen, screen

K_N = 1.1e9  # N/m
SPEED = 13.9  # m/s
RELAXATION = np.array([[3.03e-3, 1.03e-2, 2.9e-5], [2.91e-3, 9.07e-3, 2.46e-5]])  # m, m, m²


def _wheel(seed, rotating):
    """Ten wheel modes with two close pairs (mode coupling by friction); ``rotating``: full-rank,
    non-symmetric complex residues (3 terms per pole, like the rotating models)."""
    rng = np.random.default_rng(seed)
    f = np.array([420.0, 432.0, 1100.0, 1690.0, 1710.0, 2500.0, 3300.0, 4100.0, 5200.0, 6900.0])
    poles, residues = modal_poles_residues(f, np.full(f.size, 2e-4), rng.normal(size=(f.size, 3)) * 0.3)
    if rotating:
        residues = residues + 0.2 * np.abs(residues).max() * (rng.normal(size=residues.shape)
                                                              + 1j * rng.normal(size=residues.shape))
    return poles, residues


def _rail(seed, direct=1e-11):
    """Five damped pole pairs with full-rank symmetric residues, one real pole, a direct term
    (m/N; with creep and no relaxation a direct term makes the loop a descriptor system, which
    the screen solves by QZ and inverse iteration)."""
    rng = np.random.default_rng(seed)
    poles, _ = modal_poles_residues([150.0, 700.0, 1500.0, 3100.0, 5600.0], np.full(5, 0.08), np.ones((5, 3)))
    res = rng.normal(size=(5, 3, 3)) + 1j * rng.normal(size=(5, 3, 3))
    res = (res + np.swapaxes(res, 1, 2)) * 2e-6
    real = rng.normal(size=(3, 3))
    poles = np.concatenate([poles, [-2 * np.pi * 900.0]])
    res = np.concatenate([res, [(real + real.T) * 1e-3]])
    return RationalModel(poles, res, direct * np.eye(3), np.zeros((3, 3)), (20.0, 8000.0))


CONTACTS = {
    "sliding": LinearisedContact(K_N, 0.6, (0.0, 0.0), None, 1.0),
    "creep": LinearisedContact(K_N, 0.0, (6e6, 4e6), None, 0.5),
    "sliding with relaxation": LinearisedContact(K_N, -0.6, (2.2e6, 0.0), RELAXATION, 1.0),
    "creep with relaxation": LinearisedContact(K_N, 0.1, (6e6, 4e6), RELAXATION, 0.5),
}


@pytest.mark.parametrize("name", sorted(CONTACTS))
@pytest.mark.parametrize("rotating", [False, True])
def test_null_vector_shares_are_those_of_the_full_eigenvector(name, rotating):
    contact = CONTACTS[name]
    poles, residues = _wheel(3, rotating)
    rail = _rail(4, 0.0 if name == "creep" else 1e-11)
    lam, shares = closed_loop_eigen(poles, residues, rail, contact.normal_stiffness, contact.sliding_coefficient,
                                    contact.creep_stiffness, SPEED, relaxation=contact.relaxation)
    result = screen(poles, residues, rail, contact, SPEED, min_share=0.0)
    # the loop is an ordinary eigenproblem here: the low-rank (fast) path is the one taken
    a, e, low_rank, _, _ = _loop(poles, residues, rail, contact.normal_stiffness, contact.sliding_coefficient,
                                 contact.creep_stiffness, SPEED, None, contact.relaxation)
    assert e is None and low_rank is not None
    checked = [(result["margin"], result["margin_frequency"], result["margin_modes"], result["margin_shares"])]
    checked += [(p["growth_rate"], p["frequency"], p["wheel_modes"], p["participation"]) for p in result["poles"]]
    for growth, frequency, modes, part in checked:
        value = complex(growth, 2 * np.pi * frequency)
        i = np.argmin(np.abs(lam - value))
        assert abs(lam[i] - value) < 1e-9 * abs(value)  # the same eigenvalue as the dense solution
        # the shares: those of the dense solution's eigenvector to 1e-9 (the brief's tolerance for
        # eigenvalues; both eigenvectors carry round-off of a loop scaled by k_n ~ 1e9 N/m, the
        # largest difference seen is 3e-10, on a real growing pole); near-ties may swap order, so
        # compare share by mode
        assert np.allclose(np.asarray(part), shares[i][modes], rtol=0.0, atol=1e-9)
        assert np.isclose(sum(part), 1.0, atol=1e-12)  # min_share 0: every mode listed
        x = low_rank.eigenvector(lam[i])  # and it solves the eigen-equation of the dense matrix
        assert np.linalg.norm(a @ x - lam[i] * x) < 1e-9 * np.linalg.norm(a, 2) * np.linalg.norm(x)
    assert len(checked) > 1 or name.startswith("creep"), "friction coupling makes a close pair grow"


@pytest.mark.parametrize("name", sorted(CONTACTS))
def test_low_rank_form_is_the_loop_matrix(name):
    """P + L Rᵀ rebuilt from the factors is the dense loop matrix (to round-off), P block diagonal."""
    contact = CONTACTS[name]
    poles, residues = _wheel(7, True)
    a, _, low_rank, _, _ = _loop(poles, residues, _rail(8, 0.0 if name == "creep" else 1e-11), contact.normal_stiffness, contact.sliding_coefficient,
                                 contact.creep_stiffness, SPEED, None, contact.relaxation)
    p = np.diag(low_rank.diag)
    p[low_rank.first, low_rank.first + 1] = low_rank.upper
    p[low_rank.first + 1, low_rank.first] = low_rank.lower
    rebuilt = p + low_rank.left @ low_rank.right
    assert np.abs(rebuilt - a).max() <= 1e-12 * np.abs(a).max()
    # balanced factors: no column of L or row of Rᵀ carries the contact stiffness's scale alone
    norm_l, norm_r = np.linalg.norm(low_rank.left, axis=0), np.linalg.norm(low_rank.right, axis=1)
    used = (norm_l > 0) & (norm_r > 0)
    assert np.allclose(norm_l[used], norm_r[used], rtol=1e-12)
