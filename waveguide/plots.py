"""Figures of the rail waveguide results (matplotlib, Agg canvas, no pyplot global state)."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from waveguide.waves import LABELS

__all__ = ["plot_dispersion", "plot_receptances", "plot_kernel"]

_COLOURS = {"longitudinal": "tab:green", "lateral": "tab:blue", "vertical": "tab:red",
            "torsion": "tab:purple", "section": "0.6"}


def _figure(figsize):
    """A matplotlib Figure drawn by the Agg canvas (PNG output without pyplot)."""
    fig = Figure(figsize=figsize)
    FigureCanvasAgg(fig)
    return fig


def plot_dispersion(disp, path, max_decay_db=60.0):
    """Dispersion curves (Re kappa) and decay rates (dB/m) of the waves decaying less than
    ``max_decay_db`` dB/m, coloured by dominant motion. ``disp`` is the dict of
    :func:`waveguide.waves.dispersion`."""
    f, k, lab = disp["frequency"], disp["wavenumber"], disp["label"]
    decay = disp["decay"]
    fig = _figure(figsize=(10, 4))
    a1, a2 = fig.subplots(1, 2)
    for name_i, name in enumerate(LABELS):
        sel = (lab == name_i) & (decay < max_decay_db)
        ff = np.broadcast_to(f[:, None], k.shape)[sel]
        a1.plot(ff, np.abs(k.real[sel]), ".", ms=2, color=_COLOURS[name], label=name)
        a2.semilogy(ff, decay[sel], ".", ms=2, color=_COLOURS[name], label=name)
    a1.set_xlabel("frequency (Hz)")
    a1.set_ylabel("Re kappa (rad/m)")
    a2.set_xlabel("frequency (Hz)")
    a2.set_ylabel("decay (dB/m)")
    a1.legend(markerscale=4, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_receptances(frequency, receptance, distance, path):
    """Point and transfer receptances (vertical zz, lateral yy, cross yz) in dB re 1 m/N over
    log frequency. ``receptance`` (n_x, nf, 3, 3), ``distance`` (n_x,) m."""
    fig = _figure(figsize=(13, 4))
    axes = fig.subplots(1, 3, sharey=True)
    for ax, (i, j, name) in zip(axes, ((2, 2, "vertical zz"), (1, 1, "lateral yy"), (1, 2, "cross yz"))):
        for ix, x in enumerate(distance):
            ax.semilogx(frequency, 20 * np.log10(np.abs(receptance[ix, :, i, j]) + 1e-30),
                        label=f"x = {x:.2f} m")
        ax.set_title(name)
        ax.set_xlabel("frequency (Hz)")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("receptance (dB re 1 m/N)")
    axes[0].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def plot_kernel(result, path):
    """The moving Green's kernel (zz, yy, yz components) against time; ``result`` is the
    dict of :func:`waveguide.greens.moving_kernel`."""
    t, k = result["time"], result["kernel"]
    fig = _figure(figsize=(7, 4))
    ax = fig.add_subplot(1, 1, 1)
    for i, j, name in ((2, 2, "zz"), (1, 1, "yy"), (1, 2, "yz"), (0, 0, "xx")):
        ax.plot(t * 1e3, k[:, i, j], label=name)
    ax.set_xlabel("time (ms)")
    ax.set_ylabel("kernel (m/N)")
    ax.set_title(f"moving kernel, v = {result['speed']:.2f} m/s, dt = {result['time_step'] * 1e6:.0f} us")
    ax.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=120)
