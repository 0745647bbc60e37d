"""``report`` stage: figures, tables and ``report.md`` from the artefacts.

Only plotting options (``[report]``) and the artefacts feed it, so changing a plot option re-runs
this stage and no solver.

A study with one structure (every case on the same wheel and rail) gets one report of that
structure and its cases. A sweep over structural keys (e.g. ``wheel.rolling_radius``: a
reprofiling study) has one *variant* per structure (``variants/<name>/``); its report has a
comparison section (frequencies of the wheel modes with the largest lateral and vertical
contact amplitude per number of nodal diameters, squeal frequency and L_F2 against the swept value,
``figures/variant_comparison.png``) and one section per variant (its swept values, mode table,
cases, the paper's findings and the stability analysis on its cases; its figures in
``figures/<name>/``). ``modes.csv`` has a ``variant`` column; ``modes.md`` one table per variant;
``summary.csv`` (:mod:`stages.summary`) one row per case with its variant and swept values;
Figure 2 one panel per variant.
"""

from __future__ import annotations

import csv
import itertools
import logging
import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from contact_geometry.plots import plot_geometry_report
from fe.plots import plot_campbell, plot_receptance_comparison, plot_split_zooms, plot_wheel_receptance, split_branches
from interaction.wheel_models import REFERENCE, rotating_names, wheel_model, wheel_model_names, wheel_models
from interaction.frame import vectors_to_contact_frame
from interaction.metrics import DEFAULT_SQUEAL_MIN_FREQUENCY, LATERAL_SWING_LIMIT
from interaction.plots import plot_force_level, plot_lateral_force, plot_level_difference, plot_variant_comparison
from mesh.plots import plot_rail_mesh, plot_section_mesh, plot_wheel_3d
from mesh.wheel_mesh import WheelMesh
from stages.radiation_report import radiation_report
from squealcore.artefacts import add_dataset, atomic_output, canonical_json, open_artefact, read_dataset
from stability.linear import growing_poles, pole_residue_eigenvalues, sliding_instabilities
from stages.cases import CASE_VERSION, case_contact, is_structural
from stages.engine import plan_cases
from stages.greens_layout import WHEEL_GREENS_VERSION, study_geometry
from stages.rail import GREENS_VERSION as RAIL_GREENS_VERSION
from stages.rail import read_mesh as read_rail_mesh
from stages.screen import hertz_stiffness, screen_study, wheel_at_contact
from stages.screen import read_structures
from stages.summary import BASE_VARIANT, class_label, key_unit, read_case_summary, write_summary
from stages.wheel import read_greens, read_mesh, read_modes, read_wheel_state
from waveguide.plots import plot_dispersion, plot_kernel, plot_receptances

logger = logging.getLogger(__name__)

#: Nodal diameters of the wheel modes compared across variants (the paper's squeal involves n = 4
#: to 7; n = 0 and 1 couple to the axle).
COMPARED_NODAL_DIAMETERS = tuple(range(2, 8))
#: The compared modes: for each n, the mode with the largest lateral (contact_y) and the one with
#: the largest vertical (contact_z) amplitude at the contact. Chosen by amplitude, not by family
#: name: when the rim thins the same lateral mode changes from "axial, 0 circles" to "radial,
#: 1 circle" in the classification (fe/classify.py), while its contact amplitude stays.
COMPARED_DIRECTIONS = (("lateral", 1), ("vertical", 2))


@dataclass
class Variant:
    """One structure of the study as the report sees it.

    Attributes
    ----------
    name : str
        Folder name under ``variants/`` (:func:`stages.engine.variant_label`), or ``"base"`` for a
        study with one structure.
    folder : Path
        Folder of its structural artefacts.
    values : dict
        ``{dotted key: value}``: its values of the swept structural keys (empty for ``base``).
    study : dict
        The study of its cases (its structural sections are the variant's).
    summaries : list of dict
        Its case summaries (:func:`stages.summary.read_case_summary`).
    studies : dict
        ``{case id: the study of that case}`` (sweep values applied).
    """

    name: str
    folder: Path
    values: dict
    study: dict
    summaries: list = field(default_factory=list)
    studies: dict = field(default_factory=dict)

    def title(self):
        """The swept values in words, e.g. ``wheel.rolling_radius = 0.38 m`` (the name if none)."""
        if not self.values:
            return self.name
        return ", ".join(f"{key} = {_value_text(value)}{_unit_suffix(key)}" for key, value in sorted(self.values.items()))


def _value_text(value):
    return f"{value:g}" if isinstance(value, float) else str(value)


def _unit_suffix(key):
    unit = key_unit(key)
    return "" if unit in ("1", "-") else f" {unit}"


