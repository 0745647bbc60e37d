"""Stage graph of the curve-squeal toolkit: what is stale, and building it.

A stage is fresh when its artefact opens, has the expected schema and version, and both the hash
of the configuration sections it reads and the hashes of its upstream artefacts match the ones
recorded in it (squealcore/artefacts.py). Otherwise it is rebuilt, and so is everything
downstream of it, because a rebuilt artefact has new bytes.

The structural stages (wheel and rail) are built once per structural variant of a sweep; the
``simulate`` stage runs the cases of the sweep, one by one, on a local Dask cluster (``jobs > 1``)
or on a remote scheduler; the ``radiation`` stage turns each case into sound (in this process;
its cost per case: docs/benchmarks.md, *Radiation*); the ``report`` stage reads everything. No physics lives here: stage
bodies are in ``stages/`` and call the physics packages. The command line is ``pipeline.py``.
"""

from __future__ import annotations

import hashlib
import json
import logging
import multiprocessing
import os
import re
import shutil
import signal
import time
from concurrent.futures import ProcessPoolExecutor
from concurrent.futures import as_completed as as_completed_futures
from dataclasses import dataclass
from pathlib import Path

import h5py
from tqdm import tqdm

from squealcore import artefacts
from squealcore.artefacts import canonical_json, file_sha256, freshness, params_hash
from squealcore.errors import InputError
from squealcore.hooks import resolve_hook
from squealcore.library_output import configure_worker_logging
from stages.cases import CASE_VERSION, case_study, execute_case, expand_sweep, is_structural, structural_key, table_size
from stages.config import STUDY_SECTIONS
from stages.context import StageContext, key_value, read_configuration
from stages.input_files import input_file_hashes
from stages.radiation import RADIATION_INPUTS, RADIATION_SECTIONS, RADIATION_VERSION, radiation_path
from stages.greens_layout import (GEOMETRY_KEY, RAIL_FIT_KEYS, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION, RAIL_GREENS_VERSION,
                                   WHEEL_GREENS_VERSION)

logger = logging.getLogger(__name__)

#: Seconds to wait for a Dask scheduler to answer before giving up.
CONNECT_TIMEOUT = 5.0


@dataclass(frozen=True)
class Stage:
    """One node of the stage graph.

    Attributes
    ----------
    name : str
        Stage name used on the command line.
    filename : str
        Artefact file, relative to the output folder.
    schema : str
        Artefact kind written into the file.
    version : int
        Artefact layout version.
    sections : tuple of str
        Configuration sections the stage reads (hashed).
    upstream : tuple of str
        Stages whose artefacts it reads.
    body : str
        ``"module:function"`` taking a :class:`stages.context.StageContext`.
    keys : tuple of str
        Single configuration keys the stage reads besides its sections (dotted, hashed too).
    only_when : tuple of (str, str, object)
        ``(upstream stage, dotted key, value)``: that upstream stage is read only when the key
        has that value (otherwise neither checked nor hashed, so changing it reruns nothing).
    used_when : tuple of (str, object)
        ``(dotted key, value)``: the stage belongs to the study only when every key has its value;
        otherwise it is neither built nor checked, and ``status`` leaves it out (the
        ``contact-geometry`` stage with ``contact.geometry = "manual"``: no profile search).
    """

    name: str
    filename: str
    schema: str
    version: int
    sections: tuple
    upstream: tuple
    body: str
    keys: tuple = ()
    only_when: tuple = ()
    used_when: tuple = ()

    def function(self):
        """The stage body (imported on first use: each body pulls in its physics package)."""
        return resolve_hook(self.body)

    def upstream_for(self, study):
        """The upstream stages this stage reads for ``study`` (:attr:`upstream` less those of
        :attr:`only_when` whose key has another value)."""
        unused = {up for up, key, value in self.only_when if key_value(study, key) != value}
        return tuple(up for up in self.upstream if up not in unused)

    def used(self, study):
        """Whether the stage belongs to ``study`` (:attr:`used_when`)."""
        return all(key_value(study, key) == value for key, value in self.used_when)


# The Green's stages read of [time] only the time step (and the wheel's kernel length), not the
# duration of the cases: a study that only runs longer cases keeps its structures. They read of
# [contact] only the contact's source (contact.geometry, docs/design.md).
#: The Green's stages and the cases read the contact geometry only for the computed contact.
_GEOMETRY_READ = (("contact-geometry", GEOMETRY_KEY, "profiles"),)
#: ... and nothing else reads it: with the hand-set contact no profile search runs at all (a
#: user's own wheel section need not meet a rail head, issue 33).
_GEOMETRY_USED = ((GEOMETRY_KEY, "profiles"),)


