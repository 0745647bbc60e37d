r"""Complex-eigenvalue stability of the wheel on a flexible rail with a linearised contact.

The wheel (any pole-residue model of :mod:`fe.greens`: stationary, moving load, Eulerian) and
the rail (a :class:`stability.rational.RationalModel`, e.g. the vector fit of its moving
receptance) are both written as ``H(s) = Σ_k R_k / (s - p_k) + D`` over all poles (each pair
``p, p̄`` with ``R, R̄``). Each residue is factored ``R_k = U_k V_kᵀ`` (SVD, rank r_k: 1 for a
stationary wheel mode ``φφᵀ``), giving the realisation

.. math::

    \dot x_k = p_k x_k + V_k^T F_k, \qquad u = \sum_k U_k x_k + D F,

with ``F`` the force on the structure. The wheel receives the contact force ``F``, the rail
``-F``; the relative displacement wheel - rail at the contact is then
``Δu = u_w - u_r = Σ_w U x + Σ_r U x + (D_w + D_r) F`` (contact frame: x along the rail,
y lateral, z up; the convention of :mod:`stability.linear`). The linearised contact
(:class:`interaction.linear_contact.LinearContact`) is

.. math::

    F = -k_n Δu_z (0, μ_s, 1) - \frac{1}{v} \mathrm{diag}(c_x, c_y, 0)\, Δ\dot u,

the Hertz normal stiffness k_n, in full sliding (``c = 0``, ``μ_s = ±μ``) the lateral force
following the normal force, below saturation (``μ_s = 0``) the creep forces ``-c ξ``,
``-c η`` with creepages = relative velocity / v (damping-like terms). With
``Δu̇ = Σ U (p x + Vᵀ F_k) + D Ḟ``, where the wheel's states receive ``F`` and the rail's
``-F``, the closed loop is the descriptor system ``E ż = A z`` in ``z = (x, F)``:

.. math::

    \begin{aligned}
    \dot x &= P x + B F, \\
    \tfrac{1}{v} C D\, \dot F &= -\left(k_n d\, e_z^T U + \tfrac{1}{v} C U P\right) x
        - \left(I + k_n d\, e_z^T D + \tfrac{1}{v} C U B\right) F,
    \end{aligned}

(``D = D_w + D_r``, ``d = (0, μ_s, 1)``, ``C = diag(c_x, c_y, 0)``). When ``C D = 0`` (rigid
rail, or no creep terms, or no direct term) F is eliminated and the ordinary eigenproblem of
``P - B M^{-1} N`` is solved; otherwise the generalised one (QZ), whose infinite eigenvalues
(the algebraic part of F) are dropped.

A pole with ``Re λ > 0`` is an instability at ``Im λ / 2π`` Hz growing at ``Re λ`` 1/s.
Its wheel modes are those whose states carry the largest share of the contact displacement
in the eigenvector, ``|U_k x_k|`` summed over the pair ``p_k, p̄_k`` (normalised over the
wheel's modes). The screen takes the eigenvector of an ordinary loop ``A = P + L Rᵀ`` (P block
diagonal, L Rᵀ the contact's coupling of rank k ≤ 6) from the null vector c of the k×k contact
matrix ``I - Rᵀ (λ I - P)^{-1} L``: ``x = (λ I - P)^{-1} L c``, exact and of cost O(n k).

Eigenvalues: those of an ordinary loop ``A = P + L Rᵀ`` are the roots of
``det(s I - P) det(I - Rᵀ (s I - P)^{-1} L)``, found all at once by the Aberth–Ehrlich iteration
(:func:`_structured_eigenvalues`; O. Aberth, Math. Comp. 27 (1973) 339–344; L. W. Ehrlich,
Comm. ACM 10 (1967) 107–108) at O(n k r) per evaluation instead of the O(n³) of the dense QR
(LAPACK dgeev, which was most of a screen's time: docs/benchmarks.md, the row *linear stability
screen*), checked (convergence, each root's Newton step,
the roots' sum against trace(A)) and replaced by the dense eigenvalues where a check fails.
Measured and found of no use for the dense path (issue 15): a complex realisation (double the
flops); balancing off (changes eigenvalues: the loop is scaled by k_n ~ 1e9 N/m) and
scaling-only or permutation-only balancing (no faster); no two configurations of a map share
a matrix (the creep terms carry the speed); no wheel or rail term is uncoupled (no residue
below 5e-4 of the largest, the contact force of rank 3 below saturation). Newton on the
contact determinant from each open-loop pole alone misses heavily damped rail poles (their
roots travel far): the simultaneous iteration's repulsion and the trace check are what make
the root set complete.
"""

from __future__ import annotations

import logging

import numpy as np
import scipy.linalg

from squealcore.errors import InputError, require_range
from stability import kernels
from stability.linearised_contact import LinearisedContact
from stability.rational import RationalModel

logger = logging.getLogger(__name__)

__all__ = ["closed_loop_eigen", "closed_loop_eigenvalues", "growing_poles_with_rail", "screen"]

#: singular values of a residue below this fraction of its largest are dropped in R = U Vᵀ
RANK_TOLERANCE = 1e-10


