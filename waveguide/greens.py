"""Moving Green's kernels of the rail (Nordborg's moving Green's function).

The response at a point moving away from the load at the train speed v is
``g~(t) = g(x = v t, t)``. Its ramp-invariant (first-order-hold) discretisation with time
step dt is ``k[m] = int g~(tau) Lambda(tau / dt - m) dtau`` (Lambda the unit hat), so that
``u_i[n] = sum_m k[m, i, j] F_j[n - m]`` for a force interpolated linearly between samples.
Freezing x at x_m = m v dt within each hat (an error of order kappa v dt),

    k[m] = dt / (2 pi) int H(x_m, omega) sinc^2(omega dt / 2) exp(i omega m dt) domega.

The rail's hysteretic loss factors (E (1 + i eta sign omega)) are not causal: the inverse
transform of H has a small precursor at t < 0 that a one-sided kernel would cut off,
spoiling e.g. its sum. The kernel is therefore built from the real part of H only, which
for a causal response gives g(t) = 2/pi int_0^inf Re H cos(omega t) domega (t > 0):

    k[m] = w_m 2 dt / pi int_0^inf Re H(x_m, omega) sinc^2(omega dt / 2) cos(omega m dt) domega,

w_0 = 1/2 (the hat of sample 0 covers only t >= 0), w_m = 1 otherwise; this is the causal
response whose real part equals that of the hysteretic model (Kramers-Kronig). It is
evaluated on a uniform frequency grid (trapezoid rule; period 1/df in time) with the wave
sum for H. Above the patch (x_m >= L/2) each wave contributes ``q_n sinc(kappa L/2)
exp(i m (omega - kappa_n v) dt)``, a geometric series in m that the numba kernel sums.
"""

from __future__ import annotations

import logging

import numpy as np

from squealcore.errors import require_range
from waveguide.kernels import accumulate_wave_series
from waveguide.response import wave_sum

logger = logging.getLogger(__name__)

__all__ = ["moving_kernel", "kernel_from_waves", "foh_factor"]


def foh_factor(omega, dt):
    """First-order-hold factor sinc^2(omega dt / 2) (-)."""
    a = np.asarray(omega) * dt / 2
    return np.sinc(a / np.pi) ** 2


def kernel_from_waves(wave_list, df, speed, dt, n_steps, length, cutoff=1e-14):
    """Moving kernel from the waves on a uniform frequency grid ``f_k = k df``.

    Parameters
    ----------
    wave_list : list of waveguide.waves.Waves
        Waves at f = 0, df, 2 df, ... (the entry for f = 0 may be ``None``: it is skipped,
        its trapezoid weight being small for a fine grid).
    df : float
        Frequency step (Hz).
    speed : float
        v (m/s), >= 0.
    dt : float
        Time step (s).
    n_steps : int
        Kernel length.
    length : float
        Patch length L (m).
    cutoff : float
        Terms below this (m/N) are dropped in the series.

    Returns
    -------
    ndarray (n_steps, 3, 3)
        Kernel (m/N).
    """
    n_f = len(wave_list)
    out = np.zeros((n_steps, 9))
    dx = speed * dt
    m_in = int(np.ceil(length / 2 / dx)) if dx > 0 else n_steps  # samples inside the patch
    m_in = min(m_in, n_steps)
    m_idx = np.arange(m_in)
    x_in = m_idx * dx
    dw = 2 * np.pi * df
    for k, w in enumerate(wave_list):
        if w is None:
            continue
        c = 0.5 if k in (0, n_f - 1) else 1.0
        weight = c * dw * dt / np.pi * foh_factor(w.omega, dt)
        # Re H(x_m, w) cos(w t_m) = (Re[H e^{i w t}] + Re[H e^{-i w t}]) / 2: the causal
        # kernel from the real part of H only (see module docstring)
        if m_in:
            h = wave_sum(w, x_in, length).reshape(m_in, 9)
            out[:m_in] += weight * h.real * np.cos(w.omega * m_idx * dt)[:, None] * 2
        if m_in < n_steps:
            kl = w.kappa * length / 2
            sinc = np.where(np.abs(kl) < 1e-12, 1.0, np.sin(kl) / np.where(np.abs(kl) < 1e-12, 1, kl))
            for sgn in (1.0, -1.0):
                z = np.exp(1j * (sgn * w.omega - w.kappa * speed) * dt)
                amp = (weight * sinc)[:, None] * w.q.reshape(-1, 9) * (z**m_in)[:, None]
                tail = np.zeros((n_steps - m_in, 9))
                accumulate_wave_series(z.astype(np.complex128), np.ascontiguousarray(amp, np.complex128),
                                       n_steps - m_in, cutoff, tail)
                out[m_in:] += tail
    out[0] *= 0.5  # the hat of sample 0 covers only t >= 0
    return out.reshape(n_steps, 3, 3)


