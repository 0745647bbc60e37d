"""Figures and ``maps.md`` of a squeal map (``maps.h5``, :mod:`stages.maps`).

Squeal is predicted where the margin (largest growth rate of the in-band oscillating poles) is
positive. The report gives the share of configurations where a rotating wheel model and the
stationary wheel disagree on squeal / no squeal, where (per grid value), why (the contributing
mode pair's frequency gap against the spin splitting ``n Ω / 2π`` of its modes) and, for the
default wheel, from which speed on rotation changes the prediction.
"""

from __future__ import annotations

import collections
import logging
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend choice)
import numpy as np  # noqa: E402

from interaction.wheel_models import REFERENCE, rotating_names  # noqa: E402
from squealcore.artefacts import atomic_output  # noqa: E402

logger = logging.getLogger(__name__)

ROTATING = rotating_names()
"""The wheel models that include the rotation, each compared with the reference (:mod:`interaction.wheel_models`)."""
KMH = 3.6  # km/h per m/s


def _axes(keys):
    """The two grid keys drawn: speed across, rolling radius up when the grid has them."""
    order = sorted(range(len(keys)), key=lambda i: (keys[i] != "operating.speed", keys[i] != "wheel.rolling_radius", i))
    return order[0], (order[1] if len(order) > 1 else None)


def _reduce(values, cfg, ix, iy, reducer):
    xs = np.unique(cfg[:, ix])
    ys = np.unique(cfg[:, iy]) if iy is not None else np.array([0.0])
    out = np.full((ys.size, xs.size), np.nan)
    for a, y in enumerate(ys):
        for b, x in enumerate(xs):
            sel = (cfg[:, ix] == x) & ((cfg[:, iy] == y) if iy is not None else True)
            if np.any(sel):
                out[a, b] = reducer(values[sel], sel)
    return xs, ys, out


def plot_maps(data, path, dpi=120):
    """Squeal share, largest growth rate and its frequency on the two main grid axes (reduced over
    the other keys), one column per wheel model (stationary first); written to ``path``."""
    keys, cfg = data["keys"], data["configuration"]
    ix, iy = _axes(keys)
    models = data["models"]
    fig, axes = plt.subplots(3, len(models), figsize=(4.2 * len(models), 10), squeeze=False, constrained_layout=True)
    growth_max = max(np.nanmax(np.where(np.isfinite(data[f"{m}/margin"]), data[f"{m}/margin"], np.nan))
                     for m in models)
    growth_min = min(np.nanmin(np.where(np.isfinite(data[f"{m}/margin"]), data[f"{m}/margin"], np.nan))
                     for m in models)
    limit = max(abs(growth_max), abs(growth_min), 1e-9)
    for col, model in enumerate(models):
        margin = data[f"{model}/margin"]
        freq = data[f"{model}/frequency"]
        xs, ys, share = _reduce(margin > 0, cfg, ix, iy, lambda v, s: float(np.mean(v)))
        _, _, top = _reduce(margin, cfg, ix, iy, lambda v, s: float(np.max(v)))
        _, _, top_f = _reduce(np.arange(margin.size), cfg, ix, iy,
                              lambda v, s, freq=freq, margin=margin: float(freq[v[np.argmax(margin[v])]]))
        for row, (values, cmap, label, vmin, vmax) in enumerate((
                (share, "viridis", "share of configurations with squeal", 0.0, 1.0),
                (top, "RdBu_r", "largest growth rate (1/s)", -limit, limit),
                (top_f / 1e3, "plasma", "its frequency (kHz)", None, None))):
            ax = axes[row, col]
            image = ax.imshow(values, origin="lower", aspect="auto", cmap=cmap, vmin=vmin, vmax=vmax)
            fig.colorbar(image, ax=ax, label=label)
            ax.set_xticks(range(xs.size))
            xlabels = [f"{x * KMH:.0f}" if keys[ix] == "operating.speed" else f"{x:g}" for x in xs]
            ax.set_xticklabels(xlabels, fontsize=7)
            ax.set_xlabel("speed (km/h)" if keys[ix] == "operating.speed" else keys[ix])
            ax.set_yticks(range(ys.size))
            ax.set_yticklabels([f"{y:g}" for y in ys] if iy is not None else [""], fontsize=7)
            ax.set_ylabel(keys[iy] if iy is not None else "")
            if row == 0:
                ax.set_title(model)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)