def _realisation(poles, residues, sign):
    """Real states of ``Σ R/(s-p) + R̄/(s-p̄)``: per pole p_k and term j of ``R_k = Σ_j u_j v_jᵀ``
    (SVD, terms above :data:`RANK_TOLERANCE`), the complex state ``ẋ = p x + v·F`` with output
    ``u x + conj(u x)`` written in ``(Re x, Im x)``: ``[[Re p, -Im p], [Im p, Re p]]``, input rows
    ``Re v, Im v``, output columns ``2 Re u, -2 Im u``. A real pole with a real residue (u, v
    real) has ``Im x`` neither driven nor seen: its term is the single real state ``ẋ = p x +
    v·F`` with output ``2 u x`` (the dropped state would only add the eigenvalue p, unmoved).
    ``sign`` (+1 wheel, -1 rail) is the sign of the force the structure receives and of its
    displacement in Δu = u_w - u_r (both U and B carry it).

    Returns (A (n, n) block diagonal, U (3, n), B (n, 3), owner (n,) index of the pole pair), all real."""
    poles = np.asarray(poles, complex)
    residues = np.asarray(residues, complex).reshape(poles.size, 3, 3)
    if poles.size == 0:
        return np.zeros((0, 0)), np.zeros((3, 0)), np.zeros((0, 3)), np.zeros(0, int)
    u, sv, vh = np.linalg.svd(residues)  # one call for all poles (batched LAPACK)
    real = (poles.imag == 0.0) & np.all(residues.imag == 0.0, axis=(1, 2))
    if np.any(real):  # their factors real (the complex SVD may give them any common phase)
        u_r, sv_r, vh_r = np.linalg.svd(residues[real].real)
        u[real], sv[real], vh[real] = u_r, sv_r, vh_r
    keep = (sv > RANK_TOLERANCE * sv[:, :1]) & (sv[:, :1] > 0.0)
    k, j = np.nonzero(keep)  # pole-major, as the terms are listed
    uj = sign * u[k, :, j] * sv[k, j][:, None]  # (q, 3)
    vj = sign * vh[k, j, :]
    p = poles[k]
    width = np.where(real[k], 1, 2)  # states per term
    first = np.concatenate([[0], np.cumsum(width)[:-1]])  # its first state
    n = int(width.sum())
    a = np.zeros((n, n))
    a[first, first] = p.real
    u_out = np.empty((3, n))
    u_out[:, first] = 2.0 * uj.real.T
    b_in = np.empty((n, 3))
    b_in[first] = vj.real
    pair = first[width == 2]
    pc, uc, vc = p[width == 2], uj[width == 2], vj[width == 2]
    a[pair + 1, pair + 1] = pc.real
    a[pair, pair + 1] = -pc.imag
    a[pair + 1, pair] = pc.imag
    u_out[:, pair + 1] = -2.0 * uc.imag.T
    b_in[pair + 1] = vc.imag
    return a, u_out, b_in, np.repeat(k, width)


#: The rail's realisation per rail model (the same rail serves many configurations): the
#: last few models, by identity (the model is kept alive with its entry, so ids are not reused).
_RAIL_STATES = {}
_RAIL_STATES_SIZE = 8


def _rail_realisation(rail):
    entry = _RAIL_STATES.get(id(rail))
    if entry is None or entry[0] is not rail:
        if len(_RAIL_STATES) >= _RAIL_STATES_SIZE:
            _RAIL_STATES.pop(next(iter(_RAIL_STATES)))
        entry = (rail, _realisation(rail.poles, rail.residues, -1.0))
        _RAIL_STATES[id(rail)] = entry
    return entry[1]


def _block_diag(*blocks):
    """The block-diagonal matrix of 2-d arrays (as scipy.linalg.block_diag, whose generic
    path costs milliseconds at n ~ 400: a screen builds two)."""
    rows = [b.shape[0] for b in blocks]
    cols = [b.shape[1] for b in blocks]
    out = np.zeros((sum(rows), sum(cols)), np.result_type(*blocks))
    r = c = 0
    for b in blocks:
        out[r:r + b.shape[0], c:c + b.shape[1]] = b
        r, c = r + b.shape[0], c + b.shape[1]
    return out


def _blocks(grid):
    """The matrix of a 2×2 grid of 2-d blocks (as np.block, at the cost of one copy)."""
    (a, b), (c, d) = grid
    out = np.empty((a.shape[0] + c.shape[0], a.shape[1] + b.shape[1]), np.result_type(a, b, c, d))
    out[:a.shape[0], :a.shape[1]], out[:a.shape[0], a.shape[1]:] = a, b
    out[a.shape[0]:, :a.shape[1]], out[a.shape[0]:, a.shape[1]:] = c, d
    return out


def _loop(wheel_poles, wheel_residues, rail, normal_stiffness, sliding_coefficient, creep_stiffness, speed,
          wheel_direct, relaxation, friction_damping=None):
    """The closed loop as ``E ż = A z`` (E None: the identity), its :class:`_LowRank` form (None
    for a descriptor loop), the wheel's output matrix and state owners; see :func:`closed_loop_eigen`."""
    k_n = require_range("contact.normal_stiffness", normal_stiffness, 0.0, None, low_open=True, unit="N/m")
    mu = require_range("contact.sliding_coefficient", sliding_coefficient, -10.0, 10.0)
    cx, cy = (require_range("contact.creep_stiffness", float(c), 0.0, None, unit="N") for c in creep_stiffness)
    if np.any(rail.proportional != 0):
        raise InputError("rail.proportional", "the closed loop takes a rail model without proportional term")
    creep = np.diag([cx, cy, 0.0])
    if cx or cy:
        speed = require_range("operating.speed", speed, 0.0, 200.0, low_open=True, unit="m/s")
        creep = creep / speed
    aw, uw, bw, owner = _realisation(wheel_poles, wheel_residues, +1.0)
    ar, ur, br, _ = _rail_realisation(rail)
    p = _block_diag(aw, ar)  # ẋ = P x + B F
    u = np.concatenate([uw, ur], axis=1)  # Δu = U x + D F
    b = np.concatenate([bw, br], axis=0)
    direct = np.asarray(rail.direct, float) + (0.0 if wheel_direct is None else np.asarray(wheel_direct, float))
    d = np.array([0.0, mu, 1.0])
    e_z = np.array([0.0, 0.0, 1.0])
    n = p.shape[0]
    if friction_damping is not None and any(friction_damping):  # a friction characteristic's slope term
        return _damped_loop(p, u, b, direct, k_n, d, (cx, cy), speed, relaxation, friction_damping) + (uw, owner)
    if relaxation is not None and (cx or cy):
        return _relaxed_loop(p, u, b, direct, k_n, d, (cx, cy), speed, np.asarray(relaxation, float)) + (uw, owner)
    a21 = -(k_n * np.outer(d, e_z @ u) + creep @ (u @ p))
    a22 = -(np.eye(3) + k_n * np.outer(d, e_z @ direct) + creep @ (u @ b))
    e22 = creep @ direct
    if not np.any(e22):
        gain = np.linalg.solve(a22, a21)  # F = -gain x
        return p - b @ gain, None, _LowRank(p, b, -gain), uw, owner
    a = np.block([[p, b], [a21, a22]])
    e = np.zeros((n + 3, n + 3))
    e[:n, :n] = np.eye(n)
    e[n:, n:] = e22
    return a, e, None, uw, owner


