"""Pictures of a contact solution: pressure, tangential traction and stick/slip map of the half-space
model; the forces over the steps of a sequence (any model, e.g. the point model's transient)."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import ListedColormap  # noqa: E402

from squealcore.artefacts import atomic_output  # noqa: E402

__all__ = ["plot_fields", "plot_forces"]


def plot_fields(fields, path, title="", fmt="png"):
    """Save a three-panel figure of a :class:`ContactFields` to ``path`` (format ``fmt``, e.g. ``"png"``).

    Axes in mm, rolling direction x to the right (leading edge on the right), pressure and
    traction magnitude in MPa, arrows the tangential traction on the wheel.
    """
    x, y = fields.x * 1e3, fields.y * 1e3
    X, Y = np.meshgrid(x, y, indexing="ij")
    pt = fields.traction
    tmag = np.hypot(pt[..., 0], pt[..., 1])
    fig, axes = plt.subplots(1, 3, figsize=(13, 4), constrained_layout=True)
    ext = [x[0], x[-1], y[0], y[-1]]
    im = axes[0].imshow(fields.pressure.T / 1e6, origin="lower", extent=ext, aspect="equal", cmap="viridis")
    fig.colorbar(im, ax=axes[0], label="pressure (MPa)")
    axes[0].set_title("pressure")
    im = axes[1].imshow(tmag.T / 1e6, origin="lower", extent=ext, aspect="equal", cmap="magma")
    fig.colorbar(im, ax=axes[1], label="|tangential traction| (MPa)")
    m = fields.pressure > 0
    axes[1].quiver(X[m], Y[m], pt[..., 0][m], pt[..., 1][m], color="w", scale=None, width=0.003)
    axes[1].set_title("tangential traction")
    cmap = ListedColormap(["white", "tab:blue", "tab:red"])
    axes[2].imshow(fields.status.T, origin="lower", extent=ext, aspect="equal", cmap=cmap, vmin=0, vmax=2)
    axes[2].set_title("stick (blue) / slip (red)")
    for ax in axes:
        ax.set_xlabel("x, rolling (mm)")
        ax.set_ylabel("y, lateral (mm)")
    if title:
        fig.suptitle(title)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=120, format=fmt)
    plt.close(fig)


def plot_forces(results, path, title="", fmt="png"):
    """Save the tangential forces and the traction ratio |F_t| / Fn of each step to ``path`` (format ``fmt``).

    For models without traction fields (the point model) and for sequences in general.
    """
    force = np.array([r.force for r in results])
    steps = np.arange(1, len(results) + 1)
    ratio = np.hypot(force[:, 0], force[:, 1]) / np.where(force[:, 2] > 0, force[:, 2], np.inf)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8), constrained_layout=True)
    axes[0].plot(steps, force[:, 0] / 1e3, ".-", label="$F_x$")
    axes[0].plot(steps, force[:, 1] / 1e3, ".-", label="$F_y$")
    axes[0].set_ylabel("force on the wheel (kN)")
    axes[0].legend()
    axes[1].plot(steps, ratio, ".-", color="k")
    axes[1].set_ylabel("$|F_t| / F_n$ (-)")
    for ax in axes:
        ax.set_xlabel("step")
        ax.grid(True, alpha=0.3)
    if title:
        fig.suptitle(title)
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=120, format=fmt)
    plt.close(fig)
