"""The report.md section on the radiated sound: does rotation change it, by how much, where."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from radiation.bands import nominal_label
from radiation.grouping import MODEL_ORDER, case_key
from radiation.plots import plot_band_spectra
from squealcore.artefacts import ArtefactError, atomic_output
from stages.radiation import read_radiation

RELEVANT_RANGE = 30.0
"""dB below the loudest band: quieter bands are left out of the "band of largest change"."""


def collect(paths):
    """Read radiation artefacts (unreadable ones skipped): list of dicts (stages/radiation.read_radiation)."""
    out = []
    for path in paths:
        try:
            out.append(read_radiation(path))
        except (ArtefactError, OSError):
            continue
    return out


def radiation_section(paths):
    """Markdown of the report's radiation section from the cases' radiation artefacts.

    Parameters
    ----------
    paths : iterable of path
        ``radiation/<id>.h5`` files.

    Returns
    -------
    str
        A ``## Radiated sound`` section: per case L_W and L_pA, and per operating point the change
        from the stationary to the rotating models, overall and in the band where it is largest.
    """
    results = collect(paths)
    lines = ["## Radiated sound", ""]
    if not results:
        return "\n".join(lines + ["No radiation artefacts (the radiation stage failed for every case).", ""])
    lines += ["Sound power L_W (dB re 1 pW, wheel + rail) and A-weighted pressure L_pA (dB(A)) at the pass-by",
              "position (7.5 m, 1.2 m; omnidirectional wheel, hard ground): fast model, docs/design.md \"Radiation\".", "",
              "| case | wheel model | L_W | L_W wheel | L_W rail | L_pA |", "|---|---|---|---|---|---|"]
    for r in sorted(results, key=lambda r: r["case_id"]):
        lines.append(f"| {r['case_id']} | {r['wheel_model']} | {r['L_W']:.1f} | {r['L_W_wheel']:.1f} | "
                     f"{r['L_W_rail']:.1f} | {r['L_pA']:.1f} |")
    groups = defaultdict(dict)
    for r in results:
        groups[case_key(r["case_id"])][r["wheel_model"]] = r
    rows = []
    for key, models in sorted(groups.items()):
        base = models.get("stationary")
        if base is None:
            continue
        for name in MODEL_ORDER[1:]:
            other = models.get(name)
            if other is None:
                continue
            diff = other["band_LpA"] - base["band_LpA"]
            loudest = np.fmax(other["band_LpA"], base["band_LpA"])
            # only bands that matter: within RELEVANT_RANGE dB of the loudest band of either model
            finite = np.isfinite(diff) & (loudest >= np.nanmax(loudest) - RELEVANT_RANGE)
            if finite.any():
                b = int(np.nanargmax(np.where(finite, np.abs(diff), np.nan)))
                band = f"{nominal_label(base['band_centres'][b])} Hz ({diff[b]:+.1f} dB)"
            else:
                band = "-"
            rows.append(f"| {key} | {name} | {other['L_pA'] - base['L_pA']:+.1f} | "
                        f"{other['L_W'] - base['L_W']:+.1f} | {band} |")
    if rows:
        lines += ["", ("**Does rotation change the radiated sound?** Change from the stationary wheel to each "
                       "rotating model at the same operating point:"), "",
                  "| operating point | model | ΔL_pA (dB) | ΔL_W (dB) | band of largest change |", "|---|---|---|---|---|"]
        lines += rows
    lines.append("")
    return "\n".join(lines)


SPECTRA_FIGURE = "radiation_spectra.png"
"""File name of the one-third octave spectra figure in the report's figure folder."""


def radiation_report(paths, figures, out_dir, dpi=120):
    """The report's radiation part: the section's Markdown lines and the spectra figure.

    Parameters
    ----------
    paths : iterable of path
        ``radiation/<id>.h5`` files of the report's cases.
    figures : Path
        Folder of the report's figures.
    out_dir : Path
        Study folder (the figure link is relative to it).
    dpi : int
        Figure resolution.

    Returns
    -------
    (list of str, list of Path)
        Markdown lines (:func:`radiation_section`, then the figure) and the figures written.
    """
    paths = list(paths)
    lines = radiation_section(paths).splitlines()
    results = collect(paths)
    if not results:
        return lines, []
    figure = Path(figures) / SPECTRA_FIGURE
    with atomic_output(figure) as tmp:
        plot_band_spectra(results, tmp, dpi)
    link = figure.relative_to(out_dir).as_posix()
    return lines + [f"![one-third octave spectra at the receiver, per wheel model]({link})", ""], [figure]
