"""Wheel and rail at the contact point as discrete-time linear systems.

Both are driven by the force deviation ``ΔF[n] = F[n] - F_static`` (3,) in the contact frame and
return their displacement deviation at the contact point (m). Displacement samples follow the
ramp-invariant discretisation of docs/design.md §3, ``u[n] = Σ_m k[m] ΔF[n-m]``, which splits into the
instantaneous part ``k[0] ΔF[n]`` and a history that depends on earlier forces only:

- :class:`ModalStructure` evaluates the history by the exact per-pole recursion of
  :func:`fe.greens.recursion_coefficients` (any pole-residue model: every wheel model);
- :class:`ConvolutionStructure` evaluates it by direct convolution with a stored kernel (the
  rail's moving kernel; also usable for the wheel, as a check of the recursion).

A structure is used in three calls per step: ``history()`` before the contact problem,
``displacement(history, dF)`` while iterating on the coupling, and ``commit(dF)`` once the step's
force is known. :func:`compiled_structures` gives a wheel recursion and a rail convolution as
the bundle of the compiled time loops (contact/*/loop.py).
"""

from __future__ import annotations

import numpy as np

from fe.greens import recursion_coefficients
from interaction.bundles import Structures


class ModalStructure:
    """A pole-residue system advanced by exact recursion.

    Parameters
    ----------
    poles : (m,) complex array_like
        rad/s.
    residues : (m, 3, 3) complex array_like
        m/(N s), pole-residue form of fe/greens.py.
    time_step : float
        s.
    """

    def __init__(self, poles, residues, time_step):
        self.z, self.weights, self.k0 = recursion_coefficients(poles, residues, time_step)
        self.state = np.zeros((len(self.z), 3), dtype=complex)
        self.time_step = float(time_step)

    def history(self):
        """Displacement (3,) at the current step due to all earlier forces, m."""
        return 2.0 * np.real(np.einsum("mij,mj->i", self.weights, self.state))

    def displacement(self, history, force_deviation):
        """Total displacement deviation (3,) for a trial force deviation, m."""
        return history + self.k0 @ force_deviation

    def commit(self, force_deviation):
        """Advance one step with the force deviation of the step just solved."""
        self.state = self.z[:, None] * (self.state + np.asarray(force_deviation)[None, :])


class ConvolutionStructure:
    """A system given by a discrete kernel, advanced by direct convolution.

    Parameters
    ----------
    kernel : (nk, 3, 3) array_like
        m/N, ``u[n] = Σ_m k[m] ΔF[n-m]``; forces older than ``nk - 1`` steps are forgotten.
    time_step : float
        s.
    """

    def __init__(self, kernel, time_step):
        kernel = np.asarray(kernel, dtype=float)
        self.k0 = kernel[0].copy()
        # tail[m - 1] = k[m]; forces stored newest first in a buffer of the same length
        self.tail = kernel[1:].copy()
        self.buffer = np.zeros((len(self.tail), 3))
        self.time_step = float(time_step)

    def history(self):
        """Displacement (3,) at the current step due to all earlier forces, m."""
        return np.einsum("mij,mj->i", self.tail, self.buffer)

    def displacement(self, history, force_deviation):
        """Total displacement deviation (3,) for a trial force deviation, m."""
        return history + self.k0 @ force_deviation

    def commit(self, force_deviation):
        """Advance one step with the force deviation of the step just solved."""
        if len(self.buffer):
            self.buffer = np.roll(self.buffer, 1, axis=0)
            self.buffer[0] = force_deviation


def rail_rows(tail):
    """The rail kernel ``tail`` (nk, 3, 3), m/N, as the compiled loops' rows (3, 3 nk): ``[i, 3 q + j] = tail[q, i, j]``."""
    tail = np.asarray(tail, dtype=float)
    return np.ascontiguousarray(tail.transpose(1, 0, 2).reshape(3, 3 * tail.shape[0]))


