"""Benchmark of the rail stages for the default study (BV50, v = 50 km/h, dt = 36 us).

Prints wall times of meshing, model building, the moving kernel and the receptances and
dispersion curves (together the work of the ``rail-greens`` stage), the load average, and
the peak memory (ru_maxrss). Run:
``OMP_NUM_THREADS=1 python benchmarks/rail.py [--repeats N] [--damping MODEL] [--plots DIR]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import time

import numpy as np

from mesh.plots import plot_rail_mesh
from mesh.rail_mesh import mesh_rail_section
from profiles.rail_section import RailParams
from waveguide import api, plots, response, waves
from waveguide.params import TrackParams


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--plots", default=None, help="write figures to this folder")
    ap.add_argument("--damping", default="causal", help="track.damping_model")
    args = ap.parse_args(argv)
    speed, dt = 50 / 3.6, 36e-6
    rail, track = RailParams(), TrackParams.from_mapping({"damping_model": args.damping})
    times = {"mesh": [], "model": [], "kernel": [], "receptance": [], "total": []}
    cpu = []
    for _ in range(args.repeats):
        t0, c0 = time.perf_counter(), time.process_time()
        mesh = mesh_rail_section(rail)
        t1 = time.perf_counter()
        wg = api.build_waveguide(mesh, track, min(track.max_frequency, 1 / dt))
        t2 = time.perf_counter()
        res = api.moving_kernel(mesh, track, speed, dt, waveguide=wg)
        t3 = time.perf_counter()
        f = np.geomspace(20.0, min(track.max_frequency, 1 / dt), 200)  # as api.rail_greens
        wave_list = [wg.waves(2 * np.pi * fi) for fi in f]
        waves.dispersion(wg, f, wave_list)
        response.receptance_along(wg, f, np.linspace(0.0, 3.0, 31), wave_list)
        t4 = time.perf_counter()
        cpu.append(time.process_time() - c0)
        for k, v in zip(times, (t1 - t0, t2 - t1, t3 - t2, t4 - t3, t4 - t0)):
            v_list = times[k]
            v_list.append(v)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"damping model {track.damping_model}; load average {os.getloadavg()[0]:.1f} "
          f"on {os.cpu_count()} cores")
    print(f"mesh: {mesh.n_nodes} nodes, {len(mesh.cells)} {mesh.element_type}; reduced DOF {wg.n}")
    print(f"kernel: {len(res['kernel'])} steps ({res['time'][-1] * 1e3:.1f} ms), "
          f"{len(res['solve_frequency'])} frequencies up to {res['solve_frequency'][-1]:.0f} Hz, "
          f"tail/peak {res['tail']:.1e}")
    print("kernel bands: " + ", ".join(f"{lo:.0f}-{hi:.0f} Hz over {t * 1e3:.1f} ms"
                                       for lo, hi, t in res.get("bands", ())))
    for k, v in times.items():
        print(f"{k:>7s}: median {statistics.median(v):8.2f} s over {len(v)} run(s)")
    print(f"    cpu: median {statistics.median(cpu):8.2f} s (process time, all threads)")
    print(f"peak memory (ru_maxrss): {peak:.0f} MiB")
    if args.plots:
        os.makedirs(args.plots, exist_ok=True)
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
