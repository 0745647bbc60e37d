"""Command line and stage graph of the curve-squeal toolkit.

``python pipeline.py run`` builds every stage of the study whose artefact is missing or stale;
``status`` tells which are fresh and why the others are not; ``contact`` solves a stand-alone
contact problem. No physics lives here: stage bodies are in ``stages/`` and call the physics
packages.

A stage is fresh when its artefact opens, has the expected schema and version, and both the hash
of the configuration sections it reads and the hashes of its upstream artefacts match the ones
recorded in it (squealcore/artefacts.py). Otherwise it is rebuilt, and so is everything
downstream of it, because a rebuilt artefact has new bytes.
"""

from __future__ import annotations

import os

# The dense linear algebra here is many small problems (waveguide eigenproblems per frequency,
# sector and harmonic eigenproblems): threaded BLAS only adds contention, and sweeps get their
# parallelism from Dask workers. Must be set before numpy loads its BLAS; the user's own
# settings win.
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse
import importlib
import logging
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from squealcore.artefacts import ArtefactError, file_sha256, freshness, params_hash
from squealcore.errors import InputError
from squealcore.study import get_section
from stages.cases import CASE_VERSION
from stages.rail import GREENS_VERSION as RAIL_GREENS_VERSION

logger = logging.getLogger("pipeline")


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
    """

    name: str
    filename: str
    schema: str
    version: int
    sections: tuple
    upstream: tuple
    body: str

    def function(self):
        module, name = self.body.split(":")
        return getattr(importlib.import_module(module), name)


STAGES = (
    Stage("wheel-mesh", "wheel_mesh.h5", "wheel_mesh", 1, ("wheel",), (), "stages.wheel:build_mesh"),
    Stage("wheel-modes", "wheel_modes.h5", "wheel_modes", 1, ("wheel.fe",), ("wheel-mesh",), "stages.wheel:build_modes"),
    Stage("wheel-greens", "wheel_greens.h5", "wheel_greens", 1, ("operating", "time", "wheel.rotation"),
          ("wheel-modes",), "stages.wheel:build_greens"),
    Stage("rail-mesh", "rail_mesh.h5", "rail_mesh", 1, ("rail",), (), "stages.rail:build_mesh"),
    Stage("rail-greens", "rail_greens.h5", "rail_greens", RAIL_GREENS_VERSION, ("track", "operating", "time"), ("rail-mesh",),
          "stages.rail:build_greens"),
)
STAGE_BY_NAME = {stage.name: stage for stage in STAGES}
CASE_STAGE = Stage("simulate", "cases/{case}.h5", "case", CASE_VERSION, ("wheel", "contact", "simulation", "operating", "time"),
                   ("wheel-greens", "rail-greens"), "stages.cases:build_case")
REPORT_STAGE = Stage("report", "report.h5", "report", 1, ("report",), (), "stages.report:build_report")
ALL_STAGE_NAMES = [stage.name for stage in STAGES] + ["simulate", "report"]


def required_stages(until=None):
    """The structural stages needed to build ``until`` (all if None or a later stage), in order."""
    if until is None or until in ("simulate", "report"):
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
    """The configuration a stage reads: ``{section: table}``."""
    return {section: get_section(study, section) for section in stage.sections}


def _check(stage, study, output, upstream_paths, extra_params=None):
    params = stage_params(stage, study)
    if extra_params:
        params["extra"] = extra_params
    params_sha = params_hash(params)
    inputs = {}
    for path in upstream_paths:
        path = Path(path)
        if not path.exists():
            return False, f"upstream {path.name} missing", params_sha, {}
        inputs[str(path.name) if path.parent.name != "cases" else f"cases/{path.name}"] = file_sha256(path)
    fresh, reason = freshness(output, stage.schema, stage.version, params_sha, inputs)
    return fresh, reason, params_sha, inputs


def inspect(stage, study, out_dir):
    """Freshness of one structural stage in ``out_dir``: (fresh, reason, params hash, upstream hashes)."""
    upstream = [Path(out_dir) / STAGE_BY_NAME[up].filename for up in stage.upstream]
    return _check(stage, study, Path(out_dir) / stage.filename, upstream)


def _context(stage, study, out_dir, output, inputs, params_sha, input_hashes, progress):
    from stages.context import StageContext

    return StageContext(study=study, out_dir=Path(out_dir), output=Path(output), inputs=inputs, schema=stage.schema,
                        schema_version=stage.version, params_sha256=params_sha, input_hashes=input_hashes,
                        progress=progress, sections=stage.sections)


def _reuse(stage, out_dir, params_sha, inputs, donors):
    """Copy a fresh artefact of ``stage`` from another variant folder, if one has the same parameters
    and inputs (e.g. the rail of a wheel-reprofiling sweep); True if copied."""
    import shutil

    for donor in donors:
        source = Path(donor) / stage.filename
        if Path(donor) == out_dir or not source.exists():
            continue
        fresh, _ = freshness(source, stage.schema, stage.version, params_sha, inputs)
        if fresh:
            target = out_dir / stage.filename
            partial = target.with_name(target.name + ".partial")
            shutil.copy2(source, partial)
            os.replace(partial, target)
            return True
    return False


def run_structural(study, out_dir, stages, progress=True, label="", donors=()):
    """Build the stale structural stages of one variant; returns the names rebuilt.

    A stale stage whose artefact exists, fresh for the same parameters and inputs, in one of the
    ``donors`` folders (other variants of the sweep) is copied from there instead of rebuilt.
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rebuilt = []
    for stage in stages:
        fresh, reason, params_sha, inputs = inspect(stage, study, out_dir)
        name = stage.name + (f"@{label}" if label else "")
        if fresh:
            logger.info("%-13s fresh", name)
            continue
        if inputs or not stage.upstream:
            if _reuse(stage, out_dir, params_sha, inputs, donors):
                logger.info("%-13s copied from another variant (same parameters and inputs)", name)
                continue
        logger.info("%-13s running (%s)", name, reason)
        context = _context(stage, study, out_dir, out_dir / stage.filename,
                           {up: out_dir / STAGE_BY_NAME[up].filename for up in stage.upstream}, params_sha, inputs,
                           progress)
        start = time.perf_counter()
        stage.function()(context)
        logger.info("%-13s done in %.1f s", name, time.perf_counter() - start)
        rebuilt.append(name)
    return rebuilt


