"""Run the quick study from Python and print each case's L_F2 and squeal verdict.

    python examples/quick_study.py                          # a temporary folder, about a minute
    python examples/quick_study.py --out out-quick          # keep the folder (a rerun rebuilds nothing)
    python examples/quick_study.py --duration 0.2           # shorter cases (too short to squeal)

The same as ``python pipeline.py run --quick`` followed by reading ``summary.csv``, through the
Python API (``curve_squeal``, docs/user-guide.md, *Python API*).
"""

from __future__ import annotations

import argparse
import tempfile

import curve_squeal as cs


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="study folder (default: a temporary one, removed at the end)")
    parser.add_argument("--duration", type=float, help="simulated time of each case, s (default: the quick study's)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes for the cases")
    args = parser.parse_args(argv)

    overrides = {} if args.duration is None else {"time.duration": args.duration}
    study = cs.load_study(quick=True, overrides=overrides)
    with tempfile.TemporaryDirectory(prefix="quick-study-") as scratch:
        out = args.out or scratch
        rebuilt = cs.run(study, out, jobs=args.jobs)
        print(f"built {len(rebuilt)} stage(s) and case(s) in {out}")
        for row in cs.summary(out):
            case = cs.read_case(out, row["case_id"])
            lateral = case.force[:, 1]  # N, the lateral contact force's history
            print(f"{row['wheel_model']:<12} mu = {row['friction']:.2f}  eta = {100 * row['lateral_creepage']:+.1f} %  "
                  f"L_F2 = {case.L_F2:5.1f} dB re 1 N  (F_y from {lateral.min() / 1e3:6.1f} to "
                  f"{lateral.max() / 1e3:6.1f} kN)  {case.verdict}")


if __name__ == "__main__":
    main()
