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
