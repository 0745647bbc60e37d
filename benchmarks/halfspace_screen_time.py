"""Time per configuration of the half-space screen, fast against the path it replaced (issue 35 item 3).

The configurations of ``studies/maps.toml`` at the paper's rolling radius (128: 8 speeds from 10
to 80 km/h, 4 wheelset positions, 2 friction coefficients, 2 lateral creepages), every
``--every``-th timed, with ``contact.model = "halfspace"``: per configuration the half-space
linearisation (:func:`stages.screen.linear_contact`) and the three wheel models' screens on the
flexible rail (:func:`stages.screen.screen_study`, margin pole's wheel modes only, as the map),
the wheel models kept per speed and contact and the contact geometry per wheel position (as the
map keeps them). Structures built in ``--out`` as the map builds them (not timed).

Two paths, alternated configuration by configuration so that both see the same machine load:

* fast: today's code (steady sweeps on a box of lines, prescribed-approach normal problems with
  FFT products, the normal stiffness and no-slip slopes kept per normal problem and load);
* reference: the path before issue 35 item 3, restored here: the point-by-point steady sweeps
  (:func:`reference_steady_gauss_seidel`, the earlier kernel), the direct products for the
  prescribed-approach normal problems, nothing kept between configurations.

The per-process cache of whole linearisations (``cached_linearisation``) is emptied before every
configuration in both paths. Prints the median (and range) per configuration of both, their
ratio, and the largest differences of the two paths' growth rates and frequencies.

Run: ``OMP_NUM_THREADS=1 python benchmarks/halfspace_screen_time.py [--out DIR] [--every N]``.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import tempfile
import time
from pathlib import Path

for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import numba  # noqa: E402
import numpy as np  # noqa: E402

from contact.friction_kernels import element_law  # noqa: E402
from contact.halfspace import linearise, tangential  # noqa: E402
from contact.halfspace.anderson_kernels import anderson_history, anderson_input, anderson_mix  # noqa: E402
from squealcore.study import get_section  # noqa: E402
from stages.cases import case_study  # noqa: E402
from stages.config import load_study  # noqa: E402
from stages.maps import ContactCache, plan, prepare_rail, prepare_wheel  # noqa: E402
from stages.screen import WheelModels, linear_contact, read_rail_fit, screen_study, wheel_point  # noqa: E402
from stages.wheel import read_mesh, read_modes  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@numba.njit(cache=True)
def _reference_sweep(coef, shift, flat, up, wx, wy, gs, gk, px, py, ux, uy, dxx, dyy, skip, status):
    nc = px.shape[0]
    ne = ux.shape[0]
    change = 0.0
    for c in range(nc):
        j = up[c]
        sx = wx[c] + ux[c] - ux[j]
        sy = wy[c] + uy[c] - uy[j]
        qx, qy, sliding = element_law(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c])
        status[c] = 2 if sliding else 1
        if sliding:
            gs[c] = gk[c]
        dpx = qx - px[c]
        dpy = qy - py[c]
        if abs(dpx) > skip or abs(dpy) > skip:
            px[c] = qx
            py[c] = qy
            off = np.uint64(shift - flat[c])
            for t in range(ne):
                k = np.uint64(flat[t]) + off
                k12 = coef[k, 1]
                ux[t] += coef[k, 0] * dpx + k12 * dpy
                uy[t] += k12 * dpx + coef[k, 2] * dpy
            m = max(abs(dpx), abs(dpy))
            if m > change:
                change = m
    return change


@numba.njit(cache=True)
def reference_steady_gauss_seidel(K11, K12, K22, ix, iy, up, wx, wy, gs, gk, px, py, ux, uy, dxx, dyy, tol,
                                  max_sweeps, depth):
    """The steady sweeps before issue 35 item 3 (every evaluation point updated in turn); the
    signature and result of :func:`contact.halfspace.steady.steady_gauss_seidel`."""
    nc = px.shape[0]
    ne = ux.shape[0]
    my = K11.shape[1]
    ox = (K11.shape[0] + 1) // 2 - 1
    oy = (K11.shape[1] + 1) // 2 - 1
    coef = np.zeros((K11.size, 4))
    coef[:, 0] = K11.ravel()
    coef[:, 1] = K12.ravel()
    coef[:, 2] = K22.ravel()
    flat = ix * my + iy
    shift = ox * my + oy
    status = np.ones(nc, np.int8)
    skip = 1e-3 * tol
    history = anderson_history(depth, nc, ne)
    change = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        anderson_input(history, px, py)
        change = _reference_sweep(coef, shift, flat, up, wx, wy, gs, gk, px, py, ux, uy, dxx, dyy, skip, status)
        sweeps = sweep + 1
        if change <= tol:
            break
        if depth == 0:
            continue
        anderson_mix(history, change, px, py, ux, uy)
    return sweeps, change, status


@contextlib.contextmanager
def reference_path():
    """Run the half-space linearisation as before issue 35 item 3 (module docstring)."""
    saved = (tangential.steady_gauss_seidel, linearise.solve_normal, linearise._load_cached)
    direct = saved[1]
    tangential.steady_gauss_seidel = reference_steady_gauss_seidel
    linearise.solve_normal = lambda *a, **k: direct(*a, **{**k, "fft": False})
    linearise._load_cached = lambda kind, model, load, step, compute, tol=None: compute()
    try:
        yield
    finally:
        tangential.steady_gauss_seidel, linearise.solve_normal, linearise._load_cached = saved


def configurations(out, every):
    """The timed configurations (half-space contact) with their structures, built in ``out``."""
    study = load_study(ROOT / "studies" / "maps.toml", False, ["contact.model=halfspace"])
    study = {**study, "map": {**study["map"], "grid": {**study["map"]["grid"], "wheel.rolling_radius": [0.39]}}}
    layout = plan(study, out)
    (label, (wheel_dir, config)), = layout["wheels"].items()
    prepare_wheel({"label": label, "folder": str(wheel_dir), "study": config})
    for label, (folder, config, fits) in layout["rails"].items():
        prepare_rail({"label": label, "folder": str(folder), "study": config, "laterals": list(fits)})
    wheel = WheelModels(read_modes(wheel_dir / "wheel_modes.h5", with_shapes=True), read_mesh(wheel_dir / "wheel_mesh.h5"),
                        get_section(study, "wheel.rotation"))
    contacts = ContactCache()
    rails, by_state, out_list = {}, {}, []
    for index in range(0, len(layout["configurations"]), every):
        config = case_study(layout["configurations"][index][1], {})
        point = contacts(config)
        fit = layout["rail_fits"][index]
        rail = rails.setdefault(fit, read_rail_fit(fit))
        at = wheel_point(config, point)
        speed = config["operating"]["speed"]
        state = (speed, None if at is None else (at.wheel_lateral, at.rolling_radius))
        if state not in by_state:
            by_state[state] = wheel.at(speed, at)
        out_list.append((index, config, point, rail, by_state[state]))
    return out_list


def screen_once(config, point, rail, models):
    """Seconds and result of one configuration's half-space screen (linearisation + three models)."""
    linearise._CACHE.clear()
    start = time.perf_counter()
    contact = linear_contact(config, point)
    result = screen_study(config, models, rail, point=point, contact=contact, pole_modes=False)
    return time.perf_counter() - start, result


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", help="folder for the wheel's and the rail's structures (default: a temporary folder)")
    parser.add_argument("--every", type=int, default=4, help="time every N-th of the 128 configurations (default 4)")
    args = parser.parse_args(argv)
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(args.out) if args.out else Path(tmp)
        out.mkdir(parents=True, exist_ok=True)
        cases = configurations(out, args.every)
        # compile both paths' kernels first (not timed)
        screen_once(*cases[0][1:])
        with reference_path():
            screen_once(*cases[0][1:])
        linearise._LOAD_CACHE.clear()
        fast, reference, speeds, growth, frequency = [], [], [], 0.0, 0.0
        for index, config, point, rail, models in cases:
            speeds.append(config["operating"]["speed"])
            with reference_path():
                t_ref, r_ref = screen_once(config, point, rail, models)
            t_fast, r_fast = screen_once(config, point, rail, models)
            fast.append(t_fast)
            reference.append(t_ref)
            for name in r_fast:
                growth = max(growth, abs(r_fast[name]["margin"] - r_ref[name]["margin"]))
                frequency = max(frequency, abs(r_fast[name]["margin_frequency"] - r_ref[name]["margin_frequency"]))
    fast, reference = np.array(fast), np.array(reference)
    print(f"half-space screen (linearisation + three wheel models), {fast.size} configurations of studies/maps.toml:")
    print(f"  fast:      median {np.median(fast) * 1e3:6.0f} ms per configuration (min {fast.min() * 1e3:.0f}, "
          f"max {fast.max() * 1e3:.0f} ms; target <= 100 ms)")
    print(f"  reference: median {np.median(reference) * 1e3:6.0f} ms per configuration (min {reference.min() * 1e3:.0f}, "
          f"max {reference.max() * 1e3:.0f} ms)")
    speeds = np.array(speeds)
    for v in np.unique(speeds):
        sel = speeds == v
        print(f"  at {v * 3.6:.0f} km/h ({sel.sum()} configurations): fast median {np.median(fast[sel]) * 1e3:.0f} ms, "
              f"reference {np.median(reference[sel]) * 1e3:.0f} ms")
    print(f"  ratio of the medians {np.median(reference) / np.median(fast):.2f}; largest difference of the margins "
          f"{growth:.2e} 1/s, of their frequencies {frequency:.2e} Hz")


if __name__ == "__main__":
    main()
