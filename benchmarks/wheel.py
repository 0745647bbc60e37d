"""Benchmark of the wheel stages on the default (paper-size) wheel.

Each measurement runs in a fresh child process, so its peak memory (ru_maxrss) is its own:

- ``wheel-modes``, hex20 by cyclic symmetry (the default): 7776 hex20, 39,672 nodes,
  all modes up to 7 kHz;
- ``wheel-modes``, hex20 by the full sparse solver (``--full``; several minutes);
- ``wheel-modes``, axisymmetric solver on the same section mesh;
- ``wheel-greens`` rotating models: Eulerian model (V, A, K_σ with the centrifugal prestress) and
  the exact moving-load poles, from the hex20 and from the axisymmetric modes.

Run: ``python benchmarks/wheel.py [--repeats N] [--full]``. Prints medians.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys

CHILD = r"""
import json, resource, sys, time
import numpy as np
from mesh.wheel_mesh import mesh_wheel
from mesh.wheel_section import WheelParams
from fe.wheel_modes import solve_axisymmetric, solve_hex20, modal_damping
mesh = mesh_wheel(WheelParams())
material = (210e9, 0.3, 7850.0)
what = {what!r}
t0 = time.perf_counter()
if what == "axisymmetric" or what == "rotation-axisymmetric":
    modes = solve_axisymmetric(mesh.section_nodes, mesh.section_cells, mesh.section_clamped_nodes,
                               mesh.contact_section_node, *material, 7000.0)
else:
    modes = solve_hex20(mesh.hex_nodes, mesh.hex_cells, mesh.hex_clamped_nodes, mesh.contact_hex_node, *material,
                        7000.0, n_sectors=None if what == "hex20-full" else 72)
t1 = time.perf_counter()
extra = {{}}
if what.startswith("rotation"):
    from fe import moving_load
    from fe.rotation import eulerian_model_axisymmetric, eulerian_model_hex20, spin_rate
    zeta = modal_damping(modes.nodal_diameters, 1e-4, 1e-3, 1)
    spin = spin_rate(50 / 3.6, 0.39)
    if modes.solver == "axisymmetric":
        model = eulerian_model_axisymmetric(modes, mesh.section_nodes, mesh.section_cells, mesh.section_clamped_nodes,
                                            *material, zeta)
        t2 = time.perf_counter()
        moving_load.moving_poles_residues_from_modes(modes, mesh.contact_section_node, zeta, spin)
    else:
        model = eulerian_model_hex20(modes, mesh.hex_nodes, mesh.hex_cells, mesh.hex_clamped_nodes, *material, zeta,
                                     n_sectors=72)
        t2 = time.perf_counter()
    model.poles_residues(spin)
    t3 = time.perf_counter()
    extra = {{"eulerian_matrices_s": t2 - t1, "poles_s": t3 - t2}}
print(json.dumps({{"modes": int(modes.frequency.size), "solve_s": t1 - t0, **extra,
                  "peak_mib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024}}))
"""


def measure(what, repeats):
    runs = []
    for _ in range(repeats):
        out = subprocess.run([sys.executable, "-c", CHILD.format(what=what)], capture_output=True,
                             text=True, check=True, env=dict(os.environ, OMP_NUM_THREADS="1",
                                                             OPENBLAS_NUM_THREADS="1"))
        runs.append(json.loads(out.stdout.strip().splitlines()[-1]))
    keys = [k for k in runs[0] if k != "modes"]
    return runs[0]["modes"], {k: statistics.median(r[k] for r in runs) for k in keys}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--full", action="store_true", help="also time the full sparse hex20 solver (slow)")
    args = parser.parse_args(argv)
    cases = ["hex20-cyclic", "axisymmetric", "rotation-hex20", "rotation-axisymmetric"]
    if args.full:
        cases.insert(1, "hex20-full")
    print(f"default wheel (7776 hex20 / 108 quad8), modes to 7 kHz; medians of {args.repeats} run(s)")
    for what in cases:
        modes, figures = measure(what, 1 if what == "hex20-full" else args.repeats)
        text = ", ".join(f"{k} {v:.2f}" for k, v in figures.items())
        print(f"{what:22s} {modes:3d} modes: {text}")


if __name__ == "__main__":
    main()
