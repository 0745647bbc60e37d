"""The report.md section on the radiated sound: does rotation change it, by how much, where."""

from __future__ import annotations

from collections import defaultdict
from pathlib import Path

import numpy as np

from radiation.bands import nominal_label
from interaction.wheel_models import REFERENCE, wheel_model_names
from radiation.grouping import case_key
from radiation.plots import plot_band_spectra
from squealcore.artefacts import ArtefactError, atomic_output
from stages.radiation import read_radiation

QUIET_LEVEL = 20.0
"""dB(A) at the receiver: an operating point where no wheel model reaches it radiates next to nothing
(a decayed, non-squealing vibration) and is left out of the rotation comparison."""


def collect(paths):
    """Read radiation artefacts (unreadable ones skipped): list of dicts (stages/radiation.read_radiation)."""
    out = []
    for path in paths:
        try:
            out.append(read_radiation(path))
        except (ArtefactError, OSError):
            continue
    return out


def loudest_band(result):
    """``(label, level)`` of the loudest one-third octave band of a result at the receiver, dB(A)."""
    level = np.where(np.isfinite(result["band_LpA"]), result["band_LpA"], -np.inf)
    b = int(np.argmax(level))
    return f"{nominal_label(result['band_centres'][b])} Hz", float(level[b])


def rotation_rows(results, squealing=()):
    """The rotation comparison: per operating point and rotating model, the change from the
    stationary wheel.

    Parameters
    ----------
    results : list of dict
        :func:`stages.radiation.read_radiation` of the cases.
    squealing : collection of str
        Ids of the squealing cases.

    Returns
    -------
    list of dict
        ``point`` (operating point), ``model``, ``squeal`` (stationary, model: bools), ``dL_pA``,
        ``dL_W`` (dB, model minus stationary), ``band`` (loudest band label, level in dB(A): stationary,
        model); operating points where no model reaches :data:`QUIET_LEVEL` are left out.
    """
    groups = defaultdict(dict)
    for r in results:
        groups[case_key(r["case_id"])][r["wheel_model"]] = r
    rows = []
    for key, models in sorted(groups.items()):
        base = models.get(REFERENCE)
        if base is None or max(r["L_pA"] for r in models.values()) < QUIET_LEVEL:
            continue
        for name in wheel_model_names():
            if name == REFERENCE:
                continue
            other = models.get(name)
            if other is None:
                continue
            rows.append({"point": key, "model": name,
                         "squeal": (base["case_id"] in squealing, other["case_id"] in squealing),
                         "dL_pA": other["L_pA"] - base["L_pA"], "dL_W": other["L_W"] - base["L_W"],
                         "band": (loudest_band(base), loudest_band(other))})
    return rows


def _squeal_label(case_id, squealing):
    """``no``, ``yes`` or the label a mapping ``squealing`` gives the case."""
    if case_id not in squealing:
        return "no"
    return squealing[case_id] if isinstance(squealing, dict) else "yes"


def radiation_section(paths, squealing=()):
    """Markdown of the report's radiation section from the cases' radiation artefacts.

    Parameters
    ----------
    paths : iterable of path
        ``radiation/<id>.h5`` files.
    squealing : collection of str
        Ids of the squealing cases (marked in the comparison); a mapping gives each its label in
        the case table (e.g. ``"yes, impact/bouncing"``) instead of ``"yes"``.

    Returns
    -------
    str
        A ``## Radiated sound`` section: per case L_W and L_pA, and per operating point the change
        from the stationary to the rotating models (:func:`rotation_rows`), overall and in the
        loudest band of each.
    """
    results = collect(paths)
    lines = ["## Radiated sound", ""]
    if not results:
        return "\n".join(lines + ["No radiation artefacts (the radiation stage failed for every case).", ""])
    lines += ["Sound power L_W (dB re 1 pW, wheel + rail) and A-weighted pressure L_pA (dB(A)) at the pass-by",
              "position (7.5 m, 1.2 m; omnidirectional wheel, hard ground), over the limit-cycle window of",
              "L_F2: fast model, docs/design.md \"Radiation\". A case that does not squeal has the level of",
              "what it radiates in that window (its decaying vibration).", "",
              "| case | wheel model | squeal | L_W | L_W wheel | L_W rail | L_pA |", "|---|---|---|---|---|---|---|"]
    for r in sorted(results, key=lambda r: r["case_id"]):
        lines.append(f"| {r['case_id']} | {r['wheel_model']} | {_squeal_label(r['case_id'], squealing)} | "
                     f"{r['L_W']:.1f} | {r['L_W_wheel']:.1f} | {r['L_W_rail']:.1f} | {r['L_pA']:.1f} |")
    rows = rotation_rows(results, squealing)
    if rows:
        lines += ["", ("**Does rotation change the radiated sound?** Change from the stationary wheel to each "
                       "rotating model at the same operating point (operating points where no model reaches "
                       f"{QUIET_LEVEL:.0f} dB(A) left out); loudest one-third octave band of each at the "
                       "receiver:"), "",
                  "| operating point | model | squeals (stationary / model) | ΔL_pA (dB) | ΔL_W (dB) | "
                  "loudest band: stationary → model |", "|---|---|---|---|---|---|"]
        for row in rows:
            (b0, l0), (b1, l1) = row["band"]
            flags = " / ".join("yes" if s else "no" for s in row["squeal"])
            lines.append(f"| {row['point']} | {row['model']} | {flags} | {row['dL_pA']:+.1f} | {row['dL_W']:+.1f} | "
                         f"{b0} ({l0:.1f} dB(A)) → {b1} ({l1:.1f} dB(A)) |")
    lines.append("")
    return "\n".join(lines)


SPECTRA_FIGURE = "radiation_spectra.png"
"""File name of the one-third octave spectra figure in the report's figure folder."""


def radiation_report(paths, figures, out_dir, dpi=120, squealing=()):
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
    squealing : collection of str
        Ids of the squealing cases.

    Returns
    -------
    (list of str, list of Path)
        Markdown lines (:func:`radiation_section`, then the figure) and the figures written.
    """
    paths = list(paths)
    lines = radiation_section(paths, squealing).splitlines()
    results = collect(paths)
    if not results:
        return lines, []
    shown = loudest_points(results)
    figure = Path(figures) / SPECTRA_FIGURE
    with atomic_output(figure) as tmp:
        plot_band_spectra(shown, tmp, dpi)
    link = figure.relative_to(out_dir).as_posix()
    points = len({case_key(r["case_id"]) for r in results})
    caption = ("one-third octave spectra at the receiver, per wheel model" if len(shown) == len(results) else
               f"one-third octave spectra at the receiver, per wheel model: the {MAX_PANELS} loudest of "
               f"{points} operating points")
    return lines + ["", f"![{caption}]({link})", ""], [figure]


MAX_PANELS = 12
"""Operating points drawn in the spectra figure at most (one panel each): the loudest ones."""


def loudest_points(results, limit=MAX_PANELS):
    """The results of the ``limit`` operating points with the highest L_pA of any wheel model
    (all of them if there are not more)."""
    loudest = defaultdict(lambda: -np.inf)
    for r in results:
        key = case_key(r["case_id"])
        loudest[key] = max(loudest[key], r["L_pA"])
    chosen = set(sorted(loudest, key=loudest.get, reverse=True)[:limit])
    return [r for r in results if case_key(r["case_id"]) in chosen]
