"""Squeal metrics against signals whose level, frequency and build-up are known in closed form."""

import numpy as np
import pytest

from interaction.metrics import dominant_frequency, squeal_metrics

DT = 3.6e-5


def test_tone_level_and_frequency():
    # a steady tone A sin(2 pi f t) on a mean: L_F2 = 20 log10(A / sqrt(2)); over 0.15 s the
    # leakage of the Hann window is small, so the rms is exact to ~1e-3 and the interpolated
    # peak to a small fraction of the 6.7 Hz bin
    t = np.arange(int(1.0 / DT)) * DT
    amplitude, f = 2000.0, 2011.0
    m = squeal_metrics(5e3 + amplitude * np.sin(2 * np.pi * f * t), DT)
    assert m.L_F2 == pytest.approx(20 * np.log10(amplitude / np.sqrt(2)), abs=0.01)
    assert m.squeal and m.growth == pytest.approx(1.0, abs=0.01)
    assert m.squeal_frequency == pytest.approx(f, abs=1.0)


def test_squeal_frequency_of_bursts_is_the_tone_not_the_envelope():
    # 5 kHz squeal in bursts that repeat at 15 Hz (as with lift-off), plus the 15 Hz swing of the
    # mean force: the largest peak is the envelope, the squeal frequency is the tone
    t = np.arange(int(1.0 / DT)) * DT
    envelope = np.maximum(np.sin(2 * np.pi * 15 * t), 0.0)
    signal = 20e3 * envelope + 15e3 * envelope * np.sin(2 * np.pi * 5047 * t)
    tail = signal[-int(0.15 / DT):]
    assert dominant_frequency(tail, DT) == pytest.approx(15.0, abs=4.0)  # the envelope dominates
    assert squeal_metrics(signal, DT).squeal_frequency == pytest.approx(5047.0, abs=3.0)


def test_growing_tone_is_not_a_limit_cycle_and_buildup_time():
    t = np.arange(int(1.0 / DT)) * DT
    growing = np.exp(5.0 * t) * np.sin(2 * np.pi * 900 * t) * 1e3
    assert not squeal_metrics(growing, DT).squeal  # rms grows by e^(5 * 0.15) = 2.1 per window
    # a tone switched on at 0.3 s on top of a creep force that rises at t = 0 to 15 kN with a
    # 2 ms time constant (as when the creepage is switched on): the running rms (10 ms) of the
    # tonal part reaches half its final value within a few ms after 0.3 s; the quasi-static rise
    # does not count
    rise = 15e3 * (1 - np.exp(-t / 2e-3))
    on = rise + np.where(t >= 0.3, 1e3 * np.sin(2 * np.pi * 900 * t), 0.0)
    m = squeal_metrics(on, DT)
    assert m.squeal
    assert 0.3 < m.buildup_time < 0.3 + 0.01


def test_buildup_time_is_that_of_the_squeal_tone():
    # as in a simulation: the creep force rises to 30 kN in ~10 ms when the creepage is switched
    # on and rings a lightly damped 2 kHz mode (2 kN, decaying over 0.5 s); a 400 N squeal tone
    # at 5043 Hz grows from 0.3 s with a 5 ms time constant. The build-up is the tone's: its
    # running rms (10 ms) reaches half its final value about 5 ms after 0.3 s.
    t = np.arange(int(1.0 / DT)) * DT
    rise = 30e3 * (1 - np.exp(-t / 3e-3))
    ringing = 2e3 * np.exp(-t / 0.5) * np.sin(2 * np.pi * 2011 * t)
    tone = np.where(t >= 0.3, 400.0 * (1 - np.exp(-(t - 0.3) / 5e-3)), 0.0) * np.sin(2 * np.pi * 5043 * t)
    m = squeal_metrics(rise + ringing + tone, DT, threshold_db=20.0)
    assert m.squeal and m.squeal_frequency == pytest.approx(5043.0, abs=3.0)
    assert 0.3 < m.buildup_time < 0.3 + 0.015


# Build-up time on the tone's envelope (interaction.metrics.buildup_time): the first time from which
# on the envelope stays within 3 dB below its limit-cycle level. Its resolution is about half the
# running window plus twice the band filter's time spread 1 / (2 pi band f): 5 + 1.3 ms at 5 kHz,
# 12.3 + 31.4 ms at 203 Hz (w = 5 periods).

