"""Modal solution of K phi = omega^2 M phi: all modes up to a frequency, with a completeness check.

Method
------
1. Sturm count: the number n of eigenvalues below omega_max^2 = (2 pi f_max)^2 equals the
   number of negative pivots of an LDL^T factorisation of K - omega_max^2 M (Sylvester's law of
   inertia). SuperLU is used with a symmetric fill-reducing ordering (by default our own nested
   dissection, see :func:`nested_dissection`), diagonal pivoting only and
   ``SymmetricMode``; the count is only accepted if no off-diagonal pivoting happened
   (``perm_r == perm_c``), so that ``P A P^T = L U`` with ``U = D L^T``.
2. Shift-invert Lanczos (ARPACK through ``scipy.sparse.linalg.eigsh``) about a shift below the
   band (negative by default, so that a singular K of a free structure is fine), with the
   factorisation of K - sigma M computed once and passed as ``OPinv``; n plus a few guard modes
   are requested.
3. Check: the number of returned eigenvalues below omega_max^2 must equal n and the returned
   vectors must be M-orthonormal (so they span the whole n-dimensional invariant subspace);
   otherwise one retry with a larger Krylov space, then ``RuntimeError``.
"""

from __future__ import annotations

import logging
import time

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from scipy.sparse import csgraph

from squealcore.errors import require_range

logger = logging.getLogger(__name__)

#: Problems at most this size are solved densely (scipy.linalg.eigh) instead of by Lanczos.
DENSE_LIMIT = 600


def _supervariables(a):
    """Group consecutive rows with the same sparsity pattern (e.g. the 3 DOFs of a node).

    Returns the group index of each row and the number of groups. Rows are compared by
    (nnz, first, last, sum of column indices); a rare false match only affects the quality of
    the ordering, never its validity.
    """
    a = sp.csr_matrix(a)
    a.sort_indices()
    nnz = np.diff(a.indptr)
    if np.any(nnz == 0):
        raise RuntimeError("matrix has an empty row (a DOF without stiffness or mass)")
    key = np.column_stack([nnz, a.indices[a.indptr[:-1]], a.indices[a.indptr[1:] - 1],
                           np.add.reduceat(a.indices.astype(np.int64), a.indptr[:-1])])
    new = np.ones(a.shape[0], dtype=bool)
    new[1:] = np.any(key[1:] != key[:-1], axis=1)
    return np.cumsum(new) - 1, int(new.sum())


def _bfs_levels(graph, start):
    return csgraph.shortest_path(graph, method="D", unweighted=True, indices=start).astype(np.int64)


def nested_dissection(a, leaf_size=64):
    """Fill-reducing symmetric ordering by recursive graph bisection with level-set separators.

    The graph of ``a`` is compressed to supervariables (nodes), each part is split at the
    median level of a breadth-first search from a pseudo-peripheral vertex, the separator is
    thinned to the vertices of that level touching the next one, and separators are numbered
    after both halves.

    Parameters
    ----------
    a : scipy.sparse matrix, shape (n, n)
        Matrix with a symmetric sparsity pattern.
    leaf_size : int, optional
        Parts with at most this many supervariables are not split further.

    Returns
    -------
    ndarray of int64, shape (n,)
        Permutation p: the reordered matrix is ``a[p][:, p]``.
    """
    group, ng = _supervariables(a)
    n = a.shape[0]
    compress = sp.csr_matrix((np.ones(n), (group, np.arange(n))), shape=(ng, n))
    a = sp.csr_matrix(a)
    pattern = sp.csr_matrix((np.ones(a.nnz), a.indices, a.indptr), shape=a.shape)
    graph = (compress @ pattern @ compress.T).tocsr()
    graph.setdiag(0)
    graph.eliminate_zeros()
    parts = []
    stack = [("split", np.arange(ng))]
    while stack:
        action, vs = stack.pop()
        if action == "emit" or vs.size <= leaf_size:
            parts.append(vs)
            continue
        sub = graph[vs][:, vs]
        ncomp, label = csgraph.connected_components(sub, directed=False)
        if ncomp > 1:
            stack.extend(("split", vs[label == c]) for c in range(ncomp - 1, -1, -1))
            continue
        d = _bfs_levels(sub, 0)
        d = _bfs_levels(sub, int(np.argmax(d)))
        d = _bfs_levels(sub, int(np.argmax(d)))
        depth = int(d.max())
        if depth == 0:  # every vertex adjacent to the start: nothing to separate
            parts.append(vs)
            continue
        # the median level, but never the last one: the separator must touch a next level,
        # otherwise one side would be the whole part and the split would never end
        lev = min(int(np.searchsorted(np.cumsum(np.bincount(d)), vs.size / 2)), depth - 1)
        on_level = d == lev
        touches_next = (sub @ (d == lev + 1).astype(float)) > 0
        sep = on_level & touches_next
        stack.append(("emit", vs[sep]))
        stack.append(("split", vs[d > lev]))
        stack.append(("split", vs[(d < lev) | (on_level & ~touches_next)]))
    node_perm = np.concatenate(parts)
    rows_by_group = np.argsort(group, kind="stable")
    starts = np.searchsorted(group[rows_by_group], node_perm)
    sizes = np.bincount(group, minlength=ng)[node_perm]
    take = np.repeat(starts - np.cumsum(sizes) + sizes, sizes) + np.arange(sizes.sum())
    return rows_by_group[take]


