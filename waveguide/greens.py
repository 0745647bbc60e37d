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
H is evaluated on uniform frequency grids (trapezoid rule; period 1/df in time) with the
wave sum. Above the patch (x_m >= L/2) each wave contributes
``q_n sinc(kappa L/2) exp(i (+-omega - kappa_n v) t)``; its hat integral is exact
(first-order-hold factor at the frequency seen by the moving point, omega - kappa_n v),
a geometric series in m that the numba kernel sums.

**How far in frequency.** The DTFT of the kernel is the held, aliased spectrum
``K(omega) = sum_j G~(omega + j omega_s) sinc^2((omega + j omega_s) dt / 2)``,
omega_s = 2 pi / dt: the integrals above run over *all* frequencies, not only up to the
Nyquist frequency or 1/dt. Cutting them at f_c drops the aliases beyond f_c from Re K and,
since Im K is the discrete Hilbert transform of Re K (the kernel is causal), adds an error
to Im K that grows like omega / omega_c below the cut-off. The rail's patch compliance keeps
Re H near 4e-10 m/N far above 10 kHz, so the former cut at ``track.max_frequency`` (10 kHz)
made Im K, the damping that the time stepping sees, 2.2 times too large at 5 kHz
(vertical) and Re K 22 % too small at 8 kHz. The grids therefore run to
:data:`TOP_ALIASES` / dt (a zero of sinc^2), far above the range of the reduced
cross-section model (``track.max_frequency``): there H is that model's continuation, as in
the independent reference of the tests. Above ``max_frequency`` the contributions decay
within a few ms, so :func:`moving_kernel` integrates them on coarse grids of their own.
"""

from __future__ import annotations

import logging

import numpy as np

from squealcore.errors import require_range
from waveguide.kernels import accumulate_wave_series
from waveguide.response import wave_sum

logger = logging.getLogger(__name__)

__all__ = ["moving_kernel", "ordinary_kernel", "kernel_from_waves", "foh_factor", "band_weights",
           "band_partition", "grid_top_frequency", "TOP_ALIASES"]

#: the kernels' frequency grids end at TOP_ALIASES / dt (a zero of sinc^2(omega dt / 2)); for
#: the default study the moving kernel's spectrum is then within 0.5 % of the held, aliased
#: moving receptance up to 8 kHz = 0.29 / dt (4 / dt: within 2 %, xx 6 %)
TOP_ALIASES = 8
#: crossovers of the moving kernel's bands above max_frequency, times 1/dt
TOP_SPLITS = (1.0,)
#: first length (s) and fewest samples of the automatic doubling of the moving kernel's bands
#: 1 (high: split_frequency to max_frequency), 2 (top, to 1/dt) and 3 (top, above 1/dt)
BAND_START = ((0.025, 64), (0.0025, 64), (0.00125, 32))


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


def kernel_from_waves(wave_list, df, speed, dt, n_steps, length, rel_cutoff=1e-8, band=None):
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
    rel_cutoff : float
        A wave's geometric series (outside the patch) is summed until its terms fall below
        ``rel_cutoff`` times the largest wave amplitude of that frequency (-). An absolute
        cutoff (formerly 1e-14 m/N) cut the slowly decaying waves of the finely spaced
        frequencies early (each frequency's weight is proportional to df); the dropped tails
        no longer cancel between frequencies and cost up to 7 % in the kernel's spectrum.
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
                                       n_steps - m_in, rel_cutoff * np.abs(amp).max(), tail)
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
    load patch, for a force interpolated linearly between samples (docs/design.md §3), i.e.
    ``u_i(x, n dt) = sum_m k[m, i, j] F_j[n - m]``. As for the moving kernel (module
    docstring) it is built from Re H only,

        k[m] = w_m 2 dt / pi int_0^ftop Re H(x, omega) sinc^2(omega dt / 2) cos(omega m dt) domega,

    w_0 = 1/2, w_m = 1, with the trapezoid rule on the uniform grid df = 1 / (2 duration)
    (time period twice the kernel length: no wrap-around inside it) up to
    ftop = :func:`grid_top_frequency` (8 / dt; the aliases of the held spectrum, see the
    module docstring) and H from the wave sum. At x = 0 it is the limit v -> 0 of
    :func:`moving_kernel` with ``split_frequency=None`` (one grid).

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
        Upper end of the frequency grid (Hz); default :func:`grid_top_frequency` (8 / dt).

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
    fmax = grid_top_frequency(dt) if max_frequency is None else float(max_frequency)
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
    return np.where(x < 1.0, np.cos(np.pi / 2 * x) ** 2, 0.0)  # exactly 0 (cos(pi/2)^2 = 4e-33)


def band_partition(frequency, splits):
    """Weights (len(splits) + 1, nf) (-) of the bands between the crossovers ``splits``
    (Hz, increasing): band 0 lies below the first crossover, band k between crossovers k - 1
    and k, the last band above the last one. Products of :func:`band_weights`, so the bands
    sum to 1 at every frequency; band k vanishes below ``splits[k - 1] / 2`` and above
    ``1.5 splits[k]``."""
    f = np.asarray(frequency, float)
    rest = np.ones_like(f)
    out = []
    for split in splits:
        b = band_weights(f, split)
        out.append(rest * b)
        rest = rest * (1.0 - b)
    out.append(rest)
    return np.array(out)


def grid_top_frequency(time_step):
    """Default top of the kernels' frequency grids (Hz): :data:`TOP_ALIASES` / dt."""
    return TOP_ALIASES / time_step


