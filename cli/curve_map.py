"""``pipeline.py curve-map``: squeal risk over curve radius, speed and friction (:mod:`stages.curve_map`).

For every configuration of the grid the bogie of the study's ``[curve]`` table is solved in steady
curving and each of its four wheels is screened with its own creepages, tread load and contact
angle, for every wheel model. Writes ``curve_map.h5``, ``curve_map.md`` and
``figures/curve_map.png`` in ``--out``, holding the folder's lock.
"""

from __future__ import annotations

import argparse
from pathlib import Path

from squealcore.errors import InputError
from stages.curve_map import DEFAULT_FRICTIONS, DEFAULT_RADII, DEFAULT_SPEEDS, curve_map
from stages.folder import FolderLock, folder_study


def _floats(text):
    """A comma-separated list of numbers (an argparse type)."""
    try:
        return [float(v) for v in text.split(",") if v.strip()]
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected comma-separated numbers, got {text!r}") from None


def _listed(values):
    return ",".join(f"{v:g}" for v in values)


def add_args(parser):
    """Arguments of ``curve-map``."""
    parser.add_argument("--config", help="study TOML file merged over the defaults (its [curve] table: the bogie)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML); repeatable")
    parser.add_argument("--radii", type=_floats, default=list(DEFAULT_RADII), metavar="R1,R2,...",
                        help=f"curve radii, m (default {_listed(DEFAULT_RADII)})")
    parser.add_argument("--speeds", type=_floats, default=list(DEFAULT_SPEEDS), metavar="V1,V2,...",
                        help=f"speeds, m/s (default {_listed(DEFAULT_SPEEDS)})")
    parser.add_argument("--frictions", type=_floats, default=list(DEFAULT_FRICTIONS), metavar="MU1,MU2,...",
                        help=f"friction coefficients (default {_listed(DEFAULT_FRICTIONS)})")
    parser.add_argument("--jobs", type=int, default=1, help="local Dask worker processes (>= 1)")
    parser.add_argument("--scheduler", help="address of a Dask scheduler you control, e.g. tcp://host:8786")
    return parser


def command(args):
    """Run ``curve-map``; returns the exit status (0)."""
    if args.jobs < 1:
        raise InputError("--jobs", f"must be an integer >= 1, got {args.jobs}")
    study, _ = folder_study(args.out, args.config, args.quick, args.assignments, command="curve-map")
    out = Path(args.out)
    with FolderLock(out, "pipeline.py curve-map"):  # it builds, so it holds the folder's lock
        result = curve_map(study, out, args.radii, args.speeds, args.frictions, progress=not args.quiet,
                           jobs=args.jobs, scheduler=args.scheduler)
    if not args.quiet:
        print(f"curve map: {result['configurations']} configurations x 4 wheels in {result['seconds']:.0f} s: "
              f"{result['path']}, {out / 'curve_map.md'}, {out / 'figures' / 'curve_map.png'}")
    return 0