STAGES = (
    Stage("contact-geometry", "contact_geometry.h5", "contact_geometry", 1, ("wheel", "rail", "operating", "geometry"),
          (), "stages.geometry:build_contact_geometry", used_when=_GEOMETRY_USED),
    Stage("wheel-mesh", "wheel_mesh.h5", "wheel_mesh", 1, ("wheel",), (), "stages.wheel:build_mesh"),
    Stage("wheel-modes", "wheel_modes.h5", "wheel_modes", 1, ("wheel.fe",), ("wheel-mesh",), "stages.wheel:build_modes"),
    Stage("wheel-greens", "wheel_greens.h5", "wheel_greens", WHEEL_GREENS_VERSION, ("operating", "wheel.rotation"),
          ("wheel-modes", "contact-geometry"), "stages.wheel:build_greens",
          ("time.time_step", "time.wheel_kernel_duration", GEOMETRY_KEY), _GEOMETRY_READ),
    Stage("rail-mesh", "rail_mesh.h5", "rail_mesh", 1, ("rail",), (), "stages.rail:build_mesh"),
    Stage("rail-greens", "rail_greens.h5", "rail_greens", RAIL_GREENS_VERSION, ("track", "operating"),
          ("rail-mesh", "contact-geometry"), "stages.rail:build_greens", ("time.time_step", GEOMETRY_KEY),
          _GEOMETRY_READ),
    Stage("rail-fit", "rail_fit.h5", RAIL_FIT_SCHEMA, RAIL_FIT_VERSION, ("rail", "track"), ("rail-mesh", "contact-geometry"),
          "stages.screen:build_rail_fit", RAIL_FIT_KEYS + (GEOMETRY_KEY,), _GEOMETRY_READ),
)
STAGE_BY_NAME = {stage.name: stage for stage in STAGES}
CASE_STAGE = Stage("simulate", "cases/{case}.h5", "case", CASE_VERSION, ("wheel", "contact", "simulation", "operating", "time"),
                   ("wheel-greens", "rail-greens", "contact-geometry"), "stages.cases:build_case",
                   only_when=_GEOMETRY_READ)
# The report reads [map] too: its stability screen fits the rail (map.rail_*) and counts poles by
# map.min_share, as ``pipeline.py stability`` does (stages/screen.py)
REPORT_STAGE = Stage("report", "report.h5", "report", 1, ("report", "map"), (), "stages.report:build_report")
RADIATION_STAGE = Stage("radiation", "radiation/{case}.h5", "radiation", RADIATION_VERSION, RADIATION_SECTIONS,
                        ("simulate",), "stages.radiation:build_radiation")
ALL_STAGE_NAMES = [stage.name for stage in STAGES] + ["simulate", "radiation", "report"]


def required_stages(until=None):
    """The structural stages needed to build ``until`` (all if None or a later stage), in order.

    Raises
    ------
    InputError
        If ``until`` names no stage.
    """
    if until is None or until in ("simulate", "radiation", "report"):
        return list(STAGES)
    if until not in STAGE_BY_NAME:
        raise InputError("--until", f"unknown stage {until!r}; stages: {', '.join(ALL_STAGE_NAMES)}")
    needed = set()

    def visit(name):
        if name not in needed:
            needed.add(name)
            for up in STAGE_BY_NAME[name].upstream:
                visit(up)

    visit(until)
    return [stage for stage in STAGES if stage.name in needed]


def stage_params(stage, study):
    """The configuration a stage reads (:func:`stages.context.read_configuration`)."""
    return read_configuration(study, stage.sections, stage.keys)


def _input_key(path):
    """Name of an upstream artefact in a stage's ``inputs`` record: relative to the study folder
    for case files, the bare file name otherwise (never an absolute path, so that a copied study
    folder stays fresh)."""
    return f"cases/{path.name}" if path.parent.name == "cases" else path.name


_HASHES = {}


def upstream_sha256(path):
    """SHA-256 of an artefact's bytes, computed once per file version (path, size, modification
    time) in this process: a sweep checks the same Green's artefacts for every case."""
    stat = os.stat(path)
    key = (str(Path(path).resolve()), stat.st_size, stat.st_mtime_ns)
    if key not in _HASHES:
        _HASHES[key] = file_sha256(path)
    return _HASHES[key]


def _check(stage, study, output, upstream_paths, extra_params=None):
    params = stage_params(stage, study)
    files = input_file_hashes(study, stage.sections, STUDY_SECTIONS)
    if files:  # the contents of the files the sections name (absent: hashes as before files counted)
        params["files"] = files
    if extra_params:
        params["extra"] = extra_params
    params_sha = params_hash(params)
    inputs = {}
    for path in upstream_paths:
        path = Path(path)
        if not path.exists():
            return False, f"upstream {path.name} missing", params_sha, {}
        inputs[_input_key(path)] = upstream_sha256(path)
    fresh, reason = freshness(output, stage.schema, stage.version, params_sha, inputs)
    return fresh, reason, params_sha, inputs


