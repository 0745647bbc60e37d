"""``report`` stage: figures, tables and ``report.md`` from the artefacts.

Only plotting options (``[report]``) and the artefacts feed it, so changing a plot option re-runs
this stage and no solver.
"""

from __future__ import annotations

import csv
import logging

import numpy as np

from fe import moving_load
from fe.plots import plot_campbell, plot_receptance_comparison, plot_split_zooms, plot_wheel_receptance, split_branches
from fe.rotation import EulerianModel, RotationMatrices
from interaction.linear import growing_poles, pole_residue_eigenvalues, sliding_instabilities
from interaction.metrics import squeal_metrics
from interaction.plots import plot_force_level, plot_lateral_force, plot_level_difference
from mesh.plots import plot_rail_mesh, plot_section_mesh, plot_wheel_3d
from mesh.wheel_mesh import WheelMesh
from squealcore.artefacts import add_dataset, atomic_output, open_artefact, read_dataset
from interaction.frame import to_contact_frame, vectors_to_contact_frame
from stages.cases import CASE_VERSION, case_contact, contact_hertz
from stages.config import WHEEL_MODELS
from stages.rail import GREENS_VERSION as RAIL_GREENS_VERSION
from stages.rail import read_mesh as read_rail_mesh
from stages.wheel import read_greens, read_mesh, read_modes
from waveguide.plots import plot_dispersion, plot_kernel, plot_receptances

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


SUMMARY_FIELDS = ("case_id", "wheel_model", "contact_model", "friction", "lateral_creepage", "speed", "L_F2",
                  "squeal", "squeal_frequency", "buildup_time", "growth", "runtime")


def read_case_summary(path, simulation=None):
    """One case artefact as a dict of :data:`SUMMARY_FIELDS` (see stages/cases.py).

    Parameters
    ----------
    path : path-like
        ``cases/<id>.h5``.
    simulation : dict, optional
        The study's ``[simulation]`` table. When given, the squeal metrics are recomputed from the
        stored lateral force with the current :func:`interaction.metrics.squeal_metrics` (so a
        report always applies one definition to every case); otherwise those written by the run.
    """
    with open_artefact(path, "case", CASE_VERSION) as f:
        summary = {key: f.attrs[key] for key in SUMMARY_FIELDS}
        if simulation is not None:
            time = read_dataset(f, "time", "s", (None,))
            force = read_dataset(f, "force", "N", (None, 3))[:, 1]
            m = squeal_metrics(force, time[1] - time[0], window=simulation["rms_window"],
                               threshold_db=simulation["squeal_threshold"])
            summary.update(L_F2=m.L_F2, squeal=m.squeal, squeal_frequency=m.squeal_frequency,
                           buildup_time=m.buildup_time, growth=m.growth)
    for key in ("friction", "lateral_creepage", "speed", "L_F2", "squeal_frequency", "buildup_time", "growth",
                "runtime"):
        summary[key] = float(summary[key])
    summary["squeal"] = bool(summary["squeal"])
    summary["case_id"] = str(summary["case_id"])
    summary["wheel_model"] = str(summary["wheel_model"])
    summary["contact_model"] = str(summary["contact_model"])
    return summary


def read_lateral_force(path):
    """(time (s), lateral force F2 (N)) of a case artefact."""
    with open_artefact(path, "case", CASE_VERSION) as f:
        return read_dataset(f, "time", "s", (None,)), read_dataset(f, "force", "N", (None, 3))[:, 1]


def write_summary(summaries, path):
    """``summary.csv``: one row per case."""
    with atomic_output(path) as tmp:
        with open(tmp, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(SUMMARY_FIELDS))
            writer.writeheader()
            for s in summaries:
                writer.writerow({k: (f"{s[k]:.6g}" if isinstance(s[k], float) else s[k]) for k in SUMMARY_FIELDS})


