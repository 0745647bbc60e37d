"""Small compiled helpers of the contact solvers and the interaction's time loops (compiled lazily, cached on disk).

:func:`inner_product` (an inner product that runs in vector registers), :func:`cholesky_solve`
(a small symmetric positive definite system, in place: the Anderson mixing's least squares and
the interaction's force predictor), and :func:`compiled_entry`, a compiled kernel's entry point
without numba's dispatch. Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba



def compiled_entry(kernel, *example):
    """The compiled function of ``kernel`` for the argument types of ``example``, without numba's dispatch.

    Calls ``kernel(*example)`` once (compiling it, or loading it from the cache) and returns the
    compiled entry point of that signature. A call through it skips the typing of the arguments
    that the dispatcher does on every call (its cost: docs/benchmarks.md, *Notes*); it must be
    called with arguments of the same types.
    """
    kernel(*example)
    return kernel.get_overload(tuple(numba.typeof(a) for a in example))


@numba.njit(cache=True, fastmath={"reassoc"})
def inner_product(a, b, length):
    """Inner product of the first ``length`` entries of ``a`` and ``b``.

    Compiled with reassociation allowed (numba ``fastmath={"reassoc"}``, nothing else relaxed), so
    that the sum runs in vector registers, where a strict left-to-right sum waits on every
    addition (docs/benchmarks.md, *The half-space time loop*, gives the gain for the few hundred
    to tens of thousands of entries of the Anderson mixing's inner products and the rail's
    convolution). The order of the additions is
    then the compiler's, for the machine's vector width: results agree with the strict sum to
    round-off, and may differ between machines by round-off.
    """
    total = 0.0
    for i in range(length):
        total += a[i] * b[i]
    return total


@numba.njit(cache=True)
def cholesky_solve(g, rhs, count):
    """Solve ``G x = rhs`` in place for a symmetric positive definite ``G`` (its lower triangle).

    The leading ``count`` × ``count`` block of ``g`` is overwritten by its Cholesky factor L
    (lower triangle, row by row) and ``rhs[:count]`` by the solution (forward, then backward
    substitution). Returns False, with ``g`` and ``rhs`` partly overwritten, if a pivot is not
    positive (G not positive definite to round-off). Shared by the Anderson mixing of the contact
    solvers and the force predictor of the interaction's half-space loop.
    """
    for a in range(count):
        for b in range(a + 1):
            acc = g[a, b]
            for c in range(b):
                acc -= g[a, c] * g[b, c]
            if a == b:
                if acc <= 0.0:
                    return False
                g[a, a] = math.sqrt(acc)
            else:
                g[a, b] = acc / g[b, b]
    for a in range(count):
        acc = rhs[a]
        for c in range(a):
            acc -= g[a, c] * rhs[c]
        rhs[a] = acc / g[a, a]
    for a in range(count - 1, -1, -1):
        acc = rhs[a]
        for c in range(a + 1, count):
            acc -= g[c, a] * rhs[c]
        rhs[a] = acc / g[a, a]
    return True