def inspect(stage, study, out_dir):
    """Freshness of one structural stage in ``out_dir``: (fresh, reason, params hash, upstream hashes)."""
    upstream = [Path(out_dir) / STAGE_BY_NAME[up].filename for up in stage.upstream_for(study)]
    return _check(stage, study, Path(out_dir) / stage.filename, upstream)


def _context(stage, study, out_dir, output, inputs, params_sha, input_hashes, progress):
    return StageContext(study=study, out_dir=Path(out_dir), output=Path(output), inputs=inputs, schema=stage.schema,
                        schema_version=stage.version, params_sha256=params_sha, input_hashes=input_hashes,
                        progress=progress, sections=stage.sections, keys=stage.keys)


def _reuse(stage, out_dir, params_sha, inputs, donors):
    """Copy a fresh artefact of ``stage`` from another variant folder, if one has the same parameters
    and inputs (e.g. the rail of a wheel-reprofiling sweep); True if copied."""
    for donor in donors:
        source = Path(donor) / stage.filename
        if Path(donor) == out_dir or not source.exists():
            continue
        fresh, _ = freshness(source, stage.schema, stage.version, params_sha, inputs)
        if fresh:
            target = out_dir / stage.filename
            with artefacts.atomic_output(target) as partial:
                shutil.copy2(source, partial)
            return True
    return False


def _bar(total, description, unit, enabled):
    """The progress display (tqdm on stderr); disabled when ``enabled`` is false."""
    return tqdm(total=total, desc=description, unit=unit, disable=not enabled, leave=False, mininterval=0.5,
                dynamic_ncols=True)