def findings(summaries):
    """The paper's findings checked one by one on our cases; Markdown lines.

    1. squeal in some but not all stationary-wheel cases (paper: 5 of 8);
    2. where squeal occurs, the three wheel models give close force levels (we call levels within
       3 dB close: the paper's Figure 3 differences in squealing cases are of that size);
    3. rotation delays the build-up (but does not reduce the final level);
    4. the two rotating models give similar results.
    Each line states our numbers, including where they differ from the paper.
    """
    lines = []
    stat = [s for s in summaries if s["wheel_model"] == "stationary"]
    if stat:
        n_squeal = sum(s["squeal"] for s in stat)
        some = "yes" if 0 < n_squeal < len(stat) else "no"
        lines.append(f"- **Squeal in some but not all cases** (paper: 5 of 8 for the stationary wheel): {some}, "
                     f"{n_squeal} of {len(stat)} stationary-wheel cases squeal.")
    rotating = {}
    for model in ("moving_load", "eulerian"):
        pairs = [(s, t) for s in summaries if s["wheel_model"] == model for t in stat
                 if (t["friction"], t["lateral_creepage"]) == (s["friction"], s["lateral_creepage"])]
        rotating[model] = {(s["friction"], s["lateral_creepage"]): s for s, _ in pairs}
        if not pairs:
            continue
        either = [(s, t) for s, t in pairs if s["squeal"] or t["squeal"]]
        both = [(s, t) for s, t in pairs if s["squeal"] and t["squeal"]]
        if either:
            diff = np.array([s["L_F2"] - t["L_F2"] for s, t in either])
            close = "yes" if np.abs(diff).max() <= 3.0 else "no"
            lines.append(f"- **Force levels close where squeal occurs** ({model} vs stationary, paper: almost "
                         f"identical): {close}, L_F2 differences {diff.min():+.1f} to {diff.max():+.1f} dB over the "
                         f"{len(either)} cases where either squeals ({len(both)} squeal with both).")
        if both:
            delay = np.array([s["buildup_time"] - t["buildup_time"] for s, t in both])
            lines.append(f"- **Rotation delays the build-up** ({model}, paper: yes): build-up time minus the "
                         f"stationary one {np.nanmin(delay) * 1e3:+.0f} to {np.nanmax(delay) * 1e3:+.0f} ms "
                         f"(median {np.nanmedian(delay) * 1e3:+.0f} ms) over {len(both)} cases.")
        suppressed = [t for s, t in pairs if t["squeal"] and not s["squeal"]]
        if suppressed:
            lines.append(f"- **Rotation delays the build-up** ({model}): in {len(suppressed)} of the "
                         f"{sum(t['squeal'] for _, t in pairs)} cases where the stationary wheel squeals, the "
                         f"{model} model builds up no squeal within the simulated time (L_F2 "
                         f"{min(s['L_F2'] for s, t in pairs if t in suppressed):.0f} to "
                         f"{max(s['L_F2'] for s, t in pairs if t in suppressed):.0f} dB): rotation suppresses "
                         "the squeal there, not only delays it.")
    common = sorted(set(rotating.get("moving_load", {})) & set(rotating.get("eulerian", {})))
    if common:
        diff = np.array([rotating["moving_load"][k]["L_F2"] - rotating["eulerian"][k]["L_F2"] for k in common])
        same = sum(rotating["moving_load"][k]["squeal"] == rotating["eulerian"][k]["squeal"] for k in common)
        lines.append(f"- **The two rotating models agree** (paper: almost identical receptances and results): "
                     f"squeal/no squeal the same in {same} of {len(common)} cases, L_F2 (moving load − Eulerian) "
                     f"{diff.min():+.1f} to {diff.max():+.1f} dB.")
    return lines