def _eig(a, e, vectors):
    """Finite eigenvalues (and right vectors) of ``a`` or of the pencil ``(a, e)``."""
    if e is None:
        if not vectors:
            return scipy.linalg.eigvals(a, overwrite_a=True, check_finite=False), None
        return scipy.linalg.eig(a, check_finite=False)
    result = scipy.linalg.eig(a, e, right=vectors, homogeneous_eigvals=True, check_finite=False)
    (alpha, beta), vec = result if vectors else (result, None)  # without vectors eig returns w alone
    finite = np.abs(beta) > 1e-12 * np.abs(alpha).max()
    return alpha[finite] / beta[finite], (vec[:, finite] if vectors else None)


#: relative step at which a root of the Aberth iteration stops (:func:`_structured_eigenvalues`)
ABERTH_TOLERANCE = 1e-13
#: sweeps after which the Aberth iteration is given up (the dense eigenvalues are taken)
ABERTH_MAX_SWEEPS = 60
#: the roots' sum must equal trace(P + L Rᵀ) to this fraction of Σ|λ|; a root's |Im λ| below
#: this fraction of |λ| makes it real (where it has no conjugate among the roots)
ABERTH_CHECK = 1e-10
#: a root is accepted when its Newton step |q/q'| (its error to first order) is at most this
#: fraction of |λ| (the agreement with the dense eigenvalues that the screen demands)
NEWTON_CHECK = 1e-9
#: relative round-off of the loop's evaluation, of its largest pole: the absolute accuracy of a
#: root much smaller than that (and of the dense eigenvalues alike)
ROUND_OFF = 1e-14
#: eigenvalues of a pole's coupling ``V⁻¹ L Rᵀ V`` (m×m over its m equal states) below this
#: fraction of the matrix's norm count as 0 (the pole then stays an eigenvalue that many times)
GROUP_RANK_TOLERANCE = 1e-12
#: the poles' couplings G_g are written in a basis of their columns (:func:`_compressed_gains`):
#: singular values below this fraction of the largest are dropped, and each G_g must be
#: reproduced to this fraction of its norm (else no compression)
COMPRESSION_TOLERANCE = 1e-13


def _complex_diagonal(low_rank):
    """P of a :class:`_LowRank` diagonalised: its eigenvalues μ (n,) and the rows/columns of the
    coupling in that basis, ``Rᵀ V`` (k, n) and ``V⁻¹ L`` (n, k); None when a 2×2 block is
    (nearly) defective. The 2×2 blocks by batched LAPACK (their eigenvectors are exact to
    rounding: each block is a real-pole pair [[a, -b], [b, a]] or a relaxation filter)."""
    left, right = low_rank.left, low_rank.right
    n = left.shape[0]
    single = np.ones(n, bool)
    i, j = low_rank.first, low_rank.first + 1
    single[i] = single[j] = False
    blocks = np.empty((i.size, 2, 2))
    blocks[:, 0, 0], blocks[:, 1, 1] = low_rank.diag[i], low_rank.diag[j]
    blocks[:, 0, 1], blocks[:, 1, 0] = low_rank.upper, low_rank.lower
    mu2, vec = np.linalg.eig(blocks)
    if i.size and np.max(np.linalg.cond(vec)) > 1e8:
        return None
    inv = np.linalg.inv(vec)
    r2 = np.einsum("anp,npm->nma", np.stack([right[:, i], right[:, j]], axis=2), vec)  # (nb, 2, k)
    l2 = np.einsum("nmp,npb->nmb", inv, np.stack([left[i], left[j]], axis=1))  # (nb, 2, k)
    k = left.shape[1]
    mu = np.concatenate([low_rank.diag[single].astype(complex), mu2.ravel()])
    rows = np.concatenate([right[:, single].T.astype(complex), r2.reshape(-1, k)])  # (n, k): columns of Rᵀ V
    cols = np.concatenate([left[single].astype(complex), l2.reshape(-1, k)])
    return mu, rows, cols


def _pole_orders(group, multiplicity, rows, cols):
    """ρ_g: how many closed-loop eigenvalues leave the open-loop pole μ_g, the number of non-zero
    eigenvalues of the m_g×m_g coupling among its m_g equal states (``cols_s · rows_t``; the
    non-zero eigenvalues of G_g = Σ rows_s cols_sᵀ, without the zero ones that a nilpotent part
    of G_g would add to its rank); the other m_g - ρ_g stay at μ_g (exactly: no input or no
    output reaches them)."""
    rank = np.zeros(multiplicity.size, int)
    by_group = np.argsort(group, kind="stable")
    start = np.concatenate([[0], np.cumsum(multiplicity)[:-1]])
    for m in np.unique(multiplicity):
        which = np.flatnonzero(multiplicity == m)
        states = by_group[start[which][:, None] + np.arange(m)]  # (ng_m, m)
        coupling = np.einsum("gsa,gta->gst", cols[states], rows[states])
        eig = np.abs(np.linalg.eigvals(coupling))
        norm = np.linalg.norm(coupling, axis=(1, 2))
        rank[which] = np.sum(eig > GROUP_RANK_TOLERANCE * norm[:, None], axis=1)
    return rank


def _compressed_gains(gains):
    """The groups' gains G_g (ng, k, k) as ``Q Ĝ_g`` with few rows per group: returns (Ĝ (ng, r, k),
    first row, end row and width (columns used) per group, Q (k, r)).

    The columns are first ordered by how many groups use them (a similarity of M, the same
    order for rows and columns), so that the structures' force inputs come first and the
    relaxation filters' own inputs, used by the filters' few poles only, last (``width``). The
    groups of the most common width (the structures' poles) have their columns in one subspace
    Q₁ (with the relaxation: rank 3 of k = 6, the contact displacements and the forces they make),
    the others (the filters) in Q₂; ``Q = [Q₁, Q₂]`` and det(I - Q H) = det(I - H Q) make the
    evaluation per structural pole r₁ × width instead of k × width."""
    ng, k, _ = gains.shape
    used = np.abs(gains).sum(axis=1) > 0  # (ng, k)
    order = np.argsort(-used.sum(axis=0), kind="stable")
    gains = gains[:, order][:, :, order]
    used = used[:, order]
    width = np.where(used.any(axis=1), k - np.argmax(used[:, ::-1], axis=1), 0)
    main = np.bincount(width).argmax()
    big = width <= main
    basis = _column_basis(gains[big, :, :main])
    if basis.shape[1] < k:
        fit = np.einsum("ka,gkb->gab", basis.conj(), gains[big])
        residual = np.linalg.norm(gains[big] - basis @ fit, axis=(1, 2))
        if np.any(residual > COMPRESSION_TOLERANCE * np.linalg.norm(gains[big], axis=(1, 2))):
            basis = np.eye(k, dtype=complex)
    if basis.shape[1] == k:  # no compression
        lo, hi = np.zeros(ng, int), np.full(ng, k)
        return gains, lo, hi, width, np.eye(k, dtype=complex)
    r1 = basis.shape[1]
    if np.any(~big):
        extra = _column_basis(gains[~big])
        basis = np.concatenate([basis, extra], axis=1)
    r = basis.shape[1]
    compressed = np.zeros((ng, r, k), complex)
    compressed[big, :r1] = np.einsum("ka,gkb->gab", basis[:, :r1].conj(), gains[big])
    if np.any(~big):
        fit = np.linalg.lstsq(basis, np.moveaxis(gains[~big], 0, 1).reshape(k, -1), rcond=None)[0]
        compressed[~big] = np.moveaxis(fit.reshape(r, -1, k), 1, 0)
        residual = np.linalg.norm(gains[~big] - basis @ compressed[~big], axis=(1, 2))
        if np.any(residual > COMPRESSION_TOLERANCE * np.linalg.norm(gains[~big], axis=(1, 2))):
            return gains, np.zeros(ng, int), np.full(ng, k), width, np.eye(k, dtype=complex)
    lo, hi = np.zeros(ng, int), np.where(big, r1, r)
    return compressed, lo, hi, width, basis


