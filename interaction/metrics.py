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
- Build-up time: when the squeal tone's envelope has reached its limit-cycle level for good
  (:func:`buildup_time`). The squeal tone is the force in a band around the squeal frequency f
  (Gaussian, standard deviation ``band`` times f, zero phase) after the moving average over one
  period of ``min_frequency`` has been removed, zero-padded at both ends (no wrap-around):
  neither the quasi-static rise of the creep force when the creepage is switched on nor the
  ringing of other wheel modes counts. Its envelope is the centred running rms over
  ``w = max(running_window, ENVELOPE_PERIODS / f)`` (0.01 s; 5 periods for tones below 500 Hz,
  24.6 ms at 203 Hz), in dB; the limit-cycle level is the tone's rms over the last ``window``
  seconds. The build-up time is the first time from which on the envelope stays at or above
  the limit level minus :data:`BUILDUP_DROP_DB` (3 dB): the time of the sample after the last
  one below. When the limit cycle's own envelope swings wider than that (bursts, e.g. with
  loss of contact), the bound is the lowest envelope within the last two windows (those the
  limit-cycle criterion compares) instead. So a start transient that rings the mode and
  decays before the oscillation grows is not the build-up; an oscillation growing as
  ``exp(sigma t)`` up to its limit at ``t_s`` gives ``t_s - ln(10^(3/20)) / sigma``
  (= ``t_s - 0.345 / sigma``); one at its level from the first window on gives 0. The last
  ``1 / min_frequency + 4 s_f`` seconds, with ``s_f = 1 / (2 pi band f)`` the band filter's
  time spread (0.64 ms at 5 kHz, 15.7 ms at 203 Hz), are left out of the envelope and the
  limit level (there the moving average and the filter see the end of the signal).
  Resolution: about ``w / 2 + 2 s_f``. NaN without squeal (no limit cycle above the
  threshold).