def stability_lines(study, greens_path, summaries):
    """Complex-eigenvalue analysis of the wheel in full sliding on a rigid rail; Markdown lines.

    One row per friction coefficient and sliding direction of the cases. The first column gives
    the growing poles of the stationary wheel's modes (:func:`interaction.linear.sliding_instabilities`)
    with the nodal diameters of the mode each belongs to; the next, for every wheel model of the
    cases, those of its pole-residue model (:func:`interaction.linear.pole_residue_eigenvalues`;
    for the rotating wheel the modes are split by rotation). This is the linear test of which
    wheel modes can squeal; whether they do depends on the saturation.
    """
    geometry = study["contact"].get("geometry", "profiles")
    point = case_contact(study, greens_path.parent / "contact_geometry.h5")
    with open_artefact(greens_path, "wheel_greens", 1) as f:
        frequency = read_dataset(f, "modal/frequency", "Hz", (None,))
        damping = read_dataset(f, "modal/damping_ratio", "1", (None,))
        shape_path = "modal/contact_shape" if geometry == "manual" else "profiles/contact_shape"
        shapes = read_dataset(f, shape_path, "m/sqrt(kg)", (None, 3))
        diameters = read_dataset(f, "modal/nodal_diameters", "", (None,))
    # the case's contact: the wheel at it, in the frame inclined by its contact angle
    shapes = vectors_to_contact_frame(shapes, point.contact_angle)
    models = [m for m in WHEEL_MODELS if any(s["wheel_model"] == m for s in summaries)]
    greens = {m: read_greens(greens_path, m, geometry) for m in models}
    for g in greens.values():
        g["residues"] = to_contact_frame(g["residues"], point.contact_angle)
    _, hertz = contact_hertz(study, point)
    stiffness = 1.5 * hertz.normal_force / hertz.approach  # Hertz: dF/dδ = 3F/(2δ)
    lines = [f"Wheel on a rigid rail, contact stiffness {stiffness:.3g} N/m, lateral force ±μ F_z "
             "(full sliding; η < 0 gives +μ). Growing poles: frequency (Hz), growth rate (1/s); for "
             "the stationary wheel's modes also the nodal diameters n of the nearest mode.", "",
             "| μ | sliding sign | modes (stationary) | " + " | ".join(f"{m} (poles)" for m in models) + " |",
             "|---|---|---|" + "---|" * len(models)]

    def cells(poles, with_n=False):
        return "; ".join(f"{p['frequency']:.0f} Hz, {p['growth_rate']:.1f}/s"
                         + (f", n={int(diameters[p['mode']])}" if with_n else "") for p in poles) or "none"

    for mu, sign in sorted({(s["friction"], -np.sign(s["lateral_creepage"])) for s in summaries}):
        row = [cells(sliding_instabilities((frequency, damping, shapes), stiffness, sign * mu), with_n=True)]
        for m in models:
            eig = pole_residue_eigenvalues(greens[m]["poles"], greens[m]["residues"], stiffness, sign * mu)
            row.append(cells(growing_poles(eig)))
        lines.append(f"| {mu:g} | {sign:+.0f} | " + " | ".join(row) + " |")
    return lines


def contact_lines(study, geometry_path):
    """Markdown lines describing the contact the cases use (``contact.geometry``)."""
    point = case_contact(study, geometry_path)
    source = ("computed from the profiles (contact-geometry stage)" if study["contact"].get("geometry", "profiles") == "profiles"
              else "hand-set (contact.geometry = manual)")
    return [f"- contact, {source}: {1e3 * point.wheel_lateral:.2f} mm from the flange back on the wheel, "
            f"{1e3 * point.rail_lateral:.2f} mm from the rail's centre line; rolling radius "
            f"{1e3 * point.rolling_radius:.2f} mm, contact angle {point.contact_angle:.4f} rad; Hertz semi-axes "
            f"a = {1e3 * point.semi_axis_a:.2f} mm, b = {1e3 * point.semi_axis_b:.2f} mm at the normal force "
            f"{1e-3 * point.normal_force:.2f} kN", ""]