def run_structural(study, out_dir, stages, progress=True, label="", donors=(), record=None):
    """Build the stale structural stages of one variant; returns the names rebuilt.

    A stale stage whose artefact exists, fresh for the same parameters and inputs, in one of the
    ``donors`` folders (other variants of the sweep) is copied from there instead of rebuilt.

    Parameters
    ----------
    study : dict
        The validated study of this variant.
    out_dir : Path
        Folder of this variant's structural artefacts.
    stages : list of Stage
        Stages to bring up to date, in order.
    progress : bool
        Show a progress bar over the stages.
    label : str
        Variant label appended to stage names (``name@label``).
    donors : sequence of Path
        Folders of the other variants.
    record : list, optional
        Receives the name of every stage as soon as it is rebuilt.

    Returns
    -------
    list of str
        Names of the stages rebuilt (``name@label`` for a variant).
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rebuilt = []
    with _bar(len(stages), "structure" + (f" {label}" if label else ""), "stage", progress) as bar:
        for stage in stages:
            name = stage.name + (f"@{label}" if label else "")
            bar.set_postfix_str(stage.name)
            if not stage.used(study):
                logger.info("%-13s not used (%s)", name,
                            ", ".join(f"{key} = {key_value(study, key)}" for key, _ in stage.used_when))
                bar.update()
                continue
            fresh, reason, params_sha, inputs = inspect(stage, study, out_dir)
            if fresh:
                logger.info("%-13s fresh", name)
                bar.update()
                continue
            if (inputs or not stage.upstream_for(study)) and _reuse(stage, out_dir, params_sha, inputs, donors):
                logger.info("%-13s copied from another variant (same parameters and inputs)", name)
                bar.update()
                continue
            logger.info("%-13s running (%s)", name, reason)
            context = _context(stage, study, out_dir, out_dir / stage.filename,
                               {up: out_dir / STAGE_BY_NAME[up].filename for up in stage.upstream_for(study)},
                               params_sha, inputs,
                               False)
            start = time.perf_counter()
            stage.function()(context)
            logger.info("%-13s done in %.1f s", name, time.perf_counter() - start)
            rebuilt.append(name)
            if record is not None:
                record.append(name)
            bar.update()
    return rebuilt


@dataclass(frozen=True)
class Case:
    """One case of a sweep: its id, overrides, complete study and structural variant folder."""

    case_id: str
    overrides: dict
    study: dict
    variant_dir: Path
    variant_label: str


def _value_label(value):
    """A value as it appears in a label: a float by ``%g``, a file path by its name only (the
    folder of a file never shows in a label; the hash tells apart files of the same name)."""
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, str) and ("/" in value or "\\" in value):
        return Path(value.replace("\\", "/")).name or "file"
    return str(value)


def variant_label(overrides, max_readable=40):
    """Folder name of a structural variant: a short readable label plus a hash of the exact values.

    Parameters
    ----------
    overrides : dict
        ``{dotted key: value}`` of the structural keys of the variant.
    max_readable : int
        Longest readable part, characters.

    Returns
    -------
    str
        e.g. ``rolling_radius=0.375-3f2a9c1b``: only letters, digits and ``_.=+-``, never ``..``,
        never a leading dot, so the name is one safe path component.
    """
    readable = "_".join(f"{key.split('.')[-1]}={_value_label(value)}" for key, value in sorted(overrides.items()))
    readable = re.sub(r"[^A-Za-z0-9_.=+-]", "_", readable)
    readable = re.sub(r"\.{2,}", "_", readable).lstrip(".")[:max_readable] or "variant"
    digest = hashlib.sha256(canonical_json(dict(sorted(overrides.items()))).encode("ascii")).hexdigest()[:8]
    return f"{readable}-{digest}"


#: Cases from which planning a sweep shows a progress bar (on a terminal).
PLANNING_BAR = 500

#: Most cases one study may have: planning checks every case (about 5 ms each) and each case file
#: takes megabytes; a larger sweep is refused with its count (split it into several studies).
MAX_CASES = 10000


def check_sweep_size(study, limit=None):
    """Refuse a sweep of more than :data:`MAX_CASES` cases before any case is planned.

    Raises
    ------
    InputError
        (field ``sweep``) naming the count, each key's number of values and the limit.
    """
    limit = MAX_CASES if limit is None else limit
    total, sizes = table_size(study.get("sweep") or {})
    if total > limit:
        raise InputError("sweep", f"{total} cases ({sizes}), more than the {limit} one study takes (planning alone "
                                  f"would take about {total * 0.005:.0f} s, and each case writes a file of "
                                  "megabytes): split the sweep into several studies, each with its own --out")


def plan_cases(study, out_dir):
    """The cases of a study, each with the folder of its structural artefacts.

    Cases whose studies differ only outside the structural sections share one variant; when a
    sweep changes structural parameters (e.g. the wheel's rolling radius), each variant gets a
    folder ``variants/<label>`` of its own (:func:`variant_label`), otherwise the artefacts live
    in ``out_dir``.
    """
    out_dir = Path(out_dir)
    check_sweep_size(study)
    sweep = expand_sweep(study)
    # a long sweep shows its planning (each case is validated, ~5 ms): a bar on a terminal past PLANNING_BAR cases
    shown = tqdm(sweep, desc="planning", unit="case", leave=False, disable=None) if len(sweep) > PLANNING_BAR else sweep
    expanded = [(case_id, overrides, case_study(study, overrides)) for case_id, overrides in shown]
    labels = {}
    for case_id, overrides, cs in expanded:
        structural = {k: v for k, v in overrides.items() if is_structural(k)}
        labels.setdefault(structural_key(cs), variant_label(structural))
    single = len(labels) == 1
    cases = []
    for case_id, overrides, cs in expanded:
        label = labels[structural_key(cs)]
        variant_dir = out_dir if single else out_dir / "variants" / label
        cases.append(Case(case_id, overrides, cs, variant_dir, "" if single else label))
    return cases


def case_check(case, out_dir):
    """Freshness of one case artefact: (fresh, reason, params hash, upstream hashes)."""
    upstream = [case.variant_dir / STAGE_BY_NAME[up].filename for up in CASE_STAGE.upstream_for(case.study)]
    output = Path(out_dir) / "cases" / f"{case.case_id}.h5"
    return _check(CASE_STAGE, case.study, output, upstream)


def radiation_check(case, out_dir):
    """Freshness of one case's radiation artefact: (fresh, reason, params hash, upstream hashes)."""
    upstream = [Path(out_dir) / "cases" / f"{case.case_id}.h5"] + [case.variant_dir / n for n in RADIATION_INPUTS]
    return _check(RADIATION_STAGE, case.study, radiation_path(out_dir, case.case_id), upstream)


def run_radiation(cases, out_dir, progress=True, record=None):
    """Build the stale radiation artefacts of the cases, one by one in this process (the numba-compiled
    pole recursion is imported once, the wheel's surface integrals are computed once per variant and
    cached; timings: docs/benchmarks.md, *Radiation*).

    Parameters
    ----------
    cases : list of Case
        Cases whose ``simulate`` artefact exists (fresh radiation artefacts are skipped).
    out_dir : Path
        Study folder.
    progress : bool
        Show a progress bar ("radiation", cases).
    record : list, optional
        Receives ``radiation:<case id>`` of every artefact as soon as it is written.

    Returns
    -------
    (list of str, dict)
        ``radiation:<case id>`` of those built, and ``{case_id: error message}`` of those that failed.
    """
    pending = []
    for case in cases:
        fresh, reason, params_sha, inputs = radiation_check(case, out_dir)
        if fresh:
            logger.info("radiation %s fresh", case.case_id)
        else:
            pending.append((case, reason, params_sha, inputs))
    built, failed = [], {}
    if not pending:
        return built, failed
    logger.info("%d of %d radiation artefacts to build", len(pending), len(cases))
    with _bar(len(pending), "radiation", "case", progress) as bar:
        for case, reason, params_sha, inputs in pending:
            logger.info("radiation %s running (%s)", case.case_id, reason)
            context = _context(RADIATION_STAGE, case.study, out_dir, radiation_path(out_dir, case.case_id),
                               {"case": Path(out_dir) / "cases" / f"{case.case_id}.h5", "variant": case.variant_dir},
                               params_sha, inputs, False)
            start = time.perf_counter()
            try:
                levels = RADIATION_STAGE.function()(context)
            except Exception as exc:  # a failing case is reported; the others go on
                fault = artefacts.resource_fault(exc, context.output)
                if fault is not None:  # a full disk, a lost permission: the run stops (rerun resumes)
                    raise fault from None
                logger.exception("radiation of case %s failed", case.case_id)
                failed[case.case_id] = f"{type(exc).__name__}: {exc}"
                bar.set_postfix_str(f"{len(failed)} failed")
            else:
                logger.info("radiation %s done in %.1f s: L_W = %.1f dB, L_pA = %.1f dB(A)", case.case_id,
                            time.perf_counter() - start, levels["L_W"], levels["L_pA"])
                built.append(f"radiation:{case.case_id}")
                if record is not None:
                    record.append(built[-1])
            bar.update()
    return built, failed


def case_payload(case, out_dir, progress):
    """Plain-data description of a pending case, sent to a (possibly remote) worker."""
    fresh, reason, params_sha, inputs = case_check(case, out_dir)
    return {"case_id": case.case_id, "overrides": case.overrides, "study": case.study, "out_dir": str(out_dir),
            "variant_dir": str(case.variant_dir), "params_sha256": params_sha, "input_hashes": inputs,
            "schema": CASE_STAGE.schema, "schema_version": CASE_STAGE.version,
            "progress": progress, "reason": reason}


class Sweep:
    """Bookkeeping of a running sweep: cases done and failed, the progress bar and the log.

    Parameters
    ----------
    total : int
        Number of cases to run.
    progress : bool
        Show the progress bar (cases done / total, failures, time left).
    record : list, optional
        Receives ``simulate:<case id>`` of every case as soon as it is done.
    """

    def __init__(self, total, progress, record=None):
        self.record = record
        self.done = []
        self.failed = {}
        self.bar = _bar(total, "cases", "case", progress)

    def collect(self, outcome):
        """Record the outcome dict of :func:`stages.cases.execute_case`.

        Raises
        ------
        OSError
            If the case met a fault of the environment's resources (a full disk, a lost
            permission: :data:`squealcore.artefacts.RESOURCE_ERRNOS`): the run stops, the cases
            done are kept, and the rerun resumes.
        """
        case_id = outcome["case_id"]
        if outcome.get("fault"):
            raise OSError(*outcome["fault"])
        if outcome["ok"]:
            level = outcome.get("L_F2")
            squeal = outcome.get("squeal")
            details = ""
            if level is not None:
                details = f": L_F2 = {level:.1f} dB"
                if squeal:
                    details += (f", {outcome.get('oscillation') or 'squeal'} at "
                                f"{outcome.get('squeal_frequency', float('nan')):.0f} Hz")
                elif squeal is not None:
                    details += ", no squeal"
                if outcome.get("regime") == "bouncing":
                    details += ", impact/bouncing"
            logger.info("case %s done in %.1f s%s", case_id, outcome["seconds"], details)
            self.done.append(case_id)
            if self.record is not None:
                self.record.append(f"simulate:{case_id}")
        else:
            logger.error("case %s failed: %s", case_id, outcome["error"])
            self.failed[case_id] = outcome["error"]
        self.bar.update()
        if self.failed:
            self.bar.set_postfix_str(f"{len(self.failed)} failed")

    def close(self):
        self.bar.close()


def run_cases(cases, out_dir, jobs=1, scheduler=None, progress=True, record=None, isolate=False):
    """Run the stale cases, locally one by one, on a local Dask cluster or on a remote one.

    Parameters
    ----------
    cases : list of Case
        The cases of the study (fresh ones are skipped).
    out_dir : Path
        Study folder.
    jobs : int
        Local worker processes (1: in this process, no Dask).
    scheduler : str, optional
        Address of a Dask scheduler (``tcp://host:port``); overrides ``jobs``.
    progress : bool
        Show the progress bar.
    record : list, optional
        Receives ``simulate:<case id>`` of every case as soon as it is done.
    isolate : bool
        With ``jobs == 1``, run the cases one by one in a worker process instead of this one, so
        that this process stays responsive (Ctrl-C) while a case is in compiled code.

    Returns
    -------
    (list of str, dict)
        Ids of the cases computed, and ``{case_id: error message}`` of those that failed.

    Raises
    ------
    OSError
        If the scheduler cannot be reached within :data:`CONNECT_TIMEOUT`.
    """
    pending = []
    for case in cases:
        fresh, reason, _, _ = case_check(case, out_dir)
        if fresh:
            logger.info("case %s fresh", case.case_id)
        else:
            pending.append(case_payload(case, out_dir, False))
    if not pending:
        return [], {}
    logger.info("%d of %d cases to run", len(pending), len(cases))
    sweep = Sweep(len(pending), progress, record)
    try:
        if scheduler is None and jobs <= 1 and not isolate:
            for payload in pending:
                sweep.collect(execute_case(payload))
        elif scheduler is None and jobs <= 1:
            _run_in_worker_process(pending, sweep)
        else:
            _run_on_dask(pending, sweep, jobs, scheduler)
    finally:
        sweep.close()
    return sweep.done, sweep.failed


def _run_in_worker_process(pending, sweep):
    """Run the pending cases one by one in a worker process (started with ``spawn``: no state of
    this process is copied: its logging is set up as this one's, library warnings in the log,
    :func:`squealcore.library_output.configure_worker_logging`). On Ctrl-C nothing waits for the
    running case; the caller stops the worker."""
    pool = ProcessPoolExecutor(max_workers=1, mp_context=multiprocessing.get_context("spawn"),
                               initializer=configure_worker_logging, initargs=(logging.getLogger().getEffectiveLevel(),))
    try:
        for future in as_completed_futures([pool.submit(execute_case, payload) for payload in pending]):
            sweep.collect(future.result())
    except BaseException as exc:  # Ctrl-C, a stop signal, a full disk: no case waits
        workers = list(getattr(pool, "_processes", None) or {})
        pool.shutdown(wait=False, cancel_futures=True)
        if not isinstance(exc, KeyboardInterrupt):  # (after Ctrl-C the caller stops every child process)
            for pid in workers:  # the running case would go on writing in a folder no longer locked
                try:
                    os.kill(pid, signal.SIGKILL)
                except OSError:  # already gone
                    pass
        raise
    pool.shutdown(wait=True)


def quiet_dask_logs(level=logging.ERROR):
    """Keep Dask's own INFO/WARNING chatter (cluster start, heartbeats, shutdown) out of the log."""
    for name in ("distributed", "tornado", "bokeh"):
        logging.getLogger(name).setLevel(level)


def _run_on_dask(pending, sweep, jobs, scheduler):
    """Submit the pending cases to a Dask cluster (:func:`run_on_dask`)."""
    run_on_dask(execute_case, pending, [f"case-{p['case_id']}-{p['params_sha256'][:8]}" for p in pending],
                sweep.collect, jobs, scheduler)


def run_on_dask(function, payloads, keys, collect, jobs, scheduler):
    """Run ``function(payload)`` for every payload on a Dask cluster, calling ``collect(result)``
    as each finishes; on any exit the futures are cancelled and a local cluster is shut down (its
    worker processes killed if they do not stop at once).

    Parameters
    ----------
    function : callable
        Importable module-level function of one plain-data payload (runs in the workers).
    payloads : list
        Plain data, one per task.
    keys : list of str
        Dask task keys, one per payload (unique).
    collect : callable
        Called in this process with each result, in order of completion.
    jobs : int
        Local worker processes (when ``scheduler`` is None).
    scheduler : str or None
        Address of a Dask scheduler (``tcp://host:port``).

    Raises
    ------
    ConnectionError
        If the scheduler cannot be reached within :data:`CONNECT_TIMEOUT`.
    """
    # lazy: importing dask.distributed costs about 0.6 s (python -X importtime), paid only by
    # parallel sweeps.
    from dask.distributed import Client, LocalCluster, as_completed

    quiet_dask_logs()
    cluster = None
    client = None
    futures = []
    worker_pids = []
    interrupted = False
    try:
        if scheduler is None:
            # loopback only; no dashboard, and its HTTP endpoint on a free port (not 8787, which
            # another cluster may hold)
            cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True, host="127.0.0.1",
                                   dashboard_address=None, worker_dashboard_address=None,
                                   scheduler_kwargs={"dashboard_address": "127.0.0.1:0"}, silence_logs=logging.ERROR)
            client = Client(cluster, timeout=CONNECT_TIMEOUT)
            worker_pids = list(client.run(os.getpid).values())
        else:
            try:
                client = Client(scheduler, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError) as exc:
                raise ConnectionError(f"Dask scheduler {scheduler} unreachable ({exc.__class__.__name__}: {exc})") from None
        futures = [client.submit(function, payload, pure=False, key=key) for payload, key in zip(payloads, keys)]
        for future in as_completed(futures):
            collect(future.result())
    except KeyboardInterrupt:
        # Stop at once: the local workers are ours (killed, their unfinished files are removed by
        # the caller); a remote cluster is told to drop the cases. No graceful shutdown, which
        # would wait for the running cases.
        interrupted = True
        for pid in worker_pids:
            try:
                os.kill(pid, signal.SIGKILL)
            except OSError:  # already gone
                pass
        if client is not None and scheduler is not None and futures:
            try:
                client.cancel(futures)
            except Exception:  # the connection may already be gone; nothing more to cancel
                pass
        raise
    finally:
        if not interrupted:
            _close_quietly(client, cluster)


