"""Time the contact-geometry table of 200 lateral displacements (target < 2 s).

Two wheel/rail pairs, both on nominal gauge and back-to-back distance, 50 kN wheel load, Hertz
semi-axes for every contact:

* ``study``: the pair of the default study as the ``contact-geometry`` stage builds it
  (:func:`contact_geometry.study.pair_from_study`: the study's wheel running surface on its rail,
  inclined), over the study's ``[geometry]`` displacement range;
* ``s1002``: S1002 wheel on a BV50 rail inclined 1:30, displacements -8 ... +8 mm (tread,
  gauge-corner and flange contacts, two-point contact).

Run: ``OMP_NUM_THREADS=1 python benchmarks/geometry_table.py [--repeats N] [--points N]``.
Prints the median time of each table and its ratio to the target.
"""

from __future__ import annotations

import argparse
import time

import numpy as np


from contact_geometry import WheelRailPair, contact_table, flange_back_position  # noqa: E402
from contact_geometry.study import pair_from_study  # noqa: E402
from profiles.rail_head import gauge_point, rail_head_profile  # noqa: E402
from profiles.wheel_treads import s1002_profile  # noqa: E402
from stages.config import load_study  # noqa: E402

TARGET_S = 2.0


def pairs(points):
    """``{name: (pair, displacements)}`` of the benchmark."""
    study = load_study()
    geometry = study["geometry"]
    s1002 = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), 0.39,
                          flange_back_position(gauge_point("BV50", 30)))
    return {"study": (pair_from_study(study), np.linspace(geometry["displacement_min"], geometry["displacement_max"],
                                                          points)),
            "s1002": (s1002, np.linspace(-0.008, 0.008, points))}


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--points", type=int, default=200)
    args = parser.parse_args(argv)
    medians = {}
    for name, (pair, d) in pairs(args.points).items():
        contact_table(pair, d)  # warm-up
        times = []
        for _ in range(args.repeats):
            t0 = time.perf_counter()
            table = contact_table(pair, d)
            times.append(time.perf_counter() - t0)
        medians[name] = float(np.median(times))
        print(f"{name}: {pair.wheel.name} on {pair.rail.name}, {d.size} displacements "
              f"({int((table.n_contacts == 2).sum())} two-point): median {medians[name]:.4f} s over {args.repeats} "
              f"runs; target {TARGET_S:.1f} s; ratio {medians[name] / TARGET_S:.3f}")
    return medians


if __name__ == "__main__":
    main()