def build_report(ctx):
    """``report``: wheel mesh pictures, mode table, receptances, case summary and the paper's figures."""
    options = ctx.section("report")
    dpi = options["dpi"]
    figures = ctx.out_dir / "figures"
    figures.mkdir(exist_ok=True)
    base = ctx.inputs["base"]
    mesh = read_mesh(base / "wheel_mesh.h5")
    modes = read_modes(base / "wheel_modes.h5")
    greens = read_greens(base / "wheel_greens.h5", "stationary")
    written = []

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
    with atomic_output(figures / "wheel_receptance.png") as tmp:
        plot_wheel_receptance(greens["frequency"], greens["receptance"], tmp, options["receptance_f_min"],
                              options["receptance_f_max"], dpi)
    written.append("figures/wheel_receptance.png")
    written += rotation_report(base / "wheel_greens.h5", figures)
    written += _rail_figures(base, figures, options)

    summaries = [read_case_summary(path, ctx.study["simulation"]) for path in ctx.inputs["cases"]]
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
        *contact_lines(ctx.study, base / "contact_geometry.h5"),
        "![section mesh](figures/wheel_section_mesh.png)",
        "![wheel receptance](figures/wheel_receptance.png)",
        "![Figure 1](figures/fig1_wheel_receptance_rotation.png)",
        "",
    ]
    if summaries:
        write_summary(summaries, ctx.out_dir / "summary.csv")
        written.append("summary.csv")
        if any(s["wheel_model"] == "stationary" for s in summaries):
            with atomic_output(figures / "fig2_force_level.png") as tmp:
                plot_force_level(summaries, tmp, dpi)
            written.append("figures/fig2_force_level.png")
        if {"moving_load", "eulerian"} <= {s["wheel_model"] for s in summaries}:
            with atomic_output(figures / "fig3_level_difference.png") as tmp:
                plot_level_difference(summaries, tmp, dpi)
            written.append("figures/fig3_level_difference.png")
        chosen = _figure_4_cases(summaries)
        if chosen:
            histories = {s["wheel_model"]: read_lateral_force(ctx.out_dir / "cases" / f"{s['case_id']}.h5")
                         for s in chosen}
            with atomic_output(figures / "fig4_lateral_force.png") as tmp:
                plot_lateral_force(histories, tmp, dpi=dpi)
            written.append("figures/fig4_lateral_force.png")
        text += ["## Cases", "", "| case | L_F2 (dB) | squeal | f (Hz) | build-up (s) |", "|---|---|---|---|---|"]
        for s in summaries:
            text.append(f"| {s['case_id']} | {s['L_F2']:.1f} | {'yes' if s['squeal'] else 'no'} | "
                        f"{s['squeal_frequency']:.0f} | {s['buildup_time']:.3f} |")
        text += ["", "## The paper's findings on our cases", ""] + findings(summaries) + [""]
        text += ["## Linear stability in full sliding", ""] + stability_lines(ctx.study, base / "wheel_greens.h5",
                                                                              summaries) + [""]
        text += [f"![{name}]({name})" for name in written if name.startswith("figures/fig")]
    with atomic_output(ctx.out_dir / "report.md") as tmp:
        tmp.write_text("\n".join(text) + "\n")
    written.append("report.md")
    with ctx.writer() as f:
        add_dataset(f, "files", np.array(written, dtype=object), "")


def rotation_report(greens_path, figures, speeds_kmh=np.linspace(0.0, 100.0, 11), zoom_pairs=3):
    """The paper's Figure 1 (lateral receptance of the three wheel models), zooms around split
    pairs and a Campbell diagram, from ``wheel_greens.h5``. Returns the files written."""
    with open_artefact(greens_path, "wheel_greens", 1) as f:
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        curves = {label: read_dataset(f[name], "receptance", "m/N") for name, label in
                  (("stationary", "stationary"), ("moving_load", "moving load"), ("eulerian", "eulerian"))}
        speed = float(read_dataset(f, "speed", "m/s"))
        spin = float(read_dataset(f, "spin", "rad/s"))
        switches = {k: bool(f["eulerian"].attrs[k]) for k in ("gyroscopic", "convective", "centrifugal")}
        geometric = read_dataset(f, "eulerian/geometric", "1") if "geometric" in f["eulerian"] else None
        matrices = RotationMatrices(read_dataset(f, "eulerian/gyroscopic", "1"),
                                    read_dataset(f, "eulerian/convective", "1"), geometric)
        modal = {k: read_dataset(f, f"modal/{k}") for k in ("frequency", "damping_ratio", "contact_shape",
                                                             "nodal_diameters", "family", "nodal_circles")}
        axi = {k: read_dataset(f, f"axisymmetric/{k}") for k in ("frequency", "damping_ratio", "harmonic", "family",
                                                                 "contact_amplitude")}
    model = EulerianModel(modal["frequency"], modal["damping_ratio"], modal["contact_shape"], matrices)
    keep = (frequency >= 100.0) & (frequency <= 7000.0)
    paths = [figures / "fig1_wheel_receptance_rotation.png", figures / "rotation_zooms.png",
             figures / "rotation_campbell.png"]
    with atomic_output(paths[0]) as tmp:
        plot_receptance_comparison(
            frequency[keep], {k: v[keep] for k, v in curves.items()}, tmp,
            title=f"Fig. 1: lateral wheel receptance, v = {3.6 * speed:.0f} km/h")
    # lateral (axial, no nodal circle) pairs with n >= 2: where the splitting shows
    pick = ((modal["family"] == "axial") & (modal["nodal_circles"] == 0) & (modal["nodal_diameters"] >= 2))
    centres, first = np.unique(np.round(modal["frequency"][pick], 3), return_index=True)
    n_pick = modal["nodal_diameters"][pick][first][:zoom_pairs]
    centres = centres[:zoom_pairs]
    if centres.size:
        width = 2.5 * spin * max(int(n_pick.max()), 1) / (2 * np.pi)
        with atomic_output(paths[1]) as tmp:
            plot_split_zooms(frequency, curves, centres, width, tmp)
        branches = {"moving load": np.zeros((centres.size, len(speeds_kmh), 2)),
                    "eulerian": np.zeros((centres.size, len(speeds_kmh), 2))}
        r0 = speed / spin
        for j, v in enumerate(speeds_kmh):
            w = v / 3.6 / r0
            p_m = moving_load.moving_poles_residues_axisymmetric(axi["frequency"], axi["damping_ratio"], axi["harmonic"],
                                                                 axi["family"], axi["contact_amplitude"], w)[0]
            p_e = model.poles_residues(w, **switches)[0]
            for i, (fc, n) in enumerate(zip(centres, n_pick)):
                branches["moving load"][i, j] = split_branches(p_m, fc, n, w)
                branches["eulerian"][i, j] = split_branches(p_e, fc, n, w)
        with atomic_output(paths[2]) as tmp:
            plot_campbell(speeds_kmh, branches, [f"n = {n}, {fc:.0f} Hz" for n, fc in zip(n_pick, centres)], tmp)
    else:
        paths = paths[:1]
    return [f"figures/{p.name}" for p in paths]