def _column_basis(gains):
    """An orthonormal basis (k, r) of the columns of the matrices ``gains`` (g, k, c), each
    matrix normalised first (a weak pole's columns count as much as a strong one's)."""
    norm = np.linalg.norm(gains, axis=(1, 2))
    scaled = gains[norm > 0] / norm[norm > 0, None, None]
    u, sv, _ = np.linalg.svd(np.moveaxis(scaled, 0, 1).reshape(gains.shape[1], -1), full_matrices=False)
    rank = int(np.sum(sv > COMPRESSION_TOLERANCE * sv[0])) if sv.size and sv[0] > 0 else 0
    return u[:, :rank]


def _aberth(args, z, paired, active, newton):
    """:func:`stability.kernels.aberth_rational_roots` from the starts z (with room for the
    pairs that part; ``newton``: the Newton steps of the roots that do not move); returns
    (sweeps, roots, paired, Newton steps, still moving)."""
    n = z.size
    room = n + np.count_nonzero(paired)
    z = np.concatenate([z, np.zeros(room - n, complex)])
    paired = np.concatenate([paired, np.zeros(room - n, bool)])
    active = np.concatenate([active, np.ones(room - n, bool)])
    newton = np.concatenate([newton, np.zeros(room - n)])
    size = np.array([n])
    sweeps = kernels.aberth_rational_roots(*args, z, paired, size, active, ABERTH_TOLERANCE, ABERTH_MAX_SWEEPS,
                                           newton, np.zeros(room, np.int64))
    n = size[0]
    return sweeps, z[:n], paired[:n], newton[:n], active[:n]


def _structured_eigenvalues(low_rank):
    r"""The eigenvalues of ``A = P + L Rᵀ`` (:class:`_LowRank`) without the dense matrix, or None.

    They are the roots of ``q(s) = det(s I - A) = det(s I - P) det(I - Rᵀ (s I - P)^{-1} L)``,
    with P diagonal (μ_j) after its 2×2 blocks are diagonalised: the terms of one pole μ_g (a
    pole pair of rank r in the residue gives r equal μ) are summed to ``G_g`` (k×k), μ_g stays
    an eigenvalue ``m_g - ρ_g`` times (:func:`_pole_orders`) and ρ_g roots start near it. All
    roots at once by the Aberth–Ehrlich iteration (:func:`stability.kernels.aberth_rational_roots`;
    each evaluation O(n k r), :func:`_compressed_gains`), one of each conjugate pair (q is real).
    None when a check fails (the caller then takes the dense eigenvalues): the iteration did not
    converge, a root's Newton step exceeds :data:`NEWTON_CHECK` |λ|, a root of a pair lies on
    the real axis, or the sum of the roots misses ``trace(A) = Σ μ + Σ_i L_i·R_i`` by more than
    :data:`ABERTH_CHECK` Σ|λ|. Roots with ``|Im λ| <= ABERTH_CHECK |λ| + ROUND_OFF max|μ|`` whose
    conjugate is no other root are set real (the dense eigenvalues of a real matrix are).
    """
    diagonal = _complex_diagonal(low_rank)
    if diagonal is None:
        return None
    mu, rows, cols = diagonal
    k = rows.shape[1]
    poles, group = np.unique(mu, return_inverse=True)
    multiplicity = np.bincount(group, minlength=poles.size)
    gains = np.zeros((poles.size, k, k), complex)
    np.add.at(gains, group, rows[:, :, None] * cols[:, None, :])
    rank = _pole_orders(group, multiplicity, rows, cols)
    gains, lo, hi, width, basis = _compressed_gains(gains)
    kept = np.repeat(poles, multiplicity - rank)  # eigenvalues at the open-loop poles
    # one of each conjugate pair for the lightly damped poles (damping ratio below 1/√2); the
    # roots of heavily damped ones (rail poles of the fit) may meet on the real axis and part as
    # two real roots, so both of their pair start, unpaired
    upper = poles.imag > np.abs(poles.real)
    lower = poles.imag < -np.abs(poles.real)
    symmetric = (np.count_nonzero(upper) == np.count_nonzero(lower)
                 and np.array_equal(np.sort_complex(poles[upper].conj()), np.sort_complex(poles[lower])))
    start_group = np.flatnonzero(~lower) if symmetric else np.arange(poles.size)
    start_group = np.repeat(start_group, rank[start_group])
    paired = upper[start_group] & symmetric
    z = poles[start_group].copy()  # moved off the poles by first_order_roots
    orders = rank.astype(float)
    kernels.first_order_roots(poles, gains, lo, hi, width, basis, orders, start_group, z)
    args = (poles, gains, lo, hi, width, basis, orders)
    sweeps, z, paired, newton, active = _aberth(args, z, paired, np.ones(z.size, bool), np.zeros(z.size))
    trace = low_rank.diag.sum() + np.sum(low_rank.left * low_rank.right.T)
    lam = np.concatenate([kept, z, z[paired].conj()])
    if np.any(paired) and np.all(np.isfinite(z)) and (sweeps == -1 or abs(lam.sum() - trace) > ABERTH_CHECK
                                                      * np.abs(lam).sum()):
        # the pairs' mirror images move as the conjugates of their roots, not by their own
        # Aberth steps, and may not settle (a pair that must part on the real axis, a free root
        # caught at a mirror image): every root listed, the iteration goes on from there for
        # the roots that had not stopped (and their mirror images)
        z = np.concatenate([z, z[paired].conj()])
        active = np.concatenate([active, active[paired]])
        newton = np.concatenate([newton, newton[paired]])
        sweeps, z, paired, newton, _ = _aberth(args, z, np.zeros(z.size, bool), active, newton)
    lam = np.concatenate([kept, z, z[paired].conj()])
    size = np.abs(lam)
    nz = z.size
    if (sweeps < 0 or not np.all(np.isfinite(z)) or np.any(newton > NEWTON_CHECK * np.abs(z))
            or np.any(np.abs(z[paired].imag) <= ABERTH_CHECK * np.abs(z[paired]))
            or abs(lam.sum() - trace) > ABERTH_CHECK * size.sum()):
        logger.debug("structured eigenvalues rejected (sweeps %d, worst Newton step %.2g, trace error %.2g): the "
                     "dense path instead", sweeps, np.max(newton / np.abs(z), initial=0.0),
                     abs(lam.sum() - trace) / size.sum())
        return None
    free = z[~paired]  # roots without a listed conjugate: real, or both of a pair listed
    # near the real axis to ABERTH_CHECK |λ|, or to the round-off of the loop's largest pole for a
    # root much smaller than that
    near = ABERTH_CHECK * np.abs(free) + ROUND_OFF * np.abs(poles).max()
    for i in np.flatnonzero(np.abs(free.imag) <= near):
        others = np.delete(free, i)
        if np.min(np.abs(others - free[i].conjugate()), initial=np.inf) > near[i]:
            free[i] = free[i].real
    lam[kept.size:kept.size + nz][~paired] = free
    return lam


