"""Benchmark of the time-domain interaction: wall time per simulated second of one case.

Builds (or reuses) the structural artefacts of the default study in ``--out`` and times the
case μ = 0.3, η = −1 %, stationary wheel with each contact model over a short run (the
half-space model at the default lateral element size and a coarser one); the time per simulated
second and the projected time of a 3.5 s case are printed (medians for the point model). The
times include the setup of a run (for the half-space model its table of normal solutions, about
1 s), and the run starts with the start transient of the creep force; squealing cases cost more
per step than quiet ones (up to about 2x), so ``--study`` on a finished study gives the real
case times.

With ``--case MU ETA`` it runs instead one full case of the default study (``[time].duration``,
the study's contact model, wheel model ``--wheel-model``) on the structural artefacts of a
finished study folder ``--out`` (wheel and rail Green's functions, contact geometry; nothing is
rebuilt), prints its run time, and with ``--save FILE.npy`` stores the contact force history;
``--compare FILE.npy`` prints the largest difference from a stored history relative to the largest
force of each direction (e.g. before/after a change of the contact solver).

With ``--study DIR`` it also reports the run time of a finished study from its case artefacts
(each records its own run time and when it was written): median and longest case, the sum,
and the wall time from the start of the first case to the end of the last.

With ``--compare-studies A B`` it lists, case by case, the results of two finished studies that
differ to their printed digits (``summary.csv``: L_F2 and L_W, L_pA to 0.1 dB, the squeal verdict,
frequency to 1 Hz, build-up time to 0.01 s, growth to 0.01), e.g. before and after a change of a
solver, and how many cases moved.

Run: ``python -m benchmarks.simulate [--out DIR] [--seconds S] [--repeats N] [--study DIR]``,
``python -m benchmarks.simulate --compare-studies DIR_A DIR_B``, or
``python -m benchmarks.simulate --out DIR --case 0.6 -0.015 [--save F.npy] [--compare F.npy] [--duration S]
[--tolerance TOL]``.
"""

from __future__ import annotations

import argparse
import datetime
import glob
import os
import statistics
import time

import h5py  # noqa: E402
import numpy as np  # noqa: E402

from stages import engine  # noqa: E402
from interaction.simulate import simulate  # noqa: E402
from interaction.structures import ConvolutionStructure, ModalStructure  # noqa: E402
from stages.cases import case_structures, case_study, contact_model  # noqa: E402
from stages.config import load_study  # noqa: E402
from stages.summary_compare import summary_differences  # noqa: E402
from stages.rail import read_rail_greens  # noqa: E402
from stages.wheel import read_greens  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out", help="study folder (structural artefacts built if missing)")
    parser.add_argument("--seconds", type=float, default=0.1, help="simulated time per run, s")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--halfspace-seconds", type=float, default=1.0,
                        help="simulated time of the halfspace runs, s")
    parser.add_argument("--grid-dy", type=float, nargs="+", default=[5e-4, 1e-3],
                        help="lateral element sizes of the halfspace runs, m")
    parser.add_argument("--study", help="finished study folder: report its case run times and wall time")
    parser.add_argument("--case", type=float, nargs=2, metavar=("MU", "ETA"),
                        help="run one full case (friction, lateral creepage) on the artefacts in --out")
    parser.add_argument("--wheel-model", default="stationary", help="wheel model of --case")
    parser.add_argument("--duration", type=float, help="--case: simulated time, s (default: the study's)")
    parser.add_argument("--tolerance", type=float,
                        help="--case: simulation.tolerance of the case (default: the study's)")
    parser.add_argument("--save", help="--case: store the contact force history (N, steps x 3) in this .npy file")
    parser.add_argument("--compare", help="--case: compare the force history with this .npy file")
    parser.add_argument("--compare-studies", nargs=2, metavar=("A", "B"),
                        help="list the results of two finished studies that differ to their printed digits")
    args = parser.parse_args(argv)
    if args.compare_studies:
        compare_studies(*args.compare_studies)
        return
    if args.case:
        one_case(args.out, *args.case, args.wheel_model, args.save, args.compare, args.duration, args.tolerance)
        return
    if args.study:
        study_times(args.study)
    study = load_study()
    for stage in ("wheel-greens", "rail-greens"):  # each builds only its own chain
        engine.run(study, args.out, until=stage, progress=False)
    wheel = read_greens(os.path.join(args.out, "wheel_greens.h5"), "stationary")
    rail = read_rail_greens(os.path.join(args.out, "rail_greens.h5"))
    dt = wheel["time_step"]
    print(f"case mu = 0.3, eta = -1 %, stationary wheel; time step {dt * 1e6:.0f} us")
    runs = [("point", None)] + [("halfspace", dy) for dy in args.grid_dy]
    for model, dy in runs:
        seconds = args.seconds if model == "point" else args.halfspace_seconds
        steps = int(round(seconds / dt))
        overrides = {"contact.model": model, "contact.friction": 0.3, "contact.lateral_creepage": -0.01}
        if dy is not None:
            overrides["contact.grid_dy"] = dy
        cs = case_study(study, overrides)
        times = []
        for _ in range(args.repeats if model == "point" else 1):
            contact = contact_model(cs)
            start = time.perf_counter()
            result = simulate(ModalStructure(wheel["poles"], wheel["residues"], dt),
                              ConvolutionStructure(rail["kernel"], dt), contact, speed=cs["operating"]["speed"],
                              wheel_load=cs["operating"]["wheel_load"], creepage=(0.0, -0.01, 0.0), n_steps=steps,
                              tolerance=cs["simulation"]["tolerance"])
            times.append(time.perf_counter() - start)
        per_second = statistics.median(times) / seconds
        label = model if dy is None else f"{model} dy={dy * 1e3:g} mm"
        print(f"{label:22s} {per_second:8.1f} s per simulated second, {3.5 * per_second / 60:6.2f} min per 3.5 s "
              f"case, {1e6 * statistics.median(times) / steps:8.1f} us per step, "
              f"{result.iterations.mean():.2f} coupling passes per step")

