"""``pipeline.py map``: squeal maps over the study's ``[map.grid]`` (:mod:`stages.maps`)."""

from __future__ import annotations

import logging
from pathlib import Path

from squealcore.errors import InputError
from stages.folder import FolderLock, folder_study
from stages.maps import read_maps, run_map
from stages.maps_confirm import (
    DEFAULT_DURATION,
    agreement,
    check_options,
    confirmation_models,
    run_confirmation,
)

logger = logging.getLogger(__name__)


def add_args(parser):
    """Arguments of ``map``."""
    parser.add_argument("--config", help="study TOML file with a [map.grid] (e.g. studies/maps.toml)")
    parser.add_argument("--out", default="out", help="output folder (default: out): maps.h5, maps.md, figures/")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML); repeatable")
    parser.add_argument("--jobs", type=int, default=1, help="local Dask worker processes (>= 1)")
    parser.add_argument("--scheduler", help="address of a Dask scheduler you control, e.g. tcp://host:8786")
    parser.add_argument("--confirm", type=int, default=0, metavar="N",
                        help="then run N map points (borderline first, then random) in the time domain and "
                             "compare: confirm.csv and a section of maps.md")
    parser.add_argument("--confirm-models", default=",".join(confirmation_models()), metavar="MODELS",
                        help="contact models of the confirmation, comma-separated (default: point,halfspace)")
    parser.add_argument("--confirm-seed", type=int, default=0, help="seed of the random points (default 0)")
    parser.add_argument("--confirm-duration", type=float, default=DEFAULT_DURATION, metavar="SECONDS",
                        help=f"duration of each confirmation case, s (default {DEFAULT_DURATION:g})")
    return parser


def command(args):
    """Run ``map``; returns the exit status (0)."""
    if args.jobs < 1:
        raise InputError("--jobs", f"must be an integer >= 1, got {args.jobs}")
    models = tuple(m.strip() for m in args.confirm_models.split(",") if m.strip())
    if args.confirm != 0:  # before the map: a bad option fails at once
        check_options(args.confirm, models, args.confirm_duration)
    study, _ = folder_study(args.out, args.config, args.quick, args.assignments, command="map")
    out = Path(args.out)
    lock = FolderLock(out, "pipeline.py map")  # it builds, so it holds the folder's lock (stages/folder.py)
    with lock:
        result = _map_and_confirm(args, study, out, models)
    return result


def _map_and_confirm(args, study, out, models):
    """The map, then its confirmation (``--confirm``); returns the exit status (0)."""
    result = run_map(study, out, jobs=args.jobs, scheduler=args.scheduler, progress=not args.quiet)
    if not args.quiet:
        print(f"{result['configurations']} configurations ({result['chunks_computed']} chunk(s) computed) in "
              f"{result['seconds']:.0f} s: {result['path']}, {out / 'maps.md'}, {out / 'figures' / 'maps.png'}")
    if args.confirm:
        rows = run_confirmation(study, out, read_maps(result["path"]), args.confirm, models, args.confirm_seed,
                                args.confirm_duration, jobs=args.jobs, scheduler=args.scheduler,
                                progress=not args.quiet)
        agree, total = agreement(rows)
        if not args.quiet:
            print(f"time-domain confirmation: {agree} of {total} agree with the screen: {out / 'confirm.csv'}")
    return 0