def closed_loop_eigen(wheel_poles, wheel_residues, rail: RationalModel, normal_stiffness,
                      sliding_coefficient=0.0, creep_stiffness=(0.0, 0.0), speed=None, wheel_direct=None,
                      relaxation=None, friction_damping=None):
    """Eigenvalues of the wheel-contact-rail loop and the wheel modes' share in each.

    Parameters
    ----------
    wheel_poles : (m,) complex array_like
        rad/s, one of each conjugate pair.
    wheel_residues : (m, 3, 3) complex array_like
        m/(N s), the form of :func:`fe.greens.receptance`.
    rail : RationalModel
        The rail's receptance at the contact (``RationalModel.rigid()`` for a rigid rail); its
        proportional term must be zero.
    normal_stiffness : float
        k_n, N/m, > 0 (Hertz: ``3 Q / (2 δ)`` at the wheel load Q).
    sliding_coefficient : float
        μ_s = ΔF_y / ΔF_z (full sliding: ±μ; below saturation 0), -.
    creep_stiffness : (2,) tuple of float
        (c_x, c_y), N per unit creepage, >= 0 (0 in full sliding).
    speed : float, optional
        v, m/s, > 0; needed when a creep stiffness is non-zero.
    wheel_direct : (3, 3) array_like, optional
        Direct term of the wheel model, m/N (default 0).
    relaxation : (2, 3) array_like, optional
        Rows x and y: ``(b (m), a1 (m), a2 (m²))`` of the creep relaxation
        ``a2 e'' + a1 e' + e = γ + b γ'`` (derivatives in rolled distance) through which the
        creepage γ acts (the effective creepage e of the transient point contact,
        :meth:`contact.point.model.PointContact.relaxation_constants`); default none (the
        creep force follows the creepage at once).
    friction_damping : (2,) tuple of float, optional
        (d_x, d_y), N s/m: the slope term of a friction characteristic of the sliding speed
        (:attr:`stability.linearised_contact.LinearisedContact.friction_damping`), a force per
        unit relative tangential velocity acting at once (:func:`_damped_loop`); default none.

    Returns
    -------
    eigenvalues : (n,) complex ndarray
        Finite eigenvalues λ, 1/s.
    participation : (n, m) ndarray
        Share of each wheel pole pair in the contact displacement of the eigenvector, -
        (rows sum to 1 where the wheel moves at all).
    """
    a, e, _, uw, owner = _loop(wheel_poles, wheel_residues, rail, normal_stiffness, sliding_coefficient,
                               creep_stiffness, speed, wheel_direct, relaxation, friction_damping)
    lam, vec = _eig(a, e, True)
    return lam, _participation(vec, uw, owner, np.asarray(wheel_poles).size)


def _participation(x, uw, owner, m):
    """Share of each of the m wheel pole pairs in the contact displacement of each eigenvector
    (columns of ``x``, whose first ``uw.shape[1]`` rows are the wheel's states): the norm of the
    pair's displacement ``Σ U_i x_i`` over its states, normalised over the pairs."""
    nw = uw.shape[1]
    disp = uw[:, :, None] * x[None, :nw, :]  # (3, nw, n_eig)
    per_pair = np.zeros((3, m, x.shape[1]), complex)
    np.add.at(per_pair, (slice(None), owner), disp)
    part = np.sqrt(np.sum(np.abs(per_pair) ** 2, axis=0)).T  # (n_eig, m)
    tot = part.sum(axis=1, keepdims=True)
    return np.divide(part, tot, out=np.zeros_like(part), where=tot > 0)


