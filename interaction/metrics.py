r"""Squeal metrics of a lateral-force history (the paper's §4).

- Force level (the paper's Eq. 4.1–4.2): ``L_F2 = 20 log10(F2_rms / 1 N)`` with the rms of the
  transient part ``F2 - mean(F2)`` over the last ``window`` seconds of the signal.
- Squeal: ``L_F2`` above a threshold (dB re 1 N) *and* a limit cycle, i.e. the rms of the last
  window and of the window before it differ by less than ``limit_cycle_tolerance`` (the
  oscillation neither grows nor decays any more).
- Squeal frequency: the peak of the power spectrum of the transient part in the last window
  above ``min_frequency`` (default :data:`SQUEAL_MIN_FREQUENCY`, 100 Hz, below the first modes
  of railway wheels; Hann window, parabolic interpolation of the peak). Squeal is the tonal
  vibration of a wheel mode; slower content, such as the envelope of squeal bursts interrupted
  by lift-off, is not its frequency.
- Build-up time: the first time at which the running rms over ``0.01 s`` of the squeal tone
  reaches half its rms over the last window. The squeal tone is the force in a band around the
  squeal frequency (Gaussian, standard deviation ``band`` times that frequency, zero phase, after
  the moving average over one period of ``min_frequency`` has been removed): neither the rise of
  the creep force when the creepage is switched on nor the ringing of other wheel modes that
  this rise excites counts as build-up. The first ``2 / min_frequency`` seconds are skipped.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SQUEAL_MIN_FREQUENCY = 100.0
"""Lowest squeal frequency (Hz): below the first modes of railway wheels."""


@dataclass(frozen=True)
class SquealMetrics:
    """Metrics of one case.

    Attributes
    ----------
    L_F2 : float
        dB re 1 N.
    rms : float
        N.
    squeal : bool
    squeal_frequency : float
        Hz (NaN when the signal is constant).
    buildup_time : float
        s (NaN without squeal).
    growth : float
        rms of the last window over the rms of the window before it (-).
    """

    L_F2: float
    rms: float
    squeal: bool
    squeal_frequency: float
    buildup_time: float
    growth: float


def force_level(force, time_step, window):
    """``L_F2`` (dB re 1 N) and rms (N) of the transient part over the last ``window`` seconds."""
    n = max(int(round(window / time_step)), 1)
    tail = np.asarray(force[-n:], dtype=float)
    rms = float(np.sqrt(np.mean((tail - tail.mean()) ** 2)))
    return 20.0 * np.log10(max(rms, 1e-300)), rms


def dominant_frequency(signal, time_step, min_frequency=0.0):
    """Frequency (Hz) of the largest spectral peak above ``min_frequency`` (Hz) of a signal with
    its mean removed; NaN if there is no content there."""
    x = np.asarray(signal, dtype=float)
    x = (x - x.mean()) * np.hanning(x.size)
    spectrum = np.abs(np.fft.rfft(x)) ** 2
    first = max(1, int(np.ceil(min_frequency * x.size * time_step)))
    if first >= spectrum.size or spectrum[first:].max() <= 0:
        return float("nan")
    k = int(np.argmax(spectrum[first:])) + first
    shift = 0.0
    if 1 <= k < spectrum.size - 1:
        a, b, c = np.log(spectrum[k - 1:k + 2] + 1e-300)
        denominator = a - 2 * b + c
        shift = 0.5 * (a - c) / denominator if denominator != 0 else 0.0
    return float((k + shift) / (x.size * time_step))


def tonal_part(signal, time_step, min_frequency):
    """The signal minus its centred moving average over one period of ``min_frequency`` (Hz).

    A compact high-pass: content at multiples of ``min_frequency`` is kept exactly, slower
    content (the mean force, a quasi-static rise, burst envelopes) is removed.
    """
    x = np.asarray(signal, dtype=float)
    m = max(int(round(1.0 / (min_frequency * time_step))), 1)
    return x - np.convolve(x, np.ones(m) / m, mode="same")


def band_part(signal, time_step, frequency, band):
    """The signal filtered by a zero-phase Gaussian band-pass around ``frequency`` (Hz).

    The gain is ``exp(-(f - frequency)^2 / (2 (band frequency)^2))`` (and its mirror at negative
    frequencies), applied by FFT to the signal with its mean removed.
    """
    x = np.asarray(signal, dtype=float)
    f = np.fft.rfftfreq(x.size, time_step)
    gain = np.exp(-0.5 * ((f - frequency) / (band * frequency)) ** 2)
    return np.fft.irfft(np.fft.rfft(x - x.mean()) * gain, n=x.size)


def squeal_metrics(force, time_step, window=0.15, threshold_db=40.0, limit_cycle_tolerance=0.25,
                   running_window=0.01, min_frequency=SQUEAL_MIN_FREQUENCY, band=0.05):
    """All metrics of a lateral-force history.

    Parameters
    ----------
    force : (nt,) array_like
        Lateral force F2, N.
    time_step : float
        s.
    window : float
        Length of the rms window at the end of the signal, s (paper: 0.15 s).
    threshold_db : float
        ``L_F2`` above which a limit cycle counts as squeal, dB re 1 N.
    limit_cycle_tolerance : float
        Largest relative change of the rms between the last two windows for a limit cycle.
    running_window : float
        Window of the running rms used for the build-up time, s.
    min_frequency : float
        Lowest squeal frequency, Hz (below the wheel's first modes).
    band : float
        Relative width (standard deviation / squeal frequency) of the band of the squeal tone
        whose envelope gives the build-up time (-).

    Returns
    -------
    SquealMetrics
    """
    force = np.asarray(force, dtype=float)
    level, rms = force_level(force, time_step, window)
    n = max(int(round(window / time_step)), 1)
    before = force[-2 * n:-n] if force.size >= 2 * n else force[: max(force.size - n, 1)]
    rms_before = float(np.sqrt(np.mean((before - before.mean()) ** 2)))
    growth = rms / rms_before if rms_before > 0 else float("inf")
    limit_cycle = abs(growth - 1.0) <= limit_cycle_tolerance
    squeal = bool(level > threshold_db and limit_cycle)
    frequency = dominant_frequency(force[-n:], time_step, min_frequency)
    buildup = float("nan")
    if squeal:
        m = max(int(round(running_window / time_step)), 2)
        tonal = band_part(tonal_part(force, time_step, min_frequency), time_step, frequency, band)
        skip = int(round(2.0 / (min_frequency * time_step)))
        final = float(np.sqrt(np.mean(tonal[-n - skip // 2:-skip // 2 or None] ** 2)))  # away from the end
        running = np.sqrt(np.convolve(tonal**2, np.ones(m) / m, mode="valid"))
        above = np.nonzero(running[skip:] >= 0.5 * final)[0] + skip
        if above.size:
            buildup = float((above[0] + m - 1) * time_step)
    return SquealMetrics(level, rms, squeal, frequency, buildup, growth)