def report_variants(study, out_dir, case_paths, base):
    """The variants of the report's cases, in the order of the sweep.

    Parameters
    ----------
    study : dict
        The study (with its ``[sweep]``).
    out_dir : Path
        Study folder.
    case_paths : list of Path
        ``cases/<id>.h5`` of the cases the report covers.
    base : Path
        Structural folder used when there is no case.

    Returns
    -------
    list of Variant
        With their case summaries.
    """
    planned = {case.case_id: case for case in plan_cases(study, out_dir)}
    variants = {}
    for path in case_paths:
        case = planned[Path(path).stem]
        name = case.variant_label or BASE_VARIANT
        if name not in variants:
            values = {k: v for k, v in case.overrides.items() if is_structural(k)}
            variants[name] = Variant(name, case.variant_dir, values if case.variant_label else {}, case.study)
        variants[name].summaries.append(read_case_summary(path, study["simulation"], name))
        variants[name].studies[case.case_id] = case.study
    return list(variants.values()) or [Variant(BASE_VARIANT, Path(base), {}, study)]


def mode_table_rows(modes, variant=BASE_VARIANT):
    """Rows of the mode table: one per mode, with its variant and contact-point amplitude (m/√kg)."""
    rows = []
    for k in range(modes["frequency"].size):
        shape = modes["contact_shape"][k]
        rows.append({
            "variant": variant,
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


MODE_TABLE_HEADER = ["mode", "f (Hz)", "n", "circles", "family", "orient.", "zeta", "phi_x", "phi_y", "phi_z"]


def mode_table_markdown(rows):
    """The mode table (rows of :func:`mode_table_rows`) as Markdown lines, without the variant column."""
    lines = ["| " + " | ".join(MODE_TABLE_HEADER) + " |", "|" + "---|" * len(MODE_TABLE_HEADER)]
    for row in rows:
        lines.append("| " + " | ".join(str(v) for key, v in row.items() if key != "variant") + " |")
    return lines


def write_mode_tables(tables, csv_path, md_path):
    """Write the mode tables of all variants as one CSV (``variant`` column) and one Markdown file
    (one table per variant under its heading when there are several), atomically.

    Parameters
    ----------
    tables : list of (Variant, list of dict)
        Each variant with its rows (:func:`mode_table_rows`).
    """
    with atomic_output(csv_path) as tmp:
        with open(tmp, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(tables[0][1][0]))
            writer.writeheader()
            for _, rows in tables:
                writer.writerows(rows)
    if len(tables) == 1:
        lines = mode_table_markdown(tables[0][1])
    else:
        lines = ["# Wheel modes of the variants", ""]
        for variant, rows in tables:
            lines += [f"## {variant.name}: {variant.title()}", ""] + mode_table_markdown(rows) + [""]
    with atomic_output(md_path) as tmp:
        tmp.write_text("\n".join(lines) + "\n")


def compared_mode_frequencies(modes, nodal_diameters=COMPARED_NODAL_DIAMETERS):
    """Frequencies (Hz) of the modes compared across variants (:data:`COMPARED_DIRECTIONS`).

    Returns
    -------
    dict
        ``{("lateral" or "vertical", n): frequency}`` (NaN where the wheel has no mode with n
        nodal diameters below ``wheel.fe.f_max``).
    """
    out = {}
    for n in nodal_diameters:
        pick = np.flatnonzero(modes["nodal_diameters"] == n)
        for direction, component in COMPARED_DIRECTIONS:
            if pick.size:
                best = pick[np.argmax(np.abs(modes["contact_shape"][pick, component]))]
                out[direction, n] = float(modes["frequency"][best])
            else:
                out[direction, n] = math.nan
    return out


def read_lateral_force(path):
    """(time (s), lateral force F2 (N)) of a case artefact."""
    with open_artefact(path, "case", CASE_VERSION) as f:
        return read_dataset(f, "time", "s", (None,)), read_dataset(f, "force", "N", (None, 3))[:, 1]


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
    stat = [s for s in summaries if s["wheel_model"] == REFERENCE]
    if stat:
        n_squeal = sum(s["squeal"] for s in stat)
        some = "yes" if 0 < n_squeal < len(stat) else "no"
        lines.append(f"- **Squeal in some but not all cases** (paper: 5 of 8 for the stationary wheel): {some}, "
                     f"{n_squeal} of {len(stat)} stationary-wheel cases squeal.")
    rotating = {}
    for model in rotating_names():
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
    for a, b in itertools.combinations(rotating_names(), 2):
        common = sorted(set(rotating.get(a, {})) & set(rotating.get(b, {})))
        if not common:
            continue
        diff = np.array([rotating[a][k]["L_F2"] - rotating[b][k]["L_F2"] for k in common])
        same = sum(rotating[a][k]["squeal"] == rotating[b][k]["squeal"] for k in common)
        pair = "The two rotating models" if len(rotating_names()) == 2 else f"The rotating models {a} and {b}"
        lines.append(f"- **{pair} agree** (paper: almost identical receptances and results): "
                     f"squeal/no squeal the same in {same} of {len(common)} cases, L_F2 ({wheel_model(a).short_label} − {wheel_model(b).short_label}) "
                     f"{diff.min():+.1f} to {diff.max():+.1f} dB.")
    return lines


#: Relative difference of a growing pole's and the time domain's frequency for agreement (as the
#: squeal maps' confirmation, :data:`stages.maps_confirm.FREQUENCY_TOLERANCE`).
SCREEN_FREQUENCY_TOLERANCE = 0.02


def screen_cases(variant):
    """The flexible-rail stability screen of every case of a variant (the computation of
    ``pipeline.py stability``: :func:`stages.screen.read_structures` and
    :func:`stages.screen.screen_study`), once per configuration of its cases (their study less the
    wheel model), for the wheel models of its cases.

    Returns
    -------
    dict
        ``{case id: {"poles": growing poles (fastest first), "margin": 1/s, "margin_frequency": Hz}}``
        (the screen's result for the case's wheel model).
    """
    groups = {}
    for summary in variant.summaries:
        study = variant.studies.get(summary["case_id"], variant.study)
        key = canonical_json({k: v for k, v in study.items() if k not in ("simulation", "sweep")})
        groups.setdefault(key, (study, []))[1].append(summary)
    out = {}
    models = rail = None
    for study, members in groups.values():
        if models is None:  # the structures are the variant's: read once
            models, rail, _ = read_structures(study, Path(variant.folder))
        point = case_contact(study, Path(variant.folder) / "contact_geometry.h5")
        names = [m for m in wheel_model_names() if any(s["wheel_model"] == m for s in members)]
        results = screen_study(study, models, rail, names, point=point)
        for summary in members:
            out[summary["case_id"]] = results[summary["wheel_model"]]
    return out


def screen_agreement(summary, result, duration):
    """The screen's verdict on a case and whether the time domain agrees.

    The screen predicts an oscillation that shows within the run when a growing pole grows by at
    least one e-fold over the simulated time (``growth rate x duration >= 1``, 8.7 dB); a pole
    growing more slowly cannot show in the run, and the case is not decided by it. Agreement:
    predicted and the squeal criterion met at a growing pole's frequency (within
    :data:`SCREEN_FREQUENCY_TOLERANCE`) or the oscillation still growing at the end (``growth`` > 1,
    no limit cycle yet); not predicted (stable) and the criterion not met.

    Returns
    -------
    (str, str)
        The screen's verdict in words, and ``"agrees"``, ``"disagrees: ..."`` or ``"undecided: ..."``.
    """
    poles = result["poles"]
    fast = [p for p in poles if p["growth_rate"] * duration >= 1.0]
    if poles:
        screen = "; ".join(f"{p['frequency']:.0f} Hz, {p['growth_rate']:.1f}/s" for p in poles[:3])
    else:
        screen = f"stable (least damped {result['margin']:.1f}/s at {result['margin_frequency']:.0f} Hz)"
    met, frequency = summary["squeal"], summary["squeal_frequency"]
    if fast:
        if met and any(abs(frequency - p["frequency"]) <= SCREEN_FREQUENCY_TOLERANCE * p["frequency"] for p in fast):
            return screen, "agrees"
        if met:
            return screen, (f"disagrees: the time domain oscillates at {frequency:.0f} Hz, not at a growing pole's "
                            "frequency")
        if summary["growth"] > 1.0:
            return screen, f"agrees (still growing at the end: growth {summary['growth']:.2f}, no limit cycle yet)"
        return screen, ("disagrees: a pole grows by more than 8.7 dB over the run, the time domain decays "
                        "(the linearisation about steady rolling misses what damps it)")
    if poles:  # only slow growth
        return screen, (f"undecided: the fastest pole grows by {8.686 * poles[0]['growth_rate'] * duration:.1f} dB "
                        f"over the {duration:g} s run" + (", the case meets the criterion at "
                                                         f"{frequency:.0f} Hz" if met else ""))
    if met:
        return screen, "disagrees: stable in the screen, a limit cycle in the time domain (a nonlinear instability)"
    return screen, "agrees"


def screen_lines(variant, results):
    """The report's section on the flexible-rail screen against the time domain; Markdown lines."""
    study = variant.study
    duration = study["time"]["duration"]
    lines = ["The study's own linear stability screen (`python pipeline.py stability`, docs/design.md §4.9): each "
             "wheel model with the flexible rail (rational fit of its receptance at the contact), the study's "
             f"contact model ({study['contact']['model']}) linearised about steady rolling at each case's friction "
             "and creepages (creep-force slopes below saturation, the normal force's effect in full sliding, the "
             "contact's relaxation). Growing poles: frequency, growth rate (the three fastest). A pole shows within "
             f"the {duration:g} s run when it grows by at least one e-fold over it (8.7 dB); the time domain's "
             "class and frequency beside it.", "",
             "| case | μ | η | wheel model | screen: growing poles | time domain | agreement |",
             "|---|---|---|---|---|---|---|"]
    verdicts = []
    for s in variant.summaries:
        screen, agreement = screen_agreement(s, results[s["case_id"]], duration)
        verdicts.append(agreement)
        domain = case_label(s) + (f" at {s['squeal_frequency']:.0f} Hz" if s["squeal"] else
                                  f" ({s['L_F2']:.0f} dB)")
        lines.append(f"| {s['case_id']} | {s['friction']:g} | {100 * s['lateral_creepage']:g} % | {s['wheel_model']} | "
                     f"{screen} | {domain} | {agreement} |")
    agree = sum(v.startswith("agrees") for v in verdicts)
    undecided = sum(v.startswith("undecided") for v in verdicts)
    lines += ["", f"**The screen agrees with the time domain on {agree} of {len(verdicts)} cases**"
              + (f"; {undecided} undecided (poles growing too slowly to show within the run)" if undecided else "")
              + (f"; it disagrees on {len(verdicts) - agree - undecided}" if len(verdicts) - agree - undecided else "")
              + "."]
    return lines


def stability_lines(study, greens_path, summaries):
    """Complex-eigenvalue analysis of the wheel in full sliding on a rigid rail; Markdown lines.

    One row per friction coefficient and sliding direction of the cases. The first column gives
    the growing poles of the stationary wheel's modes (:func:`stability.linear.sliding_instabilities`)
    with the nodal diameters of the mode each belongs to; the next, for every wheel model of the
    cases, those of its pole-residue model (:func:`stability.linear.pole_residue_eigenvalues`;
    for the rotating wheel the modes are split by rotation). This is the linear test of which
    wheel modes can squeal; whether they do depends on the saturation.
    """
    geometry = study["contact"].get("geometry", "profiles")
    point = case_contact(study, greens_path.parent / "contact_geometry.h5")
    with open_artefact(greens_path, "wheel_greens", WHEEL_GREENS_VERSION) as f:
        frequency = read_dataset(f, "modal/frequency", "Hz", (None,))
        damping = read_dataset(f, "modal/damping_ratio", "1", (None,))
        shape_path = "modal/contact_shape" if geometry == "manual" else "profiles/contact_shape"
        shapes = read_dataset(f, shape_path, "m/sqrt(kg)", (None, 3))
        diameters = read_dataset(f, "modal/nodal_diameters", "", (None,))
    # the case's contact: the wheel at it, in the frame inclined by its contact angle
    shapes = vectors_to_contact_frame(shapes, point.contact_angle)
    models = [m for m in wheel_model_names() if any(s["wheel_model"] == m for s in summaries)]
    greens = {m: read_greens(greens_path, m, geometry) for m in models}
    greens = wheel_at_contact({m: (g["poles"], g["residues"]) for m, g in greens.items()}, point)
    stiffness = hertz_stiffness(study, point)
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
            eig = pole_residue_eigenvalues(*greens[m], stiffness, sign * mu)
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


def missing_cases(study, out_dir, case_paths):
    """Ids of the study's planned cases that the report has no result of (failed or not run)."""
    present = {Path(p).stem for p in case_paths}
    return [case.case_id for case in plan_cases(study, out_dir) if case.case_id not in present]


def missing_lines(missing, count):
    """The report's warning that it covers ``count`` cases of ``count + len(missing)`` (no lines if none is missing)."""
    if not missing:
        return []
    listed = ", ".join(f"`{case_id}`" for case_id in missing[:20]) + (" …" if len(missing) > 20 else "")
    return [f"> **Incomplete:** {len(missing)} of the study's {count + len(missing)} cases have no result (failed "
            f"or not run; the run's closing lines and log say why): {listed}. Every table and figure below covers "
            f"the other {count}.", ""]


def build_report(ctx):
    """``report``: wheel mesh pictures, mode tables, receptances, case summary, the paper's figures and,
    for a structural sweep, one section per variant and their comparison."""
    options = ctx.section("report")
    dpi = options["dpi"]
    out_dir = Path(ctx.out_dir)
    figures = out_dir / "figures"
    figures.mkdir(exist_ok=True)
    variants = report_variants(ctx.study, out_dir, ctx.inputs["cases"], ctx.inputs["base"])
    several = len(variants) > 1
    written = []

    def record(paths):
        written.extend(Path(p).relative_to(out_dir).as_posix() for p in paths)

    sections, tables, compared = [], [], []
    for variant in variants:
        folder = figures / variant.name if several else figures
        folder.mkdir(exist_ok=True)
        modes = read_modes(variant.folder / "wheel_modes.h5")
        rows = mode_table_rows(modes, variant.name)
        tables.append((variant, rows))
        compared.append(compared_mode_frequencies(modes))
        lines, paths = variant_section(variant, modes, rows, folder, out_dir, options, level=3 if several else 2)
        record(paths)
        sections.append(lines)
    write_mode_tables(tables, out_dir / "modes.csv", out_dir / "modes.md")
    written += ["modes.csv", "modes.md"]

    summaries = [s for variant in variants for s in variant.summaries]
    swept = sorted(ctx.study.get("sweep", {}))
    missing = missing_cases(ctx.study, out_dir, ctx.inputs["cases"])
    text = ["# Curve squeal study report", ""] + missing_lines(missing, len(summaries))
    if summaries:
        write_summary(summaries, out_dir / "summary.csv", swept, missing=missing)
        written.append("summary.csv")
        if any(s["wheel_model"] == REFERENCE for s in summaries):
            with atomic_output(figures / "fig2_force_level.png") as tmp:
                plot_force_level(summaries, tmp, dpi, {v.name: v.title() for v in variants} if several else None)
            written.append("figures/fig2_force_level.png")
    if several:
        text += comparison_section(variants, compared, figures, dpi, record)
        for variant, lines in zip(variants, sections):
            text += [f"## Variant `{variant.name}`: {variant.title()}", "",
                     f"Artefacts in `{Path(variant.folder).relative_to(out_dir).as_posix()}/`; figures in "
                     f"`figures/{variant.name}/`.", ""] + lines
        text += ["![Figure 2](figures/fig2_force_level.png)"] if "figures/fig2_force_level.png" in written else []
    else:
        text += sections[0]
        text += [f"![{name}]({name})" for name in sorted(written) if name.startswith("figures/fig")
                 and name != "figures/fig1_wheel_receptance_rotation.png"]  # Figure 1 is in the wheel section
    lines, paths = radiation_report(ctx.inputs.get("radiation", ()), figures, out_dir, dpi,
                                    {s["case_id"]: f"yes ({case_label(s)})" for s in summaries if s["squeal"]})
    record(paths)
    text += [""] + lines
    with atomic_output(out_dir / "report.md") as tmp:
        tmp.write_text("\n".join(text) + "\n")
    written.append("report.md")
    with ctx.writer() as f:
        add_dataset(f, "files", np.array(written, dtype=object), "")


def variant_section(variant, modes, rows, figures, out_dir, options, level=2):
    """One structure's part of the report: wheel, modes, figures, cases, findings, stability.

    Parameters
    ----------
    variant : Variant
    modes : dict
        Its modes (:func:`stages.wheel.read_modes`).
    rows : list of dict
        Its mode table (:func:`mode_table_rows`).
    figures : Path
        Folder of its figures.
    out_dir : Path
        Study folder (links in the text are relative to it).
    options : dict
        ``[report]``.
    level : int
        Markdown heading level of its subsections.

    Returns
    -------
    (list of str, list of Path)
        Markdown lines and the figures written.
    """
    dpi = options["dpi"]
    base = Path(variant.folder)
    head = "#" * level
    mesh = read_mesh(base / "wheel_mesh.h5")
    greens = read_greens(base / "wheel_greens.h5", REFERENCE)
    wheel_mesh = WheelMesh(None, mesh["section_nodes"], mesh["section_cells"], mesh["section_clamped"],
                           mesh["hex_nodes"], mesh["hex_cells"], mesh["hex_clamped"], mesh["contact_section_node"],
                           mesh["contact_hex_node"], mesh["contact_position"], mesh["mass"])
    paths = [figures / "wheel_section_mesh.png", figures / "wheel_mesh_3d.png", figures / "wheel_receptance.png"]
    with atomic_output(paths[0]) as tmp:
        plot_section_mesh(wheel_mesh, tmp)
    with atomic_output(paths[1]) as tmp:
        plot_wheel_3d(wheel_mesh, tmp)
    with atomic_output(paths[2]) as tmp:
        plot_wheel_receptance(greens["frequency"], greens["receptance"], tmp, options["receptance_f_min"],
                              options["receptance_f_max"], dpi)
    paths += rotation_report(base / "wheel_greens.h5", figures)
    paths += _rail_figures(base, figures, options)

    def link(name):
        return (figures / name).relative_to(out_dir).as_posix()

    text = [
        f"{head} Wheel", "",
        f"- mesh: {len(mesh['section_cells'])} section elements, {len(mesh['hex_cells'])} hex20 elements, "
        f"{len(mesh['hex_nodes'])} nodes; mass {mesh['mass']:.1f} kg",
        f"- modes: {modes['frequency'].size} below {modes['frequency'].max():.0f} Hz ({modes['solver']} solver); "
        "table in `modes.md`",
        "",
        *contact_lines(variant.study, base / "contact_geometry.h5"),
    ]
    # with the hand-set contact no contact geometry is computed (a file left by an earlier run with
    # the computed contact is not this study's)
    if study_geometry(variant.study) == "profiles" and (base / "contact_geometry.h5").exists():
        geometry_figures = plot_geometry_report(base / "contact_geometry.h5", figures, dpi=dpi)
        paths += geometry_figures
        text += [f"![{p.stem}]({link(p.name)})" for p in geometry_figures] + [""]
    if level > 2:
        text += ["Modes without nodal circle (one row per pair; all modes in `modes.md` and `modes.csv`):", ""]
        text += mode_table_markdown([r for r in _one_per_pair(rows) if r["nodal_circles"] == 0]) + [""]
    text += [f"![section mesh]({link('wheel_section_mesh.png')})", f"![wheel receptance]({link('wheel_receptance.png')})",
             f"![Figure 1]({link('fig1_wheel_receptance_rotation.png')})", ""]
    summaries = variant.summaries
    if summaries:
        if set(rotating_names()) <= {s["wheel_model"] for s in summaries}:
            paths.append(figures / "fig3_level_difference.png")
            with atomic_output(paths[-1]) as tmp:
                plot_level_difference(summaries, tmp, dpi)
        chosen = _figure_4_cases(summaries)
        if chosen:
            histories = {s["wheel_model"]: read_lateral_force(out_dir / "cases" / f"{s['case_id']}.h5")
                         for s in chosen}
            paths.append(figures / "fig4_lateral_force.png")
            with atomic_output(paths[-1]) as tmp:
                plot_lateral_force(histories, tmp, dpi=dpi)
        text += [f"{head} Cases", ""] + case_table(summaries, variant.study["simulation"]["squeal_min_frequency"])
        text += ["", f"{head} The paper's findings on {'these' if level > 2 else 'our'} cases", ""]
        text += findings(summaries) + [""]
        text += [f"{head} Linear stability: the flexible-rail screen against the time domain", ""]
        text += screen_lines(variant, screen_cases(variant)) + [""]
        text += [f"{head} Rigid rail in full sliding (not the study's screen)", "",
                 "The textbook mode-coupling test of the wheel alone, kept for comparison with the paper. It differs "
                 "from the screen and the time domain above, and is no prediction of squeal: the rail is rigid, the "
                 "lateral force is μF_z at every instant (full sliding: no creep-force slope below saturation, "
                 "which damps the wheel), and the contact has no dynamics of its own (no relaxation). So it can "
                 "show growing poles — e.g. of the rotating models' split pairs — where the screen, which has "
                 "all three, and the time domain find none.", ""]
        text += stability_lines(variant.study, base / "wheel_greens.h5", summaries) + [""]
        if level > 2:
            text += [f"![{p.stem}]({link(p.name)})" for p in paths if p.name.startswith(("fig3", "fig4"))] + [""]
    return text, paths


def case_label(summary):
    """A case's class in the report: ``squeal``, ``low-frequency oscillation`` or ``quiet``
    (:func:`stages.summary.class_label`), with ``, impact/bouncing`` when the wheel loses contact
    or the lateral force swings beyond the friction limit (:func:`interaction.metrics.contact_regime`)."""
    return class_label(summary) + (", impact/bouncing" if summary["regime"] == "bouncing" else "")


def case_table(summaries, squeal_min_frequency=DEFAULT_SQUEAL_MIN_FREQUENCY):
    """The report's table of cases (Markdown lines): L_F2, the paper's squeal criterion, the class of
    the oscillation with the contact regime next to it, frequency, build-up time and the contact's
    loss share and peaks, and a count of the classes."""
    lines = [f"Squeal criterion (the paper's): L_F2 above the threshold with a limit cycle. Class: *squeal* when "
             f"it is met at {squeal_min_frequency:g} Hz or above (`simulation.squeal_min_frequency`; curve squeal is "
             "tonal noise of about 1–10 kHz), *low-frequency oscillation* when it is met below, else *quiet*. "
             "Contact over the L_F2 window: share out of contact (F_n ≤ 0), peak normal force over the static one "
             f"Q, peak |F_y| over μQ; *impact/bouncing* when the wheel leaves the rail or |F_y| exceeds "
             f"{LATERAL_SWING_LIMIT:g} μQ — then the limit cycle is the wheel hammering the rail, not plain squeal "
             "(docs/design.md §4.6).", "",
             "| case | L_F2 (dB) | squeal criterion | class | f (Hz) | build-up (s) | out of contact | peak F_n / Q | "
             "peak abs(F_y) / μQ |",
             "|---|---|---|---|---|---|---|---|---|"]
    for s in summaries:
        lines.append(f"| {s['case_id']} | {s['L_F2']:.1f} | {'yes' if s['squeal'] else 'no'} | {case_label(s)} | "
                     f"{s['squeal_frequency']:.0f} | {s['buildup_time']:.3f} | {100 * s['contact_loss']:.0f} % | "
                     f"{s['peak_normal_ratio']:.2f} | {s['peak_lateral_ratio']:.2f} |")
    count = {label: sum(class_label(s) == label for s in summaries)
             for label in ("squeal", "low-frequency oscillation", "quiet")}
    bouncing = sum(s["regime"] == "bouncing" and s["squeal"] for s in summaries)
    lines += ["", f"{sum(s['squeal'] for s in summaries)} of {len(summaries)} cases meet the squeal criterion: "
                  f"{count['squeal']} squeal, {count['low-frequency oscillation']} low-frequency oscillation(s); "
                  f"{bouncing} of them impact/bouncing."]
    return lines


def _one_per_pair(rows):
    """Mode table rows with one row per (n, circles, family, frequency) pair (cos/sin orientations)."""
    seen, out = set(), []
    for row in rows:
        key = (row["nodal_diameters"], row["nodal_circles"], row["family"], row["frequency_hz"])
        if key not in seen:
            seen.add(key)
            out.append(row)
    return out


def comparison_section(variants, compared, figures, dpi, record):
    """The comparison of the variants: tables and ``figures/variant_comparison.png``; Markdown lines.

    Against the swept value (a number axis when one numeric structural key is swept, the variants
    in sweep order otherwise): the wheel mode frequencies of :func:`compared_mode_frequencies`, and
    per (wheel model, μ, η) the squeal frequency and L_F2.
    """
    keys = sorted({key for v in variants for key in v.values})
    numeric = len(keys) == 1 and all(isinstance(v.values.get(keys[0]), (int, float))
                                     and not isinstance(v.values.get(keys[0]), bool) for v in variants)
    swept = ", ".join(f"`{key}` ({key_unit(key)})" for key in keys)
    text = ["## Comparison of the variants", "",
            f"{len(variants)} structural variants, swept over {swept}: the comparison first, then one section per "
            "variant. `summary.csv` has one row per case with its variant and swept values (units in its "
            "second comment line); `modes.csv` the modes of every variant (`variant` column).", "",
            "Wheel modes (Hz): for each number of nodal diameters n, the mode with the largest lateral and the "
            "one with the largest vertical amplitude at the contact (chosen by amplitude: the family names of "
            "`modes.md` change as the rim thins):", "",
            "| variant | " + " | ".join(f"{key} ({key_unit(key)})" for key in keys) + " | mass (kg) | "
            + " | ".join(f"{d} n = {n}" for d, _ in COMPARED_DIRECTIONS for n in COMPARED_NODAL_DIAMETERS) + " |",
            "|---|" + "---|" * (len(keys) + 1 + len(COMPARED_DIRECTIONS) * len(COMPARED_NODAL_DIAMETERS))]
    for variant, freqs in zip(variants, compared):
        mass = float(read_mesh(Path(variant.folder) / "wheel_mesh.h5")["mass"])
        text.append(f"| `{variant.name}` | " + " | ".join(_value_text(variant.values.get(k, "")) for k in keys)
                    + f" | {mass:.1f} | " + " | ".join(f"{freqs[d, n]:.0f}" for d, _ in COMPARED_DIRECTIONS
                                                      for n in COMPARED_NODAL_DIAMETERS) + " |")
    settings = sorted({(s["wheel_model"], s["friction"], s["lateral_creepage"]) for v in variants for s in v.summaries},
                      key=lambda t: (wheel_model_names().index(t[0]) if t[0] in wheel_model_names() else 99, t[1], -t[2]))
    text += ["", "Cases: L_F2 (dB re 1 N), the class of the oscillation and, where the squeal criterion is met, its "
                 "frequency:", "",
             "| wheel model | μ | η | " + " | ".join(v.title() for v in variants) + " |",
             "|---|---|---|" + "---|" * len(variants)]
    for model, mu, eta in settings:
        cells = []
        for variant in variants:
            match = [s for s in variant.summaries if (s["wheel_model"], s["friction"], s["lateral_creepage"])
                     == (model, mu, eta)]
            cells.append(" / ".join(f"{s['L_F2']:.1f} dB, {case_label(s)}"
                                    + (f" {s['squeal_frequency']:.0f} Hz" if s["squeal"] else "") for s in match) or "-")
        text.append(f"| {model} | {mu:g} | {100 * eta:g} % | " + " | ".join(cells) + " |")
    if numeric:
        x, x_label, ticks = [float(v.values[keys[0]]) for v in variants], f"{keys[0]} ({key_unit(keys[0])})", None
    else:
        x, x_label, ticks = list(range(len(variants))), "variant", [v.title() for v in variants]
    modes_curves = {f"{d} n = {n}": [freqs[d, n] for freqs in compared]
                    for d, _ in COMPARED_DIRECTIONS for n in COMPARED_NODAL_DIAMETERS}
    # one colour per n; lateral modes solid, vertical ones dashed
    styles = {f"{d} n = {n}": {"color": f"C{n % 10}", "ls": "-" if d == "lateral" else "--"}
              for d, _ in COMPARED_DIRECTIONS for n in COMPARED_NODAL_DIAMETERS}
    case_curves = {}
    for model, mu, eta in settings:
        label = f"{model}, μ = {mu:g}, η = {100 * eta:g} %"
        level, squeal, frequency = [], [], []
        for variant in variants:
            match = [s for s in variant.summaries if (s["wheel_model"], s["friction"], s["lateral_creepage"])
                     == (model, mu, eta)]
            level.append(match[0]["L_F2"] if match else math.nan)
            squeal.append(bool(match and match[0]["squeal"]))
            frequency.append(match[0]["squeal_frequency"] if match else math.nan)
        case_curves[label] = {"L_F2": level, "squeal": squeal, "squeal_frequency": frequency}
    path = figures / "variant_comparison.png"
    with atomic_output(path) as tmp:
        plot_variant_comparison(x, x_label, modes_curves, case_curves, tmp, tick_labels=ticks, dpi=dpi,
                                mode_styles=styles)
    record([path])
    text += ["", "![comparison of the variants](figures/variant_comparison.png)", ""]
    return text


def rotation_report(greens_path, figures, speeds_kmh=np.linspace(0.0, 100.0, 11), zoom_pairs=3):
    """The paper's Figure 1 (lateral receptance of the wheel models), zooms around split pairs and a
    Campbell diagram of the rotating models (:mod:`interaction.wheel_models`, each rebuilt at every speed
    from the :class:`~fe.wheel_models.WheelState` the artefact holds), from ``wheel_greens.h5``.
    Returns the paths written."""
    with open_artefact(greens_path, "wheel_greens", WHEEL_GREENS_VERSION) as f:
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        curves = {model.short_label: read_dataset(f[model.name], "receptance", "m/N")
                  for model in wheel_models() if model.name in f}
        speed = float(read_dataset(f, "speed", "m/s"))
        state = read_wheel_state(f)
        modal = {k: read_dataset(f, f"modal/{k}") for k in ("frequency", "nodal_diameters", "family", "nodal_circles")}
    spin = state.spin
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
        rotating = [model for model in wheel_models() if model.rotating]
        branches = {model.short_label: np.zeros((centres.size, len(speeds_kmh), 2)) for model in rotating}
        r0 = speed / spin
        for j, v in enumerate(speeds_kmh):
            w = v / 3.6 / r0
            at_speed = replace(state, spin=w)
            for model in rotating:
                poles = model.poles_residues(at_speed)[0]
                for i, (fc, n) in enumerate(zip(centres, n_pick)):
                    branches[model.short_label][i, j] = split_branches(poles, fc, n, w)
        with atomic_output(paths[2]) as tmp:
            plot_campbell(speeds_kmh, branches, [f"n = {n}, {fc:.0f} Hz" for n, fc in zip(n_pick, centres)], tmp)
    else:
        paths = paths[:1]
    return paths


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
    ``base``. Returns the paths written."""
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
    return [figures / name for name in ("rail_section_mesh.png", "rail_dispersion.png", "rail_receptance.png",
                                        "rail_moving_kernel.png")]