def _damped_loop(p, u, b, direct, k_n, d, creep, speed, relaxation, friction_damping):
    r"""The loop when a friction characteristic's slope term damps the contact.

    The tangential force gets ``-D_f Δu̇``, ``D_f = diag(d_x, d_y, 0)`` (N s/m), at once; the
    creep force acts as in :func:`_loop` (``-C Δu̇`` with ``C = diag(c_x, c_y, 0) / v``) or, with
    a relaxation, as in :func:`_relaxed_loop` (direct stiffness ``K_t`` and the states ``w``).
    With ``G = C + D_f``, ``K = k_n d e_zᵀ + K_t``, ``ẋ = P x + B F`` and ``Δu = U x + D F``, the
    damping's velocity is the structures' modal part, ``U P x + U B F``: the direct compliance's
    rate ``D Ḟ`` is left out of it (its share ``|d D ω|`` is about 1e-4 at 5 kHz for a rail's
    direct compliance of 4e-10 m/N and ``d`` of 1e4 N s/m; kept, it makes a descriptor pencil
    whose scale, with the relaxation's ``v²/a2`` entries, spoils its finite eigenvalues). The
    unrelaxed creep force keeps its ``C D Ḟ`` as in :func:`_loop` (a descriptor loop). With the
    relaxation, ``F = -(I + K D + G U B)⁻¹ ((K U + G U P) x + C_z w)``: an ordinary eigenproblem
    in ``(x, w)``.

    Returns (the loop matrix, its descriptor matrix or None, the :class:`_LowRank` form or None)."""
    damping = np.diag([require_range("contact.friction_damping", float(c), None, None, unit="N s/m")
                       for c in friction_damping] + [0.0])
    stiff = k_n * np.outer(d, np.array([0.0, 0.0, 1.0]))
    gain = damping.copy()
    if relaxation is not None and any(creep):
        a_z, b_z, c_z = _relaxation_states(stiff, creep, speed, relaxation)
    else:
        for j, c in enumerate(creep):
            gain[j, j] += c / speed
        a_z, b_z, c_z = np.zeros((0, 0)), np.zeros((0, 3)), np.zeros((3, 0))
    nz = a_z.shape[0]
    creep_gain = gain - damping  # C: the unrelaxed creep force's, whose D Ḟ is kept as _loop keeps it
    e22 = creep_gain @ direct
    n = p.shape[0]
    if np.any(e22):  # no relaxation: the descriptor loop of _loop with the damping added
        a = np.block([[p, b], [-(stiff @ u + gain @ (u @ p)), -(np.eye(3) + stiff @ direct + gain @ (u @ b))]])
        e = np.zeros((n + 3, n + 3))
        e[:n, :n] = np.eye(n)
        e[n:, n:] = e22
        return a, e, None
    m = np.eye(3) + stiff @ direct + gain @ (u @ b)
    f_x = -np.linalg.solve(m, stiff @ u + gain @ (u @ p))  # F = f_x x + f_z w
    f_z = -np.linalg.solve(m, c_z)
    a = _blocks([[p + b @ f_x, b @ f_z], [b_z @ (u + direct @ f_x), a_z + b_z @ direct @ f_z]])
    left = np.block([[b, np.zeros((n, 3))], [b_z @ direct, b_z]])  # as in _relaxed_loop
    right = np.block([[f_x, f_z], [u, np.zeros((3, nz))]])
    return a, None, _LowRank(_block_diag(p, a_z), left, right)


def _relaxation_states(stiff, creep, speed, relaxation):
    """The relaxation of the creep force as states (:func:`_relaxed_loop` derives it): per
    tangential direction j with creep stiffness ``creep[j]`` its direct part ``c_j b / a2`` is added
    to ``stiff[j, j]`` (in place) and its strictly proper remainder realised by two states.

    Returns ``(a_z, b_z, c_z)``: the states' matrix, their input from the relative displacement
    and their force output."""
    blocks = []
    for j, c in enumerate(creep):
        if not c:
            continue
        b_j, a1, a2 = np.asarray(relaxation, float)[j]
        if a2 <= 0.0:
            raise InputError("contact.relaxation", f"a2 must be > 0 m^2, got {a2!r}")
        stiff[j, j] += c * b_j / a2
        r1, r0 = 1.0 - b_j * a1 / a2, -b_j / a2
        a_f = np.array([[0.0, 1.0], [-speed**2 / a2, -a1 * speed / a2]])
        c_f = c * np.array([r0 * speed**2 / a2, r1 * speed / a2])
        blocks.append((j, a_f, c_f))
    nz = 2 * len(blocks)
    a_z = np.zeros((nz, nz))
    b_z = np.zeros((nz, 3))
    c_z = np.zeros((3, nz))
    for i, (j, a_f, c_f) in enumerate(blocks):
        a_z[2 * i:2 * i + 2, 2 * i:2 * i + 2] = a_f
        b_z[2 * i + 1, j] = 1.0
        c_z[j, 2 * i:2 * i + 2] = c_f
    return a_z, b_z, c_z


def _relaxed_loop(p, u, b, direct, k_n, d, creep, speed, relaxation):
    r"""The loop matrix when the creep force acts through the relaxation.

    Per tangential direction j with creep stiffness c_j, the force per unit relative
    displacement is ``W_j(s) = c_j τ (1 + b τ) / (1 + a1 τ + a2 τ²)`` with ``τ = s / v``
    (creepage ``γ = τ Δu``), split into its direct part ``c_j b / a2`` (the contact's tangential
    stiffness: the high-frequency limit) and a strictly proper remainder
    ``c_j (r1 τ + r0) / (a2 τ² + a1 τ + 1)``, ``r1 = 1 - b a1 / a2``, ``r0 = -b / a2``, realised by
    two states w_j (controllable form, input Δu_j). With ``K = k_n d e_zᵀ + diag(k_tx, k_ty, 0)``
    and the remainders' outputs ``C_z w``, the force ``F = -K Δu - C_z w`` and
    ``Δu = U x + D F`` give ``F = -(I + K D)^{-1} (K U x + C_z w)``: an ordinary eigenproblem in
    ``(x, w)`` (the structure's states first).

    Returns (the loop matrix, None (no descriptor matrix), its :class:`_LowRank` form)."""
    e_z = np.array([0.0, 0.0, 1.0])
    stiff = k_n * np.outer(d, e_z)
    a_z, b_z, c_z = _relaxation_states(stiff, creep, speed, relaxation)
    nz = a_z.shape[0]
    m_inv = np.linalg.inv(np.eye(3) + stiff @ direct)
    f_x = -m_inv @ stiff @ u  # F = f_x x + f_z w
    f_z = -m_inv @ c_z
    a = _blocks([[p + b @ f_x, b @ f_z], [b_z @ (u + direct @ f_x), a_z + b_z @ direct @ f_z]])
    # the same matrix as blockdiag(P, A_z) + L Rᵀ: the force F = [f_x, f_z] z enters through
    # [B; B_z D], the structure's displacement U x through [0; B_z]
    n = p.shape[0]
    left = np.block([[b, np.zeros((n, 3))], [b_z @ direct, b_z]])
    right = np.block([[f_x, f_z], [u, np.zeros((3, nz))]])
    return a, None, _LowRank(_block_diag(p, a_z), left, right)