def _close_quietly(client, cluster):
    """Shut a Dask client and local cluster down, ignoring the errors of an already broken one."""
    for thing in (client, cluster):
        if thing is None:
            continue
        try:
            thing.close(timeout=5)
        except Exception:  # closing a cluster whose workers died may time out or assert
            logger.debug("closing %s failed", thing, exc_info=True)


def _report_inputs(study, out_dir, cases):
    """Upstream artefacts, extra parameters and base folder of the report stage."""
    out_dir = Path(out_dir)
    base = cases[0].variant_dir if cases else out_dir
    base_study = cases[0].study if cases else study
    upstream = [base / stage.filename for stage in STAGES if stage.used(base_study)]
    upstream += [out_dir / "cases" / f"{case.case_id}.h5" for case in cases]
    upstream += [radiation_path(out_dir, case.case_id) for case in cases]
    upstream = [p for p in upstream if p.exists()]
    # the base folder relative to the study folder: a copied study folder keeps its report
    extra = {"cases": [case.case_id for case in cases], "base": Path(os.path.relpath(base, out_dir)).as_posix()}
    return upstream, extra, base


def report_check(study, out_dir, cases):
    """Freshness of the report: (fresh, reason, params hash, upstream hashes)."""
    upstream, extra, _ = _report_inputs(study, out_dir, cases)
    return _check(REPORT_STAGE, study, Path(out_dir) / REPORT_STAGE.filename, upstream, extra)


