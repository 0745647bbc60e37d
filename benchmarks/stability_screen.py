"""Cost of the linear stability screen and of a squeal map.

1. Time per configuration of the screen once the structures exist (the three wheel models at
   the configuration's speed and contact, the contact linearisation and three closed-loop
   eigenproblems on the flexible rail; the contact computed from the profiles, like the map,
   once per wheel position; the wheel modes of the margin pole only, as the map), median over
   32 of the 128 configurations of ``studies/maps.toml`` with the paper's wheel (its structures
   built as the map builds them). Target: < 0.1 s. Beside it, in the same run, the median
   with the dense eigenvalues of the loop matrix (LAPACK's QR: the screen before issue 15's
   structured eigenvalues).
2. Wall time of a map: read from ``maps.h5`` of a map run (``--map DIR``: the attribute
   ``run_wall_time``, which the run that computed every chunk records), or measured by running
   ``studies/maps.toml`` (``--run-map DIR``; 1024 configurations, two local workers). Target
   on 2 cores: < 10 min, wheel rebuilds included.

Run: ``OMP_NUM_THREADS=1 python benchmarks/stability_screen.py [--out DIR] [--map DIR | --run-map DIR]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")
# the repository first: run as a script, this folder would come first and its contact_geometry.py
# would shadow the contact_geometry package (which the contact from the profiles imports)

import numpy as np  # noqa: E402

from squealcore.study import get_section  # noqa: E402
from stages.config import load_study  # noqa: E402
from stages.maps import ContactCache, plan, prepare_rail, prepare_wheel, read_maps, run_map  # noqa: E402
from stages.screen import WheelModels, read_rail_fit, screen_study, wheel_point  # noqa: E402
from stages.wheel import read_mesh, read_modes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def screen_times(out, every=4, structured=True, radius=0.39):
    """Seconds per configuration of the screen on the map's structures for its default wheel.

    The configurations of ``studies/maps.toml`` with the rolling radius ``radius`` (m; default the
    paper's, 0.39 m: 128 of them, every ``every``-th timed), their wheel and rail built in ``out`` as the map builds them
    (:func:`stages.maps.prepare_wheel`, :func:`stages.maps.prepare_rail`); per configuration the
    wheel models at its speed and contact (kept per speed and contact, as the map does), the
    contact linearisation and the three screens (margin pole's wheel modes only, as the map).
    ``structured``: the screen's eigenvalues as roots of the contact determinant (else the
    dense eigenvalues of the loop matrix, the path before issue 15's fast screen)."""
    study = load_study(ROOT / "studies" / "maps.toml", False, [])
    study = {**study, "map": {**study["map"], "grid": {**study["map"]["grid"], "wheel.rolling_radius": [radius]}}}
    layout = plan(study, out)
    (label, (wheel_dir, config)), = layout["wheels"].items()
    prepare_wheel({"label": label, "folder": str(wheel_dir), "study": config})
    for label, (folder, config, fits) in layout["rails"].items():
        prepare_rail({"label": label, "folder": str(folder), "study": config, "laterals": list(fits)})
    wheel = WheelModels(read_modes(wheel_dir / "wheel_modes.h5", with_shapes=True), read_mesh(wheel_dir / "wheel_mesh.h5"),
                        get_section(study, "wheel.rotation"))
    contacts = ContactCache()
    rails, by_state, times = {}, {}, []
    for index in range(0, len(layout["configurations"]), every):
        config = layout["configurations"][index][1]
        point = contacts(config)  # the contact geometry: once per wheel position in a map
        fit = layout["rail_fits"][index]
        rail = rails.setdefault(fit, read_rail_fit(fit))
        start = time.perf_counter()
        at = wheel_point(config, point)
        speed = config["operating"]["speed"]
        state = (speed, None if at is None else (at.wheel_lateral, at.rolling_radius))
        if state not in by_state:
            by_state[state] = wheel.at(speed, at)
        models = by_state[state]
        screen_study(config, models, rail, point=point, pole_modes=False, structured=structured)
        times.append(time.perf_counter() - start)
    return np.array(times)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="folder for the default wheel's and the rail's structures (default: a temporary "
                                      "folder)")
    group = parser.add_mutually_exclusive_group()
    group.add_argument("--map", help="folder of a finished map run (reads its maps.h5)")
    group.add_argument("--run-map", help="run studies/maps.toml with --jobs 2 into this folder and time it")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(args.out) if args.out else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        screen_times(out, every=32)  # builds the structures and compiles the kernels: not timed
        t = screen_times(out)
        dense = screen_times(out, structured=False)
    print(f"screen, three wheel models on the flexible rail: median {np.median(t) * 1e3:.0f} ms per configuration "
          f"(min {t.min() * 1e3:.0f}, max {t.max() * 1e3:.0f} ms; target < 100 ms); with the dense eigenvalues "
          f"instead: median {np.median(dense) * 1e3:.0f} ms")
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
