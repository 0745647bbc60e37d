"""Run one map point in the time domain with the half-space contact (the check of a screen prediction).

Usage: python benchmarks/halfspace_case.py OUT INDEX WHEEL_MODEL [VARIANT_DONOR ...]

OUT: a new output folder (the case and its structures go to OUT/confirm, as ``map --confirm``
puts them); INDEX: the configuration of ``studies/maps.toml``'s grid; WHEEL_MODEL: stationary,
moving_load or eulerian; VARIANT_DONOR: folders whose fresh structural artefacts are copied (e.g.
a map's ``confirm/variants/<label>``). Prints the time domain's verdict (growth rate and
frequency of the dominant tone, and the tone at 212.12 Hz, the half-space screen's pole of
configuration 870; docs/results.md). 1 s of rolling; about 18 min at load 10 with the rail's
Green's functions rebuilt.
"""
import argparse
import logging
import time
from pathlib import Path

from stages import engine
from stages.config import load_study
from stages.maps_confirm import (
    DEFAULT_DURATION,
    case_verdict,
    plan_confirmation,
    prepare_variant,
)

#: The half-space screen's pole at configuration 870 (Hz), whose tone the verdict also reports.
SCREEN_FREQUENCY = 212.12


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("out", type=Path, help="new output folder (the case goes to OUT/confirm)")
    parser.add_argument("index", type=int, help="configuration of studies/maps.toml's grid")
    parser.add_argument("wheel_model", choices=("stationary", "moving_load", "eulerian"))
    parser.add_argument("donors", nargs="*", metavar="VARIANT_DONOR",
                        help="folders whose fresh structural artefacts are copied")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO)
    out, index, wheel_model = args.out, args.index, args.wheel_model
    study = load_study("studies/maps.toml")
    (_, case), = plan_confirmation(study, [(index, wheel_model, "check")], ["halfspace"], out, DEFAULT_DURATION)
    start = time.perf_counter()
    prepare_variant({"label": case.variant_label, "folder": str(case.variant_dir), "study": case.study,
                     "donors": args.donors})
    _, failed = engine.run_cases([case], out / "confirm", 1, None, False)
    print(f"{case.case_id}: {time.perf_counter() - start:.0f} s, failed: {failed or 'none'}")
    print(case_verdict(out / "confirm" / "cases" / f"{case.case_id}.h5", SCREEN_FREQUENCY))


if __name__ == "__main__":
    main()