def run_report(study, out_dir, cases, progress=True):
    """Build the report if its inputs (base artefacts, all case files, ``[report]``) changed."""
    out_dir = Path(out_dir)
    _, _, base = _report_inputs(study, out_dir, cases)
    fresh, reason, params_sha, inputs = report_check(study, out_dir, cases)
    if fresh:
        logger.info("%-13s fresh", "report")
        return []
    logger.info("%-13s running (%s)", "report", reason)
    context = _context(REPORT_STAGE, study, out_dir, out_dir / REPORT_STAGE.filename,
                       {"base": base, "cases": [out_dir / "cases" / f"{c.case_id}.h5" for c in cases],
                        "radiation": [p for p in (radiation_path(out_dir, c.case_id) for c in cases) if p.exists()]},
                       params_sha,
                       inputs, progress)
    with _bar(1, "report", "stage", progress) as bar:
        REPORT_STAGE.function()(context)
        bar.update()
    return ["report"]


def _variants(study, out_dir, cases):
    variants = {}
    for case in cases:
        variants.setdefault(case.variant_dir, case)
    if not variants:
        variants[Path(out_dir)] = Case("base", {}, study, Path(out_dir), "")
    return variants


def remove_stale_temporaries(out_dir):
    """Remove temporary files left by killed runs in ``out_dir`` (if the artefact layer offers it).

    Returns
    -------
    list of Path
        The files removed.
    """
    if not Path(out_dir).is_dir():
        return []
    removed = artefacts.remove_stale_temporaries(out_dir)
    for path in removed:
        logger.info("removed temporary file of an interrupted run: %s", path)
    return removed


