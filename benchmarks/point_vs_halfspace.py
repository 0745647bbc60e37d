"""The point contact against the half-space contact on the same structures, case by case (issue 32).

For each case (friction, lateral creepage, wheel model) it runs the interaction with the point
contact's transient strips, the half-space contact and, with ``--relaxation``, the point
contact's former relaxed creep law, on the structural artefacts of a finished study folder
(wheel and rail Green's functions and the contact geometry; nothing is rebuilt), and prints per
model: L_F2, squeal frequency, the paper's squeal verdict, build-up time, the normal and lateral
force ranges over the L_F2 window, the share of it out of contact, and the CPU time per step
(with the half-space's over the point model's). The tables of docs/results.md ("Point contact
against the half-space") come from this script.

Run: ``python -m benchmarks.point_vs_halfspace --out STUDY_DIR [--quick] --case 0.6 -0.015 stationary
[--case MU ETA WHEEL_MODEL ...] [--relaxation]`` (``--quick`` for a folder of the quick study's
structures, e.g. one made by ``python pipeline.py run --quick --until rail-greens --out DIR``).
A half-space case of the paper-size study takes 1-3 min, a quick one 0.3-1 min.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from interaction.metrics import squeal_metrics
from interaction.simulate import simulate
from stages.cases import case_structures, case_study
from stages.config import load_study

MODELS = {"strips": {"contact.model": "point", "contact.point_tangential": "strip"},
          "half-space": {"contact.model": "halfspace"},
          "relaxation": {"contact.model": "point", "contact.point_tangential": "relaxation"}}


def run_case(folder, quick, friction, creepage, wheel_model, model):
    """One case on the artefacts of ``folder``; returns a dict of the printed measures."""
    overrides = {"contact.friction": friction, "contact.lateral_creepage": creepage,
                 "simulation.wheel_model": wheel_model, **MODELS[model]}
    study = case_study(load_study(quick=quick), overrides)
    inputs = {"wheel-greens": os.path.join(folder, "wheel_greens.h5"),
              "rail-greens": os.path.join(folder, "rail_greens.h5"),
              "contact-geometry": os.path.join(folder, "contact_geometry.h5")}
    wheel, rail, contact, kwargs, _ = case_structures(study, inputs)
    dt = study["time"]["time_step"]
    steps = int(round(study["time"]["duration"] / dt))
    start = time.process_time()
    result = simulate(wheel, rail, contact, n_steps=steps, **kwargs)
    cpu = time.process_time() - start
    sim = study["simulation"]
    metrics = squeal_metrics(result.force[:, 1], dt, window=sim["rms_window"], threshold_db=sim["squeal_threshold"])
    window = result.force[-int(round(sim["rms_window"] / dt)):]
    return {"L_F2": metrics.L_F2, "frequency": metrics.squeal_frequency, "squeal": metrics.squeal,
            "buildup": metrics.buildup_time, "fz": (window[:, 2].min(), window[:, 2].max()),
            "fy": (window[:, 1].min(), window[:, 1].max()), "off": float(np.mean(window[:, 2] <= 0.0)),
            "cpu_per_step": cpu / steps}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", required=True, help="finished study folder with the structural artefacts")
    parser.add_argument("--quick", action="store_true", help="the folder holds the quick study's structures")
    parser.add_argument("--case", nargs=3, action="append", metavar=("MU", "ETA", "WHEEL_MODEL"), required=True)
    parser.add_argument("--relaxation", action="store_true", help="also the former relaxed creep law")
    args = parser.parse_args(argv)
    models = ["strips", "half-space"] + (["relaxation"] if args.relaxation else [])
    print("| μ | η | wheel | model | L_F2 (dB) | f (Hz) | squeal | build-up (s) | F_z (kN) | F_y (kN) | "
          "out of contact | CPU per step (µs) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for mu, eta, wheel_model in args.case:
        cpu = {}
        for model in models:
            m = run_case(args.out, args.quick, float(mu), float(eta), wheel_model, model)
            cpu[model] = m["cpu_per_step"]
            print(f"| {mu} | {float(eta) * 100:g} % | {wheel_model} | {model} | {m['L_F2']:.1f} | "
                  f"{m['frequency']:.0f} | {m['squeal']} | {m['buildup']:.3f} | {m['fz'][0] / 1e3:.1f}–"
                  f"{m['fz'][1] / 1e3:.1f} | {m['fy'][0] / 1e3:.1f}–{m['fy'][1] / 1e3:.1f} | "
                  f"{100 * m['off']:.1f} % | {1e6 * m['cpu_per_step']:.0f} |", flush=True)
        print(f"  half-space / strips CPU per step: {cpu['half-space'] / cpu['strips']:.1f}")


if __name__ == "__main__":
    main()
