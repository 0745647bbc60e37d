"""Figures of the contact geometry: profiles with contact points, and the tables over y.

matplotlib's object interface with the Agg canvas (no pyplot global state), as in
:mod:`mesh.wheel_plots`. :func:`plot_contact_geometry` draws one overview of a pair and its table;
:func:`plot_geometry_report` draws the report's figures from ``contact_geometry.h5``.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from squealcore.artefacts import atomic_output

from .artefact import read_operating_contacts, read_pair, read_table, read_wheelset
from .contact_search import ContactTable, WheelRailPair
from .wheelset import rolling_radius_difference

__all__ = ["plot_contact_geometry", "plot_geometry_report", "draw_profiles", "REPORT_FIGURES"]

#: File names of the report's figures (in the report's figure folder).
REPORT_FIGURES = ("contact_geometry_profiles.png", "contact_geometry_curves.png")


def draw_profiles(ax, pair: WheelRailPair, table: ContactTable, show=(0.0,)):
    """Draw the rail and the wheel touching it at the table rows nearest to ``show`` (m), with the
    contact points (red dots) in the track frame (mm)."""
    rail = pair.rail
    ax.plot(rail.y * 1e3, rail.z * 1e3, "k-", label=rail.name)
    for y_show in show:
        k = int(np.argmin(np.abs(table.displacement - y_show)))
        off = pair.flange_back + table.displacement[k]
        yr = table.y_rail[k, 0]
        lift = rail.height(yr) + pair.wheel.height(yr - off)  # wheel surface touches at slot 0
        ax.plot((pair.wheel.y + off) * 1e3, (lift - pair.wheel.z) * 1e3, "-",
                label=f"wheel at y_w = {table.displacement[k] * 1e3:.2f} mm")
        ok = np.isfinite(table.y_rail[k])
        ax.plot(table.y_rail[k, ok] * 1e3, rail.height(table.y_rail[k, ok]) * 1e3, "ro")
    top = rail.z.max() * 1e3
    ax.set_ylim(top - 40.0, top + 35.0)
    ax.set_xlabel("lateral position, track frame (mm)")
    ax.set_ylabel("height (mm)")
    ax.set_aspect("equal")
    ax.legend(fontsize="small")


def _per_slot(ax, d_mm, values, label):
    """Slot 0 as a line, slot 1 (second contact of a two-point contact) as dots."""
    ax.plot(d_mm, values[:, 0], "-", label=label)
    if np.isfinite(values[:, 1]).any():
        ax.plot(d_mm, values[:, 1], "o", ms=3, label=f"{label}, second contact")


def plot_contact_geometry(pair: WheelRailPair, table: ContactTable, show=(0.0,), path=None):
    """Plot both profiles with the contact points, and r, contact angle and dr over y_w.

    Parameters
    ----------
    pair : WheelRailPair
    table : ContactTable
        From :func:`~geometry.contact_search.contact_table` over a displacement range.
    show : sequence of float
        Displacements (m) at which the wheel profile is drawn on the rail (nearest table rows).
    path : str or Path, optional
        Save the figure there (format from the suffix).

    Returns
    -------
    matplotlib.figure.Figure
    """
    fig = Figure(figsize=(10, 7))
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, 2)
    draw_profiles(axes[0, 0], pair, table, show)
    d = table.displacement * 1e3
    for k, style in ((0, "-"), (1, "o")):
        axes[0, 1].plot(d, table.rolling_radius[:, k] * 1e3, style, ms=3)
        axes[1, 0].plot(d, np.degrees(table.contact_angle[:, k]), style, ms=3)
    axes[0, 1].set_ylabel("rolling radius (mm)")
    axes[1, 0].set_ylabel("contact angle (deg)")
    dr = rolling_radius_difference(pair, table.displacement)
    axes[1, 1].plot(d, dr * 1e3)
    axes[1, 1].set_ylabel("rolling radius difference dr (mm)")
    for a in (axes[0, 1], axes[1, 0], axes[1, 1]):
        a.set_xlabel("lateral displacement y (mm)")
        a.grid(True)
    fig.tight_layout()
    if path is not None:
        fig.savefig(path)
    return fig


def _save(fig, path, dpi):
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format=Path(path).suffix.lstrip("."))
    return Path(path)


def plot_geometry_report(h5_path, out_dir, dpi: int = 120) -> list[Path]:
    """The report's contact-geometry figures from ``contact_geometry.h5``.

    1. ``contact_geometry_profiles.png``: rail and wheel profiles with the contact points at the
       ends of the displacement range, at 0 and at the operating displacement;
    2. ``contact_geometry_curves.png``: rolling radius, contact angle, contact positions on wheel
       and rail, Hertz semi-axes and the rolling radius difference dr(y) against the displacement.

    Parameters
    ----------
    h5_path : str or Path
        The ``contact-geometry`` artefact.
    out_dir : str or Path
        Folder of the figures (created if needed); files are written atomically.
    dpi : int
        Resolution (dots per inch).

    Returns
    -------
    list of Path
        The figures written.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    pair, table = read_pair(h5_path), read_table(h5_path)
    wheelset = read_wheelset(h5_path)
    operating = read_operating_contacts(h5_path)[0].lateral_displacement
    d_all = table.displacement
    show = sorted({float(d_all[0]), float(d_all[np.argmin(np.abs(d_all))]), operating, float(d_all[-1])})

    fig = Figure(figsize=(9, 6))
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    draw_profiles(ax, pair, table, show)
    ax.set_title(f"{pair.wheel.name} on {pair.rail.name}")
    fig.tight_layout()
    written = [_save(fig, out_dir / REPORT_FIGURES[0], dpi)]

    fig = Figure(figsize=(11, 8))
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, 3)
    d = d_all * 1e3
    _per_slot(axes[0, 0], d, table.rolling_radius * 1e3, "rolling radius")
    axes[0, 0].set_ylabel("rolling radius (mm)")
    _per_slot(axes[0, 1], d, np.degrees(table.contact_angle), "contact angle")
    axes[0, 1].set_ylabel("contact angle, track frame (deg)")
    _per_slot(axes[0, 2], d, table.y_wheel * 1e3, "on the wheel (from the flange back)")
    axes[0, 2].set_ylabel("wheel contact position (mm)")
    _per_slot(axes[1, 0], d, table.y_rail * 1e3, "on the rail (from its centre line)")
    axes[1, 0].set_ylabel("rail contact position, track frame (mm)")
    _per_slot(axes[1, 1], d, table.semi_axis_a * 1e3, "a (longitudinal)")
    _per_slot(axes[1, 1], d, table.semi_axis_b * 1e3, "b (lateral)")
    axes[1, 1].set_ylabel("Hertz semi-axes (mm)")
    axes[1, 1].legend(fontsize="small")
    axes[1, 2].plot(wheelset["displacement"] * 1e3, wheelset["rolling_radius_difference"] * 1e3, "-")
    axes[1, 2].set_ylabel("rolling radius difference dr (mm)")
    axes[1, 2].set_title(f"equivalent conicity {wheelset['equivalent_conicity']:.3g} at "
                         f"{wheelset['conicity_amplitude'] * 1e3:.3g} mm", fontsize="small")
    for a in axes.ravel():
        a.set_xlabel("lateral displacement y (mm)")
        a.axvline(operating * 1e3, color="0.6", lw=0.8, ls="--")
        a.grid(True)
    fig.tight_layout()
    written.append(_save(fig, out_dir / REPORT_FIGURES[1], dpi))
    return written