class ShiftedFactor:
    """LDL^T-type factorisation of K - sigma M by SuperLU with diagonal pivoting only.

    Parameters
    ----------
    K, M : scipy.sparse matrix, shape (n, n)
        Symmetric stiffness (N/m) and mass (kg) matrices.
    sigma : float
        Shift in rad^2/s^2.
    ordering : str, optional
        ``"ND"`` (default): :func:`nested_dissection`, then SuperLU with its natural order;
        or a SuperLU symmetric ordering name (``"MMD_AT_PLUS_A"``, ``"NATURAL"``).
    """

    def __init__(self, K, M, sigma, ordering="ND"):
        a = sp.csc_matrix(K - sigma * M)
        t0 = time.perf_counter()
        if ordering == "ND":
            self.perm = nested_dissection(a)
            a = a[self.perm][:, self.perm].tocsc()
            spec = "NATURAL"
        else:
            self.perm = None
            spec = ordering
        t1 = time.perf_counter()
        self.lu = spla.splu(a, permc_spec=spec, diag_pivot_thresh=0.0, options={"SymmetricMode": True})
        self.sigma = sigma
        self.n_solves = 0
        logger.info("factorised K - sigma M (sigma = %.4e rad^2/s^2, n = %d, ordering %s): "
                    "ordering %.2f s, factorisation %.2f s", sigma, a.shape[0], ordering,
                    t1 - t0, time.perf_counter() - t1)

    def solve(self, b):
        """Solve (K - sigma M) x = b for b of shape (n,) or (n, k)."""
        self.n_solves += 1 if b.ndim == 1 else b.shape[1]
        if self.perm is None:
            return self.lu.solve(b)
        y = self.lu.solve(np.ascontiguousarray(b[self.perm]))
        x = np.empty_like(y)
        x[self.perm] = y
        return x

    def negative_pivots(self):
        """Number of negative pivots, or None if off-diagonal pivoting occurred."""
        if not np.array_equal(self.lu.perm_r, self.lu.perm_c):
            return None
        return int(np.count_nonzero(np.real(self.lu.U.diagonal()) < 0.0))


def sturm_count(K, M, f, *, ordering="ND"):
    """Number of eigenvalues of K phi = omega^2 M phi with frequency below ``f``.

    Parameters
    ----------
    K, M : scipy.sparse matrix, shape (n, n)
        Symmetric stiffness (N/m) and positive definite mass (kg) matrices.
    f : float
        Frequency in Hz (> 0).
    ordering : str, optional
        Fill-reducing ordering, see :class:`ShiftedFactor`.

    Returns
    -------
    int
        Number of eigenvalues omega^2 < (2 pi f)^2 (counted with multiplicity).

    Raises
    ------
    RuntimeError
        If (2 pi f)^2 is an eigenvalue to working precision and slightly moved shifts do not
        give a factorisation without off-diagonal pivoting.
    """
    f = require_range("f", f, 0.0, None, low_open=True, unit="Hz")
    sigma = (2.0 * np.pi * f) ** 2
    K = sp.csc_matrix(K)
    M = sp.csc_matrix(M)
    # Nudges of 1e-10 relative only matter if sigma is (numerically) an eigenvalue.
    for nudge in (0.0, -1e-10, 1e-10):
        s = sigma * (1.0 + nudge)
        try:
            factor = ShiftedFactor(K, M, s, ordering)
        except RuntimeError as exc:  # exactly singular
            logger.debug("Sturm factorisation at %.6e failed (%s); nudging", s, exc)
            continue
        count = factor.negative_pivots()
        del factor
        if count is not None:
            return count
        logger.debug("Sturm factorisation at %.6e pivoted off the diagonal; nudging", s)
    raise RuntimeError(f"Sturm count at f = {f} Hz failed: the shift coincides with an eigenvalue")


def _dense_modes(K, M, lam_max):
    lam, phi = sla.eigh(K.toarray(), M.toarray())
    keep = lam < lam_max
    return lam[keep], phi[:, keep]


def _normalise(phi, M):
    """Scale columns to unit modal mass and return the orthonormality error."""
    mphi = M @ phi
    mm = np.real(np.einsum("ij,ij->j", phi.conj(), mphi))
    phi = phi / np.sqrt(mm)[None, :]
    gram = phi.conj().T @ (M @ phi)
    return phi, float(np.abs(gram - np.eye(gram.shape[0])).max()) if gram.size else 0.0


