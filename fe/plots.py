"""Figures of the wheel's finite-element results (matplotlib, Agg canvas, no pyplot global state).

* :func:`plot_wheel_receptance` — point receptances of the stationary wheel at the contact.
* :func:`plot_receptance_comparison` — the paper's Figure 1: |H_yy| (dB re 1 m/N) of the
  stationary wheel, the stationary wheel with a moving load and the Eulerian rotating wheel.
* :func:`plot_split_zooms` — the same curves zoomed around chosen split pairs.
* :func:`plot_campbell` — split pole frequencies of chosen pairs against speed.
"""

from __future__ import annotations

import logging

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from interaction.wheel_models import wheel_models

logger = logging.getLogger(__name__)

_STYLE = {model.short_label: model.receptance_style for model in wheel_models()}
"""Line properties of each wheel model's receptance curves, by short label (:mod:`interaction.wheel_models`)."""


def _figure(figsize):
    """A matplotlib Figure drawn by the Agg canvas (PNG output without pyplot)."""
    fig = Figure(figsize=figsize)
    FigureCanvasAgg(fig)
    return fig


def receptance_db(h, i=1, j=1):
    """``20 log10 |H_ij|`` in dB re 1 m/N from receptances (nf, 3, 3) (m/N)."""
    return 20.0 * np.log10(np.maximum(np.abs(np.asarray(h)[:, i, j]), 1e-300))


def plot_wheel_receptance(frequency_hz, receptance, path, f_min, f_max, dpi=120):
    """Wheel point receptances at the contact (vertical, lateral, cross) in dB re 1 m/N.

    Parameters
    ----------
    frequency_hz : (nf,) ndarray
        Hz.
    receptance : (nf, 3, 3) ndarray
        Contact-frame receptance of the stationary wheel, m/N.
    path : str or Path
        Output PNG.
    f_min, f_max : float
        Frequency range shown, Hz.
    dpi : int
        Resolution of the PNG.
    """
    f = np.asarray(frequency_hz)
    keep = (f >= f_min) & (f <= f_max)
    h = np.asarray(receptance)[keep]
    fig = _figure(figsize=(8, 4.5))
    ax = fig.add_subplot(1, 1, 1)
    for (i, j), label in (((2, 2), "vertical $H_{zz}$"), ((1, 1), "lateral $H_{yy}$"), ((1, 2), "cross $H_{yz}$")):
        ax.semilogx(f[keep], 20 * np.log10(np.abs(h[:, i, j]) + 1e-30), label=label, lw=0.8)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("receptance (dB re 1 m/N)")
    ax.set_title("Wheel point receptance at the contact point (stationary wheel)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)


def plot_receptance_comparison(frequency_hz, curves, path, title="", component=(1, 1), ax=None):
    """Plot |H_ij| (dB re 1 m/N) of several models on one axis.

    Parameters
    ----------
    frequency_hz : (nf,) array_like
        Hz.
    curves : dict[str, (nf, 3, 3) ndarray]
        Receptances (m/N) by label (the wheel models' short labels get their styles, :mod:`interaction.wheel_models`).
    path : str or Path or None
        Output PNG (None: draw on ``ax`` only).
    title : str
    component : (int, int)
        Contact-frame indices (1, 1) = lateral.
    ax : matplotlib Axes, optional

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = None
    if ax is None:
        fig = _figure(figsize=(8, 4.5))
        ax = fig.add_subplot(1, 1, 1)
    for label, h in curves.items():
        ax.plot(frequency_hz, receptance_db(h, *component), label=label, **_STYLE.get(label, {}))
    ax.set_xlabel("Frequency (Hz)")
    ax.set_ylabel(f"|H_{'xyz'[component[0]]}{'xyz'[component[1]]}| (dB re 1 m/N)")
    ax.set_title(title)
    ax.grid(True, lw=0.3)
    ax.legend(loc="lower right", fontsize=8)
    fig = fig or ax.figure
    if path is not None:
        fig.tight_layout()
        fig.savefig(path, dpi=150)
        logger.info("wrote %s", path)
    return fig


def plot_split_zooms(frequency_hz, curves, centres_hz, half_width_hz, path, component=(1, 1)):
    """Zooms of :func:`plot_receptance_comparison` around ``centres_hz`` (Hz), ±``half_width_hz``."""
    centres = np.atleast_1d(centres_hz)
    cols = min(3, centres.size)
    rows = int(np.ceil(centres.size / cols))
    fig = _figure(figsize=(4 * cols, 3.2 * rows))
    axes = fig.subplots(rows, cols, squeeze=False)
    f = np.asarray(frequency_hz)
    for ax, fc in zip(axes.ravel(), centres):
        sel = np.abs(f - fc) <= half_width_hz
        plot_receptance_comparison(f[sel], {k: np.asarray(v)[sel] for k, v in curves.items()}, None,
                                   title=f"around {fc:.0f} Hz", component=component, ax=ax)
    for ax in axes.ravel()[centres.size:]:
        ax.set_visible(False)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    logger.info("wrote %s", path)
    return fig


def split_branches(poles, centre_hz, n, spin):
    """Frequencies (Hz) of the poles nearest ``centre ± nΩ/2π`` (the two branches of a split pair).

    Parameters
    ----------
    poles : (p,) complex array_like
        rad/s.
    centre_hz : float
        Stationary frequency of the pair, Hz.
    n : int
        Nodal diameters.
    spin : float
        rad/s.

    Returns
    -------
    (2,) ndarray
        Hz: lower and upper branch.
    """
    f = np.abs(np.asarray(poles).imag) / (2.0 * np.pi)
    out = []
    for sign in (-1, 1):
        target = abs(centre_hz + sign * n * spin / (2.0 * np.pi))
        out.append(f[np.argmin(np.abs(f - target))])
    return np.array(out)


def plot_campbell(speeds_kmh, branches, titles, path):
    """Split pole frequencies against rolling speed, one panel per mode pair.

    Parameters
    ----------
    speeds_kmh : (ns,) array_like
        km/h.
    branches : dict[str, (k, ns, 2) ndarray]
        For each model label, the lower/upper branch frequency (Hz) of k pairs at each speed.
    titles : sequence of str
        Panel titles (k).
    path : str or Path
    """
    k = len(titles)
    fig = _figure(figsize=(4 * k, 3.6))
    axes = fig.subplots(1, k, squeeze=False)
    for i, ax in enumerate(axes.ravel()):
        for label, data in branches.items():
            for b in range(2):
                ax.plot(speeds_kmh, np.asarray(data)[i, :, b], label=label if b == 0 else None,
                        **_STYLE.get(label, {}))
        ax.set_xlabel("Speed (km/h)")
        ax.set_ylabel("Peak frequency (Hz)")
        ax.set_title(titles[i])
        ax.grid(True, lw=0.3)
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=150)
    logger.info("wrote %s", path)
    return fig