def closed_loop_eigenvalues(*args, **kwargs):
    """The eigenvalues λ (1/s) of :func:`closed_loop_eigen` (same arguments)."""
    return closed_loop_eigen(*args, **kwargs)[0]


def growing_poles_with_rail(wheel_poles, wheel_residues, rail: RationalModel, normal_stiffness,
                            sliding_coefficient=0.0, creep_stiffness=(0.0, 0.0), speed=None,
                            min_share=0.1, relaxation=None):
    """The growing poles of the wheel-contact-rail loop, fastest first.

    Parameters are those of :func:`closed_loop_eigen`; ``min_share`` (-) is the smallest
    participation of a wheel mode that is listed.

    Returns
    -------
    list of dict
        Per growing pole (``Re λ > 0``, ``Im λ >= 0``): ``frequency`` (Hz, ``Im λ / 2π``),
        ``growth_rate`` (1/s, ``Re λ``), ``eigenvalue`` (complex, 1/s), ``wheel_modes`` (indices
        into ``wheel_poles``, largest participation first, those with at least ``min_share``),
        ``participation`` (their shares, -), ``in_band`` (False when ``|λ| / 2π`` lies above the
        rail model's fitted band, where the rail is an extrapolation and the pole may be an
        artefact of the fit).
    """
    lam, part = closed_loop_eigen(wheel_poles, wheel_residues, rail, normal_stiffness,
                                  sliding_coefficient, creep_stiffness, speed, relaxation=relaxation)
    return _poles(lam, part, rail, min_share, lam.real > 0)


def _poles(lam, part, rail, min_share, selected):
    """The pole dicts of :func:`growing_poles_with_rail` for the eigenvalues ``selected`` with
    ``Im λ >= 0``, fastest growth first (``part[i]``: the wheel modes' shares in pole i)."""
    out = []
    for i in np.flatnonzero(selected & (lam.imag >= 0)):
        row = part[i]
        # largest share first; shares equal to SHARE_TIE (the two modes of a degenerate pair in a pole
        # that the contact leaves in place) in the order of the modes, not of rounding
        order = np.lexsort((np.arange(row.size), -np.round(row / SHARE_TIE)))
        order = [int(k) for k in order if row[k] >= min_share]
        out.append({"frequency": float(lam[i].imag / (2 * np.pi)), "growth_rate": float(lam[i].real),
                    "eigenvalue": complex(lam[i]), "wheel_modes": order,
                    "participation": [float(row[k]) for k in order],
                    "in_band": bool(rail.band is None or abs(lam[i]) / (2 * np.pi) <= rail.band[1])})
    out.sort(key=lambda d: -d["growth_rate"])
    return out


class _Participation:
    """The wheel modes' shares in eigenvalue i of the loop, ``self[i]``, from its eigenvector
    by :data:`INVERSE_ITERATION_STEPS` steps of inverse iteration on one LU per pole asked for
    (instead of all eigenvectors): the descriptor loop's path (an ordinary loop takes
    :class:`_NullVectorParticipation`, exact and of cost O(n) instead of O(n³)). One step is not enough: the loop matrix is badly scaled
    (norm ~1e17 with the contact stiffness), and after one step a mode with a large output
    (e.g. a longitudinal mode at 576 Hz) could still dominate the shares of a 203 Hz pole."""

    def __init__(self, a, e, lam, uw, owner, m):
        self.a, self.e, self.lam, self.uw, self.owner, self.m = a, e, lam, uw, owner, m
        self.start = np.random.default_rng(0).normal(size=a.shape[0])

    def __getitem__(self, i):
        lam = self.lam[i]
        shift = lam + 1e-9 * abs(lam) * (1 + 1j)  # off the eigenvalue: a regular, ill-conditioned solve
        e = np.eye(self.a.shape[0]) if self.e is None else self.e
        lu = scipy.linalg.lu_factor(self.a - shift * e, check_finite=False)
        x = self.start.astype(complex)
        for _ in range(INVERSE_ITERATION_STEPS):
            x = scipy.linalg.lu_solve(lu, e @ x, check_finite=False)
            x /= np.linalg.norm(x)
        return _participation(x[:, None], self.uw, self.owner, self.m)[0]


class _LowRank:
    r"""The loop matrix as ``A = P + L Rᵀ``: ``P`` block diagonal with 1×1 and 2×2 blocks (the
    open-loop states: the structures' pole pairs, the relaxation filters), ``L`` (n, k) and
    ``Rᵀ`` (k, n) the contact's coupling, k = 3 or 6.

    An eigenvector for the eigenvalue λ follows from the k×k contact matrix: with ``c = Rᵀ x``,
    ``(λ I - P) x = L c`` gives ``x = (λ I - P)^{-1} L c`` and ``(I - Rᵀ (λ I - P)^{-1} L) c = 0``,
    c its null vector (the right singular vector of its smallest singular value). P's blocks
    make ``(λ I - P)^{-1} L`` a cost of order n k instead of the dense LU's n³."""

    def __init__(self, p, left, right):
        # the columns of L and rows of Rᵀ balanced (L D⁻¹, D Rᵀ: the same product): the contact
        # gains are ~1e15 beside displacements of ~1e-3, and unbalanced, the contact matrix's
        # null vector carried errors of 1e-8 in the shares of a real growing pole
        norm_l, norm_r = np.linalg.norm(left, axis=0), np.linalg.norm(right, axis=1)
        scale = np.ones(norm_l.size)
        used = (norm_l > 0) & (norm_r > 0)
        scale[used] = np.sqrt(norm_l[used] / norm_r[used])
        self.left, self.right = left / scale, right * scale[:, None]
        n = p.shape[0]
        self.diag = np.diag(p).copy()
        upper, lower = np.diag(p, 1), np.diag(p, -1)
        coupled = (upper != 0) | (lower != 0)  # states i, i+1 form a 2×2 block
        self.first = np.flatnonzero(coupled)
        if np.any(coupled[:-1] & coupled[1:]) or np.count_nonzero(p) > n + 2 * self.first.size:
            raise ValueError("the open-loop matrix is not block diagonal with 1x1 and 2x2 blocks")
        self.upper, self.lower = upper[self.first], lower[self.first]

    def solve(self, lam, rhs):
        """``(λ I - P)^{-1} rhs`` for a complex λ (1/s) and rhs (n, k)."""
        x = rhs / (lam - self.diag)[:, None]
        i, j = self.first, self.first + 1
        a, d = lam - self.diag[i], lam - self.diag[j]
        b, c = -self.upper, -self.lower  # the block of λ I - P: [[a, b], [c, d]]
        det = a * d - b * c
        x[i] = (d[:, None] * rhs[i] - b[:, None] * rhs[j]) / det[:, None]
        x[j] = (a[:, None] * rhs[j] - c[:, None] * rhs[i]) / det[:, None]
        return x

    def eigenvector(self, lam):
        """The right eigenvector (n,) of A for its eigenvalue λ (any scale)."""
        with np.errstate(divide="ignore", invalid="ignore"):
            resolvent_l = self.solve(lam, self.left.astype(complex))  # (n, k)
        if not np.all(np.isfinite(resolvent_l)):
            # λ is exactly an open-loop pole that the contact leaves in place (the structured
            # eigenvalues give it exactly): its eigenvector lies in that pole's states, the
            # limit of the null vector's construction as λ → the pole
            resolvent_l = self.solve(lam + 1e-12 * abs(lam) * (1 + 1j), self.left.astype(complex))
        contact = np.eye(self.left.shape[1]) - self.right @ resolvent_l
        null = np.linalg.svd(contact)[2][-1].conj()
        return resolvent_l @ null