RAIL_NEAR_STEPS = 512
"""Samples of the rail kernel (after the instantaneous one) that the compiled loops sum directly
each step; the rest, the far part, is summed by FFT once per block of as many steps
(:class:`RailFarField`). The direct sum costs ~9 multiply-adds per sample and step, a block's
FFTs (length >= the kernel's) about as much as 500 samples' direct sums for the default rail."""


class RailFarField:
    """The rail's displacement due to forces older than its near kernel, a block of steps at a time.

    With ``B`` near samples (:data:`RAIL_NEAR_STEPS`), the displacement at step ``n`` due to the
    kernel samples ``q > B``, ``sum_{q > B} k[q] dF[n - q]``, needs only forces before ``n - B``:
    for the ``B`` steps of the block ``[m, m + B)`` it depends on forces before ``m`` only, so it
    is one linear convolution of the far kernel with the last ``nk`` forces, taken by FFT
    (overlap-save: a circular convolution of length ``L >= nk`` is exact at the block's
    outputs). Round-off: that of the FFT, ~1e-15 of the displacement.

    Parameters
    ----------
    tail : (nk, 3, 3) ndarray
        The rail kernel's samples 1..nk (m/N), as :attr:`ConvolutionStructure.tail`.
    near : int
        Samples summed directly (B); the far part holds the rest (may be empty).
    """

    def __init__(self, tail, near=RAIL_NEAR_STEPS):
        tail = np.asarray(tail, dtype=float)
        self.near = int(near)
        self.size = tail.shape[0]
        far = tail[self.near:]  # g[r] = k[B + 1 + r]
        self.active = far.shape[0] > 0
        if self.active:
            self.length = 1 << int(np.ceil(np.log2(self.size)))  # L >= nk: no alias at the outputs
            self.spectrum = np.fft.rfft(far.transpose(1, 2, 0), self.length, axis=-1)  # (3, 3, L/2 + 1)

    def fill(self, force, load, start, state):
        """Put the far part of the rail's displacement for the steps ``[start, start + B)`` into ``state.far``.

        Parameters
        ----------
        force : (nt, 3) ndarray
            Forces of the run so far (N); those before ``start`` are used.
        load : float
            Static load Q (N): the force deviations are ``force - (0, 0, Q)``, zero before step 0.
        start : int
            First step of the block (a multiple of B).
        state : LoopState
            Receives ``far`` and ``far_start``.
        """
        state.far_start[0] = start
        if not self.active:
            return
        nk, b = self.size, self.near
        segment = np.zeros((nk, 3))  # deviations at the steps start - nk .. start - 1
        first = start - nk
        lo = max(first, 0)
        if start > lo:
            segment[lo - first:] = force[lo:start]
            segment[lo - first:, 2] -= load
        spectrum = np.fft.rfft(segment.T, self.length, axis=-1)  # (3, L/2 + 1)
        product = np.einsum("ijf,jf->if", self.spectrum, spectrum)
        # u[start + t] = c[t + nk - B - 1], c the linear convolution of g and the segment
        state.far[:, :] = np.fft.irfft(product, self.length, axis=-1)[:, nk - b - 1:nk - 1].T


def compiled_structures(wheel, rail) -> Structures | None:
    """The bundle of the compiled time loops for a :class:`ModalStructure` wheel and a :class:`ConvolutionStructure` rail.

    Returns None for other combinations (the interaction then runs its Python loop). Raises
    ValueError if either structure has already been advanced (the compiled loops start from rest).
    """
    if type(wheel) is not ModalStructure or type(rail) is not ConvolutionStructure:
        return None
    if np.any(wheel.state != 0) or np.any(rail.buffer != 0):
        raise ValueError("the compiled loop starts from rest: structures must be fresh")
    return Structures(np.ascontiguousarray(wheel.z), np.ascontiguousarray(wheel.weights),
                      np.ascontiguousarray(wheel.k0), rail_rows(rail.tail[:RAIL_NEAR_STEPS]),
                      np.ascontiguousarray(rail.k0))