@dataclass(frozen=True)
class Case:
    """One case of a sweep: its id, overrides, complete study and structural variant folder."""

    case_id: str
    overrides: dict
    study: dict
    variant_dir: Path
    variant_label: str


def plan_cases(study, out_dir):
    """The cases of a study, each with the folder of its structural artefacts.

    Cases whose studies differ only outside the structural sections share one variant; when a
    sweep changes structural parameters (e.g. the wheel's rolling radius), each variant gets a
    folder ``variants/<label>`` of its own, otherwise the artefacts live in ``out_dir``.
    """
    from stages.cases import STRUCTURAL_SECTIONS, case_study, expand_sweep, structural_key

    out_dir = Path(out_dir)
    expanded = [(case_id, overrides, case_study(study, overrides)) for case_id, overrides in expand_sweep(study)]
    keys = {}
    for case_id, overrides, cs in expanded:
        label = "_".join(f"{k.split('.')[-1]}={v}" for k, v in overrides.items()
                         if k.split(".")[0] in STRUCTURAL_SECTIONS)
        keys.setdefault(structural_key(cs), label)
    single = len(keys) == 1
    cases = []
    for case_id, overrides, cs in expanded:
        label = keys[structural_key(cs)]
        variant_dir = out_dir if single else out_dir / "variants" / label
        cases.append(Case(case_id, overrides, cs, variant_dir, "" if single else label))
    return cases


def case_check(case, out_dir):
    """Freshness of one case artefact: (fresh, reason, params hash, upstream hashes)."""
    upstream = [case.variant_dir / STAGE_BY_NAME[up].filename for up in CASE_STAGE.upstream]
    output = Path(out_dir) / "cases" / f"{case.case_id}.h5"
    return _check(CASE_STAGE, case.study, output, upstream)


def case_payload(case, out_dir, progress):
    """Plain-data description of a pending case, sent to a (possibly remote) worker."""
    fresh, reason, params_sha, inputs = case_check(case, out_dir)
    return {"case_id": case.case_id, "overrides": case.overrides, "study": case.study, "out_dir": str(out_dir),
            "variant_dir": str(case.variant_dir), "params_sha256": params_sha, "input_hashes": inputs,
            "schema": CASE_STAGE.schema, "schema_version": CASE_STAGE.version,
            "progress": progress, "reason": reason}


