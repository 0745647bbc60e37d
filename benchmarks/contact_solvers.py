"""Contact solver timings: issue 16's table against CONTACT, and the default study's contact step.

Issue 16's table (our time, CONTACT's time as measured in the issue, the ratio): steady rolling
with spin on a = 8, b = 4 mm at 40 x 40 to 80 x 80 elements, steady rolling without spin at
100 x 100 (150 x 150 with ``--full``), and the transient step from rest on the 22 x 18 grid
(a = 5, b = 4 mm, +10 %) and on the 44 x 36 grid of half the element size, at eta = -0.3 %
and in full slip. Normal force 50 kN, G = 80 GPa, nu = 0.3, mu = 0.3, tolerance 1e-9.
The issue does not give its creepages; these are: spin cases xi = 0.1 %, eta = -0.2 %,
phi = -3 /m (partial slip); no-spin cases xi = 0.1 %, eta = -0.2 %; full slip eta = -3 %.

Then the default study's contact: dx = dy = 0.5 mm over the Hertz patch (about 10.5 x 8.8 mm)
of a 50 kN load on a 0.39 m wheel (flat tread across) and a 0.3 m rail head radius, steel
E = 210 GPa, nu = 0.3, mu = 0.3, eta = -1 %, v = 50 km/h. Targets: halfspace < 1 ms, point < 5 us.

With ``--scaling``, only the transient step at eta = -0.3 % on grids of 0.75 to 4 times the
44 x 36 grid's element count per direction (same patch, finer elements): the growth of our cost
with the number of elements, relative to n log n, with the local sweeps' coarse level (the
solver) and without it (no reference times: the issue measured CONTACT on the two grids of its
table). About two minutes.

Run: ``OMP_NUM_THREADS=1 python benchmarks/contact_solvers.py [--steps N] [--repeat N] [--full] [--only transient] [--clock cpu]``
or ``... --scaling``. Prints medians.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_curvatures, hertz_from_semi_axes
from contact.params import Friction, Material
from contact.point.model import PointContact

CONTACT_SECONDS = {
    # CONTACT (Vollebregt, gfortran -O2, MKL FFTs, one thread, tolerance 1e-9) on this machine,
    # source: issue 16's table
    "steady, spin, 40 x 40": 0.20,
    "steady, spin, 60 x 60": 1.37,
    "steady, spin, 80 x 80": 5.35,
    "steady, no spin, 100 x 100": 7.9,
    "steady, no spin, 150 x 150": 56.0,
    "transient, 22 x 18, eta = -0.3 %, per step": 1.10e-3,
    "transient, 22 x 18, full slip, per step": 0.63e-3,
    "transient, 44 x 36, eta = -0.3 %, per step": 4.8e-3,
    "transient, 44 x 36, full slip, per step": 2.6e-3,
}
OURS_BEFORE = {
    # our time before the steady Gauss-Seidel solver (issue 16's table)
    "steady, spin, 40 x 40": 6.7,
    "steady, spin, 60 x 60": 52.0,
    "steady, spin, 80 x 80": 236.0,
    "steady, no spin, 100 x 100": 438.0,
    "steady, no spin, 150 x 150": float("nan"),
    "transient, 22 x 18, eta = -0.3 %, per step": 2.49e-3,
    "transient, 22 x 18, full slip, per step": 1.22e-3,
    "transient, 44 x 36, eta = -0.3 %, per step": 40.4e-3,
    "transient, 44 x 36, full slip, per step": 16.1e-3,
}
ISSUE_MATERIAL = Material(80e9, 0.3)
CLOCKS = {"wall": time.perf_counter, "cpu": time.process_time}
clock = CLOCKS["wall"]  # --clock cpu: the process's CPU time, less disturbed than wall time on a loaded machine
clock_name = "wall"
SPIN = (1e-3, -2e-3, -3.0)
NO_SPIN = (1e-3, -2e-3, 0.0)


def issue_model(kind, a, b, nx, ny, force=50e3, mu=0.3):
    """The half-space model of an issue-16 row: Hertz gap of semi-axes a, b (m), grid over the patch + 10 %."""
    hz = hertz_from_semi_axes(a, b, force, ISSUE_MATERIAL.contact_modulus)
    grid = Grid.covering(a, b, nx=nx, ny=ny)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    return HalfspaceContact(material=ISSUE_MATERIAL, friction=Friction(mu), grid=grid,
                            gap=hz.A * X ** 2 + hz.B * Y ** 2, kind=kind, speed=20.0)


def _steady_row(n, creepage, repeat):
    model = issue_model("steady", 8e-3, 4e-3, n, n)
    times = []
    for _ in range(repeat):
        t0 = clock()
        res = model.solve(model.initial_state(), normal_force=50e3, creepage=creepage)
        times.append(clock() - t0)
    return float(np.median(times)), res


def _transient_row(n, creepage, steps):
    model = issue_model("transient", 5e-3, 4e-3, *n)
    t, res = _time_steps(model, steps, creepage, warmup=0, force=50e3)
    return float(np.median(t)), res


def _time_steps(model, steps, creepage, warmup, force=50e3):
    state = model.initial_state()
    times = []
    for n in range(warmup + steps):
        t0 = clock()
        res = model.solve(state, normal_force=force, creepage=creepage)
        times.append(clock() - t0)
        state = res.new_state
    return np.array(times[warmup:]), res


def issue_table(full=False, repeat=3, steps=100, kinds=("steady", "transient")):
    """Rows (problem, our seconds, CONTACT's seconds, result) of issue 16's table that run here."""
    rows = []
    if "steady" in kinds:
        for n in (40, 60, 80):
            rows.append((f"steady, spin, {n} x {n}", *_steady_row(n, SPIN, repeat if n < 80 else 1)))
        if full:
            rows.append(("steady, no spin, 100 x 100", *_steady_row(100, NO_SPIN, 1)))
            rows.append(("steady, no spin, 150 x 150", *_steady_row(150, NO_SPIN, 1)))
    for grid in ((22, 18), (44, 36)) if "transient" in kinds else ():
        for label, creep in (("eta = -0.3 %", (0.0, -3e-3, 0.0)), ("full slip", (0.0, -3e-2, 0.0))):
            rows.append((f"transient, {grid[0]} x {grid[1]}, {label}, per step", *_transient_row(grid, creep, steps)))
    return rows


SCALING_GRIDS = ((33, 27), (44, 36), (66, 54), (88, 72), (132, 108), (176, 144))


def scaling_rows(steps=100, coarse=True):
    """(grid, elements in contact, median seconds per step, median sweeps per step) of the transient at eta = -0.3 %.

    ``coarse=False``: without the local sweeps' coarse level (transient_fft.COARSE_MIN_CONTACT
    set out of reach), as before it.
    """
    from contact.halfspace import transient_fft
    kept = transient_fft.COARSE_MIN_CONTACT
    transient_fft.COARSE_MIN_CONTACT = kept if coarse else 10 ** 12
    rows = []
    try:
        for grid in SCALING_GRIDS:
            model = issue_model("transient", 5e-3, 4e-3, *grid)
            state = model.initial_state()
            times, sweeps = [], []
            for _ in range(steps):
                t0 = clock()
                res = model.solve(state, normal_force=50e3, creepage=(0.0, -3e-3, 0.0))
                times.append(clock() - t0)
                sweeps.append(res.diagnostics.iterations)
                state = res.new_state
            rows.append((grid, res.diagnostics.n_contact, float(np.median(times)), float(np.median(sweeps))))
    finally:
        transient_fft.COARSE_MIN_CONTACT = kept
    return rows


def print_scaling(steps):
    """The ``--scaling`` table: the solver (with its coarse level from transient_fft.COARSE_MIN_CONTACT elements) and
    without it, and the cost per step relative to n log n, 44 x 36 = 1."""
    print(f"({clock_name} time; transient from rest, eta = -0.3 %, median of the first {steps} steps; "
          f"without: no coarse level)")
    print("| grid | in contact | ms per step | iterations per step | us per step and element | "
          "per n log n (44 x 36 = 1) | without: ms | without: iterations | without: per n log n |")
    print("|---|---|---|---|---|---|---|---|---|")
    with_rows = scaling_rows(steps, coarse=True)
    without_rows = scaling_rows(steps, coarse=False)
    n_log_n = {grid: n * np.log(n) for grid, n, _, _ in with_rows}
    base = dict((grid, seconds / n_log_n[grid]) for grid, _, seconds, _ in with_rows)[(44, 36)]
    base_without = dict((grid, seconds / n_log_n[grid]) for grid, _, seconds, _ in without_rows)[(44, 36)]
    for (grid, n, seconds, sweeps), (_, _, seconds_without, sweeps_without) in zip(with_rows, without_rows):
        nx, ny = grid
        print(f"| {nx} x {ny} | {n} | {seconds * 1e3:.3g} | {sweeps:.1f} | {seconds * 1e6 / n:.3g} | "
              f"{seconds / n_log_n[grid] / base:.2f} | {seconds_without * 1e3:.3g} | {sweeps_without:.1f} | "
              f"{seconds_without / n_log_n[grid] / base_without:.2f} |", flush=True)


def warm_kernels():
    """Compile or load every kernel the rows use (numba caches) before timing, the FFT-product paths' too."""
    from contact.halfspace import tangential
    limits = tangential.STEADY_FFT_MIN_CONTACT, tangential.TRANSIENT_FFT_MIN_CONTACT
    tangential.STEADY_FFT_MIN_CONTACT = tangential.TRANSIENT_FFT_MIN_CONTACT = 0
    try:
        for kind in ("steady", "transient"):
            model = issue_model(kind, 8e-3, 4e-3, 20, 20)
            model.solve(model.initial_state(), normal_force=50e3, creepage=SPIN)
    finally:
        tangential.STEADY_FFT_MIN_CONTACT, tangential.TRANSIENT_FFT_MIN_CONTACT = limits
    for kind in ("steady", "transient"):  # and the exact paths
        model = issue_model(kind, 8e-3, 4e-3, 20, 20)
        model.solve(model.initial_state(), normal_force=50e3, creepage=SPIN)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=400)
    parser.add_argument("--repeat", type=int, default=3, help="repetitions of a steady solution (median)")
    parser.add_argument("--full", action="store_true", help="also the 100 x 100 and 150 x 150 steady rows (minutes)")
    parser.add_argument("--only", choices=("steady", "transient"), help="only these rows of issue 16's table, "
                        "and not the default study's contact step")
    parser.add_argument("--clock", choices=tuple(CLOCKS), default="wall",
                        help="time the steps by wall time (default) or by the process's CPU time")
    parser.add_argument("--scaling", action="store_true",
                        help="only the transient step at eta = -0.3 %% on grids from 33 x 27 to 176 x 144, "
                             "with and without the local sweeps' coarse level")
    args = parser.parse_args(argv)
    global clock, clock_name
    clock, clock_name = CLOCKS[args.clock], args.clock
    warm_kernels()
    if args.scaling:
        print_scaling(min(args.steps, 100))
        print(f"(load average {os.getloadavg()[0]:.1f})")
        return
    kinds = (args.only,) if args.only else ("steady", "transient")
    print(f"({args.clock} time)")
    print("| problem | ours (s) | before (s) | CONTACT (s, issue 16) | ratio | slip/contact |")
    print("|---|---|---|---|---|---|")
    for name, ours, res in issue_table(args.full, args.repeat, min(args.steps, 100), kinds):
        ref = CONTACT_SECONDS[name]
        print(f"| {name} | {ours:.4g} | {OURS_BEFORE[name]:.3g} | {ref:.3g} | {ours / ref:.2f} | "
              f"{res.diagnostics.n_slip}/{res.diagnostics.n_contact} |", flush=True)
    print(f"(load average {os.getloadavg()[0]:.1f})")
    if args.only:
        return
    print()
    mat = Material.from_young(210e9, 0.3)
    fr = Friction(0.3)
    hz = hertz_from_curvatures(1 / (2 * 0.39), 1 / (2 * 0.3), 50e3, mat.contact_modulus)
    speed = 50 / 3.6
    grid = Grid.covering(hz.a, hz.b, dx=0.5e-3, dy=0.5e-3)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    hs = HalfspaceContact(material=mat, friction=fr, grid=grid, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                          kind="transient", speed=speed)
    pt = PointContact(material=mat, friction=fr, hertz=hz, kind="transient", speed=speed,
                      time_step=hs.time_step)
    print(f"Hertz patch 2a x 2b = {2e3 * hz.a:.2f} x {2e3 * hz.b:.2f} mm, grid {grid.nx} x {grid.ny}, "
          f"dt = {hs.time_step * 1e6:.1f} us")
    creep = (0.0, -0.01, 0.0)
    t, res = _time_steps(hs, args.steps, creep, warmup=100)
    print(f"halfspace, constant eta = -1 %: median {np.median(t) * 1e3:.3f} ms/step "
          f"(target < 1 ms); Fy = {res.force[1]:.1f} N, {res.diagnostics.n_slip}/"
          f"{res.diagnostics.n_contact} slip")
    # partial slip, stick-dominated: eta = -0.2 %
    t, res = _time_steps(hs, args.steps, (0.0, -0.002, 0.0), warmup=100)
    print(f"halfspace, constant eta = -0.2 %: median {np.median(t) * 1e3:.3f} ms/step; "
          f"{res.diagnostics.n_slip}/{res.diagnostics.n_contact} slip")
    t, res = _time_steps(pt, 20 * args.steps, creep, warmup=100)
    print(f"point (second-order relaxation), constant eta = -1 %: median {np.median(t) * 1e6:.2f} us/step "
          f"(target < 5 us); Fy = {res.force[1]:.1f} N")
    # harmonic lateral creepage: the relaxation states change every step
    eta = -0.002 + 1e-4 * np.sin(2 * np.pi * 1000.0 * pt.time_step * np.arange(20 * args.steps))
    state = pt.initial_state()
    times = np.empty(eta.size)
    for n, e in enumerate(eta):
        t0 = clock()
        state = pt.solve(state, normal_force=50e3, creepage=(0.0, e, 0.0)).new_state
        times[n] = clock() - t0
    print(f"point, eta = -0.2 % + 0.01 % sin(2 pi 1 kHz t): median {np.median(times[100:]) * 1e6:.2f} us/step")


if __name__ == "__main__":
    main()
