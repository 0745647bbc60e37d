"""Read the wheel models' lateral receptance at the contact and print its first peaks.

    python examples/receptance.py                   # builds the quick study's wheel in a temporary folder
    python examples/receptance.py --out out-quick   # a folder built before (at least until wheel-greens)

Rotation splits each peak of the stationary wheel into a pair about f_n ± n Ω / 2π (the
README's figure); the poles give the same frequencies exactly.
"""

from __future__ import annotations

import argparse
import tempfile

import numpy as np
from scipy.signal import find_peaks

import curve_squeal as cs


def first_peaks(wheel, count=5, f_min=100.0):
    """The first ``count`` peaks of |H_yy| above ``f_min``: (frequency Hz, magnitude m/N) pairs."""
    magnitude = np.abs(wheel.receptance[:, 1, 1])
    peaks, _ = find_peaks(magnitude)
    peaks = peaks[wheel.frequency[peaks] >= f_min][:count]
    return list(zip(wheel.frequency[peaks], magnitude[peaks]))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="a study folder with wheel_greens.h5 (default: build the quick study's)")
    parser.add_argument("--peaks", type=int, default=5, help="peaks printed per model")
    args = parser.parse_args(argv)

    with tempfile.TemporaryDirectory(prefix="receptance-") as scratch:
        out = args.out
        if out is None:
            out = scratch
            cs.run(cs.load_study(quick=True), out, until="wheel-greens")
        for model in cs.wheel_model_names():  # stationary, moving_load, eulerian
            wheel = cs.read_wheel(out, model)
            print(f"{model} (spin {wheel.spin:.1f} rad/s, {wheel.poles.size} poles):")
            for frequency, magnitude in first_peaks(wheel, args.peaks):
                print(f"  {frequency:8.1f} Hz  |H_yy| = {magnitude:.3e} m/N")


if __name__ == "__main__":
    main()
