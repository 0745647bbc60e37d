"""Benchmark: hex20 assembly and modal solve on a paper-size annular disc.

Default mesh: annulus r_in = 0.1 m, r_out = 0.39 m, thickness 0.03 m, 22 x 5 x 72 elements
(7920 hex20 elements, 37656 nodes, about 113,000 DOFs; the paper's wheel mesh had 7920 elements
and 37800 nodes), steel, clamped on the inner face, all modes up to 7 kHz.

Run (one configuration per process, so that the peak memory is that of the configuration)::

    OMP_NUM_THREADS=1 python benchmarks/fe_eigen.py --repeats 3
    OMP_NUM_THREADS=1 python benchmarks/fe_eigen.py --ordering MMD_AT_PLUS_A --repeats 1

Prints assembly time, eigen-solve time (medians over the repeats), number of modes and the
peak resident memory (``resource.getrusage(...).ru_maxrss``).
"""

from __future__ import annotations

import argparse
import logging
import resource
import time

import numpy as np

from fe.assembly import apply_dirichlet, assemble_hex20, total_mass
from fe.eigen import solve_modes, sturm_count
from fe.material import isotropic_elasticity
from mesh.structured import annulus_hex20

logger = logging.getLogger("benchmarks.fe_eigen")


def _peak_mib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # Linux: kB


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--r-in", type=float, default=0.10)
    parser.add_argument("--r-out", type=float, default=0.39)
    parser.add_argument("--thickness", type=float, default=0.03)
    parser.add_argument("--n-r", type=int, default=22)
    parser.add_argument("--n-z", type=int, default=5)
    parser.add_argument("--n-theta", type=int, default=72)
    parser.add_argument("--f-max", type=float, default=7000.0)
    parser.add_argument("--shift", type=float, default=None, help="Lanczos shift in Hz (<0: negative)")
    parser.add_argument("--ordering", default="ND", help="ND (own nested dissection) or a SuperLU ordering, e.g. MMD_AT_PLUS_A")
    parser.add_argument("--tol", type=float, default=0.0, help="ARPACK tolerance")
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--sturm-only", action="store_true", help="time one Sturm count only")
    parser.add_argument("-v", "--verbose", action="store_true")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO if args.verbose else logging.WARNING,
                        format="%(asctime)s %(name)s %(message)s")

    nodes, cells = annulus_hex20(args.r_in, args.r_out, args.thickness, args.n_r, args.n_z, args.n_theta)
    d = isotropic_elasticity(210e9, 0.3)
    t_asm = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        K, M = assemble_hex20(nodes, cells, d, 7850.0)
        t_asm.append(time.perf_counter() - t0)
    r = np.hypot(nodes[:, 0], nodes[:, 2])
    inner = np.nonzero(np.isclose(r, args.r_in, rtol=0, atol=1e-9))[0]
    fixed = (3 * inner[:, None] + np.arange(3)).ravel()
    Kf, Mf, free = apply_dirichlet(K, M, fixed)
    print(f"mesh: {cells.shape[0]} elements, {nodes.shape[0]} nodes, {K.shape[0]} DOFs, "
          f"{free.size} free; nnz(K) = {K.nnz}; mass {total_mass(M)[0]:.2f} kg")
    print(f"assembly (element matrices + sparse): median {np.median(t_asm):.2f} s "
          f"over {args.repeats} (all: {', '.join(f'{t:.2f}' for t in t_asm)})")
    del K, M
    if args.sturm_only:
        t0 = time.perf_counter()
        n = sturm_count(Kf, Mf, args.f_max, ordering=args.ordering)
        print(f"Sturm count ({args.ordering}): {n} modes below {args.f_max} Hz in "
              f"{time.perf_counter() - t0:.2f} s")
    else:
        t_eig = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            f, phi = solve_modes(Kf, Mf, args.f_max, shift=args.shift, tol=args.tol, ordering=args.ordering)
            t_eig.append(time.perf_counter() - t0)
        print(f"eigen solve ({args.ordering}, shift {args.shift}, tol {args.tol}): median "
              f"{np.median(t_eig):.2f} s (all: {', '.join(f'{t:.2f}' for t in t_eig)}); "
              f"{f.size} modes up to {args.f_max} Hz, lowest {f[:4].round(1).tolist()} Hz")
    print(f"peak memory (ru_maxrss): {_peak_mib():.0f} MiB")


if __name__ == "__main__":
    main()