class _NullVectorParticipation:
    """The wheel modes' shares in eigenvalue i of the loop, ``self[i]``, from its eigenvector
    built by :meth:`_LowRank.eigenvector` (the exact eigenvector: no iteration)."""

    def __init__(self, low_rank, lam, uw, owner, m):
        self.low_rank, self.lam, self.uw, self.owner, self.m = low_rank, lam, uw, owner, m

    def __getitem__(self, i):
        x = self.low_rank.eigenvector(self.lam[i])
        return _participation(x[:, None], self.uw, self.owner, self.m)[0]


#: relative tolerance (of |λ|) within which two poles' growth rates tie for the margin pole
MARGIN_TIE = 1e-10
#: wheel-mode shares (-) equal to this much are listed in the order of the modes
SHARE_TIE = 1e-6

#: steps of inverse iteration for a pole's wheel-mode shares (3: converged to the full
#: eigenvector's shares to 1e-3 on the default study, where 1 step named the wrong mode)
INVERSE_ITERATION_STEPS = 3


class _NoParticipation:
    """No wheel-mode shares (every pole's ``wheel_modes`` empty): for callers that need the
    eigenvalues only, which then skip the eigenvector per pole."""

    def __init__(self, m):
        self.m = m

    def __getitem__(self, i):
        return np.zeros(self.m)


def screen(wheel_poles, wheel_residues, rail: RationalModel, contact: LinearisedContact, speed, min_share=0.1,
           pole_modes=True, structured=True):
    """The linear stability screen of one wheel model in one operating state.

    Parameters
    ----------
    wheel_poles, wheel_residues
        As :func:`closed_loop_eigen`.
    rail : RationalModel
    contact : LinearisedContact
    speed : float
        m/s.
    min_share : float
        Smallest wheel-mode participation listed, -.
    pole_modes : bool
        Whether the growing poles get their wheel modes (each from the null vector of the
        contact matrix, :class:`_LowRank`, or, for a descriptor loop, by inverse iteration); the
        margin pole always does. False: their ``wheel_modes`` and ``participation`` are empty.
    structured : bool
        Whether an ordinary loop's eigenvalues are the roots of its contact determinant
        (:func:`_structured_eigenvalues`, checked, the dense eigenvalues where a check fails)
        instead of the dense eigenvalues (LAPACK's QR) alone; the same eigenvalues to rounding.

    Returns
    -------
    dict
        ``poles``: the growing poles in the rail model's band (dicts of
        :func:`growing_poles_with_rail`), fastest first; ``margin``: the largest ``Re λ`` (1/s)
        of the oscillating (``Im λ > 0``) in-band eigenvalues, the growth rate when it is
        positive, the decay rate of the least damped pole otherwise (of poles whose ``Re λ``
        ties to :data:`MARGIN_TIE` |λ|, the lowest in frequency); ``margin_frequency`` (Hz)
        ``margin_modes`` (wheel modes of that pole) and ``margin_shares`` (their shares, -);
        ``out_of_band``: growing poles above the band (not counted).
    """
    a, e, low_rank, uw, owner = _loop(wheel_poles, wheel_residues, rail, contact.normal_stiffness,
                                      contact.sliding_coefficient, contact.creep_stiffness, speed, None,
                                      contact.relaxation, contact.friction_damping)
    m = np.asarray(wheel_poles).size
    if low_rank is None:  # the descriptor loop: inverse iteration on the pencil
        lam, _ = _eig(a.copy(), e, False)
        part = _Participation(a, e, lam, uw, owner, m)
    else:
        lam = _structured_eigenvalues(low_rank) if structured else None
        if lam is None:
            lam, _ = _eig(a, e, False)  # a is overwritten
        part = _NullVectorParticipation(low_rank, lam, uw, owner, m)
    in_band = np.ones(lam.size, bool) if rail.band is None else np.abs(lam) / (2 * np.pi) <= rail.band[1]
    oscillating = in_band & (lam.imag > 0)
    poles = _poles(lam, part if pole_modes else _NoParticipation(m), rail, min_share, (lam.real > 0) & in_band)
    out_of_band = int(np.count_nonzero((lam.real > 0) & ~in_band & (lam.imag >= 0)))
    if not np.any(oscillating):
        return {"poles": poles, "margin": float("-inf"), "margin_frequency": float("nan"), "margin_modes": [],
                "margin_shares": [], "out_of_band": out_of_band}
    # the margin pole: the largest Re λ; poles whose Re λ ties with it to MARGIN_TIE |λ| (open-loop
    # poles that the contact leaves in place, e.g. the moving-load model's n Ω-shifted copies of one
    # mode, all of one damping) are told apart by frequency, the lowest taken, not by rounding
    candidates = np.flatnonzero(oscillating)
    top_re = lam.real[candidates].max()
    tied = candidates[lam.real[candidates] >= top_re - MARGIN_TIE * np.abs(lam[candidates])]
    i = tied[np.argmin(lam.imag[tied])]
    top = _poles(lam, part, rail, min_share, np.arange(lam.size) == i)[0]
    return {"poles": poles, "margin": top["growth_rate"], "margin_frequency": top["frequency"],
            "margin_modes": top["wheel_modes"], "margin_shares": top["participation"], "out_of_band": out_of_band}
