"""Moving Green's kernels of the rail (Nordborg's moving Green's function).

The response at a point moving away from the load at the train speed v is
``g~(t) = g(x = v t, t)``. Its ramp-invariant (first-order-hold) discretisation with time
step dt is ``k[m] = int g~(tau) Lambda(tau / dt - m) dtau`` (Lambda the unit hat), so that
``u_i[n] = sum_m k[m, i, j] F_j[n - m]`` for a force interpolated linearly between samples.
Freezing x at x_m = m v dt within each hat (done only under the patch, x < L/2),

    k[m] = dt / (2 pi) int H(x_m, omega) sinc^2(omega dt / 2) exp(i omega m dt) domega.

The kernel is built from the real part of H only, which for a causal response gives
g(t) = 2/pi int_0^inf Re H cos(omega t) domega (t > 0):

    k[m] = w_m 2 dt / pi int_0^inf Re H(x_m, omega) sinc^2(omega dt / 2) cos(omega m dt) domega,

w_0 = 1/2 (the hat of sample 0 covers only t >= 0), w_m = 1 otherwise. With the default
causal track damping (:mod:`waveguide.damping`) Re H and Im H are a Hilbert pair and this is
the kernel of the model itself (its spectrum reproduces Im H too; tested). With
``damping_model = "hysteretic"`` (E (1 + i eta sign omega), not causal) it is the causal
response that has the hysteretic model's Re H, and its Im H differs from the hysteretic one.
H is evaluated on a uniform frequency grid (trapezoid rule; period 1/df in time) with the
wave sum. Above the patch (x_m >= L/2) each wave contributes
``q_n sinc(kappa L/2) exp(i (+-omega - kappa_n v) t)``; its hat integral is exact
(first-order-hold factor at the frequency seen by the moving point, omega - kappa_n v),
a geometric series in m that the numba kernel sums.
"""

from __future__ import annotations

import logging

import numpy as np

from squealcore.errors import require_range
from waveguide.kernels import accumulate_wave_series
from waveguide.response import wave_sum

logger = logging.getLogger(__name__)

__all__ = ["moving_kernel", "ordinary_kernel", "kernel_from_waves", "foh_factor", "band_weights"]


def foh_factor(omega, dt):
    """First-order-hold factor sinc^2(omega dt / 2) (-)."""
    a = np.asarray(omega) * dt / 2
    return np.sinc(a / np.pi) ** 2


def _sinc2(a):
    """sinc^2 with sinc(a) = sin(a) / a for complex ``a``."""
    a = np.asarray(a, complex)
    small = np.abs(a) < 1e-6
    safe = np.where(small, 1.0, a)
    return np.where(small, 1.0 - a**2 / 3, (np.sin(safe) / safe) ** 2)


