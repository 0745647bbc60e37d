"""Figure of the contact geometry: profiles with contact points, and the tables over y.

matplotlib's object interface with the Agg canvas (no pyplot global state), as in
:mod:`mesh.wheel_plots`.
"""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from .contact_search import ContactTable, WheelRailPair
from .wheelset import rolling_radius_difference

__all__ = ["plot_contact_geometry"]


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
    ax = axes[0, 0]
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
    ax.set_xlabel("lateral position, rail frame (mm)")
    ax.set_ylabel("height (mm)")
    ax.set_aspect("equal")
    ax.legend(fontsize="small")
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
