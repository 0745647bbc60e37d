"""Run one map point in the time domain with the half-space contact (the check of a screen prediction).

Usage: PYTHONPATH=$PWD python benchmarks/halfspace_case.py OUT INDEX WHEEL_MODEL [VARIANT_DONOR ...]

OUT: a new output folder (the case and its structures go to OUT/confirm, as ``map --confirm``
puts them); INDEX: the configuration of ``studies/maps.toml``'s grid; WHEEL_MODEL: stationary,
moving_load or eulerian; VARIANT_DONOR: folders whose fresh structural artefacts are copied (e.g.
a map's ``confirm/variants/<label>``). Prints the time domain's verdict (growth rate and
frequency of the dominant tone, and the tone at 212.12 Hz, the half-space screen's pole of
configuration 870; docs/results.md). 1 s of rolling; about 18 min at load 10 with the rail's
Green's functions rebuilt.
"""
import logging
import os
import sys
import time
from pathlib import Path

sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))  # noqa: the package first
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


def main():
    logging.basicConfig(level=logging.INFO)
    out, index, wheel_model = Path(sys.argv[1]), int(sys.argv[2]), sys.argv[3]
    study = load_study("studies/maps.toml")
    (_, case), = plan_confirmation(study, [(index, wheel_model, "check")], ["halfspace"], out, DEFAULT_DURATION)
    start = time.perf_counter()
    prepare_variant({"label": case.variant_label, "folder": str(case.variant_dir), "study": case.study,
                     "donors": sys.argv[4:]})
    _, failed = engine.run_cases([case], out / "confirm", 1, None, False)
    print(f"{case.case_id}: {time.perf_counter() - start:.0f} s, failed: {failed or 'none'}")
    print(case_verdict(out / "confirm" / "cases" / f"{case.case_id}.h5", SCREEN_FREQUENCY))


if __name__ == "__main__":
    main()