def kernel_from_waves(wave_list, df, speed, dt, n_steps, length, cutoff=1e-14, band=None):
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
    band : ndarray (len(wave_list),), optional
        Weight of each frequency (-), e.g. one of the two bands of :func:`band_weights`;
        entries with weight 0 may be ``None`` in ``wave_list``.

    Returns
    -------
    ndarray (n_steps, 3, 3)
        Kernel (m/N).
    """
    n_f = len(wave_list)
    band = np.ones(n_f) if band is None else np.asarray(band, float)
    out = np.zeros((n_steps, 9))
    dx = speed * dt
    m_in = int(np.ceil(length / 2 / dx)) if dx > 0 else n_steps  # samples inside the patch
    m_in = min(m_in, n_steps)
    m_idx = np.arange(m_in)
    x_in = m_idx * dx
    dw = 2 * np.pi * df
    for k, w in enumerate(wave_list):
        if w is None or band[k] == 0:
            continue
        c = 0.5 if k in (0, n_f - 1) else 1.0
        weight_tail = c * band[k] * dw * dt / np.pi
        weight = weight_tail * foh_factor(w.omega, dt)
        # Re H(x_m, w) cos(w t_m) = (Re[H e^{i w t}] + Re[H e^{-i w t}]) / 2: the causal
        # kernel from the real part of H only (see module docstring)
        if m_in:
            h = wave_sum(w, x_in, length).reshape(m_in, 9)
            out[:m_in] += weight * h.real * np.cos(w.omega * m_idx * dt)[:, None] * 2
        if m_in < n_steps:
            kl = w.kappa * length / 2
            sinc = np.where(np.abs(kl) < 1e-12, 1.0, np.sin(kl) / np.where(np.abs(kl) < 1e-12, 1, kl))
            for sgn in (1.0, -1.0):
                beta = sgn * w.omega - w.kappa * speed  # rad/s, frequency seen by the contact
                z = np.exp(1j * beta * dt)
                # exact hat integral of exp(i beta tau): dt sinc^2(beta dt / 2) exp(i beta m dt)
                amp = (weight_tail * _sinc2(beta * dt / 2) * sinc)[:, None] * w.q.reshape(-1, 9) \
                    * (z**m_in)[:, None]
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


def ordinary_kernel(waveguide, distances, time_step, duration, max_frequency=None):
    """Ramp-invariant kernels of the ordinary (fixed-point) Green's function g(x, t).

    ``k[m] = int g(x, tau) Lambda(tau / dt - m) dtau`` at fixed distances x >= 0 from the
    load patch, for a force interpolated linearly between samples (DESIGN section 3), i.e.
    ``u_i(x, n dt) = sum_m k[m, i, j] F_j[n - m]``. As for the moving kernel (module
    docstring) it is built from Re H only,

        k[m] = w_m 2 dt / pi int_0^fmax Re H(x, omega) sinc^2(omega dt / 2) cos(omega m dt) domega,

    w_0 = 1/2, w_m = 1, with the trapezoid rule on the uniform grid df = 1 / (2 duration)
    (time period twice the kernel length: no wrap-around inside it) and H from the wave
    sum. At x = 0 it is the limit v -> 0 of :func:`moving_kernel`.

    Parameters
    ----------
    waveguide : waveguide.waves.RailWaveguide
    distances : array_like (n_x,)
        x >= 0 (m).
    time_step : float
        dt (s).
    duration : float
        Kernel length (s); the caller chooses it long enough for the tail to be negligible
        (the response at fixed x of the causal track lasts about 0.2 s).
    max_frequency : float, optional
        Upper end of the frequency grid (Hz); default ``min(track.max_frequency, 1/dt)``.

    Returns
    -------
    dict
        ``kernel`` (n_x, nt, 3, 3) m/N, ``time`` (nt,) s, ``distance`` (n_x,) m,
        ``static_compliance`` (n_x, 3, 3) m/N (the kernels' sums), ``time_step`` s.
    """
    _, dt = _check(0.0, time_step)
    x = np.atleast_1d(np.asarray(distances, float))
    if x.ndim != 1 or not np.all(np.isfinite(x)) or np.any(x < 0):
        raise ValueError("distances must be finite and >= 0 (m)")
    duration = require_range("duration", duration, 0.0, 100.0, low_open=True, unit="s")
    track = waveguide.track
    fmax = min(track.max_frequency, 1.0 / dt) if max_frequency is None else float(max_frequency)
    nt = max(int(round(duration / dt)), 1)
    t_len = nt * dt
    df = 1.0 / (2 * t_len)
    f = np.arange(int(round(fmax / df)) + 1) * df
    length = track.load_patch_length
    t = np.arange(nt) * dt
    out = np.zeros((len(x), nt, 9))
    dw = 2 * np.pi * df
    for k, fk in enumerate(f):
        if fk == 0 and not track.supported:
            continue  # the free rail has no static solution (as in moving_kernel)
        w = waveguide.waves(2 * np.pi * fk)
        c = 0.5 if k in (0, len(f) - 1) else 1.0
        weight = 2 * c * dw * dt / np.pi * foh_factor(w.omega, dt)
        h = wave_sum(w, x, length).reshape(len(x), 9).real
        out += weight * np.cos(w.omega * t)[None, :, None] * h[:, None, :]
    out[:, 0] *= 0.5  # the hat of sample 0 covers only t >= 0
    ker = out.reshape(len(x), nt, 3, 3)
    return {"kernel": ker, "time": t, "distance": x, "static_compliance": ker.sum(axis=1),
            "time_step": dt}


def band_weights(frequency, split):
    """Smooth partition of unity (-) of the frequency axis into a low band (returned) and a
    high band (1 - returned): 1 below split/2, cos^2 ramp to 0 at 1.5 split (Hz)."""
    x = np.clip((np.asarray(frequency, float) / split - 0.5), 0.0, 1.0)
    return np.cos(np.pi / 2 * x) ** 2


def moving_kernel(waveguide, speed, time_step, duration=None, max_frequency=None,
                  tolerance=None, max_duration=1.0, split_frequency=300.0):
    """Moving Green's kernel of the rail at the contact patch.

    The kernel is the sum of two parts from a smooth split of the spectrum at
    ``split_frequency``: the high band decays within tens of ms and needs only a coarse
    frequency grid (df = 1 / (2 T_high)); the low band (the support resonances and the
    creep of the causal pad model) lasts longer but needs frequencies up to
    1.5 split_frequency only. Each part's length is found by doubling until the last quarter
    of it is below ``tolerance`` times the peak, so the few thousand eigenproblems of a
    single fine grid up to ``max_frequency`` are not needed.

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
    split_frequency : float or None
        Centre (Hz) of the crossover between the two bands; ``None`` or 0 uses one fine grid
        up to ``max_frequency`` (slower; the reference for the split).

    Returns
    -------
    dict
        ``kernel`` (nt, 3, 3) m/N; ``time`` (nt,) s; ``frequency`` (nf,) Hz of the spectrum;
        ``moving_receptance`` (nf, 3, 3) m/N, the spectrum of g~ on that grid (from the
        kernel, divided by the first-order-hold factor, below 1/(2 dt));
        ``static_compliance`` (3, 3) m/N = sum of the kernel; ``tail`` relative size of the
        last quarter; ``speed``, ``time_step``; ``solve_frequency`` (Hz) the frequencies
        at which the waves were computed; ``high_band_duration`` (s).
    """
    speed, dt = _check(speed, time_step)
    track = waveguide.track
    tol = track.kernel_tolerance if tolerance is None else tolerance
    fmax = min(track.max_frequency, 1.0 / dt) if max_frequency is None else max_frequency
    length = track.load_patch_length
    t_max = max_duration if duration is None else float(duration)
    split = split_frequency if split_frequency and 1.5 * split_frequency < fmax else None
    cache = {}

    def part(t_len, f_top, low_band):
        """Kernel (nt, 3, 3) of length t_len from the band below f_top."""
        nt = int(round(t_len / dt))
        df = 1.0 / (2 * t_len)  # time period 2 T: no wrap-around inside the kernel
        f = np.arange(int(round(f_top / df)) + 1) * df
        if split is None:
            band = np.ones(len(f))
        else:
            band = band_weights(f, split)
            band = band if low_band else 1.0 - band
        lst = []
        for fk, bk in zip(f, band):
            key = round(fk, 9)
            # f = 0 is needed (its trapezoid weight sets the kernel's sum); the free rail has
            # no static solution there, so it is skipped
            if bk == 0 or (key == 0 and not track.supported):
                lst.append(None)
                continue
            if key not in cache:
                cache[key] = waveguide.waves(2 * np.pi * key)
            lst.append(cache[key])
        return kernel_from_waves(lst, df, speed, dt, nt, length, band=band)

    def tail_of(ker, peak):
        return np.abs(ker[int(0.75 * len(ker)):]).max() / peak

    # high band: short, coarse grid up to fmax
    high = None
    if split is not None:
        t_high = min(0.025, t_max)
        while True:
            high = part(t_high, fmax, low_band=False)
            tail = tail_of(high, np.abs(high).max())
            logger.info("moving kernel, band above %.0f Hz: T=%.3f s, tail/peak=%.2e",
                        split / 2, t_high, tail)
            if tail < tol or 2 * t_high > t_max:
                break
            t_high *= 2
    # low band (or everything without a split): fine grid
    t_len = min(max(0.05, high.shape[0] * dt if high is not None else 0.0), t_max) \
        if duration is None else t_max
    while True:
        ker = part(t_len, 1.5 * split if split is not None else fmax, low_band=True)
        if high is not None:
            n = min(len(high), len(ker))
            ker[:n] += high[:n]
        peak = np.abs(ker).max()
        tail = tail_of(ker, peak)
        logger.info("moving kernel: T=%.3f s, %d frequencies solved, tail/peak=%.2e", t_len,
                    len(cache), tail)
        if duration is not None or tail < tol or 2 * t_len > max_duration:
            if duration is None and tail >= tol:
                logger.warning("moving kernel tail %.2e above tolerance at %.2f s", tail, t_len)
            break
        t_len *= 2
    nt = len(ker)
    nfft = 2 * nt
    spec = np.fft.rfft(ker, n=nfft, axis=0) * 1.0  # sum_m k[m] exp(-i w m dt)
    fgrid = np.fft.rfftfreq(nfft, dt)
    sfac = foh_factor(2 * np.pi * fgrid, dt)
    moving = spec / sfac[:, None, None]
    return {"kernel": ker, "time": np.arange(nt) * dt, "frequency": fgrid,
            "moving_receptance": moving, "static_compliance": ker.sum(axis=0), "tail": tail,
            "speed": speed, "time_step": dt, "solve_frequency": np.array(sorted(cache)),
            "high_band_duration": 0.0 if high is None else len(high) * dt}
