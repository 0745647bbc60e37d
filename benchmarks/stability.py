"""Cost of the linear stability screen and of a squeal map.

1. Time per configuration of the screen once the structures exist (the three wheel models at
   the configuration's speed and contact, the contact linearisation and three closed-loop
   eigenproblems on the flexible rail; the contact computed from the profiles, like the map,
   once per wheel position; the wheel modes of the margin pole only, as the map), median over
   the speeds x frictions x creepages of the quick study's wheel and rail. Target: < 0.1 s.
2. Wall time of a map: read from ``maps.h5`` of a map run (``--map DIR``: the attribute
   ``run_wall_time``, which the run that computed every chunk records), or measured by running
   ``studies/maps.toml`` (``--run-map DIR``; 1024 configurations, two local workers). Target
   on 2 cores: < 10 min, wheel rebuilds included.

Run: ``OMP_NUM_THREADS=1 python benchmarks/stability.py [--out DIR] [--map DIR | --run-map DIR]``.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
# the repository first: run as a script, this folder would come first and its contact_geometry.py
# would shadow the contact_geometry package (which the contact from the profiles imports)
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

import numpy as np  # noqa: E402

from squealcore.study import get_section  # noqa: E402
from stages import engine  # noqa: E402
from stages.config import load_study  # noqa: E402
from stages.maps import ContactCache, read_maps, run_map  # noqa: E402
from stages.screen import (  # noqa: E402
    WheelModels,
    rail_lateral,
    rail_model,
    screen_study,
    wheel_point,
)
from stages.wheel import read_mesh, read_modes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def screen_times(out):
    """Seconds per configuration of the screen on the quick study's structures in ``out``."""
    study = load_study(None, True, [])
    engine.run_structural(study, out, engine.required_stages("wheel-modes"), progress=False)
    engine.run_structural(study, out, engine.required_stages("rail-mesh"), progress=False)
    contacts = ContactCache()
    point = contacts(study)
    lateral = rail_lateral(study, point)
    rail = rail_model(study, out / "rail_mesh.h5", out / ("rail_fit.h5" if lateral is None else "rail_fit_profiles.h5"),
                      lateral)
    wheel = WheelModels(read_modes(out / "wheel_modes.h5", with_shapes=True), read_mesh(out / "wheel_mesh.h5"),
                        get_section(study, "wheel.rotation"))
    times = []
    for speed in (2.8, 8.3, 13.9, 19.4):
        for mu in (0.3, 0.6):
            for eta in (-0.003, -0.01):
                config = load_study(None, True, [f"operating.speed={speed}", f"contact.friction={mu}",
                                                 f"contact.lateral_creepage={eta}"])
                point = contacts(config)  # the contact geometry: once per wheel position in a map
                start = time.perf_counter()
                screen_study(config, wheel.at(speed, wheel_point(config, point)), rail, point=point, pole_modes=False)
                times.append(time.perf_counter() - start)
    return np.array(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="folder for the quick study's structures (default: a temporary folder)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--map", help="folder of a finished map run (reads its maps.h5)")
    group.add_argument("--run-map", help="run studies/maps.toml with --jobs 2 into this folder and time it")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(args.out) if args.out else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        t = screen_times(out)
    print(f"screen, three wheel models on the flexible rail: median {np.median(t) * 1e3:.0f} ms per configuration "
          f"(min {t.min() * 1e3:.0f}, max {t.max() * 1e3:.0f} ms; target < 100 ms)")
    if args.run_map:
        study = load_study(ROOT / "studies" / "maps.toml", False, [])
        result = run_map(study, Path(args.run_map), jobs=2, progress=True)
        print(f"map of {result['configurations']} configurations, {result['chunks_computed']} chunk(s) computed: "
              f"{result['seconds'] / 60:.1f} min wall time (target < 10 min)")
    elif args.map:
        data = read_maps(Path(args.map) / "maps.h5")
        n = data["configuration"].shape[0]
        print(f"map of {n} configurations: {data['run_wall_time'] / 60:.1f} min wall time of the run that computed "
              f"{data['run_chunks_computed']} chunk(s) (target < 10 min); screen median "
              f"{np.median(data['seconds']) * 1e3:.0f} ms per configuration in the workers")


if __name__ == "__main__":
    main()