def run_cases(cases, out_dir, jobs=1, scheduler=None, progress=True):
    """Run the stale cases, locally one by one, on a local Dask cluster or on a remote one.

    Returns
    -------
    (list of str, dict)
        Ids of the cases computed, and ``{case_id: error message}`` of those that failed.
    """
    from stages.cases import execute_case

    pending = []
    for case in cases:
        fresh, reason, _, _ = case_check(case, out_dir)
        if fresh:
            logger.info("case %s fresh", case.case_id)
        else:
            pending.append(case_payload(case, out_dir, progress and jobs == 1 and scheduler is None))
    done, failed = [], {}
    if not pending:
        return done, failed
    logger.info("%d of %d cases to run", len(pending), len(cases))
    if scheduler is None and jobs <= 1:
        outcomes = (execute_case(payload) for payload in pending)
        for outcome in outcomes:
            _collect(outcome, done, failed)
        return done, failed
    from dask.distributed import Client, LocalCluster, as_completed

    cluster = None
    if scheduler is None:
        cluster = LocalCluster(n_workers=jobs, threads_per_worker=1, processes=True, dashboard_address=None)
    client = Client(scheduler if scheduler is not None else cluster)
    try:
        futures = [client.submit(execute_case, payload, pure=False, key=f"case-{payload['case_id']}-{payload['params_sha256'][:8]}")
                   for payload in pending]
        for future in as_completed(futures):
            _collect(future.result(), done, failed)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()
    return done, failed


def _collect(outcome, done, failed):
    if outcome["ok"]:
        logger.info("case %s done in %.1f s", outcome["case_id"], outcome["seconds"])
        done.append(outcome["case_id"])
    else:
        logger.error("case %s failed: %s", outcome["case_id"], outcome["error"])
        failed[outcome["case_id"]] = outcome["error"]


def run_report(study, out_dir, cases, progress=True):
    """Build the report if its inputs (base artefacts, all case files, ``[report]``) changed."""
    out_dir = Path(out_dir)
    base = cases[0].variant_dir if cases else out_dir
    upstream = [base / stage.filename for stage in STAGES]
    upstream += [out_dir / "cases" / f"{case.case_id}.h5" for case in cases]
    upstream = [p for p in upstream if p.exists()]
    extra = {"cases": [case.case_id for case in cases], "base": str(base)}
    fresh, reason, params_sha, inputs = _check(REPORT_STAGE, study, out_dir / REPORT_STAGE.filename, upstream, extra)
    if fresh:
        logger.info("%-13s fresh", "report")
        return []
    logger.info("%-13s running (%s)", "report", reason)
    context = _context(REPORT_STAGE, study, out_dir, out_dir / REPORT_STAGE.filename,
                       {"base": base, "cases": [out_dir / "cases" / f"{c.case_id}.h5" for c in cases]}, params_sha,
                       inputs, progress)
    REPORT_STAGE.function()(context)
    return ["report"]


def run(study, out_dir, until=None, progress=True, jobs=1, scheduler=None):
    """Build what is stale, up to ``until``.

    Returns
    -------
    list of str
        What was rebuilt: stage names (``name@variant`` for sweep variants), ``simulate:<case>``
        and ``report``.

    Raises
    ------
    CasesFailed
        After every other case has finished, if some cases failed.
    """
    out_dir = Path(out_dir)
    stages = required_stages(until)
    cases = plan_cases(study, out_dir)
    rebuilt = []
    variants = {}
    for case in cases:
        variants.setdefault(case.variant_dir, case)
    if not variants:
        variants[out_dir] = Case("base", {}, study, out_dir, "")
    for variant_dir, case in variants.items():
        rebuilt += run_structural(case.study, variant_dir, stages, progress, case.variant_label, donors=list(variants))
    if until is not None and until not in ("simulate", "report"):
        return rebuilt
    done, failed = run_cases(cases, out_dir, jobs, scheduler, progress)
    rebuilt += [f"simulate:{case_id}" for case_id in done]
    if until != "simulate":
        rebuilt += run_report(study, out_dir, [c for c in cases if c.case_id not in failed], progress)
    if failed:
        raise CasesFailed(failed)
    return rebuilt


