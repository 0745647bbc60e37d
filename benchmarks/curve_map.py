"""Wall time of a curve's squeal-risk map on 2 cores (issue 35 item 3).

The map of :mod:`stages.curve_map` for the quick study: 16 curve radii (50–1000 m) x 4 speeds
(5, 8, 11, 14 m/s) x 4 friction coefficients (0.2–0.5) = 256 curving configurations, each with its
four wheels screened for the three wheel models (1024 wheel screens), on two local Dask workers
(``--jobs``). The structures are built first in ``--out`` (not timed); the map's own artefact is
removed first, so that every configuration is computed. Prints the wall time, the wall time per
configuration and per wheel screen, and the CPU time of the curving and of the screens per
configuration (medians, from the artefact).

Run: ``OMP_NUM_THREADS=1 python benchmarks/curve_map.py [--out DIR] [--jobs 2]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
from pathlib import Path

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import numpy as np  # noqa: E402

from stages.config import load_study  # noqa: E402
from stages.curve_map import DEFAULT_RADII, curve_map, read_curve_map  # noqa: E402
from stages.screen import structures  # noqa: E402

SPEEDS = (5.0, 8.0, 11.0, 14.0)
FRICTIONS = (0.2, 0.3, 0.4, 0.5)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="output folder (default: a temporary folder)")
    parser.add_argument("--jobs", type=int, default=2, help="local workers (default 2)")
    args = parser.parse_args(argv)
    study = load_study(quick=True)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(args.out) if args.out else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        structures(study, out)  # not timed
        (out / "curve_map.h5").unlink(missing_ok=True)
        result = curve_map(study, out, DEFAULT_RADII, SPEEDS, FRICTIONS, progress=True, jobs=args.jobs)
        data = read_curve_map(result["path"])
    n, wall = result["configurations"], result["seconds"]
    screens = data["seconds"] - data["curving_seconds"]
    solved = data["solved"][..., 0] > 0
    print(f"curve map: {n} configurations (radius x speed x friction) x 4 wheels = {result['wheel_screens']} wheel "
          f"screens, {args.jobs} workers: wall time {wall:.0f} s ({wall / 60:.1f} min); "
          f"{wall / n:.2f} s per configuration, {wall / result['wheel_screens']:.3f} s per wheel screen")
    print(f"  per configuration in the workers (median): curving {np.median(data['curving_seconds']):.2f} s, "
          f"four wheel screens {np.median(screens[solved]):.2f} s; curving without equilibrium: {int((~solved).sum())}")


if __name__ == "__main__":
    main()