def _pct(count, total):
    return f"{count} of {total} ({100.0 * count / total:.1f} %)" if total else "0 of 0"


def _default_selection(study, keys, cfg):
    """Configurations of the default wheel: every ``wheel.*`` grid key at the grid value nearest
    the study's own (the map's base value)."""
    sel = np.ones(cfg.shape[0], bool)
    chosen = {}
    for i, key in enumerate(keys):
        if not key.startswith("wheel."):
            continue
        table = study
        for part in key.split("."):
            table = table[part]
        base = float(table)
        values = np.unique(cfg[:, i])
        nearest = values[np.argmin(np.abs(values - base))]
        chosen[key] = nearest
        sel &= cfg[:, i] == nearest
    return sel, chosen


def _why_lines(data, model, stat_only, rot_only):
    """Mode pairs of the disagreements: the pair's gap against the spin splitting n Ω / 2π."""
    lines = []
    spin_hz = data["spin"] / (2 * np.pi)
    if np.any(stat_only):
        f = data[f"{REFERENCE}/mode_frequency"][stat_only]
        n = data[f"{REFERENCE}/mode_n"][stat_only]
        gap = np.abs(f[:, 0] - f[:, 1])
        split = np.nanmax(np.abs(n), axis=1) * spin_hz[stat_only]
        split_apart = int(np.count_nonzero(split > gap))
        pairs = collections.Counter(
            f"{a:.0f} Hz (n={na}) + {b:.0f} Hz (n={nb})" if np.isfinite(b) else f"{a:.0f} Hz (n={na}) alone"
            for (a, b), (na, nb) in zip(f, n))
        common = "; ".join(f"{pair}: {count}" for pair, count in pairs.most_common(4))
        lines.append(f"- Stationary squeals, {model} not ({int(np.count_nonzero(stat_only))}): the stationary "
                     f"squeal pole comes from the wheel modes {common}. In {_pct(split_apart, len(gap))} of them "
                     f"the spin splitting n Ω/2π of the pair's modes exceeds the pair's frequency gap "
                     f"(median gap {np.nanmedian(gap):.0f} Hz, median splitting {np.nanmedian(split):.0f} Hz): "
                     "rotation splits the coupled pair apart.")
    if np.any(rot_only):
        f = data[f"{model}/mode_frequency"][rot_only]
        fs = data[f"{REFERENCE}/mode_frequency"][rot_only]
        gap_rot = np.abs(f[:, 0] - f[:, 1])
        gap_stat = np.abs(fs[:, 0] - fs[:, 1])
        both = np.isfinite(gap_rot) & np.isfinite(gap_stat)
        closer = int(np.count_nonzero(gap_rot[both] < gap_stat[both]))
        pairs = collections.Counter(f"{a:.0f} + {b:.0f} Hz" if np.isfinite(b) else f"{a:.0f} Hz alone" for a, b in f)
        common = "; ".join(f"{pair}: {count}" for pair, count in pairs.most_common(4))
        text = (f"- {model} squeals, stationary not ({int(np.count_nonzero(rot_only))}): the rotating wheel's "
                f"squeal pole comes from its poles {common}.")
        if np.any(both):
            text += (f" Where both poles are pairs ({int(np.count_nonzero(both))}), the rotating pair is closer "
                     f"than the stationary wheel's least stable pair in {_pct(closer, int(np.count_nonzero(both)))} "
                     f"(median gaps {np.median(gap_rot[both]):.0f} and {np.median(gap_stat[both]):.0f} Hz): "
                     "rotation brings a pair together.")
        lines.append(text)
    return lines