class CasesFailed(RuntimeError):
    """Some cases of a sweep failed (the others finished)."""

    def __init__(self, failed):
        self.failed = failed
        super().__init__(f"{len(failed)} case(s) failed: " + "; ".join(f"{k}: {v}" for k, v in failed.items()))


def status(study, out_dir):
    """Freshness of every stage and case: list of (name, fresh, reason), stale upstream propagated."""
    rows = []
    cases = plan_cases(study, out_dir)
    variants = {}
    for case in cases:
        variants.setdefault(case.variant_dir, case)
    for variant_dir, case in variants.items():
        stale = set()
        for stage in STAGES:
            fresh, reason, _, _ = inspect(stage, case.study, variant_dir)
            blocked = [up for up in stage.upstream if up in stale]
            if blocked and fresh:
                fresh, reason = False, f"upstream {blocked[0]} stale"
            if not fresh:
                stale.add(stage.name)
            rows.append((stage.name + (f"@{case.variant_label}" if case.variant_label else ""), fresh, reason))
    for case in cases:
        fresh, reason, _, _ = case_check(case, out_dir)
        rows.append((f"simulate:{case.case_id}", fresh, reason))
    return rows


def _study_arguments(parser):
    parser.add_argument("--config", help="study TOML file merged over the defaults (studies/paper.toml)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML; a bare word is a string); repeatable")
    parser.add_argument("--quiet", action="store_true", help="no progress output")


def build_parser():
    """The argument parser of ``pipeline.py``."""
    parser = argparse.ArgumentParser(prog="pipeline.py", description=__doc__.split("\n\n")[0])
    commands = parser.add_subparsers(dest="command", required=True)
    run_parser = commands.add_parser("run", help="build the stale stages of a study")
    _study_arguments(run_parser)
    run_parser.add_argument("--until", help=f"last stage to build ({', '.join(ALL_STAGE_NAMES)})")
    run_parser.add_argument("--jobs", type=int, default=1, help="run cases in parallel on a local Dask cluster")
    run_parser.add_argument("--scheduler", help="address of an existing Dask scheduler, e.g. tcp://host:8786")
    status_parser = commands.add_parser("status", help="which stages are fresh, and why the others are not")
    _study_arguments(status_parser)
    export_parser = commands.add_parser("export-modes", help="write the wheel's mode shapes to a VTU file for ParaView")
    _study_arguments(export_parser)
    export_parser.add_argument("--file", default=None, help="output .vtu (default: OUT/wheel_modes.vtu)")
    export_parser.add_argument("--modes", type=int, nargs="*", help="mode numbers (1-based); default all")
    commands.add_parser("contact", help="stand-alone contact problem: pipeline.py contact CASE.toml [--json] ...",
                        add_help=False)
    return parser


def main(argv=None):
    """Run the command line; returns the exit status (2 for bad input)."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "contact":
        from interaction.contact.cli import main as contact_main

        return contact_main(argv[1:])
    parser = build_parser()
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.WARNING if args.quiet else logging.INFO,
                        format="%(levelname)s %(name)s: %(message)s", force=True)
    try:
        from stages.config import load_study

        study = load_study(args.config, args.quick, args.assignments)
        if args.command == "status":
            for name, fresh, reason in status(study, args.out):
                print(f"{name:60s} {'fresh' if fresh else 'stale'}{'' if fresh else '  (' + reason + ')'}")
            return 0
        if args.command == "export-modes":
            from stages.export import export_modes

            run(study, args.out, "wheel-modes", progress=not args.quiet)
            target = Path(args.file) if args.file else Path(args.out) / "wheel_modes.vtu"
            export_modes(Path(args.out), target, args.modes)
            return 0
        if args.jobs < 1:
            raise InputError("--jobs", f"must be >= 1, got {args.jobs}")
        rebuilt = run(study, args.out, args.until, progress=not args.quiet, jobs=args.jobs, scheduler=args.scheduler)
        logger.info("rebuilt: %s", ", ".join(rebuilt) or "nothing (all fresh)")
        return 0
    except CasesFailed as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except ArtefactError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
