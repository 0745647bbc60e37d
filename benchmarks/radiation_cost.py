"""Benchmark of the radiation models.

- the fast model per case (``stages.radiation_inputs.radiate_case``): median wall and CPU time
  per wheel model over the cases of a built study folder, beside the 1 s target, with the
  wheel's surface integrals computed once per variant (timed separately: they are cached in the
  stage's process), and the machine's load average (the machine is shared: CPU time is the
  steadier figure);
- the BEM (bempp-cl) per frequency on a wheel variant's own surface mesh: wall time of each
  axial mode with no nodal circle, n = 2…7 by default, ``--bem-n 0 1 2 3`` for the modes whose
  fast-model laws were fitted to it (with ``--bem-factor 0.5`` at half their frequency, the
  fit's second point; the solves are stored in radiation/bem_wheel_solves.py; the first one
  includes bempp-cl's numba compilation), the fast model's agreement, and the peak memory of the
  process (ru_maxrss).

Run: ``python benchmarks/radiation_cost.py --study <folder built with --until radiation> [--bem]
[--bem-n 2 3 4] [--bem-factor 0.5] [--json out.json]``. Needs a study folder (e.g. ``pipeline.py
run --quick --until radiation --out out-quick``).
"""

from __future__ import annotations

import argparse
import importlib.util
import json
import logging
import os
import resource
import statistics
import time
from pathlib import Path

import h5py


from stages.radiation_inputs import radiate_case, wheel_modes_and_surfaces  # noqa: E402
from stages.wheel import read_mesh, read_modes  # noqa: E402
from radiation.plots import plot_efficiency_comparison  # noqa: E402
from stages.config import load_study  # noqa: E402


#: Target wall time of the fast model per case, s (issue 17).
TARGET_SECONDS = 1.0


def time_fast_model(study_dir, wheel_load, rms_window):
    """Surface-integral time (s) and per-case times of the fast model in a study folder.

    Returns
    -------
    (float, dict)
        Seconds for the surface integrals, and ``{wheel model: [(wall s, CPU s), ...]}``.
    """
    study_dir = Path(study_dir)
    start = time.perf_counter()
    wheel_modes_and_surfaces(study_dir)
    surfaces = time.perf_counter() - start
    times = {}
    for case in sorted((study_dir / "cases").glob("*.h5")):
        with h5py.File(case, "r") as f:
            model = str(f.attrs["wheel_model"])
        start, cpu = time.perf_counter(), time.process_time()
        radiate_case(case, study_dir, wheel_load, rms_window)
        times.setdefault(model, []).append((time.perf_counter() - start, time.process_time() - cpu))
    return surfaces, times


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", required=True, help="study folder with cases/ and the structural artefacts")
    parser.add_argument("--bem", action="store_true", help="also time the BEM per frequency")
    parser.add_argument("--bem-n", type=int, nargs="+", default=[2, 3, 4, 5, 6, 7])
    parser.add_argument("--bem-factor", type=float, default=1.0,
                        help="solve each mode at this multiple of its own frequency (default 1)")
    parser.add_argument("--json", help="write the results to this file (updated after every BEM frequency)")
    parser.add_argument("--figure", help="with --bem: draw the efficiencies, fast model vs BEM, into this PNG")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    study = load_study(quick=True)
    out = {}
    load_before = os.getloadavg()[0]
    surfaces, times = time_fast_model(args.study, study["operating"]["wheel_load"], study["simulation"]["rms_window"])
    load = (load_before, os.getloadavg()[0])
    out["fast"] = {"surface_integrals_s": surfaces, "target_s": TARGET_SECONDS, "load_average": load, "models": {}}
    print(f"fast model: surface integrals {surfaces:.2f} s once per variant (load average {load[0]:.1f} -> {load[1]:.1f})")
    for model, rows in times.items():
        wall, cpu = [w for w, _ in rows], [c for _, c in rows]
        out["fast"]["models"][model] = {"cases": len(rows), "median_wall_s": statistics.median(wall),
                                        "max_wall_s": max(wall), "median_cpu_s": statistics.median(cpu)}
        print(f"  {model:12s} {len(rows):3d} cases: median {statistics.median(wall):.2f} s wall, "
              f"{statistics.median(cpu):.2f} s CPU, max {max(wall):.2f} s wall (target {TARGET_SECONDS:.0f} s)")
    if args.bem and importlib.util.find_spec("bempp_cl") is None:
        print("BEM: bempp-cl is not installed (pip install -e '.[bem]'): not timed")
    elif args.bem:
        from radiation.bem_compare import compare_axial_modes  # lazy: bempp-cl import ~1 s, only with --bem

        mesh = read_mesh(Path(args.study) / "wheel_mesh.h5")
        modes = read_modes(Path(args.study) / "wheel_modes.h5", with_shapes=True)
        rows = []
        for n in args.bem_n:
            rows += compare_axial_modes(mesh, modes, [n], frequency_factor=args.bem_factor)
            out["bem"] = rows
            out["peak_memory_MB"] = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
            if args.json:
                Path(args.json).write_text(json.dumps(out, indent=1))
        for row in rows:
            print(f"BEM n = {row['n']} at {row['frequency']:.0f} Hz ({row['triangles']} triangles): "
                  f"{row['seconds']:.0f} s, sigma BEM {row['sigma_bem']:.3g}, fast {row['sigma_fast']:.3g} "
                  f"({row['difference_db']:+.1f} dB)")
        print(f"peak memory {out.get('peak_memory_MB', float('nan')):.0f} MB")
        if args.figure:
            _, surfaces = wheel_modes_and_surfaces(args.study)
            plot_efficiency_comparison(surfaces.outer_radius, rows, args.figure)
    if args.json:
        Path(args.json).write_text(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
