"""Benchmark of the rail stages for the default study (BV50, v = 50 km/h, dt = 36 us).

Prints wall times of meshing, model building and the moving kernel, and the peak memory
(ru_maxrss). Run: ``OMP_NUM_THREADS=1 python benchmarks/rail.py [--repeats N] [--plots DIR]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from mesh.rail_mesh import mesh_rail_section, plot_rail_mesh  # noqa: E402
from mesh.rail_section import RailParams  # noqa: E402
from waveguide import api, plots  # noqa: E402
from waveguide.params import TrackParams  # noqa: E402


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--plots", default=None, help="write figures to this folder")
    args = ap.parse_args(argv)
    speed, dt = 50 / 3.6, 36e-6
    rail, track = RailParams(), TrackParams()
    times = {"mesh": [], "model": [], "kernel": [], "total": []}
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        mesh = mesh_rail_section(rail)
        t1 = time.perf_counter()
        wg = api.build_waveguide(mesh, track, min(track.max_frequency, 1 / dt))
        t2 = time.perf_counter()
        res = api.moving_kernel(mesh, track, speed, dt, waveguide=wg)
        t3 = time.perf_counter()
        for k, v in zip(times, (t1 - t0, t2 - t1, t3 - t2, t3 - t0)):
            v_list = times[k]
            v_list.append(v)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"mesh: {mesh.n_nodes} nodes, {len(mesh.cells)} {mesh.element_type}; reduced DOF {wg.n}")
    print(f"kernel: {len(res['kernel'])} steps ({res['time'][-1] * 1e3:.1f} ms), "
          f"{len(res['solve_frequency'])} frequencies up to {res['solve_frequency'][-1]:.0f} Hz, "
          f"tail/peak {res['tail']:.1e}")
    for k, v in times.items():
        print(f"{k:>7s}: median {statistics.median(v):8.2f} s over {len(v)} run(s)")
    print(f"peak memory (ru_maxrss): {peak:.0f} MiB")
    if args.plots:
        os.makedirs(args.plots, exist_ok=True)
        import numpy as np

        f = np.geomspace(20, 10000, 150)
        plot_rail_mesh(mesh, os.path.join(args.plots, "rail_mesh.png"))
        plots.plot_dispersion(api.dispersion(mesh, track, f, waveguide=wg),
                              os.path.join(args.plots, "rail_dispersion.png"))
        x = np.array([0.0, 0.5, 2.0])
        plots.plot_receptances(f, api.receptance_along(mesh, track, f, x, waveguide=wg), x,
                               os.path.join(args.plots, "rail_receptance.png"))
        plots.plot_kernel(res, os.path.join(args.plots, "rail_kernel.png"))


if __name__ == "__main__":
    main()