def _figure_4_cases(summaries):
    """Cases of Figure 4: mu = 0.3 and eta = -1 % if present, else the loudest case's settings."""
    target = [s for s in summaries if np.isclose(s["friction"], 0.3) and np.isclose(s["lateral_creepage"], -0.01)]
    if not target:
        loudest = max(summaries, key=lambda s: s["L_F2"])
        target = [s for s in summaries if (s["friction"], s["lateral_creepage"]) ==
                  (loudest["friction"], loudest["lateral_creepage"])]
    return target


def _rail_figures(base, figures, options):
    """Rail pictures (section mesh, dispersion, receptances, moving kernel) if the rail artefacts exist in
    ``base``. Returns the files written (relative to the report folder)."""
    mesh_path, greens_path = base / "rail_mesh.h5", base / "rail_greens.h5"
    if not (mesh_path.exists() and greens_path.exists()):
        return []
    with atomic_output(figures / "rail_section_mesh.png") as tmp:
        plot_rail_mesh(read_rail_mesh(mesh_path), tmp)
    with open_artefact(greens_path, "rail_greens", RAIL_GREENS_VERSION) as f:
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        distance = read_dataset(f, "distance", "m", (None,))
        receptance = read_dataset(f, "receptance", "m/N")
        dispersion = {"frequency": frequency, "wavenumber": read_dataset(f, "wavenumbers", "rad/m"),
                      "decay": read_dataset(f, "decay", "dB/m"), "label": read_dataset(f, "wave_label", "")}
        moving = {"time": read_dataset(f, "moving/time", "s"), "kernel": read_dataset(f, "moving/kernel", "m/N"),
                  "speed": float(read_dataset(f, "speed", "m/s")),
                  "time_step": float(read_dataset(f, "time_step", "s"))}
    with atomic_output(figures / "rail_dispersion.png") as tmp:
        plot_dispersion(dispersion, tmp)
    shown = [0, int(np.argmin(np.abs(distance - 0.5))), int(np.argmin(np.abs(distance - 2.0)))]
    with atomic_output(figures / "rail_receptance.png") as tmp:
        plot_receptances(frequency, receptance[shown], distance[shown], tmp)
    with atomic_output(figures / "rail_moving_kernel.png") as tmp:
        plot_kernel(moving, tmp)
    return ["figures/rail_section_mesh.png", "figures/rail_dispersion.png", "figures/rail_receptance.png",
            "figures/rail_moving_kernel.png"]
