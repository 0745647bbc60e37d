"""Forced response of the rail: receptances along the rail by the wave (residue) sum, and a
direct wavenumber-integration check.

The load is uniform over the patch (width ``load_patch_width`` across the head top,
length ``L = load_patch_length`` along the rail, centred at x = 0); the response is the
displacement at distance x >= 0 on the rail axis through the patch centre, averaged across
the patch width. In the contact frame (x along the rail, y lateral, z up),
``H[i, j]`` (m/N) is the displacement in i due to a unit total force in j.

For a point force at s the response at x > s is ``sum_n q_n exp(-i kappa_n (x - s))`` and
at x < s it is ``sum_n S q_n S exp(-i kappa_n (s - x))`` with ``S = diag(-1, 1, 1)``
(mirror symmetry of the rail in x). Integrating over the patch gives, per wave,

* x >= L/2: ``q_n exp(-i kappa x) sin(kappa L/2) / (kappa L/2)``
* 0 <= x < L/2: ``q_n (1 - exp(-i kappa (x + L/2))) / (i kappa L)
  + S q_n S (1 - exp(-i kappa (L/2 - x))) / (i kappa L)``.
"""

from __future__ import annotations

import logging

import numpy as np

logger = logging.getLogger(__name__)

__all__ = ["patch_factors", "wave_sum", "receptance_along", "wavenumber_integral"]

_S = np.array([-1.0, 1.0, 1.0])


def patch_factors(kappa, distances, length):
    """Longitudinal patch factors of each wave at each distance.

    Parameters
    ----------
    kappa : ndarray (n,)
        Wavenumbers (rad/m), Im <= 0.
    distances : ndarray (n_x,)
        x >= 0 (m).
    length : float
        Patch length L (m), > 0.

    Returns
    -------
    forward, backward : ndarray (n_x, n)
        Factors multiplying ``q_n`` and ``S q_n S``.
    """
    k = np.asarray(kappa)[None, :]
    x = np.asarray(distances, float)[:, None]
    half = length / 2
    kl = k * length
    small = np.abs(kl) < 1e-6
    kl_safe = np.where(small, 1.0, kl)
    inside = x < half
    with np.errstate(over="ignore", invalid="ignore"):
        sinc = np.where(small, 1.0, np.sin(k * half) / np.where(small, 1.0, k * half))
        fwd_out = np.exp(-1j * k * x) * sinc
        xi = np.minimum(x, half)
        fwd_in = np.where(small, (xi + half) / length, (1 - np.exp(-1j * k * (xi + half))) / (1j * kl_safe))
        bwd_in = np.where(small, (half - xi) / length, (1 - np.exp(-1j * k * (half - xi))) / (1j * kl_safe))
    fwd = np.where(inside, fwd_in, fwd_out)
    bwd = np.where(inside, bwd_in, 0.0)
    return fwd, bwd


def wave_sum(waves, distances, length):
    """Receptance at distances x >= 0 from the waves of one frequency.

    Parameters
    ----------
    waves : waveguide.waves.Waves
    distances : array_like (n_x,)
        m, >= 0.
    length : float
        Patch length (m).

    Returns
    -------
    ndarray (n_x, 3, 3) complex, m/N
    """
    fwd, bwd = patch_factors(waves.kappa, distances, length)
    q = waves.q
    qm = q * _S[None, :, None] * _S[None, None, :]
    return np.einsum("xn,nij->xij", fwd, q) + np.einsum("xn,nij->xij", bwd, qm)


def receptance_along(waveguide, frequencies, distances, wave_list=None):
    """Receptance H(x, f) along the rail by the wave sum.

    Parameters
    ----------
    waveguide : waveguide.waves.RailWaveguide
    frequencies : array_like (nf,)
        Hz, > 0.
    distances : array_like (n_x,)
        m, >= 0.
    wave_list : list of waveguide.waves.Waves, optional
        The waves at ``frequencies`` if already computed.

    Returns
    -------
    ndarray (n_x, nf, 3, 3) complex
        m/N, contact frame.
    """
    f = np.atleast_1d(np.asarray(frequencies, float))
    x = np.atleast_1d(np.asarray(distances, float))
    out = np.empty((len(x), len(f), 3, 3), complex)
    length = waveguide.track.load_patch_length
    for i, fi in enumerate(f):
        w = waveguide.waves(2 * np.pi * fi) if wave_list is None else wave_list[i]
        out[:, i] = wave_sum(w, x, length)
    return out


def wavenumber_integral(solve, distances, length, kappa_max, breakpoints=(), n_per_panel=64,
                        panel_width=None, vectorized=False):
    """Direct numerical evaluation of H(x) = 1/(2 pi) int H^(kappa) exp(-i kappa x) dkappa.

    A second method for checking the wave sum: composite Gauss-Legendre quadrature over
    real kappa in [-kappa_max, kappa_max], with panels refined around ``breakpoints``
    (e.g. +-Re kappa of lightly damped waves).

    Parameters
    ----------
    solve : callable
        ``solve(kappa) -> (3, 3)`` complex wavenumber-domain receptance for a point force
        spread across the patch width (m/N per (1/m)).
    distances : array_like (n_x,)
    length : float
        Patch length (m); the force spectrum is ``sin(kappa L/2) / (kappa L/2)``.
    kappa_max : float
        Truncation (rad/m).
    breakpoints : sequence of (centre, half_width)
        Refine panels to ``half_width / 8`` within ``centre +- half_width``.
    n_per_panel : int
        Gauss points per panel.
    panel_width : float, optional
        Panel width (rad/m) up to 100 panel widths; geometrically growing panels beyond.
    vectorized : bool
        ``solve`` takes all wavenumbers at once, ``solve(kappa (nk,)) -> (nk, 3, 3)``
        (e.g. :meth:`waveguide.waves.RailWaveguide.receptance_kappa_many`).

    Returns
    -------
    ndarray (n_x, 3, 3)
    """
    x = np.atleast_1d(np.asarray(distances, float))
    pw = panel_width or kappa_max / 40
    kb = min(kappa_max, 100 * pw)  # uniform panels up to kb, geometric panels beyond
    edges = set(np.linspace(-kb, kb, int(np.ceil(2 * kb / pw)) + 1).tolist())
    if kappa_max > kb:
        tail = np.geomspace(kb, kappa_max, 40)
        edges.update(tail.tolist())
        edges.update((-tail).tolist())
    for c, hw in breakpoints:
        for sgn in (1, -1):
            edges.update((sgn * c + np.linspace(-hw, hw, 17)).tolist())
    edges = np.array(sorted(e for e in edges if -kappa_max <= e <= kappa_max))
    g, w = np.polynomial.legendre.leggauss(n_per_panel)
    a, b = edges[:-1], edges[1:]
    kap = (0.5 * (b - a)[:, None] * g[None, :] + 0.5 * (a + b)[:, None]).ravel()
    wk = (0.5 * (b - a)[:, None] * w[None, :]).ravel()
    hk = np.asarray(solve(kap)) if vectorized else np.array([solve(k) for k in kap])  # (nk, 3, 3)
    kl = kap * length / 2
    sinc = np.where(np.abs(kl) < 1e-12, 1.0, np.sin(kl) / np.where(np.abs(kl) < 1e-12, 1, kl))
    phase = np.exp(-1j * np.outer(x, kap)) * (wk * sinc)[None, :]
    return phase @ hk.reshape(len(kap), 9) / (2 * np.pi)