- Class of the oscillation (:func:`oscillation_class`): ``"squeal"`` when it meets the squeal
  criterion above and its frequency is at least ``squeal_min_frequency``
  (``simulation.squeal_min_frequency``, default 1000 Hz: curve squeal is tonal noise of about
  1–10 kHz, carried by wheel modes with several nodal diameters; a 203 Hz oscillation of the
  wheel's n = 0 mode is not what an engineer calls squeal), ``"low-frequency oscillation"`` when
  it meets the criterion below that frequency, else ``"none"``. The criterion itself (the
  ``squeal`` flag, the paper's) does not use the frequency.
- Contact regime (:func:`contact_regime`), over the same last ``window`` seconds as ``L_F2``:
  the share of the samples out of contact (``F_n <= 0``), the peak normal force and its ratio to
  the static normal force ``Q``, and the peak ``|F_y|`` over ``mu Q``. The oscillation is
  *impact/bouncing* (``regime = "bouncing"``) when the wheel leaves the rail in that window
  (share > 0) or the lateral force swings beyond :data:`LATERAL_SWING_LIMIT` times ``mu Q``
  (only a normal force that swings that far above ``Q`` allows it: ``|F_y| <= mu F_n``); else
  ``"contact"``. The margin of 20 %: a saturated creep force in the inclined contact frame
  already sits 1–2 % above ``mu Q`` (the lateral force's share in the normal direction), and
  the paper's 5 kHz squeal (55.7 dB) peaks at 1.04 ``mu Q``; a limit cycle with loss of contact
  reaches 2.8 ``mu Q``. A "squeal" of such a case is the wheel hammering the rail, outside what
  the squeal models (and the paper's criterion) describe.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SQUEAL_MIN_FREQUENCY = 100.0
"""Lowest squeal frequency (Hz): below the first modes of railway wheels."""

BUILDUP_DROP_DB = 3.0
"""The build-up ends when the tone's envelope stays within this many dB below its limit-cycle level."""

ENVELOPE_PERIODS = 5.0
"""The envelope's running window covers at least this many periods of the tone."""

LATERAL_SWING_LIMIT = 1.2
"""A peak ``|F_y|`` above this many times ``mu Q`` (static normal force Q) marks impact/bouncing."""

SQUEAL, LOW_FREQUENCY, NO_OSCILLATION = "squeal", "low-frequency oscillation", "none"
"""Classes of :func:`oscillation_class`."""

DEFAULT_SQUEAL_MIN_FREQUENCY = 1000.0
"""Default lowest frequency (Hz) of an oscillation classed as squeal (``simulation.squeal_min_frequency``)."""

BOUNCING, IN_CONTACT = "bouncing", "contact"
"""Values of :attr:`ContactRegime.regime`."""


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
        Shortest window of the running rms (the tone's envelope) used for the build-up time, s.
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
        buildup = buildup_time(force, time_step, frequency, window, running_window, min_frequency, band)
    return SquealMetrics(level, rms, squeal, frequency, buildup, growth)


def tone_envelope(force, time_step, frequency, window=0.15, running_window=0.01, min_frequency=SQUEAL_MIN_FREQUENCY,
                  band=0.05):
    """The squeal tone's envelope and limit-cycle level (the build-up time's, see the module doc).

    Parameters
    ----------
    force : (nt,) array_like
        Lateral force, N.
    time_step : float
        s.
    frequency : float
        The tone's frequency (the squeal frequency), Hz.
    window : float
        Length of the limit-cycle window at the end, s.
    running_window : float
        Shortest window of the running rms, s (longer for slow tones: :data:`ENVELOPE_PERIODS`).
    min_frequency : float
        Period of the moving average removed first (its inverse), Hz.
    band : float
        Relative width of the tone's band (-).

    Returns
    -------
    (time, envelope, limit)
        ``time`` (s): the centres of the running windows that lie inside the signal and end
        before its end region; ``envelope`` (N): the running rms there; ``limit`` (N): the
        tone's rms over the last ``window`` seconds before the end region.
    """
    x = np.asarray(force, dtype=float)
    spread = 1.0 / (2.0 * np.pi * band * frequency)  # time spread (std) of the band filter, s
    pad = int(np.ceil(8.0 * spread / time_step))
    tonal = tonal_part(x, time_step, min_frequency)
    padded = np.concatenate([np.zeros(pad), tonal - tonal.mean(), np.zeros(pad)])
    tone = band_part(padded, time_step, frequency, band)[pad:pad + x.size]
    end = x.size - int(np.ceil((1.0 / min_frequency + 4.0 * spread) / time_step))
    m = max(int(round(max(running_window, ENVELOPE_PERIODS / frequency) / time_step)), 1) | 1  # odd
    n = max(int(round(window / time_step)), 1)
    if end - m < 1:
        return np.zeros(0), np.zeros(0), float("nan")
    limit = float(np.sqrt(np.mean(tone[max(end - n, 0):end] ** 2)))
    running = np.sqrt(np.maximum(np.convolve(tone[:end] ** 2, np.ones(m) / m, mode="valid"), 0.0))
    time = (np.arange(running.size) + m // 2) * time_step
    return time, running, limit


def buildup_time(force, time_step, frequency, window=0.15, running_window=0.01, min_frequency=SQUEAL_MIN_FREQUENCY,
                 band=0.05, drop_db=BUILDUP_DROP_DB):
    """The build-up time (s) of a tone at ``frequency`` (Hz) in a lateral-force history.

    The first time from which on the tone's envelope (:func:`tone_envelope`) stays at or above
    its limit-cycle level minus ``drop_db`` (dB), or above the lowest envelope of the last two
    windows when that is lower (a limit cycle in bursts): the time of the sample after the last
    one below; 0 when the envelope is never below; NaN when ``frequency`` is not finite or the tone
    has no level. The other parameters are those of :func:`squeal_metrics`.
    """
    if not np.isfinite(frequency) or frequency <= 0:
        return float("nan")
    time, envelope, limit = tone_envelope(force, time_step, frequency, window, running_window, min_frequency, band)
    if not time.size or not limit > 0:
        return float("nan")
    n = max(int(round(window / time_step)), 1)
    # a limit cycle whose own envelope swings wider (bursts): its lowest envelope is the bound
    # (over the two windows the limit-cycle criterion compares)
    threshold = min(limit * 10.0 ** (-drop_db / 20.0), float(envelope[-2 * n:].min()))
    below = np.flatnonzero(envelope < threshold)
    if not below.size:
        return 0.0
    if below[-1] + 1 >= time.size:
        return float(time[-1])
    return float(time[below[-1] + 1])


@dataclass(frozen=True)
class ContactRegime:
    """Whether a case's oscillation keeps the wheel on the rail (:func:`contact_regime`).

    Attributes
    ----------
    contact_loss : float
        Share of the window's samples out of contact (``F_n <= 0``), -.
    peak_normal_force : float
        Largest normal force in the window, N.
    peak_normal_ratio : float
        ``peak_normal_force`` over the static normal force, -.
    peak_lateral_ratio : float
        Largest ``|F_y|`` in the window over ``mu`` times the static normal force, -.
    regime : str
        :data:`BOUNCING` (loss of contact, or ``peak_lateral_ratio`` above
        :data:`LATERAL_SWING_LIMIT`) or :data:`IN_CONTACT`.
    """

    contact_loss: float
    peak_normal_force: float
    peak_normal_ratio: float
    peak_lateral_ratio: float
    regime: str

    @property
    def bouncing(self):
        """True for impact/bouncing."""
        return self.regime == BOUNCING

    def describe(self, mu="μ"):
        """The regime in words, e.g. ``impact/bouncing (out of contact 11 % of the window, peak F_n
        2.85 Q, peak |F_y| 2.85 μQ)``; ``in contact`` otherwise (``mu``: the friction symbol)."""
        if not self.bouncing:
            return "in contact"
        return (f"impact/bouncing (out of contact {100 * self.contact_loss:.0f} % of the window, peak F_n "
                f"{self.peak_normal_ratio:.2f} Q, peak |F_y| {self.peak_lateral_ratio:.2f} {mu}Q)")


def contact_regime(force, time_step, friction, static_normal_force, window=0.15, lateral_limit=LATERAL_SWING_LIMIT):
    """The contact regime of a force history over its last ``window`` seconds (the ``L_F2`` window).

    Parameters
    ----------
    force : (nt, 3) array_like
        Contact force of the rail on the wheel in the contact frame (F_x, F_y, F_n), N.
    time_step : float
        s.
    friction : float
        Friction coefficient mu (-).
    static_normal_force : float
        The static normal force Q, N.
    window : float
        s.
    lateral_limit : float
        Peak ``|F_y| / (mu Q)`` above which the case counts as bouncing.

    Returns
    -------
    ContactRegime
    """
    force = np.asarray(force, dtype=float)
    n = max(int(round(window / time_step)), 1)
    tail = force[-n:]
    loss = float(np.mean(tail[:, 2] <= 0.0))
    peak_normal = float(tail[:, 2].max())
    lateral = float(np.abs(tail[:, 1]).max()) / (friction * static_normal_force)
    regime = BOUNCING if loss > 0.0 or lateral > lateral_limit else IN_CONTACT
    return ContactRegime(loss, peak_normal, peak_normal / static_normal_force, lateral, regime)


def oscillation_class(squeal, frequency, squeal_min_frequency=DEFAULT_SQUEAL_MIN_FREQUENCY):
    """The class of a case's oscillation.

    Parameters
    ----------
    squeal : bool
        Whether it meets the squeal criterion (``L_F2`` above the threshold, limit cycle).
    frequency : float
        Its frequency (the squeal frequency of :func:`squeal_metrics`), Hz.
    squeal_min_frequency : float
        Lowest frequency of squeal, Hz.

    Returns
    -------
    str
        :data:`SQUEAL` (criterion met at ``frequency >= squeal_min_frequency``),
        :data:`LOW_FREQUENCY` (met below it, or at an unknown frequency) or :data:`NO_OSCILLATION`.
    """
    if not squeal:
        return NO_OSCILLATION
    return SQUEAL if frequency >= squeal_min_frequency else LOW_FREQUENCY
