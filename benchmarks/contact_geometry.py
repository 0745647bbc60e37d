"""Time the contact-geometry table of 200 lateral displacements (target < 2 s).

S1002 wheel on a BV50 rail inclined 1:30, nominal gauge and back-to-back distance, wheel
displacements -8 ... +8 mm (tread, gauge-corner and flange contacts), 50 kN wheel load, Hertz
semi-axes for every contact.

Run: ``OMP_NUM_THREADS=1 python benchmarks/geometry.py [--repeats N]``. Prints the median.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

from contact_geometry import (WheelRailPair, contact_table, flange_back_position, gauge_point,  # noqa: E402
                      rail_head_profile, s1002_profile)

logger = logging.getLogger("benchmarks.geometry")
TARGET_S = 2.0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--points", type=int, default=200)
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    pair = WheelRailPair(s1002_profile(), rail_head_profile("BV50", 30), 0.39,
                         flange_back_position(gauge_point("BV50", 30)))
    d = np.linspace(-0.008, 0.008, args.points)
    contact_table(pair, d)  # warm-up
    times = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        table = contact_table(pair, d)
        times.append(time.perf_counter() - t0)
    med = float(np.median(times))
    logger.info("contact table, %d displacements (%d two-point): median %.4f s over %d runs; "
                "target %.1f s; ratio %.3f", d.size, int((table.n_contacts == 2).sum()), med,
                args.repeats, TARGET_S, med / TARGET_S)
    return med


if __name__ == "__main__":
    main()