def _resolution(f, band=0.05):
    return 0.5 * max(0.01, 5.0 / f) + 2.0 / (2 * np.pi * band * f)


def _saturating(t, f, sigma, t_s, amplitude):
    """A sine growing as exp(sigma t) up to ``amplitude`` at ``t_s``, then steady."""
    return amplitude * np.exp(sigma * np.minimum(t - t_s, 0.0)) * np.sin(2 * np.pi * f * t)


@pytest.mark.parametrize("f, sigma, t_s, duration", [(5043.0, 20.0, 0.6, 1.0), (203.0, 1.53, 1.5, 2.5)])
def test_buildup_time_of_exponential_growth_to_a_limit(f, sigma, t_s, duration):
    # the envelope A exp(sigma (t - t_s)) / sqrt(2) reaches the limit minus 3 dB at
    # t_s - ln(10^(3/20)) / sigma (0.583 s for the 5 kHz tone, 1.274 s for the 203 Hz one)
    t = np.arange(int(duration / DT)) * DT
    m = squeal_metrics(_saturating(t, f, sigma, t_s, 200.0), DT)
    assert m.squeal
    expected = t_s - np.log(10 ** (3 / 20)) / sigma
    assert m.buildup_time == pytest.approx(expected, abs=_resolution(f))


def test_buildup_time_skips_the_start_transient():
    # the case: the creep force rises to 30 kN when the creepage is switched on and rings
    # the 203 Hz mode at the limit cycle's level, which decays (20 1/s); the oscillation then grows
    # from 23 dB (re 1 N rms) at 0.1 s into a 41.6 dB limit cycle at 1.5 s. The running rms reaches
    # half its final value within the transient, at ~0.03 s; the build-up is the growth's, 1.33 s.
    f, t_s = 203.0, 1.5
    t = np.arange(int(2.5 / DT)) * DT
    limit = np.sqrt(2) * 10 ** (41.6 / 20)
    sigma = np.log(10 ** ((41.6 - 23.0) / 20)) / (t_s - 0.1)
    rise = 30e3 * (1 - np.exp(-t / 3e-3))
    ringing = limit * np.exp(-20.0 * t) * np.sin(2 * np.pi * f * t + 1.0)
    m = squeal_metrics(rise + ringing + _saturating(t, f, sigma, t_s, limit), DT)
    assert m.squeal and m.squeal_frequency == pytest.approx(f, abs=1.0)
    assert m.buildup_time == pytest.approx(t_s - np.log(10 ** (3 / 20)) / sigma, abs=_resolution(f))


def test_buildup_time_of_a_limit_cycle_in_bursts():
    # growth to 0.6 s, then a limit cycle whose envelope swings by +-5 dB at 15 Hz (bursts): the
    # envelope never stays within 3 dB, so the bound is its lowest level in the last two windows
    # and the build-up ends where the growth reaches it (before 0.6 s), not in the last window
    t = np.arange(int(1.0 / DT)) * DT
    swing = 10 ** (5 * np.sin(2 * np.pi * 15 * t) * (t > 0.6) / 20)
    m = squeal_metrics(swing * _saturating(t, 5043.0, 20.0, 0.6, 200.0), DT)
    assert m.squeal
    assert 0.5 < m.buildup_time < 0.6 + _resolution(5043.0)


def test_decaying_tone_has_no_buildup_time():
    t = np.arange(int(1.0 / DT)) * DT
    m = squeal_metrics(1e4 * np.exp(-4.0 * t) * np.sin(2 * np.pi * 5043 * t), DT)
    assert m.L_F2 > 40.0 and not m.squeal  # loud, but it decays (no limit cycle)
    assert np.isnan(m.buildup_time)


@pytest.mark.parametrize("f", [5043.0, 203.0])
def test_steady_tone_from_the_start_builds_up_at_once(f):
    t = np.arange(int(1.0 / DT)) * DT
    m = squeal_metrics(300.0 * np.sin(2 * np.pi * f * t), DT)
    assert m.squeal
    assert 0.0 <= m.buildup_time <= _resolution(f)