def moving_kernel(waveguide, speed, time_step, duration=None, max_frequency=None,
                  tolerance=None, max_duration=1.0, split_frequency=300.0, top_frequency=None):
    """Moving Green's kernel of the rail at the contact patch.

    The kernel is the sum of parts from a smooth partition of the spectrum
    (:func:`band_partition`) with crossovers at ``split_frequency`` and ``max_frequency``:
    the low band (the support resonances and the creep of the causal pad model) lasts
    longest but needs frequencies up to 1.5 split_frequency only; the high band up to
    1.5 max_frequency decays within tens of ms and needs only a coarse frequency grid
    (df = 1 / (2 T_high)); the top band from max_frequency / 2 to ``top_frequency``
    (:func:`grid_top_frequency`; the reduced model's continuation, see the module docstring)
    decays within a few ms and is integrated on a still coarser grid. Each part's length is
    found by doubling until the last quarter of it is below ``tolerance`` times its peak, so
    the tens of thousands of eigenproblems of a single fine grid up to ``top_frequency`` are
    not needed.

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
        Crossover (Hz) between the high band and the coarse top band; default
        ``min(track.max_frequency, 1/dt)``, the range of the reduced model's basis.
    tolerance : float, optional
        Default ``track.kernel_tolerance``.
    max_duration : float
        Upper limit of the automatic duration (s).
    split_frequency : float or None
        Centre (Hz) of the crossover between the low and the high band; ``None`` or 0 uses one
        fine grid up to ``top_frequency`` (slower; the reference for the split).
    top_frequency : float, optional
        Upper end (Hz) of the frequency grid; default :func:`grid_top_frequency` (8 / dt).
        ``top_frequency=max_frequency`` gives the former grid (no top band), whose spectrum
        lacks the aliases and whose Im part is too large below max_frequency (module
        docstring).

    Returns
    -------
    dict
        ``kernel`` (nt, 3, 3) m/N; ``time`` (nt,) s; ``frequency`` (nf,) Hz of the spectrum;
        ``moving_receptance`` (nf, 3, 3) m/N, the kernel's spectrum (DTFT) divided by the
        first-order-hold factor, below 1/(2 dt): G~ plus its aliases
        ``sum_{j != 0} G~(omega + j omega_s) S(omega + j omega_s) / S(omega)`` (S = sinc^2);
        ``static_compliance`` (3, 3) m/N = sum of the kernel; ``tail`` relative size of the
        last quarter; ``speed``, ``time_step``; ``solve_frequency`` (Hz) the frequencies
        at which the waves were computed; ``high_band_duration`` (s); ``bands``: list of
        (lowest, highest frequency (Hz), duration (s)) of every band, low band last;
        ``top_frequency`` (Hz).
    """
    speed, dt = _check(speed, time_step)
    track = waveguide.track
    tol = track.kernel_tolerance if tolerance is None else tolerance
    fmax = min(track.max_frequency, 1.0 / dt) if max_frequency is None else float(max_frequency)
    f_end = grid_top_frequency(dt) if top_frequency is None else float(top_frequency)
    f_end = max(f_end, fmax) if top_frequency is None else f_end
    length = track.load_patch_length
    t_max = max_duration if duration is None else float(duration)
    # crossovers whose ramp lies inside the grid: low | high (| top)
    splits = []
    if split_frequency and 1.5 * split_frequency < min(fmax, f_end):
        splits.append(float(split_frequency))
        for c in (fmax,) + tuple(a / dt for a in TOP_SPLITS):
            if c > splits[-1] and 1.5 * c < f_end:
                splits.append(c)
    cache = {}

    def part(t_len, k):
        """Kernel (nt, 3, 3) of length t_len from band k (of len(splits) + 1)."""
        nt = int(round(t_len / dt))
        df = 1.0 / (2 * t_len)  # time period 2 T: no wrap-around inside the kernel
        f_top = 1.5 * splits[k] if k < len(splits) else f_end
        f = np.arange(int(round(f_top / df)) + 1) * df
        band = band_partition(f, splits)[k]
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

    # the bands above the low one: short, on coarse grids; the top bands start shorter
    upper, bands = [], []
    ref_peak = 0.0
    for k in range(1, len(splits) + 1):
        t0, n0 = BAND_START[min(k, len(BAND_START)) - 1]
        t_band = min(max(t0, n0 * dt), t_max)
        while True:
            ker = part(t_band, k)
            # relative to the largest peak of the bands below at least (the high band: the
            # fast part of the kernel); the top bands' own peaks are small
            peak = max(np.abs(ker).max(), ref_peak)
            tail = tail_of(ker, peak)
            logger.info("moving kernel, band %d above %.0f Hz: T=%.4f s, tail/peak=%.2e", k,
                        splits[k - 1] / 2, t_band, tail)
            if tail < tol or 2 * t_band > t_max:
                break
            t_band *= 2
        upper.append(ker)
        ref_peak = max(ref_peak, peak)
        bands.append((splits[k - 1] / 2, 1.5 * splits[k] if k < len(splits) else f_end, t_band))
    # low band (or everything without a split): fine grid
    longest = max((len(u) for u in upper), default=0) * dt
    t_len = min(max(0.05, longest), t_max) if duration is None else t_max
    while True:
        ker = part(t_len, 0)
        for u in upper:
            n = min(len(u), len(ker))
            ker[:n] += u[:n]
        peak = np.abs(ker).max()
        tail = tail_of(ker, peak)
        logger.info("moving kernel: T=%.3f s, %d frequencies solved, tail/peak=%.2e", t_len,
                    len(cache), tail)
        if duration is not None or tail < tol or 2 * t_len > max_duration:
            if duration is None and tail >= tol:
                logger.warning("moving kernel tail %.2e above tolerance at %.2f s", tail, t_len)
            break
        t_len *= 2
    bands.append((0.0, 1.5 * splits[0] if splits else f_end, t_len))
    nt = len(ker)
    nfft = 2 * nt
    spec = np.fft.rfft(ker, n=nfft, axis=0) * 1.0  # sum_m k[m] exp(-i w m dt)
    fgrid = np.fft.rfftfreq(nfft, dt)
    sfac = foh_factor(2 * np.pi * fgrid, dt)
    moving = spec / sfac[:, None, None]
    return {"kernel": ker, "time": np.arange(nt) * dt, "frequency": fgrid,
            "moving_receptance": moving, "static_compliance": ker.sum(axis=0), "tail": tail,
            "speed": speed, "time_step": dt, "solve_frequency": np.array(sorted(cache)),
            "high_band_duration": bands[0][2] if upper else 0.0, "bands": bands,
            "top_frequency": f_end}