def _check(speed, dt):
    speed = require_range("operating.speed", speed, 0.0, 200.0, unit="m/s")
    dt = require_range("time.time_step", dt, 0.0, 1e-2, low_open=True, unit="s")
    return speed, dt


def moving_kernel(waveguide, speed, time_step, duration=None, max_frequency=None,
                  tolerance=None, max_duration=1.0):
    """Moving Green's kernel of the rail at the contact patch.

    Parameters
    ----------
    waveguide : waveguide.waves.RailWaveguide
    speed : float
        Train speed v (m/s); 0 gives the stationary kernel at x = 0.
    time_step : float
        dt (s).
    duration : float, optional
        Kernel length (s). If omitted it is found by doubling from 0.05 s until the last
        quarter of the kernel is below ``tolerance`` times its peak.
    max_frequency : float, optional
        Upper end of the frequency grid (Hz); default ``min(track.max_frequency, 1/dt)``
        (1/dt is the first zero of the first-order-hold factor).
    tolerance : float, optional
        Default ``track.kernel_tolerance``.
    max_duration : float
        Upper limit of the automatic duration (s).

    Returns
    -------
    dict
        ``kernel`` (nt, 3, 3) m/N; ``time`` (nt,) s; ``frequency`` (nf,) Hz of the grid;
        ``moving_receptance`` (nf, 3, 3) m/N, the spectrum of g~ on that grid (from the
        kernel, divided by the first-order-hold factor, below 1/(2 dt));
        ``static_compliance`` (3, 3) m/N = sum of the kernel; ``tail`` relative size of the
        last quarter; ``speed``, ``time_step``.
    """
    speed, dt = _check(speed, time_step)
    track = waveguide.track
    tol = track.kernel_tolerance if tolerance is None else tolerance
    fmax = min(track.max_frequency, 1.0 / dt) if max_frequency is None else max_frequency
    length = track.load_patch_length
    cache = {}

    def waves_on(df):
        n = int(round(fmax / df))
        lst = []
        for k in range(n + 1):
            key = round(k * df, 9)
            if key not in cache:
                # f = 0 is needed (its trapezoid weight sets the kernel's sum); the free rail has
                # no static solution there, so it is skipped
                cache[key] = (waveguide.waves(2 * np.pi * key)
                              if k > 0 or waveguide.track.supported else None)
            lst.append(cache[key])
        return lst

    t_len = 0.05 if duration is None else float(duration)
    while True:
        nt = int(round(t_len / dt))
        df = 1.0 / (2 * t_len)  # time period 2 T: no wrap-around inside the kernel
        lst = waves_on(df)
        ker = kernel_from_waves(lst, df, speed, dt, nt, length)
        peak = np.abs(ker).max()
        tail = np.abs(ker[int(0.75 * nt):]).max() / peak
        logger.info("moving kernel: T=%.3f s, %d frequencies, tail/peak=%.2e", t_len, len(lst), tail)
        if duration is not None or tail < tol or 2 * t_len > max_duration:
            if duration is None and tail >= tol:
                logger.warning("moving kernel tail %.2e above tolerance at %.2f s", tail, t_len)
            break
        t_len *= 2
    freq = np.arange(len(lst)) * df
    nfft = 2 * nt
    spec = np.fft.rfft(ker, n=nfft, axis=0) * 1.0  # sum_m k[m] exp(-i w m dt)
    fgrid = np.fft.rfftfreq(nfft, dt)
    sfac = foh_factor(2 * np.pi * fgrid, dt)
    moving = spec / sfac[:, None, None]
    return {"kernel": ker, "time": np.arange(nt) * dt, "frequency": fgrid,
            "moving_receptance": moving, "static_compliance": ker.sum(axis=0), "tail": tail,
            "speed": speed, "time_step": dt, "solve_frequency": freq}