def run(study, out_dir, until=None, progress=True, jobs=1, scheduler=None, record=None, isolate=False, on_start=None):
    """Build what is stale, up to ``until``.

    Parameters
    ----------
    study : dict
        The validated study.
    out_dir : str or Path
        Study folder; nothing is written outside it.
    until : str, optional
        Last stage to build (default: all, with the report).
    progress : bool
        Show progress bars on stderr.
    jobs : int
        Local worker processes for the cases.
    scheduler : str, optional
        Address of a Dask scheduler for the cases.
    record : list, optional
        Receives the same names as the return value, each as soon as it is done (what finished
        before an interruption).
    isolate : bool
        Run even sequential cases in a worker process (see :func:`run_cases`).
    on_start : callable, optional
        Called with the planned cases once every case is checked, before anything is written
        (``pipeline.py run`` takes the folder's lock and records its study there).

    Returns
    -------
    list of str
        What was rebuilt: stage names (``name@variant`` for sweep variants), ``simulate:<case>``,
        ``radiation:<case>`` and ``report``.

    Raises
    ------
    CasesFailed
        After every other case has finished, if some cases failed.
    """
    out_dir = Path(out_dir)
    stages = required_stages(until)
    cases = plan_cases(study, out_dir)
    if on_start is not None:
        on_start(cases)
    remove_stale_temporaries(out_dir)
    rebuilt = [] if record is None else record
    start = len(rebuilt)
    variants = _variants(study, out_dir, cases)
    for variant_dir, case in variants.items():
        run_structural(case.study, variant_dir, stages, progress, case.variant_label, donors=list(variants),
                       record=rebuilt)
    if until is None or until in ("simulate", "radiation", "report"):
        _, failed = run_cases(cases, out_dir, jobs, scheduler, progress, record=rebuilt, isolate=isolate)
        simulated = [c for c in cases if c.case_id not in failed]
        if until != "simulate":
            # the sound of every simulated case (a case whose radiation fails stays in the report,
            # its levels empty, and is reported as failed at the end)
            _, radiation_failed = run_radiation(simulated, out_dir, progress, record=rebuilt)
            failed = {**failed, **{k: f"radiation: {v}" for k, v in radiation_failed.items()}}
        if until != "simulate" and until != "radiation":
            rebuilt += run_report(study, out_dir, simulated, progress)
        if failed:
            raise CasesFailed(failed)
    return list(rebuilt[start:])


