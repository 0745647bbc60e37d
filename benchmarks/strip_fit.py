"""Where the half-space reaches full slip, and the strip model's creep factor that matches it there.

For three contacts (the default study's, a/b = 1.19 at 50 kN; a/b = 2.18 at 40 kN; a/b = 0.62
at 80 kN) the transient half-space is rolled to steady state (two patch lengths) at lateral
creepages r times the Shen-Hedrick-Elkins full-slip creepage 3 mu Fn / (G a b C22), r = 0.5 ...
1.1, on the study grid (dx = dy = 0.5 mm) and on a grid twice as fine; it prints the slip area and
F / mu Fn per r, the linear force against Kalker's, and for the strip model the creep factor k
(``contact.point.model.STRIP_CREEP_FACTOR``) whose saturated creep law,
``1 - (1 - beta / 3)^3`` with ``beta = k r 3`` (the strip's exact steady state), is nearest to the
half-space (least squares) over r >= 0.8, where the stick area of a squealing contact opens and
closes. About a minute.

Run: ``python -m benchmarks.strip_fit``.
"""

from __future__ import annotations

import numpy as np

from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_curvatures
from contact.kalker import creep_coefficients
from contact.params import Friction, Material

MATERIAL = Material.from_young(210e9, 0.3)
SPEED = 50 / 3.6
MU = 0.6
RATIOS = np.array([0.5, 0.7, 0.8, 0.85, 0.9, 0.95, 1.0, 1.1])
CONTACTS = {  # wheel radius 0.39 m; rail head radius (m), load (N)
    "a/b 1.19, 50 kN (default)": (0.3, 50e3),
    "a/b 2.18, 40 kN": (0.12, 40e3),
    "a/b 0.62, 80 kN": (0.8, 80e3),
}


def saturated(beta):
    """The Shen-Hedrick-Elkins cubic, F / mu Fn, for beta = |F_linear| / mu Fn."""
    beta = np.asarray(beta, float)
    return np.where(beta < 3.0, beta - beta ** 2 / 3 + beta ** 3 / 27, 1.0)


def steady_halfspace(hz, element, creepages):
    """F_y / mu Fn and the slip area fraction of the transient half-space rolled to steady state."""
    grid = Grid.covering(hz.a, hz.b, dx=element, dy=element)
    x, y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=MATERIAL, friction=Friction(MU), grid=grid, gap=hz.A * x ** 2 + hz.B * y ** 2,
                             kind="transient", speed=SPEED)
    forces, slips = [], []
    for eta in creepages:
        state = model.solve(model.initial_state(), normal_force=hz.normal_force, creepage=(0, 0, 0)).new_state
        for _ in range(2 * grid.nx):
            result = model.solve(state, normal_force=hz.normal_force, creepage=(0.0, -eta, 0.0))
            state = result.new_state
        forces.append(result.force[1] / (MU * result.force[2]))
        slips.append(result.diagnostics.slip_fraction)
    return np.array(forces), np.array(slips)


def main():
    factors = np.linspace(1.0, 1.25, 251)
    for name, (rail_radius, load) in CONTACTS.items():
        hz = hertz_from_curvatures(1 / (2 * 0.39), 1 / (2 * rail_radius), load, MATERIAL.contact_modulus)
        c22 = creep_coefficients(hz.a / hz.b, MATERIAL.poisson_ratio)[1]
        stiffness = MATERIAL.shear_modulus * hz.a * hz.b * c22
        full_slip = 3 * MU * load / stiffness
        print(f"{name}: a = {hz.a * 1e3:.2f} mm, b = {hz.b * 1e3:.2f} mm, 3 mu Fn / (G a b C22) = "
              f"{100 * full_slip:.3f} %")
        for element in (0.5e-3, 0.25e-3):
            linear, _ = steady_halfspace(hz, element, [1e-3 * full_slip])
            force, slip = steady_halfspace(hz, element, RATIOS * full_slip)
            near = RATIOS >= 0.8
            errors = [np.sqrt(np.mean((saturated(3 * k * RATIOS[near]) - force[near]) ** 2)) for k in factors]
            best = factors[int(np.argmin(errors))]
            print(f"  dx = dy = {element * 1e3:.2f} mm: linear force / Kalker's {linear[0] / 3e-3:.4f}; "
                  f"best strip factor (r >= 0.8) {best:.3f}, rms {min(errors):.1e} of mu Fn")
            for r, f, s in zip(RATIOS, force, slip):
                print(f"    r = {r:4.2f}: half-space F/muFn {f:.4f}, slip area {s:.3f}; strip k = 1: "
                      f"{float(saturated(3 * r)):.4f}, k = 1.1: {float(saturated(3.3 * r)):.4f}")


if __name__ == "__main__":
    main()