def solve_modes(K, M, f_max, *, shift=None, max_modes=None, tol=0.0, ordering="ND"):
    """All eigenmodes of K phi = omega^2 M phi with frequency up to ``f_max``.

    Parameters
    ----------
    K : scipy.sparse matrix, shape (n, n)
        Symmetric (or complex Hermitian, as in the cyclic-symmetry reduction of fe/cyclic.py)
        positive semi-definite stiffness matrix in N/m (may be singular, e.g. for a free
        structure with rigid-body modes).
    M : scipy.sparse matrix, shape (n, n)
        Symmetric positive definite mass matrix in kg.
    f_max : float
        Upper end of the frequency band in Hz (> 0).
    shift : float, optional
        Lanczos shift in Hz; a negative value means the negative eigenvalue shift
        ``-(2 pi |shift|)^2``. Default: ``-0.1 f_max`` (below all modes, so rigid-body modes
        of a singular K are fine).
    max_modes : int, optional
        Refuse to compute more than this many modes (raises ``RuntimeError`` if the Sturm count
        exceeds it); default unlimited.
    tol : float, optional
        ARPACK relative tolerance (0 = machine precision).
    ordering : str, optional
        Fill-reducing ordering of both factorisations, see :class:`ShiftedFactor`.

    Returns
    -------
    frequencies_hz : ndarray, shape (m,)
        Natural frequencies in Hz, ascending (rigid-body modes give ~0; tiny negative
        eigenvalues from round-off are returned as 0 Hz).
    shapes : ndarray, shape (n, m)
        Mode shapes normalised so that ``shapes.T @ M @ shapes = I`` (units m / sqrt(kg)).

    Raises
    ------
    RuntimeError
        If the number of modes found below f_max disagrees with the Sturm count, the shapes
        are not M-orthonormal, or the count exceeds ``max_modes``.
    """
    f_max = require_range("f_max", f_max, 0.0, None, low_open=True, unit="Hz")
    K = sp.csc_matrix(K)
    M = sp.csc_matrix(M)
    n = K.shape[0]
    lam_max = (2.0 * np.pi * f_max) ** 2
    t0 = time.perf_counter()
    count = sturm_count(K, M, f_max, ordering=ordering)
    logger.info("Sturm count: %d modes below %.1f Hz (n = %d DOFs, %.2f s)", count, f_max, n,
                time.perf_counter() - t0)
    if max_modes is not None and count > max_modes:
        raise RuntimeError(f"{count} modes below {f_max} Hz exceed max_modes = {max_modes}")
    if count == 0:
        return np.zeros(0), np.zeros((n, 0))

    if n <= DENSE_LIMIT or count + 4 >= n - 1:
        lam, phi = _dense_modes(K, M, lam_max)
    else:
        if shift is None:
            sigma = -((0.1 * 2.0 * np.pi * f_max) ** 2)
        else:
            shift = require_range("shift", shift, None, f_max, unit="Hz")
            sigma = np.sign(shift) * (2.0 * np.pi * shift) ** 2
        lam, phi = _lanczos(K, M, sigma, count, lam_max, tol, ordering)

    phi, err = _normalise(phi, M)
    logger.info("modes: %d in [0, %.1f] Hz, M-orthonormality error %.1e, total %.2f s",
                lam.size, f_max, err, time.perf_counter() - t0)
    if lam.size != count:
        raise RuntimeError(f"found {lam.size} modes below {f_max} Hz but the Sturm count is {count}")
    if err > 1e-6:
        raise RuntimeError(f"mode shapes are not M-orthonormal (error {err:.1e}): modes may be missing")
    freqs = np.sqrt(np.clip(lam, 0.0, None)) / (2.0 * np.pi)
    return freqs, phi


def _start_vector(n, dtype):
    """A fixed Lanczos start vector of length ``n`` (ARPACK's own random one differs from run to run,
    which rotates the basis of degenerate mode pairs and makes results irreproducible bit for bit)."""
    vector = np.random.default_rng(20131).standard_normal(n)
    return vector.astype(dtype) if np.dtype(dtype).kind == "c" else vector


def _lanczos(K, M, sigma, count, lam_max, tol, ordering):
    """Shift-invert Lanczos for the lowest ``count`` modes, with guard modes and one retry."""
    n = K.shape[0]
    factor = ShiftedFactor(K, M, sigma, ordering)
    opinv = spla.LinearOperator((n, n), matvec=factor.solve, matmat=factor.solve, dtype=K.dtype)
    guard = max(4, count // 20)
    for attempt in range(2):
        k = min(count + guard, n - 1)
        ncv = min(n, max(2 * k + 1, k + 40) * (attempt + 1))
        t1 = time.perf_counter()
        lam, phi = spla.eigsh(K, k=k, M=M, sigma=sigma, which="LM", OPinv=opinv, ncv=ncv, tol=tol,
                              v0=_start_vector(n, K.dtype))
        order = np.argsort(lam)
        lam, phi = lam[order], phi[:, order]
        found = int(np.count_nonzero(lam < lam_max))
        logger.info("Lanczos (k = %d, ncv = %d): %d modes below the band edge in %.2f s "
                    "(%d solves so far)", k, ncv, found, time.perf_counter() - t1, factor.n_solves)
        if found == count:
            return lam[:found], phi[:, :found]
        logger.warning("Lanczos found %d modes, Sturm count %d; retrying with more vectors", found, count)
    return lam[:found], phi[:, :found]
