"""One case for users' tools (``pipeline.py export case``): time histories as CSV, contact
tractions of chosen steps as VTU.

Files written into the target folder:

``<case_id>_histories.csv``
    the histories of ``cases/<case_id>.h5``, one row per time step: ``time_s``, the force of the
    rail on the wheel ``force_{x,y,z}_N``, the creepages ``creepage_xi_1``, ``creepage_eta_1``,
    ``creepage_phi_1_per_m``, ``slip_fraction_1`` and the wheel's and the rail's displacement
    (m) and velocity (m/s) at the contact, deviations from static equilibrium; contact frame
    (x rolling direction, y lateral, z up). ``#`` comment lines carry the case's parameters and
    results.
``<case_id>_tractions.vtu``
    (half-space contact, when steps are given) the contact grid as quads in the plane z = 0
    (x, y in m, centred on the contact point) with, per step n (time n x time_step), the cell
    data ``step0001234_pressure_Pa``, ``step0001234_traction_Pa`` (tangential traction on the
    wheel, (t_x, t_y, 0)) and ``step0001234_status`` (0 exterior, 1 stick, 2 slip). Each cell
    is one element of the half-space model, whose tractions are constant over an element.

The tractions are not stored in the case artefact; :func:`case_snapshots` re-runs the case's
simulation up to the last chosen step from the very Green's artefacts that made the case (found
by their SHA-256 recorded in the case file) and checks that the re-run reproduces the stored
force history.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

import meshio
import numpy as np

from contact.registry import contact_model_names, contact_spec
from interaction.simulate import simulate
from squealcore.artefacts import ArtefactError, atomic_output, file_sha256, open_artefact, params_hash, read_dataset
from squealcore.errors import InputError
from squealcore.study import get_section
from stages import cases
from stages.cases import CASE_SECTIONS, CASE_VERSION, case_study, expand_sweep
from squealcore.csv_tables import write_csv

logger = logging.getLogger(__name__)

HISTORY_COLUMNS = (
    ("time", "time_s", None),
    ("force", "force_{}_N", "xyz"),
    ("creepage", "creepage_{}", ("xi_1", "eta_1", "phi_1_per_m")),
    ("slip_fraction", "slip_fraction_1", None),
    ("wheel/displacement", "wheel_displacement_{}_m", "xyz"),
    ("wheel/velocity", "wheel_velocity_{}_m_per_s", "xyz"),
    ("rail/displacement", "rail_displacement_{}_m", "xyz"),
    ("rail/velocity", "rail_velocity_{}_m_per_s", "xyz"),
)
"""(dataset of ``cases/<id>.h5``, column name pattern, component suffixes or None)."""

REPRODUCTION_TOLERANCE = 10.0
"""A re-run force history may differ from the stored one by this many coupling tolerances
(``simulation.tolerance`` x wheel load) before :func:`case_snapshots` warns."""


def case_path(out_dir, case_id):
    """``out_dir/cases/<case_id>.h5``."""
    return Path(out_dir) / "cases" / f"{case_id}.h5"


def find_case(study, case_id):
    """The overrides and complete study of one case of ``study``'s sweep.

    Raises
    ------
    InputError
        (field ``case``) if the sweep has no case ``case_id``.
    """
    cases = dict(expand_sweep(study))
    if case_id not in cases:
        listed = ", ".join(sorted(cases)) or "none"
        raise InputError("case", f"no case {case_id!r} in this study; its cases: {listed}")
    overrides = cases[case_id]
    return overrides, case_study(study, overrides)


def read_histories(path):
    """The time histories and attributes of a case artefact.

    Returns
    -------
    (dict, dict)
        Datasets by name (see :data:`HISTORY_COLUMNS`) and the root attributes.
    """
    with open_artefact(path, "case", CASE_VERSION) as f:
        data = {name: read_dataset(f, name) for name, _, _ in HISTORY_COLUMNS}
        attrs = {key: (value.item() if isinstance(value, np.generic) else value) for key, value in f.attrs.items()}
    return data, attrs


def history_columns(data):
    """CSV columns (name, values) of the histories of :func:`read_histories`."""
    columns = []
    for name, pattern, parts in HISTORY_COLUMNS:
        values = np.asarray(data[name], dtype=float)
        if parts is None:
            columns.append((pattern, values))
        else:
            columns += [(pattern.format(part), values[:, k]) for k, part in enumerate(parts)]
    return columns


def check_steps(steps, n_steps, time_step):
    """Validated snapshot steps: sorted unique ints in [0, n_steps - 1].

    Raises
    ------
    InputError
        (field ``--steps``) for a step that is not an integer in that range.
    """
    bad = [s for s in steps if isinstance(s, bool) or not isinstance(s, (int, np.integer)) or not 0 <= s < n_steps]
    if bad:
        raise InputError("--steps", f"must be integers in [0, {n_steps - 1}] (time = step x {time_step!r} s), "
                                    f"got {', '.join(map(repr, bad))}")
    return sorted({int(s) for s in steps})


def variant_folder(out_dir, input_hashes):
    """The folder (``out_dir`` or ``out_dir/variants/*``) whose Green's artefacts have the SHA-256
    recorded in a case file.

    Raises
    ------
    ArtefactError
        If no folder holds them unchanged (rebuilt since the case ran: rerun the study).
    """
    out_dir = Path(out_dir)
    candidates = [out_dir] + sorted(p for p in (out_dir / "variants").glob("*") if p.is_dir())
    for folder in candidates:
        if all((folder / name).exists() and file_sha256(folder / name) == sha for name, sha in input_hashes.items()):
            return folder
    raise ArtefactError(f"{out_dir}: no folder holds the Green's artefacts {', '.join(sorted(input_hashes))} the "
                        "case was computed with (rebuilt since?); run the study again")


def case_structures(case_study_dict, variant_dir):
    """What :func:`interaction.simulate.simulate` needs for a case, built as the ``simulate`` stage
    builds it (``stages.cases.build_case``).

    Parameters
    ----------
    case_study_dict : dict
        The complete study of the case (sweep overrides applied).
    variant_dir : Path
        Folder with its ``wheel_greens.h5`` and ``rail_greens.h5``.

    Returns
    -------
    (wheel, rail, contact, dict)
        Structures, contact model and the keyword arguments ``speed``, ``wheel_load``,
        ``creepage``, ``tolerance``.
    """
    variant_dir = Path(variant_dir)
    inputs = {"wheel-greens": variant_dir / "wheel_greens.h5", "rail-greens": variant_dir / "rail_greens.h5",
              "contact-geometry": variant_dir / "contact_geometry.h5"}
    wheel, rail, contact, kwargs, _ = cases.case_structures(case_study_dict, inputs)
    return wheel, rail, contact, kwargs


def case_snapshots(study, out_dir, case_id, steps):
    """Contact fields of a half-space case at chosen steps, by re-running its simulation.

    Parameters
    ----------
    study : dict
        The validated study.
    out_dir : Path
        Study folder (with ``cases/<case_id>.h5``).
    case_id : str
        Case of the study's sweep.
    steps : sequence of int
        Time steps (0-based; time = step x time_step).

    Returns
    -------
    dict
        ``{step: ContactFields}`` (:class:`contact.model.ContactFields`).

    Raises
    ------
    InputError
        Unknown case, point-contact case (no traction field), or a step out of range.
    ArtefactError
        Missing case file, computed with other parameters, or its Green's artefacts changed.
    """
    _, cs = find_case(study, case_id)
    if not contact_spec(cs["contact"]["model"]).traction_fields:
        with_fields = [name for name in contact_model_names() if contact_spec(name).traction_fields]
        raise InputError("--steps", f"case {case_id!r} uses contact.model = {cs['contact']['model']!r}, which has "
                                    f"no traction field; tractions need contact.model = "
                                    f"{' or '.join(repr(n) for n in with_fields)} (export the case without --steps "
                                    "for its time histories)")
    path = case_path(out_dir, case_id)
    data, attrs = read_histories(path)
    chosen = check_steps(steps, data["time"].size, cs["time"]["time_step"])
    if not chosen:
        return {}
    if attrs.get("params_sha256") != params_hash({s: get_section(cs, s) for s in CASE_SECTIONS}):
        raise ArtefactError(f"{path} was computed with other parameters than this study's case {case_id!r}; "
                            "run the study first")
    variant = variant_folder(out_dir, json.loads(attrs["inputs"]))
    wheel, rail, contact, kwargs = case_structures(cs, variant)
    n_steps = chosen[-1] + 1
    logger.info("case %s: re-running %d steps for the contact fields of steps %s", case_id, n_steps, chosen)
    result = simulate(wheel, rail, contact, n_steps=n_steps, snapshot_steps=tuple(chosen), **kwargs)
    deviation = float(np.max(np.abs(result.force - data["force"][:n_steps])))
    allowed = REPRODUCTION_TOLERANCE * kwargs["tolerance"] * kwargs["wheel_load"]
    if deviation > allowed:
        logger.warning("case %s: the re-run force history differs from the stored one by up to %.3g N "
                       "(more than %.3g N); the tractions may not belong to the stored history", case_id,
                       deviation, allowed)
    snapshots = result.extra["snapshots"]
    missing = [s for s in chosen if s not in snapshots]
    if missing:
        raise RuntimeError(f"simulate returned no contact fields for steps {missing}")
    return {s: snapshots[s] for s in chosen}


def traction_grid(fields):
    """Corner points (P, 3) and quads (E, 4) of the uniform contact grid of ``fields``.

    Cell ``i * ny + j`` is element (i, j) (x index i, y index j), corners counter-clockwise seen
    from +z.
    """
    x, y = np.asarray(fields.x, dtype=float), np.asarray(fields.y, dtype=float)
    nx, ny = x.size, y.size
    if nx < 2 or ny < 2:
        raise ValueError("the contact grid needs at least 2 elements per direction")
    dx, dy = x[1] - x[0], y[1] - y[0]
    xe = np.concatenate([x - 0.5 * dx, [x[-1] + 0.5 * dx]])
    ye = np.concatenate([y - 0.5 * dy, [y[-1] + 0.5 * dy]])
    px, py = np.meshgrid(xe, ye, indexing="ij")
    points = np.column_stack([px.ravel(), py.ravel(), np.zeros(px.size)])
    i, j = np.meshgrid(np.arange(nx), np.arange(ny), indexing="ij")
    corner = (i * (ny + 1) + j).ravel()
    quads = np.column_stack([corner, corner + ny + 1, corner + ny + 2, corner + 1])
    return points, quads


def write_traction_vtu(fields_by_step, path):
    """Write contact fields of several steps as one VTU file of quads on the contact grid.

    Parameters
    ----------
    fields_by_step : dict
        ``{step: ContactFields}`` on one grid (``x`` (nx,) m, ``y`` (ny,) m, ``pressure``
        (nx, ny) Pa, ``traction`` (nx, ny, 2) Pa, ``status`` (nx, ny) 0/1/2).
    path : Path
        Output ``.vtu``.

    Returns
    -------
    Path
        ``path``. Cell data per step ``step{n:07d}_pressure_Pa``, ``step{n:07d}_traction_Pa``
        ((t_x, t_y, 0) on the wheel) and ``step{n:07d}_status`` (int8: 0 exterior, 1 stick,
        2 slip).
    """
    if not fields_by_step:
        raise ValueError("no contact fields to write")
    steps = sorted(fields_by_step)
    first = fields_by_step[steps[0]]
    points, quads = traction_grid(first)
    nx, ny = len(first.x), len(first.y)
    cell_data = {}
    for step in steps:
        fields = fields_by_step[step]
        if not (np.array_equal(fields.x, first.x) and np.array_equal(fields.y, first.y)):
            raise ValueError(f"step {step}: contact fields on another grid than step {steps[0]}")
        traction = np.zeros((nx * ny, 3))
        traction[:, :2] = np.asarray(fields.traction, dtype=float).reshape(nx * ny, 2)
        cell_data[f"step{step:07d}_pressure_Pa"] = [np.asarray(fields.pressure, dtype=float).ravel()]
        cell_data[f"step{step:07d}_traction_Pa"] = [traction]
        cell_data[f"step{step:07d}_status"] = [np.asarray(fields.status, dtype=np.int8).ravel()]
    mesh = meshio.Mesh(points, [("quad", quads)], cell_data=cell_data)
    with atomic_output(path) as tmp:
        meshio.write(str(tmp), mesh, file_format="vtu")
    return Path(path)


def export_case(study, out_dir, case_id, target_dir, steps=()):
    """Write a case's time histories as CSV and, for chosen steps, its contact tractions as VTU.

    Parameters
    ----------
    study : dict
        The validated study.
    out_dir : Path
        Study folder (with ``cases/<case_id>.h5``).
    case_id : str
        Case of the study's sweep.
    target_dir : Path
        Folder for the files (created if needed).
    steps : sequence of int
        Time steps for the tractions (half-space cases only); none: histories only.

    Returns
    -------
    list of Path
        ``<case_id>_histories.csv`` and, with steps, ``<case_id>_tractions.vtu``.

    Raises
    ------
    InputError, ArtefactError
        See :func:`case_snapshots`; nothing is written then.
    """
    out_dir, target_dir = Path(out_dir), Path(target_dir)
    steps = list(steps)
    overrides, cs = find_case(study, case_id)
    data, attrs = read_histories(case_path(out_dir, case_id))
    snapshots = case_snapshots(study, out_dir, case_id, steps) if steps else {}
    keys = ("case_id", "friction", "lateral_creepage", "wheel_model", "contact_model", "speed", "L_F2", "squeal",
            "squeal_frequency", "buildup_time", "growth", "runtime")
    comments = (
        f"curve-squeal case {case_id!r}: time histories of cases/{case_id}.h5 (time step "
        f"{cs['time']['time_step']!r} s, wheel load {cs['operating']['wheel_load']!r} N)",
        "case: " + ", ".join(f"{k}={attrs.get(k)!r}" for k in keys) + " (speed m/s, L_F2 dB re 1 N, "
        "squeal_frequency Hz, buildup_time s, runtime s)",
        "overrides: " + json.dumps(overrides, sort_keys=True),
        "frame: contact frame, x longitudinal (rolling direction), y lateral (flange towards field side), z up",
        "force: exerted by the rail on the wheel (force_z_N > 0 in compression); creepages of the wheel relative "
        "to the rail (Kalker)",
        "displacement, velocity: at the contact point, deviations from static equilibrium; velocities are "
        "backward differences",
        "numbers: shortest decimal text that reads back to the same binary64 value",
    )
    written = [write_csv(target_dir / f"{case_id}_histories.csv", history_columns(data), comments)]
    if snapshots:
        written.append(write_traction_vtu(snapshots, target_dir / f"{case_id}_tractions.vtu"))
    logger.info("wrote %s", ", ".join(str(p) for p in written))
    return written
