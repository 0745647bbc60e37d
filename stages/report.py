"""``report`` stage: figures, tables and ``report.md`` from the artefacts.

Only plotting options (``[report]``) and the artefacts feed it, so changing a plot option re-runs
this stage and no solver.
"""

from __future__ import annotations

import csv
import logging

import numpy as np

from squealcore.artefacts import add_dataset, atomic_output

logger = logging.getLogger(__name__)


def mode_table_rows(modes):
    """Rows of the mode table: one per mode, with the contact-point amplitude (m/√kg)."""
    rows = []
    for k in range(modes["frequency"].size):
        shape = modes["contact_shape"][k]
        rows.append({
            "mode": k + 1,
            "frequency_hz": f"{modes['frequency'][k]:.1f}",
            "nodal_diameters": int(modes["nodal_diameters"][k]),
            "nodal_circles": int(modes["nodal_circles"][k]),
            "family": str(modes["family"][k]),
            "orientation": str(modes["orientation"][k]),
            "damping_ratio": f"{modes['damping_ratio'][k]:.1e}",
            "contact_x": f"{shape[0]:.4e}",
            "contact_y": f"{shape[1]:.4e}",
            "contact_z": f"{shape[2]:.4e}",
        })
    return rows


def write_mode_tables(rows, csv_path, md_path):
    """Write the mode table as CSV and Markdown (atomically)."""
    with atomic_output(csv_path) as tmp:
        with open(tmp, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerows(rows)
    header = ["mode", "f (Hz)", "n", "circles", "family", "orient.", "zeta", "phi_x", "phi_y", "phi_z"]
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    for row in rows:
        lines.append("| " + " | ".join(str(v) for v in row.values()) + " |")
    with atomic_output(md_path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")


def plot_wheel_receptance(greens, path, f_min, f_max, dpi):
    """Wheel point receptances at the contact (vertical, lateral, cross), dB re 1 m/N."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    f = greens["frequency"]
    keep = (f >= f_min) & (f <= f_max)
    h = greens["receptance"][keep]
    fig, ax = plt.subplots(figsize=(8, 4.5))
    for (i, j), label in (((2, 2), "vertical $H_{zz}$"), ((1, 1), "lateral $H_{yy}$"), ((1, 2), "cross $H_{yz}$")):
        ax.semilogx(f[keep], 20 * np.log10(np.abs(h[:, i, j]) + 1e-30), label=label, lw=0.8)
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel("receptance (dB re 1 m/N)")
    ax.set_title("Wheel point receptance at the contact point (stationary wheel)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    fig.tight_layout()
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=dpi)
    plt.close(fig)


def build_report(ctx):
    """``report``: wheel mesh pictures, mode table and receptance plot (more with later stages)."""
    from stages.wheel import read_greens, read_mesh, read_modes

    options = ctx.section("report")
    figures = ctx.out_dir / "figures"
    figures.mkdir(exist_ok=True)
    mesh = read_mesh(ctx.inputs["wheel-mesh"])
    modes = read_modes(ctx.inputs["wheel-modes"])
    greens = read_greens(ctx.inputs["wheel-greens"], "stationary")
    written = []

    from mesh.wheel_mesh import WheelMesh
    from mesh.wheel_plots import plot_section_mesh, plot_wheel_3d

    wheel_mesh = WheelMesh(None, mesh["section_nodes"], mesh["section_cells"], mesh["section_clamped"],
                           mesh["hex_nodes"], mesh["hex_cells"], mesh["hex_clamped"], mesh["contact_section_node"],
                           mesh["contact_hex_node"], mesh["contact_position"], mesh["mass"])
    with atomic_output(figures / "wheel_section_mesh.png") as tmp:
        plot_section_mesh(wheel_mesh, tmp)
    with atomic_output(figures / "wheel_mesh_3d.png") as tmp:
        plot_wheel_3d(wheel_mesh, tmp)
    written += ["figures/wheel_section_mesh.png", "figures/wheel_mesh_3d.png"]

    rows = mode_table_rows(modes)
    write_mode_tables(rows, ctx.out_dir / "modes.csv", ctx.out_dir / "modes.md")
    written += ["modes.csv", "modes.md"]

    plot_wheel_receptance(greens, figures / "wheel_receptance.png", options["receptance_f_min"],
                          options["receptance_f_max"], options["dpi"])
    written.append("figures/wheel_receptance.png")

    text = [
        "# Curve squeal study report",
        "",
        "## Wheel",
        "",
        f"- mesh: {len(mesh['section_cells'])} section elements, {len(mesh['hex_cells'])} hex20 elements, "
        f"{len(mesh['hex_nodes'])} nodes; mass {mesh['mass']:.1f} kg",
        f"- modes: {modes['frequency'].size} below {modes['frequency'].max():.0f} Hz ({modes['solver']} solver); "
        "table in `modes.md`",
        "",
        "![section mesh](figures/wheel_section_mesh.png)",
        "![wheel receptance](figures/wheel_receptance.png)",
        "",
    ]
    with atomic_output(ctx.out_dir / "report.md") as tmp:
        tmp.write_text("\n".join(text))
    written.append("report.md")
    with ctx.writer() as f:
        add_dataset(f, "files", np.array(written, dtype=object), "")
