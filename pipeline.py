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
    Stage("wheel-greens", "wheel_greens.h5", "wheel_greens", 1, ("operating", "time"), ("wheel-modes",),
          "stages.wheel:build_greens"),
    Stage("report", "report.h5", "report", 1, ("report",), ("wheel-mesh", "wheel-modes", "wheel-greens"),
          "stages.report:build_report"),
)
STAGE_BY_NAME = {stage.name: stage for stage in STAGES}


def required_stages(until=None):
    """The stages needed to build ``until`` (all stages if None), in build order."""
    if until is None:
        return list(STAGES)
    if until not in STAGE_BY_NAME:
        raise InputError("--until", f"unknown stage {until!r}; stages: {', '.join(STAGE_BY_NAME)}")
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


def inspect(stage, study, out_dir):
    """Freshness of one stage given the current upstream files.

    Returns
    -------
    (bool, str, str, dict)
        fresh, reason, params hash, upstream hashes.
    """
    params_sha = params_hash(stage_params(stage, study))
    inputs = {}
    for up in stage.upstream:
        path = Path(out_dir) / STAGE_BY_NAME[up].filename
        if not path.exists():
            return False, f"upstream {up} missing", params_sha, {}
        inputs[STAGE_BY_NAME[up].filename] = file_sha256(path)
    fresh, reason = freshness(Path(out_dir) / stage.filename, stage.schema, stage.version, params_sha, inputs)
    return fresh, reason, params_sha, inputs


def run(study, out_dir, until=None, progress=True):
    """Build the stale stages needed for ``until``.

    Parameters
    ----------
    study : dict
        Validated study.
    out_dir : str or Path
        Output folder.
    until : str, optional
        Last stage to build.
    progress : bool
        Show progress bars.

    Returns
    -------
    list of str
        Names of the stages that were rebuilt.
    """
    from stages.context import StageContext

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rebuilt = []
    for stage in required_stages(until):
        fresh, reason, params_sha, inputs = inspect(stage, study, out_dir)
        if fresh:
            logger.info("%-13s fresh", stage.name)
            continue
        logger.info("%-13s running (%s)", stage.name, reason)
        context = StageContext(
            study=study,
            out_dir=out_dir,
            output=out_dir / stage.filename,
            inputs={up: out_dir / STAGE_BY_NAME[up].filename for up in stage.upstream},
            schema=stage.schema,
            schema_version=stage.version,
            params_sha256=params_sha,
            input_hashes=inputs,
            progress=progress,
        )
        start = time.perf_counter()
        stage.function()(context)
        logger.info("%-13s done in %.1f s", stage.name, time.perf_counter() - start)
        rebuilt.append(stage.name)
    return rebuilt


def status(study, out_dir):
    """Freshness of every stage: list of (name, fresh, reason), stale upstream propagated."""
    rows = []
    stale = set()
    for stage in STAGES:
        fresh, reason, _, _ = inspect(stage, study, out_dir)
        blocked = [up for up in stage.upstream if up in stale]
        if blocked and fresh:
            fresh, reason = False, f"upstream {blocked[0]} stale"
        if not fresh:
            stale.add(stage.name)
        rows.append((stage.name, fresh, reason))
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
    run_parser.add_argument("--until", help=f"last stage to build ({', '.join(STAGE_BY_NAME)})")
    status_parser = commands.add_parser("status", help="which stages are fresh, and why the others are not")
    _study_arguments(status_parser)
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
                print(f"{name:13s} {'fresh' if fresh else 'stale'}{'' if fresh else '  (' + reason + ')'}")
            return 0
        rebuilt = run(study, args.out, args.until, progress=not args.quiet)
        logger.info("rebuilt: %s", ", ".join(rebuilt) or "nothing (all fresh)")
        return 0
    except InputError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 2
    except ArtefactError as exc:
        print(f"error: {exc}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