def _answer_lines(keys, cfg, squeal, data):
    """The short answer: per rotating model the share that disagrees, the grid values where
    most do, the share of stationary-only squeal whose pair rotation splits apart."""
    total = cfg.shape[0]
    lines = ["## Answer", ""]
    spin_hz = data["spin"] / (2 * np.pi)
    for m in ROTATING:
        if m not in squeal:
            continue
        differ = squeal[m] != squeal[REFERENCE]
        stat_only = squeal[REFERENCE] & ~squeal[m]
        where = []
        for i, key in enumerate(keys):
            values = np.unique(cfg[:, i])
            shares = np.array([np.mean(differ[cfg[:, i] == v]) for v in values])
            if values.size > 1 and shares.max() > 0:
                v = values[np.argmax(shares)]
                shown = f"{v * KMH:.0f} km/h" if key == "operating.speed" else f"{v:g}"
                where.append((shares.max() - shares.min(), f"`{key}` = {shown} ({100 * shares.max():.0f} %)"))
        where = "; ".join(text for _, text in sorted(where, reverse=True)[:3])
        text = (f"- **{m}** and the stationary wheel disagree on squeal / no squeal in "
                f"{_pct(int(np.count_nonzero(differ)), total)} of the configurations "
                f"({int(np.count_nonzero(stat_only))} where only the stationary wheel squeals, "
                f"{int(np.count_nonzero(squeal[m] & ~squeal[REFERENCE]))} the reverse)")
        if where:
            text += f"; most often at {where}"
        if np.any(stat_only):
            f = data[f"{REFERENCE}/mode_frequency"][stat_only]
            n = data[f"{REFERENCE}/mode_n"][stat_only]
            split = np.nanmax(np.abs(n), axis=1) * spin_hz[stat_only] > np.abs(f[:, 0] - f[:, 1])
            text += (f". Where only the stationary wheel squeals, the spin splitting n Ω/2π exceeds the frequency "
                     f"gap of the mode pair that friction couples in {_pct(int(np.count_nonzero(split)), split.size)}"
                     " (rotation splits the pair apart)")
        lines.append(text + ".")
    return lines + [""]


