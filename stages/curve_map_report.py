"""Figure and ``curve_map.md`` of a curve's squeal-risk map (``curve_map.h5``, :mod:`stages.curve_map`).

A wheel is at risk where any of the three wheel models has a growing pole (margin > 0). The
summary gives, per friction coefficient, speed and wheel, the largest radius at which the wheel
is at risk (the radius below which it squeals, if the risk is monotone in R; where it is not,
the radii at risk are listed), and which wheel is at risk in the most configurations.
"""

from __future__ import annotations

import logging
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend choice)
import numpy as np  # noqa: E402
from matplotlib.colors import SymLogNorm  # noqa: E402

from squealcore.artefacts import atomic_output  # noqa: E402

logger = logging.getLogger(__name__)

KMH = 3.6  # km/h per m/s


def risk(data):
    """``(largest margin over the wheel models, 1/s; at risk)``, both (nR, nV, nμ, 4); NaN and
    False where the curving was not solved."""
    margins = np.stack([data[f"{m}/margin"] for m in data["models"]])
    worst = np.where(np.isfinite(margins).any(axis=0), np.nanmax(np.where(np.isfinite(margins), margins, -np.inf),
                                                                    axis=0), np.nan)
    solved = data["solved"] > 0
    worst = np.where(solved, worst, np.nan)
    return worst, solved & (worst > 0)


def squeal_radius(data):
    """Per friction, speed and wheel: the largest radius (m) at which the wheel is at risk (NaN if
    at none), shape (nμ, nV, 4)."""
    _, at_risk = risk(data)
    radius = np.asarray(data["radius"])
    out = np.full((len(data["friction"]), len(data["speed"]), len(data["wheels"])), np.nan)
    for k in range(out.shape[0]):
        for j in range(out.shape[1]):
            for w in range(out.shape[2]):
                sel = at_risk[:, j, k, w]
                if sel.any():
                    out[k, j, w] = radius[sel].max()
    return out


def plot_curve_map(data, path, dpi=120):
    """Largest growth rate over the three wheel models over radius (across, log) and speed (up),
    one column per wheel and one row per friction coefficient; configurations at risk marked
    with a dot, unsolved curving blank. Written to ``path``."""
    worst, at_risk = risk(data)
    radius, speed, friction = (np.asarray(data[k]) for k in ("radius", "speed", "friction"))
    wheels = data["wheels"]
    finite = worst[np.isfinite(worst)]
    limit = max(float(np.abs(finite).max()) if finite.size else 1.0, 1e-3)
    norm = SymLogNorm(linthresh=0.1, vmin=-limit, vmax=limit)
    fig, axes = plt.subplots(len(friction), len(wheels), figsize=(3.6 * len(wheels), 2.8 * len(friction) + 0.6),
                             squeeze=False, sharex=True, sharey=True, constrained_layout=True)

    def edges(v, log):
        v = np.log(v) if log else np.asarray(v, float)
        mid = 0.5 * (v[1:] + v[:-1]) if v.size > 1 else np.array([])
        lo = v[0] - (mid[0] - v[0] if mid.size else 0.5)
        hi = v[-1] + (v[-1] - mid[-1] if mid.size else 0.5)
        e = np.concatenate([[lo], mid, [hi]])
        return np.exp(e) if log else e

    rx, vy = edges(radius, True), edges(speed * KMH, False)
    image = None
    for k, mu in enumerate(friction):
        for w, label in enumerate(wheels):
            ax = axes[k, w]
            image = ax.pcolormesh(rx, vy, worst[:, :, k, w].T, cmap="RdBu_r", norm=norm, shading="flat")
            ri, vj = np.nonzero(at_risk[:, :, k, w])
            ax.plot(radius[ri], speed[vj] * KMH, "k.", ms=4)
            ax.set_xscale("log")
            ax.set_title(f"{label.replace('_', ' ')}, μ = {mu:g}", fontsize=9)
            if k == len(friction) - 1:
                ax.set_xlabel("curve radius (m)")
            if w == 0:
                ax.set_ylabel("speed (km/h)")
    fig.colorbar(image, ax=axes, label="largest growth rate of the three wheel models (1/s); dots: > 0")
    fig.suptitle("Squeal risk over the curve: half-space screen of each wheel of the bogie", fontsize=10)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png")
    plt.close(fig)