def one_case(folder, friction, creepage, wheel_model, save=None, compare=None, duration=None, tolerance=None):
    """Run one full case of the default study on the artefacts of ``folder`` and print its run time."""
    overrides = {"contact.friction": friction, "contact.lateral_creepage": creepage,
                 "simulation.wheel_model": wheel_model}
    if tolerance is not None:
        overrides["simulation.tolerance"] = tolerance
    cs = case_study(load_study(), overrides)
    inputs = {"wheel-greens": os.path.join(folder, "wheel_greens.h5"),
              "rail-greens": os.path.join(folder, "rail_greens.h5")}
    geometry = os.path.join(folder, "contact_geometry.h5")
    if os.path.exists(geometry):
        inputs["contact-geometry"] = geometry
    wheel, rail, contact, kwargs, _ = case_structures(cs, inputs)
    n_steps = int(round((duration or cs["time"]["duration"]) / cs["time"]["time_step"]))
    start = time.perf_counter()
    start_cpu = time.process_time()
    result = simulate(wheel, rail, contact, n_steps=n_steps, **kwargs)
    runtime = time.perf_counter() - start
    cpu = time.process_time() - start_cpu
    print(f"case mu = {friction:g}, eta = {creepage:g}, {wheel_model} wheel, {cs['contact']['model']} contact: "
          f"{n_steps} steps in {runtime:.1f} s wall, {cpu:.1f} s CPU ({1e6 * cpu / n_steps:.1f} us CPU per step), "
          f"load {os.getloadavg()[0]:.2f}")
    if "sweeps" in result.extra:
        print(f"per step: {result.iterations.mean():.2f} coupling passes, "
              f"{np.mean(result.extra['normal_iterations']):.1f} normal iterations, "
              f"{np.mean(result.extra['sweeps']):.1f} tangential sweeps (all passes)")
    force = np.asarray(result.force)
    if save:
        np.save(save, force)
    if compare:
        ref = np.load(compare)[:len(force)]  # a shorter run compares with the start of a longer one
        force = force[:len(ref)]
        scale = np.abs(ref).max(axis=0)
        diff = np.abs(force - ref).max(axis=0) / np.where(scale > 0, scale, 1.0)
        print("largest difference from " + compare + " relative to the largest force (x, y, z): "
              + ", ".join(f"{d:.2e}" for d in diff))


def compare_studies(folder_a, folder_b):
    """Print the cases of two finished studies whose results differ to their printed digits; returns how many."""
    lines, n_cases = summary_differences(folder_a, folder_b)
    for line in lines:
        print(line)
    print(f"cases with a printed result moved: {len(lines)} of {n_cases}")
    return len(lines)


def study_times(folder):
    """Print the case run times and the wall time of a finished study (from its case artefacts)."""
    runtimes, starts, ends, models = [], [], [], set()
    for path in sorted(glob.glob(os.path.join(folder, "cases", "*.h5"))):
        with h5py.File(path, "r") as f:
            runtime = float(f.attrs["runtime"])
            end = datetime.datetime.fromisoformat(str(f.attrs["created"]))
            models.add(str(f.attrs["contact_model"]))
        runtimes.append(runtime)
        ends.append(end)
        starts.append(end - datetime.timedelta(seconds=runtime))
    if not runtimes:
        print(f"{folder}: no case artefacts")
        return
    wall = (max(ends) - min(starts)).total_seconds()
    print(f"study {folder}: {len(runtimes)} cases ({', '.join(sorted(models))} contact); per case median "
          f"{statistics.median(runtimes):.1f} s, longest {max(runtimes):.1f} s, sum {sum(runtimes) / 60:.1f} min; "
          f"wall time of the cases {wall / 60:.1f} min")


if __name__ == "__main__":
    main()