def report_text(study, data):
    """The Markdown of ``maps.md``, the map study's report (not named ``report.md``: a map and
    the time-domain study share an output folder by default, and ``report.md`` is the study's)."""
    keys, cfg = data["keys"], data["configuration"]
    total = cfg.shape[0]
    squeal = {m: data[f"{m}/margin"] > 0 for m in data["models"]}
    lines = ["# Squeal maps: report of the map study", "",
             f"{total} configurations × {len(data['models'])} wheel models, screened by the linear stability "
             "analysis of the wheel on the flexible rail (stability/screen.py): squeal is predicted where a "
             f"pole in the rail model's band grows; the contact it linearises: {study['contact']['model']}. Grid:", ""]
    for i, key in enumerate(keys):
        values = np.unique(cfg[:, i])
        shown = ", ".join(f"{v * KMH:.0f} km/h" if key == "operating.speed" else f"{v:g}" for v in values)
        lines.append(f"- `{key}`: {shown}")
    lines += [""] + _answer_lines(keys, cfg, squeal, data)
    lines += ["## Squeal predicted", "", "| wheel model | configurations with squeal | largest growth rate |",
              "|---|---|---|"]
    for m in data["models"]:
        lines.append(f"| {m} | {_pct(int(np.count_nonzero(squeal[m])), total)} | "
                     f"{np.max(data[f'{m}/margin']):.1f} 1/s |")
    lines += ["", "## Does rotation matter?", "",
              "| rotating model | disagrees with the stationary wheel | stationary squeals, rotating not | "
              "rotating squeals, stationary not |", "|---|---|---|---|"]
    for m in ROTATING:
        if m not in squeal:
            continue
        differ = squeal[m] != squeal[REFERENCE]
        lines.append(f"| {m} | {_pct(int(np.count_nonzero(differ)), total)} | "
                     f"{int(np.count_nonzero(squeal[REFERENCE] & ~squeal[m]))} | "
                     f"{int(np.count_nonzero(squeal[m] & ~squeal[REFERENCE]))} |")
    lines += ["", "### Where", "", "Share of configurations with a different verdict, per grid value:", ""]
    for i, key in enumerate(keys):
        lines += [f"| `{key}` | " + " | ".join(ROTATING) + " |", "|---|" + "---|" * len(ROTATING)]
        for v in np.unique(cfg[:, i]):
            sel = cfg[:, i] == v
            shown = f"{v * KMH:.0f} km/h" if key == "operating.speed" else f"{v:g}"
            cells = [f"{100.0 * np.mean(squeal[m][sel] != squeal[REFERENCE][sel]):.0f} %" for m in ROTATING]
            lines.append(f"| {shown} | " + " | ".join(cells) + " |")
        lines.append("")
    lines += ["### Why", ""]
    for m in ROTATING:
        lines += _why_lines(data, m, squeal[REFERENCE] & ~squeal[m], squeal[m] & ~squeal[REFERENCE])
    lines += [""]
    if "operating.speed" in keys:
        sel, chosen = _default_selection(study, keys, cfg)
        i = keys.index("operating.speed")
        wheel = ", ".join(f"{k} = {v:g}" for k, v in chosen.items()) or "the study's wheel"
        lines += ["## Speed dependence for the default wheel", "",
                  f"Default wheel: {wheel}; over the other grid keys.", "",
                  "| speed | stationary squeals | " + " | ".join(f"{m} differs" for m in ROTATING) + " |",
                  "|---|---|" + "---|" * len(ROTATING)]
        first = {}
        for v in np.unique(cfg[sel, i]):
            s = sel & (cfg[:, i] == v)
            cells = []
            for m in ROTATING:
                count = int(np.count_nonzero(squeal[m][s] != squeal[REFERENCE][s]))
                cells.append(f"{count} of {int(np.count_nonzero(s))}")
                if count and m not in first:
                    first[m] = v
            lines.append(f"| {v * KMH:.0f} km/h | {int(np.count_nonzero(squeal[REFERENCE][s]))} of "
                         f"{int(np.count_nonzero(s))} | " + " | ".join(cells) + " |")
        lines.append("")
        speeds = np.unique(cfg[sel, i])
        for m in ROTATING:
            if m in first:
                always = all(np.any(squeal[m][sel & (cfg[:, i] == v)] != squeal[REFERENCE][sel & (cfg[:, i] == v)])
                             for v in speeds[speeds >= first[m]])
                lines.append(f"- {m}: rotation changes the squeal prediction from {first[m] * KMH:.0f} km/h on "
                             "(the lowest speed of the grid with a different verdict; "
                             + ("at every speed above it too)." if always else "not at every speed above it)."))
            else:
                lines.append(f"- {m}: rotation changes no squeal prediction of the default wheel on this grid.")
        lines.append("")
    seconds = data["seconds"]
    lines += ["## Cost", "", f"Screen (three wheel models, contact linearisation, rotating models per speed): "
              f"median {np.median(seconds) * 1e3:.0f} ms per configuration, {seconds.sum():.0f} s in all "
              "(time in the workers, structures not included); the run that computed "
              f"{data['run_chunks_computed']} chunk(s) took {data['run_wall_time'] / 60:.1f} min of wall time "
              "(structures included).", "",
              "![squeal maps](figures/maps.png)", ""]
    return "\n".join(lines)


def write_report(study, out_dir, data):
    """Write ``figures/maps.png`` and ``maps.md`` (in ``out_dir``, next to ``maps.h5``) from the
    map's data (:func:`stages.maps.read_maps`)."""
    out_dir = Path(out_dir)
    plot_maps(data, out_dir / "figures" / "maps.png", study["report"]["dpi"])
    with atomic_output(out_dir / "maps.md") as tmp:
        Path(tmp).write_text(report_text(study, data), encoding="utf-8")
