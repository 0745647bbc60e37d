"""Numba kernels of the waveguide package (compiled lazily, on first call)."""

from __future__ import annotations

import numba


@numba.njit(cache=True)
def accumulate_wave_series(z, amp, n_steps, cutoff, out):
    """Add ``Re sum_p amp[p] z[p]**m`` to ``out[m]`` for m = 0 .. n_steps - 1.

    Parameters
    ----------
    z : complex128 (P,)
        Per-step factors (|z| <= 1 for decaying terms).
    amp : complex128 (P, 9)
        Amplitudes of the 3x3 components.
    n_steps : int
    cutoff : float
        A term is dropped once |amp| |z|^m falls below ``cutoff``.
    out : float64 (n_steps, 9)
        Accumulator (modified in place).
    """
    for p in range(z.shape[0]):
        zp = z[p]
        a0 = 0.0
        for c in range(9):
            a0 = max(a0, abs(amp[p, c]))
        if a0 == 0.0:
            continue
        cur = 1.0 + 0.0j
        mag = a0
        for m in range(n_steps):
            for c in range(9):
                out[m, c] += (amp[p, c] * cur).real
            cur *= zp
            if (m & 15) == 15:
                mag = a0 * abs(cur)
                if mag < cutoff:
                    break
    return out
