"""The paper's result figures from case summaries and histories (matplotlib, Agg canvas, no
pyplot global state).

- :func:`plot_force_level` (the paper's Figure 2): ``L_F2`` over the friction × lateral-creepage
  grid for the stationary wheel.
- :func:`plot_level_difference` (Figure 3): ``L_F2 − L_F2,stat`` for the moving-load and the
  Eulerian wheel.
- :func:`plot_variant_comparison`: structural variants of a sweep (e.g. wheel radii) compared:
  wheel mode frequencies, squeal frequency and ``L_F2`` against the swept value.
- :func:`plot_lateral_force` (Figure 4): lateral force of one case for the three wheel models:
  time series, zoom, power spectrum.

A case summary is a dict with at least ``friction``, ``lateral_creepage``, ``wheel_model``,
``L_F2`` and ``squeal``.
"""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from interaction.wheel_models import REFERENCE, rotating_names, wheel_model




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


def plot_force_level(summaries, path, dpi=120, variant_titles=None):
    """``L_F2`` of the stationary wheel over friction × creepage (hatched: squeal).

    Parameters
    ----------
    summaries : list of dict
        Case summaries.
    path : str or Path
        Output PNG.
    dpi : int
    variant_titles : dict, optional
        ``{variant name: title}`` of a study with several structural variants (summaries carry
        ``variant``): one panel per variant, in this order, on a common level axis.

    Returns
    -------
    matplotlib.figure.Figure
        The figure drawn (its panels carry the variant titles).
    """
    if not variant_titles:
        frictions, creepages, table, squeal = _grid(summaries, REFERENCE)
        fig = Figure(figsize=(7, 4))
        ax = fig.add_subplot(1, 1, 1)
        _bars(ax, frictions, creepages, table, squeal, "$L_{F2}$ (dB re 1 N)")
        ax.set_title("Fig. 2: force level, stationary wheel (hatched: squeal)")
        _save(fig, path, dpi)
        return fig
    count = len(variant_titles)
    columns = min(count, 4)
    rows = -(-count // columns)
    fig = Figure(figsize=(3.6 * columns + 0.8, 3.4 * rows + 0.6))
    first = None
    for k, (name, title) in enumerate(variant_titles.items()):
        ax = fig.add_subplot(rows, columns, k + 1, sharey=first)
        first = first or ax
        frictions, creepages, table, squeal = _grid([s for s in summaries if s.get("variant") == name], REFERENCE)
        _bars(ax, frictions, creepages, table, squeal, "$L_{F2}$ (dB re 1 N)" if k % columns == 0 else "")
        ax.set_title(title, fontsize=9)
    fig.suptitle("Fig. 2: force level of the stationary wheel per variant (hatched: squeal)")
    _save(fig, path, dpi)
    return fig


def plot_variant_comparison(x, x_label, mode_curves, case_curves, path, tick_labels=None, dpi=120, mode_styles=None):
    """Structural variants compared: wheel mode frequencies, squeal frequency and ``L_F2`` against
    the swept value.

    Parameters
    ----------
    x : sequence of float
        Position of each variant on the horizontal axis: the swept value (e.g. the rolling radius,
        m), or 0, 1, ... with ``tick_labels``.
    x_label : str
        Label of that axis, with its unit.
    mode_curves : dict
        ``{label: (nv,) frequencies (Hz)}``: one line per mode (e.g. ``"axial n = 4"``).
    case_curves : dict
        ``{label: {"L_F2": (nv,) dB re 1 N, "squeal": (nv,) bool, "squeal_frequency": (nv,) Hz}}``:
        one series per case setting (wheel model, μ, η); NaN where a variant lacks the case.
    path : str or Path
        Output PNG.
    tick_labels : sequence of str, optional
        Names of the variants at ``x`` (a categorical axis).
    dpi : int
    mode_styles : dict, optional
        ``{label: matplotlib line keywords}`` of some mode curves (e.g. dashed, one colour per n).

    Returns
    -------
    matplotlib.figure.Figure
        Panels (a) modes, (b) squeal frequency, (c) level.

    Notes
    -----
    Panel (b) shows the squeal frequency of squealing cases only (filled markers); panel (c) the
    level of every case, filled where it squeals and hollow where it is quiet.
    """
    x = np.asarray(x, dtype=float)
    fig = Figure(figsize=(9.5, 10))
    ax_m = fig.add_subplot(3, 1, 1)
    ax_f, ax_l = (fig.add_subplot(3, 1, k, sharex=ax_m) for k in (2, 3))
    for k, (label, freq) in enumerate(mode_curves.items()):
        style = (mode_styles or {}).get(label, {})
        ax_m.plot(x, np.asarray(freq, dtype=float), **{"marker": "o", "ms": 4, "lw": 1, "color": f"C{k % 10}",
                                                       **style}, label=label)
    ax_m.set_ylabel("frequency (Hz)")
    ax_m.set_title("(a) wheel modes")
    ax_m.legend(fontsize=7, ncol=2, loc="center left", bbox_to_anchor=(1.01, 0.5))
    markers = "osD^v<>p*h"
    for k, (label, curve) in enumerate(case_curves.items()):
        color, marker = f"C{k % 10}", markers[k % len(markers)]
        level = np.asarray(curve["L_F2"], dtype=float)
        squeal = np.asarray(curve["squeal"], dtype=bool)
        frequency = np.where(squeal, np.asarray(curve["squeal_frequency"], dtype=float), np.nan)
        ax_f.plot(x, frequency, marker=marker, color=color, ls="-", lw=1, label=label)
        ax_l.plot(x, level, color=color, lw=0.8, ls=":")
        ax_l.plot(x[squeal], level[squeal], marker, color=color, label=label)
        ax_l.plot(x[~squeal], level[~squeal], marker, color=color, mfc="none")
    ax_f.set_ylabel("squeal frequency (Hz)")
    ax_f.set_title("(b) squeal frequency (squealing cases)")
    ax_l.set_ylabel("$L_{F2}$ (dB re 1 N)")
    ax_l.set_title("(c) force level (filled: squeal, hollow: quiet)")
    for ax in (ax_m, ax_f, ax_l):
        ax.grid(True, alpha=0.3)
        ax.set_xlabel(x_label)
        if tick_labels is not None:
            ax.set_xticks(x, list(tick_labels), fontsize=7)
    if case_curves:
        ax_f.legend(fontsize=7, loc="center left", bbox_to_anchor=(1.01, 0.5))
    _save(fig, path, dpi)
    return fig


def plot_level_difference(summaries, path, dpi=120):
    """``L_F2 − L_F2,stat`` for each rotating wheel model (the paper's Fig. 3: moving load (a), Eulerian (b))."""
    frictions, creepages, stationary, _ = _grid(summaries, REFERENCE)
    rotating = rotating_names()
    fig = Figure(figsize=(5.5 * len(rotating), 4))
    for k, model in enumerate(rotating):
        ax = fig.add_subplot(1, len(rotating), k + 1)
        f2, c2, table, squeal = _grid(summaries, model)
        if f2 == frictions and c2 == creepages:
            _bars(ax, frictions, creepages, table - stationary, squeal, "$L_{F2} - L_{F2,stat}$ (dB)")
        ax.set_title(f"Fig. 3{chr(ord('a') + k)}: {wheel_model(model).label}")
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
        style = wheel_model(model).curve_style
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
