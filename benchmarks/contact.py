"""Time per transient rolling step of the contact models on the default study contact.

Default grid dx = dy = 0.5 mm over the Hertz patch (about 10.5 x 8.8 mm) of a 50 kN load on
a 0.39 m wheel (flat tread across) and a 0.3 m rail head radius, steel E = 210 GPa,
nu = 0.3, mu = 0.3, eta = -1 %, v = 50 km/h. Targets: halfspace < 1 ms, point < 5 us.

Run: ``OMP_NUM_THREADS=1 python benchmarks/contact.py [--steps N]``. Prints medians.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from interaction.contact.halfspace import Grid, HalfspaceContact  # noqa: E402
from interaction.contact.hertz import hertz_from_curvatures  # noqa: E402
from interaction.contact.params import Friction, Material  # noqa: E402
from interaction.contact.point import PointContact  # noqa: E402


def _time_steps(model, steps, creepage, warmup):
    state = model.initial_state()
    times = []
    for n in range(warmup + steps):
        t0 = time.perf_counter()
        res = model.solve(state, normal_force=50e3, creepage=creepage)
        times.append(time.perf_counter() - t0)
        state = res.new_state
    return np.array(times[warmup:]), res


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=400)
    args = parser.parse_args(argv)
    mat = Material.from_young(210e9, 0.3)
    fr = Friction(0.3)
    hz = hertz_from_curvatures(1 / (2 * 0.39), 1 / (2 * 0.3), 50e3, mat.contact_modulus)
    speed = 50 / 3.6
    grid = Grid.covering(hz.a, hz.b, dx=0.5e-3, dy=0.5e-3)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    hs = HalfspaceContact(material=mat, friction=fr, grid=grid, gap=hz.A * X ** 2 + hz.B * Y ** 2,
                          kind="transient", speed=speed)
    pt = PointContact(material=mat, friction=fr, hertz=hz, kind="transient", speed=speed,
                      time_step=hs.time_step)
    print(f"Hertz patch 2a x 2b = {2e3 * hz.a:.2f} x {2e3 * hz.b:.2f} mm, grid {grid.nx} x {grid.ny}, "
          f"dt = {hs.time_step * 1e6:.1f} us")
    creep = (0.0, -0.01, 0.0)
    t, res = _time_steps(hs, args.steps, creep, warmup=100)
    print(f"halfspace, constant eta = -1 %: median {np.median(t) * 1e3:.3f} ms/step "
          f"(target < 1 ms); Fy = {res.force[1]:.1f} N, {res.diagnostics.n_slip}/"
          f"{res.diagnostics.n_contact} slip")
    # partial slip, stick-dominated: eta = -0.2 %
    t, res = _time_steps(hs, args.steps, (0.0, -0.002, 0.0), warmup=100)
    print(f"halfspace, constant eta = -0.2 %: median {np.median(t) * 1e3:.3f} ms/step; "
          f"{res.diagnostics.n_slip}/{res.diagnostics.n_contact} slip")
    t, res = _time_steps(pt, 20 * args.steps, creep, warmup=100)
    print(f"point (second-order relaxation), constant eta = -1 %: median {np.median(t) * 1e6:.2f} us/step "
          f"(target < 5 us); Fy = {res.force[1]:.1f} N")
    # harmonic lateral creepage: the relaxation states change every step
    eta = -0.002 + 1e-4 * np.sin(2 * np.pi * 1000.0 * pt.time_step * np.arange(20 * args.steps))
    state = pt.initial_state()
    times = np.empty(eta.size)
    for n, e in enumerate(eta):
        t0 = time.perf_counter()
        state = pt.solve(state, normal_force=50e3, creepage=(0.0, e, 0.0)).new_state
        times[n] = time.perf_counter() - t0
    print(f"point, eta = -0.2 % + 0.01 % sin(2 pi 1 kHz t): median {np.median(times[100:]) * 1e6:.2f} us/step")


if __name__ == "__main__":
    main()