def summary_markdown(data):
    """``curve_map.md``: per friction and speed the largest radius at risk of each wheel, the
    count of configurations at risk per wheel and per wheel model, and the curving failures."""
    worst, at_risk = risk(data)
    radius, speed, friction, wheels = data["radius"], data["speed"], data["friction"], data["wheels"]
    largest = squeal_radius(data)
    solved = data["solved"] > 0
    lines = ["# Squeal risk over the curve", "",
             f"Half-space screen of each wheel of the bogie, {len(radius)} radii ({radius[0]:g}–{radius[-1]:g} m) × "
             f"{len(speed)} speeds × {len(friction)} friction coefficients; a wheel is at risk where any of the "
             f"wheel models ({', '.join(data['models'])}) has a growing pole. Wall time of the run: "
             f"{data['run_wall_time']:.0f} s.", "",
             "Largest curve radius (m) at which each wheel is at risk (–: at none):", "",
             "| μ | speed (km/h) | " + " | ".join(w.replace("_", " ") for w in wheels) + " |",
             "|---|---|" + "---|" * len(wheels)]
    for k, mu in enumerate(friction):
        for j, v in enumerate(speed):
            cells = ["–" if np.isnan(r) else f"{r:g}" for r in largest[k, j]]
            lines.append(f"| {mu:g} | {v * KMH:.0f} | " + " | ".join(cells) + " |")
    lines += ["", "Configurations at risk per wheel (of those whose curving was solved):", "",
              "| wheel | at risk | " + " | ".join(data["models"]) + " |", "|---|---|" + "---|" * len(data["models"])]
    for w, label in enumerate(wheels):
        per_model = [int(((data[f"{m}/margin"][..., w] > 0) & solved[..., w]).sum()) for m in data["models"]]
        lines.append(f"| {label.replace('_', ' ')} | {int(at_risk[..., w].sum())} / {int(solved[..., w].sum())} | "
                     + " | ".join(str(n) for n in per_model) + " |")
    unscreened = int((solved & (data["screened"] == 0)).sum())
    if unscreened:
        lines += ["", f"Wheel screens that did not run (a contact solver failed, logged): {unscreened}."]
    failed = np.argwhere(~solved[..., 0])
    if failed.size:
        lines += ["", "No steady-curving equilibrium (not screened): "
                  + ", ".join(f"R = {radius[i]:g} m, V = {speed[j] * KMH:.0f} km/h, μ = {friction[k]:g}"
                              for i, j, k in failed) + "."]
    monotone = True
    for k in range(len(friction)):
        for j in range(len(speed)):
            for w in range(len(wheels)):
                r = at_risk[:, j, k, w]
                if r.any() and not r[: np.flatnonzero(r).max() + 1].all():
                    monotone = False
    lines += ["", "The risk is " + ("monotone in the radius (every radius below the largest at risk is at risk)"
                                    if monotone else "not monotone in the radius for some wheels (gaps below "
                                                     "the largest radius at risk)") + "."]
    return "\n".join(lines) + "\n"


def write_report(study, out, data):
    """Write ``figures/curve_map.png`` and ``curve_map.md`` into ``out``."""
    out = Path(out)
    (out / "figures").mkdir(parents=True, exist_ok=True)
    plot_curve_map(data, out / "figures" / "curve_map.png", dpi=study.get("report", {}).get("dpi", 120))
    with atomic_output(out / "curve_map.md") as tmp:
        Path(tmp).write_text(summary_markdown(data))
    logger.info("curve map report: %s", out / "curve_map.md")
