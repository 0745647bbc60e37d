"""Dense influence rows against indexed products in the transient tangential sweeps.

The exact Gauss-Seidel sweeps update the displacement at every contact element after each
traction change. With the dense rows (``contact.halfspace.bundles.DenseTangential``) an update
reads three contiguous rows; without, it gathers the coefficients from the Toeplitz kernels.
Both give the same numbers. This prints, per grid, the CPU time per step of a transient from
rest (issue 16's geometry: a = 5, b = 4 mm, grid over the patch + 10 %, 50 kN, mu = 0.3,
eta = -0.3 %: partial slip), with and without the rows, the two alternating in one process
(median of ``--repeat`` runs of ``--steps`` steps each), and the elements in contact. The FFT
sweeps are switched off and the rows' size limit lifted, so that both columns time the exact
sweeps at every size: the crossover sets ``bundles.DENSE_MAX_CONTACT``.

Run: ``OMP_NUM_THREADS=1 python -m benchmarks.dense_rows [--grids 22x18 33x27 44x36] [--steps N] [--repeat N]``.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from benchmarks.contact_solvers import issue_model
from contact.halfspace import bundles, influence, tangential
from contact.halfspace.influence_kernels import no_dense_rows


def _indexed_only(self, cix, ciy):
    """Stand-in for ``Kernels.dense_rows``: no rows, the sweeps gather from the kernels."""
    return no_dense_rows()


def time_per_step(grid, steps, dense):
    """CPU seconds per step of a transient from rest on ``grid`` (nx, ny), and the elements in contact."""
    original = influence.Kernels.dense_rows
    if not dense:
        influence.Kernels.dense_rows = _indexed_only
    try:
        model = issue_model("transient", 5e-3, 4e-3, *grid)
        state = model.initial_state()
        start = time.process_time()
        for _ in range(steps):
            result = model.solve(state, normal_force=50e3, creepage=(0.0, -3e-3, 0.0))
            state = result.new_state
        return (time.process_time() - start) / steps, result.diagnostics.n_contact
    finally:
        influence.Kernels.dense_rows = original


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--grids", nargs="+", default=["22x18", "28x23", "33x27", "38x31", "44x36"],
                        help="grids NXxNY")
    parser.add_argument("--steps", type=int, default=100)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args(argv)
    limit = bundles.DENSE_MAX_CONTACT
    tangential.TRANSIENT_FFT_MIN_CONTACT = 10 ** 9  # exact sweeps at every size
    bundles.DENSE_MAX_CONTACT = influence.DENSE_MAX_CONTACT = 10 ** 4  # rows at every size
    print("| grid | in contact | dense rows (ms per step) | indexed (ms per step) | ratio |")
    print("|---|---|---|---|---|")
    for text in args.grids:
        grid = tuple(int(v) for v in text.lower().split("x"))
        times = {True: [], False: []}
        for _ in range(args.repeat):
            for dense in (True, False):
                seconds, n_contact = time_per_step(grid, args.steps, dense)
                times[dense].append(seconds)
        d, i = np.median(times[True]), np.median(times[False])
        print(f"| {grid[0]} x {grid[1]} | {n_contact} | {1e3 * d:.2f} | {1e3 * i:.2f} | {d / i:.2f} |")
    print(f"(CPU time; load average {os.getloadavg()[0]:.1f}; the solver uses the rows up to "
          f"DENSE_MAX_CONTACT = {limit} elements in contact)")


if __name__ == "__main__":
    main()
