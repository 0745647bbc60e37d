"""Figures of the radiation: one-third octave spectra per wheel model, radiation efficiencies."""

from __future__ import annotations

from collections import defaultdict

import numpy as np
from matplotlib import colormaps
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from radiation.efficiency import wheel_axial_efficiency
from interaction.wheel_models import wheel_models
from radiation.grouping import case_key

DISPLAY_RANGE = 80.0
"""dB shown below the loudest band of a panel."""



def plot_band_spectra(results, path, dpi=120):
    """L_pA per one-third octave band at the receiver, one panel per operating point, one line per
    wheel model. ``results``: dicts of stages.radiation.read_radiation. Returns the path."""
    groups = defaultdict(dict)
    for r in results:
        groups[case_key(r["case_id"])][r["wheel_model"]] = r
    keys = sorted(groups)
    fig = Figure(figsize=(7, 2.6 * max(len(keys), 1)))
    FigureCanvasAgg(fig)
    axes = fig.subplots(max(len(keys), 1), 1, squeeze=False, sharex=True)
    for ax, key in zip(axes[:, 0], keys):
        for model in wheel_models():
            name = model.name
            r = groups[key].get(name)
            if r is None:
                continue
            colour, style = model.spectrum_style
            level = np.where(np.isfinite(r["band_LpA"]), r["band_LpA"], np.nan)
            ax.semilogx(r["band_centres"], level, color=colour, linestyle=style, marker="o", markersize=3,
                        label=f"{name}: {r['L_pA']:.1f} dB(A)")
        tops = [np.nanmax(r["band_LpA"]) for r in groups[key].values() if np.isfinite(r["band_LpA"]).any()]
        if tops:
            ax.set_ylim(max(tops) - DISPLAY_RANGE, max(tops) + 5.0)
        ax.set_title(key, fontsize=8)
        ax.set_ylabel("L_pA (dB(A))")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    axes[-1, 0].set_xlabel("one-third octave band (Hz)")
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    return path


def plot_efficiency_comparison(radius, bem_rows, path, dpi=120):
    """Axial radiation efficiency of the fast model (lines) and the BEM (markers) per n.

    Parameters
    ----------
    radius : float
        Wheel radius, m.
    bem_rows : list of dict
        Rows of :func:`radiation.bem_compare.compare_axial_modes` (``n``, ``frequency`` Hz,
        ``sigma_bem``, ``sigma_fast``: effective efficiencies of the mode, axial and radial
        surfaces together); may be empty.
    path : path
        Figure file.
    """
    fig = Figure(figsize=(7, 4))
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    f = np.logspace(np.log10(100.0), np.log10(10000.0), 300)
    colours = colormaps["viridis"](np.linspace(0, 1, 8))
    for n in range(8):
        ax.loglog(f, wheel_axial_efficiency(f, n, radius), color=colours[n], label=f"n = {n}")
        rows = [row for row in bem_rows if row["n"] == n]
        if rows:
            x = [row["frequency"] for row in rows]
            ax.loglog(x, [row["sigma_bem"] for row in rows], "o", color=colours[n])
            ax.loglog(x, [row["sigma_fast"] for row in rows], "x", color=colours[n])
    ax.set_ylim(1e-4, 3)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("radiation efficiency σ_ax")
    ax.set_title("axial modes: σ_ax of the fast model (lines); modes: BEM (o), fast (x)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=dpi)
    return path