class CasesFailed(RuntimeError):
    """Some cases of a sweep failed (the others finished).

    Attributes
    ----------
    failed : dict
        ``{case_id: error message}``.
    """

    def __init__(self, failed):
        self.failed = failed
        super().__init__(f"{len(failed)} case(s) failed: " + "; ".join(f"{k}: {v}" for k, v in failed.items()))


def status(study, out_dir):
    """Freshness of every stage, case and the report.

    Returns
    -------
    list of (str, bool, str)
        ``(name, fresh, reason)``; a stage downstream of a stale one is stale too.
    """
    out_dir = Path(out_dir)
    rows = []
    cases = plan_cases(study, out_dir)
    variant_stale = {}
    for variant_dir, case in _variants(study, out_dir, cases).items():
        stale = set()
        for stage in STAGES:
            if not stage.used(case.study):  # not part of this study (no row)
                continue
            fresh, reason, _, _ = inspect(stage, case.study, variant_dir)
            blocked = [up for up in stage.upstream_for(case.study) if up in stale]
            if blocked and fresh:
                fresh, reason = False, f"upstream {blocked[0]} stale"
            if not fresh:
                stale.add(stage.name)
            rows.append((stage.name + (f"@{case.variant_label}" if case.variant_label else ""), fresh, reason))
        variant_stale[variant_dir] = bool(stale)
    for case in cases:
        fresh, reason, _, _ = case_check(case, out_dir)
        if fresh and variant_stale[case.variant_dir]:
            fresh, reason = False, "upstream stale"
        rows.append((f"simulate:{case.case_id}", fresh, reason))
        case_fresh = fresh
        fresh, reason, _, _ = radiation_check(case, out_dir)
        if fresh and not case_fresh:
            fresh, reason = False, "upstream stale"
        rows.append((f"radiation:{case.case_id}", fresh, reason))
    fresh, reason, _, _ = report_check(study, out_dir, cases)
    if fresh and not all(f for _, f, _ in rows):
        fresh, reason = False, "upstream stale"
    rows.append(("report", fresh, reason))
    return rows


def case_results(cases, out_dir):
    """Results recorded in the case artefacts (missing or unreadable files skipped).

    Returns
    -------
    list of dict
        ``{"case_id", "L_F2" (dB), "squeal" (bool), "squeal_frequency" (Hz), "wav" (Path or None)}``
        the contact regime (``contact_loss``, ``peak_normal_force`` (N), ``peak_normal_ratio``,
        ``peak_lateral_ratio``, ``regime``) and the class ``oscillation`` (NaN and ``""`` when the
        artefact lacks them).
    """
    out_dir = Path(out_dir)
    results = []
    for case in cases:
        path = out_dir / "cases" / f"{case.case_id}.h5"
        try:
            with h5py.File(path, "r") as f:
                attrs = dict(f.attrs)
                # the metrics as the case wrote them: an edited attribute is not believed
                edited = artefacts.attribute_problems(f, json.loads(attrs.get("checksums", "{}")))
        except (OSError, ValueError):
            continue
        if edited:
            logger.warning("case %s left out: %s", case.case_id, "; ".join(edited))
            continue
        wav = out_dir / "sounds" / f"{case.case_id}.wav"
        results.append({"case_id": case.case_id, "L_F2": float(attrs.get("L_F2", float("nan"))),
                        "squeal": bool(attrs.get("squeal", False)),
                        "squeal_frequency": float(attrs.get("squeal_frequency", float("nan"))),
                        "wav": wav if wav.exists() else None,
                        **{key: float(attrs.get(key, float("nan"))) for key in
                           ("contact_loss", "peak_normal_force", "peak_normal_ratio", "peak_lateral_ratio")},
                        "regime": str(attrs.get("regime", "")), "oscillation": str(attrs.get("oscillation", ""))})
    return results
