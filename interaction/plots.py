"""The paper's result figures from case summaries and histories (matplotlib, Agg canvas, no
pyplot global state).

- :func:`plot_force_level` (the paper's Figure 2): ``L_F2`` over the friction × lateral-creepage
  grid for the stationary wheel.
- :func:`plot_level_difference` (Figure 3): ``L_F2 − L_F2,stat`` for the moving-load and the
  Eulerian wheel.
- :func:`plot_lateral_force` (Figure 4): lateral force of one case for the three wheel models:
  time series, zoom, power spectrum.

A case summary is a dict with at least ``friction``, ``lateral_creepage``, ``wheel_model``,
``L_F2`` and ``squeal``.
"""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

MODEL_STYLE = {
    "stationary": dict(color="0.25", ls="--", label="stationary wheel"),
    "moving_load": dict(color="0.65", ls="-", label="stationary wheel, moving load"),
    "eulerian": dict(color="k", ls="-", label="rotating wheel (Eulerian)"),
}


def _grid(summaries, model):
    rows = [s for s in summaries if s["wheel_model"] == model]
    frictions = sorted({s["friction"] for s in rows})
    creepages = sorted({s["lateral_creepage"] for s in rows}, key=abs)
    table = np.full((len(frictions), len(creepages)), np.nan)
    squeal = np.zeros_like(table, dtype=bool)
    for s in rows:
        i, j = frictions.index(s["friction"]), creepages.index(s["lateral_creepage"])
        table[i, j] = s["L_F2"]
        squeal[i, j] = bool(s["squeal"])
    return frictions, creepages, table, squeal


def _bars(ax, frictions, creepages, values, squeal=None, ylabel=""):
    width = 0.8 / max(len(frictions), 1)
    x = np.arange(len(creepages))
    for i, mu in enumerate(frictions):
        bars = ax.bar(x + (i - (len(frictions) - 1) / 2) * width, values[i], width, label=f"μ = {mu:g}",
                      color=f"C{i}")
        if squeal is not None:
            for bar, s in zip(bars, squeal[i]):
                if s:
                    bar.set_hatch("//")
    ax.set_xticks(x, [f"{100 * c:g} %" for c in creepages])
    ax.set_xlabel("lateral creepage η")
    ax.set_ylabel(ylabel)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend()


def _save(fig, path, dpi):
    FigureCanvasAgg(fig)
    fig.tight_layout()
    fig.savefig(str(path), dpi=dpi)


def plot_force_level(summaries, path, dpi=120):
    """``L_F2`` of the stationary wheel over friction × creepage (hatched: squeal)."""
    frictions, creepages, table, squeal = _grid(summaries, "stationary")
    fig = Figure(figsize=(7, 4))
    ax = fig.add_subplot(1, 1, 1)
    _bars(ax, frictions, creepages, table, squeal, "$L_{F2}$ (dB re 1 N)")
    ax.set_title("Fig. 2: force level, stationary wheel (hatched: squeal)")
    _save(fig, path, dpi)


def plot_level_difference(summaries, path, dpi=120):
    """``L_F2 − L_F2,stat`` for the moving-load (a) and Eulerian (b) wheel."""
    frictions, creepages, stationary, _ = _grid(summaries, "stationary")
    fig = Figure(figsize=(11, 4))
    for k, model in enumerate(("moving_load", "eulerian")):
        ax = fig.add_subplot(1, 2, k + 1)
        f2, c2, table, squeal = _grid(summaries, model)
        if f2 == frictions and c2 == creepages:
            _bars(ax, frictions, creepages, table - stationary, squeal, "$L_{F2} - L_{F2,stat}$ (dB)")
        ax.set_title(f"Fig. 3{'ab'[k]}: {MODEL_STYLE[model]['label']}")
    _save(fig, path, dpi)


def plot_lateral_force(histories, path, zoom=0.01, dpi=120):
    """Lateral force of one case for several wheel models.

    Parameters
    ----------
    histories : dict
        wheel model -> (time (nt,) s, lateral force (nt,) N).
    path : str or Path
    zoom : float
        Length of the zoomed window at the end, s.
    """
    fig = Figure(figsize=(8, 9))
    ax_t, ax_z, ax_s = (fig.add_subplot(3, 1, k) for k in (1, 2, 3))
    for model, (t, f) in histories.items():
        style = MODEL_STYLE.get(model, dict(label=model))
        ax_t.plot(t, f / 1e3, lw=0.5, **style)
        tail = t >= t[-1] - zoom
        ax_z.plot(t[tail], f[tail] / 1e3, lw=0.8, **style)
        dt = t[1] - t[0]
        window = f[-int(round(0.15 / dt)):]
        x = (window - window.mean()) * np.hanning(window.size)
        psd = np.abs(np.fft.rfft(x)) ** 2 * 2 * dt / np.sum(np.hanning(window.size) ** 2)
        freq = np.fft.rfftfreq(window.size, dt)
        ax_s.semilogy(freq, psd + 1e-30, lw=0.7, **style)
    ax_t.set_xlabel("time (s)")
    ax_t.set_ylabel("$F_2$ (kN)")
    ax_t.set_title("Fig. 4a: lateral contact force")
    ax_t.legend(fontsize=8)
    ax_z.set_xlabel("time (s)")
    ax_z.set_ylabel("$F_2$ (kN)")
    ax_z.set_title("Fig. 4b: zoom")
    ax_s.set_xlabel("frequency (Hz)")
    ax_s.set_ylabel("PSD (N²/Hz)")
    ax_s.set_xlim(0, 7000)
    ax_s.set_title("Fig. 4c: power spectrum of the last 0.15 s")
    _save(fig, path, dpi)
