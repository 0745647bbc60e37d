"""Benchmark of the time-domain interaction: wall time per simulated second of one case.

Builds (or reuses) the structural artefacts of the default study in ``--out`` and times the
case μ = 0.3, η = −1 %, stationary wheel with each contact model over a short run; the
time per simulated second and the projected time of a 3.5 s case are printed (medians).

Run: ``python benchmarks/simulate.py [--out DIR] [--seconds S] [--repeats N]``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
sys.path.insert(0, ROOT)

import pipeline  # noqa: E402
from interaction.simulate import simulate  # noqa: E402
from interaction.structures import ConvolutionStructure, ModalStructure  # noqa: E402
from stages.cases import case_study, contact_model  # noqa: E402
from stages.config import load_study  # noqa: E402
from stages.rail import read_rail_greens  # noqa: E402
from stages.wheel import read_greens  # noqa: E402


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default="out", help="study folder (structural artefacts built if missing)")
    parser.add_argument("--seconds", type=float, default=0.1, help="simulated time per run, s")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--halfspace-seconds", type=float, default=0.005,
                        help="simulated time of the (slow) halfspace run, s")
    args = parser.parse_args(argv)
    study = load_study()
    pipeline.run(study, args.out, until="rail-greens", progress=False)
    wheel = read_greens(os.path.join(args.out, "wheel_greens.h5"), "stationary")
    rail = read_rail_greens(os.path.join(args.out, "rail_greens.h5"))
    dt = wheel["time_step"]
    print(f"case mu = 0.3, eta = -1 %, stationary wheel; time step {dt * 1e6:.0f} us")
    for model in ("point", "halfspace"):
        seconds = args.seconds if model == "point" else args.halfspace_seconds
        steps = int(round(seconds / dt))
        cs = case_study(study, {"contact.model": model, "contact.friction": 0.3, "contact.lateral_creepage": -0.01})
        times = []
        for _ in range(args.repeats if model == "point" else 1):
            contact = contact_model(cs)
            start = time.perf_counter()
            simulate(ModalStructure(wheel["poles"], wheel["residues"], dt), ConvolutionStructure(rail["kernel"], dt),
                     contact, speed=cs["operating"]["speed"], wheel_load=cs["operating"]["wheel_load"],
                     creepage=(0.0, -0.01, 0.0), n_steps=steps)
            times.append(time.perf_counter() - start)
        per_second = statistics.median(times) / seconds
        print(f"{model:10s} {per_second:8.1f} s per simulated second, {3.5 * per_second:8.1f} s per 3.5 s case, "
              f"{1e6 * statistics.median(times) / steps:8.1f} us per step")


if __name__ == "__main__":
    main()
