"""Mean-square spectra of the limit cycle: one window at the end of a history, Hann-tapered.

Per bin the one-sided mean square is ``2 |X_k|² / (N² <w²>)`` (k ≥ 1) with X the FFT of the
tapered signal and <w²> the mean square of the Hann window, so that the bins sum to the mean
square of the signal (Parseval, exact for a stationary signal; tested).
"""

from __future__ import annotations

import numpy as np

from squealcore.errors import InputError


#: Fewest samples a spectrum window may hold.
MIN_WINDOW_SAMPLES = 16


def window_slice(n_samples, time_step, window):
    """The last ``window`` seconds of a history of ``n_samples`` samples, or the whole history
    when it is shorter (as L_F2 takes it, interaction/metrics.py).

    Raises
    ------
    InputError
        If the window (or the history) holds fewer than :data:`MIN_WINDOW_SAMPLES` samples.
    """
    n = min(round(window / time_step), n_samples)
    if n < MIN_WINDOW_SAMPLES:
        raise InputError("simulation.rms_window", f"must hold at least {MIN_WINDOW_SAMPLES} samples of "
                                                  f"{time_step} s (of a history of {n_samples}); {window} s holds "
                                                  f"{round(window / time_step)}")
    return slice(n_samples - n, n_samples)


def hann(n):
    """Periodic Hann window of n samples."""
    return 0.5 - 0.5 * np.cos(2.0 * np.pi * np.arange(n) / n)


def one_sided_spectrum(signal, time_step):
    """Frequencies (Hz) and complex one-sided amplitudes of the tapered signal(s) along the last axis.

    Returns
    -------
    frequency : (nf,) ndarray
        Hz, ``k / (N Δt)``, k = 0 .. N/2.
    amplitude : (..., nf) complex ndarray
        Scaled so that ``|amplitude|²`` is the mean square per bin (DC bin set to zero).
    """
    x = np.asarray(signal, dtype=float)
    n = x.shape[-1]
    w = hann(n)
    spectrum = np.fft.rfft((x - x.mean(axis=-1, keepdims=True)) * w, axis=-1)
    scale = np.sqrt(2.0 / (n**2 * np.mean(w**2)))
    amplitude = spectrum * scale
    amplitude[..., 0] = 0.0
    if n % 2 == 0:
        amplitude[..., -1] /= np.sqrt(2.0)
    return np.fft.rfftfreq(n, time_step), amplitude
