"""Fit the second-order creep-force relaxation of the ``point`` model to the transient half-space.

Run ``python -m contact.point.fit_relaxation [--out FILE]`` to rebuild the package table
``data/point_relaxation.csv`` (its run time: docs/benchmarks.md, *Point contact*).

For each semi-axis ratio a/b and Poisson ratio nu of the table, and for each creepage direction
(longitudinal xi, lateral eta), the linear (no-slip: friction coefficient 1e3) transient rolling
response of the ``halfspace`` model to a creepage step is computed on a grid of
``dx = a / 12``, ``dy = b / 12`` (one element rolled per step), normalised by its steady value.
The point model's law (see point.py) relaxes each creepage u into an effective creepage y
over the rolled distance x by ``a2 y'' + a1 y' + y = u + b u'`` (primes: d/dx), i.e. the
rolling-distance transfer function

    H(s) = (1 + b s) / (1 + a1 s + a2 s^2),     b = beta a, a1 = alpha1 a, a2 = alpha2 a^2.

The three non-dimensional constants (beta, alpha1, alpha2) are fitted, in the least-squares
sense, to the logarithm (amplitude ratio and phase) of the half-space transfer function at 40
non-dimensional frequencies ``Omega = omega a / V`` log-spaced over [0.03, 15] (the band
100 Hz - 5 kHz of the default contact at 50 km/h is Omega = 0.24 - 12). Both transfer functions
are those of the sampled systems (creepage held over each step), computed from the step
responses. The halfspace's response is normalised by its value after 8 a of rolling, where it
has settled to about 1e-4.
"""

from __future__ import annotations

import argparse
import logging
import math
import os
from dataclasses import dataclass

import numpy as np
from scipy import signal
from scipy.optimize import least_squares

from contact.halfspace.model import Grid, HalfspaceContact
from contact.hertz import hertz_from_semi_axes
from contact.params import Friction, Material

log = logging.getLogger(__name__)

__all__ = ["RelaxationFit", "halfspace_step_response", "relaxation_step_response", "sampled_transfer",
           "fit_relaxation", "fit_table", "write_table", "RATIOS", "POISSON", "OMEGA"]

RATIOS = (0.3, 0.5, 0.7, 1.0, 1.0 / 0.7, 2.0, 1.0 / 0.3)
"""Semi-axis ratios a/b of the table (-)."""
POISSON = (0.25, 0.3, 0.35)
"""Poisson ratios of the table (-)."""
OMEGA = np.logspace(math.log10(0.03), math.log10(15.0), 40)
"""Non-dimensional frequencies omega a / V of the fit (-)."""
PER_A = 12
"""Elements per semi-axis of the reference grid."""
LENGTHS = 8.0
"""Rolled distance of a step response, in semi-axes a."""


@dataclass(frozen=True)
class RelaxationFit:
    """Fitted constants of one direction (lengths in units of the semi-axis a).

    Attributes
    ----------
    beta, alpha1, alpha2 : float
        b / a, a1 / a and a2 / a^2 of ``H(s) = (1 + b s) / (1 + a1 s + a2 s^2)`` (-).
    max_log_error : float
        Largest |ln(H_point / H_halfspace)| over the fitted band (-): the amplitude ratio's
        logarithm and the phase difference (rad).
    """

    beta: float
    alpha1: float
    alpha2: float
    max_log_error: float


def halfspace_step_response(a_over_b, nu, component, per_a=PER_A, lengths=LENGTHS):
    """Normalised linear step response of the transient half-space.

    Parameters
    ----------
    a_over_b : float
        Semi-axis ratio (-).
    nu : float
        Poisson ratio (-).
    component : {0, 1}
        Creepage direction: 0 longitudinal (xi), 1 lateral (eta).
    per_a : int
        Elements per semi-axis in each direction.
    lengths : float
        Rolled distance, in semi-axes a.

    Returns
    -------
    x : ndarray
        Rolled distance after each step divided by a (-).
    response : ndarray
        Force divided by its final value (-).
    """
    material = Material(80e9, nu)  # the normalised response does not depend on G, a or F_n
    a = 5e-3
    hz = hertz_from_semi_axes(a, a / a_over_b, 50e3, material.contact_modulus)
    grid = Grid.covering(hz.a, hz.b, dx=hz.a / per_a, dy=hz.b / per_a)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    model = HalfspaceContact(material=material, friction=Friction(1e3), grid=grid,
                             gap=hz.A * X ** 2 + hz.B * Y ** 2, kind="transient", speed=10.0)
    creepage = [0.0, 0.0, 0.0]
    creepage[component] = -1e-5
    steps = int(math.ceil(lengths * per_a))
    state = model.initial_state()
    force = np.empty(steps)
    for n in range(steps):
        res = model.solve(state, normal_force=hz.normal_force, creepage=tuple(creepage))
        state = res.new_state
        force[n] = res.force[component]
    return np.arange(1, steps + 1) * grid.dx / hz.a, force / force[-1]


def relaxation_step_response(x, beta, alpha1, alpha2):
    """Unit-step response of ``(1 + beta s) / (1 + alpha1 s + alpha2 s^2)`` at x (scipy.signal)."""
    x = np.asarray(x, float)
    system = signal.lti([beta, 1.0], [alpha2, alpha1, 1.0])
    return signal.step(system, T=np.concatenate(([0.0], x)))[1][1:]


def sampled_transfer(response, step, omega):
    """Transfer function of a sampled linear system from its normalised step response.

    Parameters
    ----------
    response : ndarray
        Step response after steps 1, 2, ... (input held from step 1 on), settled to 1 at the end.
    step : float
        Rolled distance per step divided by a (-).
    omega : ndarray
        Non-dimensional frequencies omega a / V (-).

    Returns
    -------
    ndarray of complex
        ``sum_n h[n] exp(-i omega n step)`` with the impulse response h = diff(response).
    """
    h = np.diff(np.concatenate(([0.0], response)))
    n = np.arange(h.size)
    return np.exp(-1j * np.outer(omega, n) * step) @ h


def fit_relaxation(x, response, omega=OMEGA) -> RelaxationFit:
    """Fit (beta, alpha1, alpha2) to a step response sampled at uniform rolled distances x (in a)."""
    step = x[1] - x[0]
    # the model's response is followed until it has settled: extend both to 60 a
    xl = np.arange(1, int(math.ceil(60.0 / step)) + 1) * step
    target = sampled_transfer(np.concatenate((response, np.ones(xl.size - x.size))), step, omega)

    def residual(p):
        ratio = sampled_transfer(relaxation_step_response(xl, *p), step, omega) / target
        return np.concatenate((np.log(np.abs(ratio)), np.angle(ratio)))

    sol = least_squares(residual, (0.5, 1.7, 0.9), bounds=([0.0, 1e-3, 1e-3], [10.0, 10.0, 10.0]))
    return RelaxationFit(*(float(v) for v in sol.x), float(np.abs(sol.fun).max()))


def fit_table(ratios=RATIOS, poisson=POISSON, per_a=PER_A):
    """Fit every (a/b, nu, direction); returns a list of row dicts."""
    rows = []
    for nu in poisson:
        for ab in ratios:
            row = {"a_over_b": ab, "nu": nu}
            for comp, name in ((0, "x"), (1, "y")):
                x, resp = halfspace_step_response(ab, nu, comp, per_a=per_a)
                fit = fit_relaxation(x, resp)
                row.update({f"beta_{name}": fit.beta, f"alpha1_{name}": fit.alpha1,
                            f"alpha2_{name}": fit.alpha2, f"err_{name}": fit.max_log_error})
                log.info("a/b = %.4g, nu = %.3g, %s: beta = %.4f, alpha1 = %.4f, alpha2 = %.4f, "
                         "max |ln H ratio| = %.4f", ab, nu, name, fit.beta, fit.alpha1, fit.alpha2,
                         fit.max_log_error)
            rows.append(row)
    return rows


COLUMNS = ("a_over_b", "nu", "beta_x", "alpha1_x", "alpha2_x", "err_x", "beta_y", "alpha1_y", "alpha2_y",
           "err_y")
HEADER = """\
# Second-order creep-force relaxation of the point contact model (contact/point/model.py),
# fitted to the linear (no-slip) transient rolling response of the halfspace model by
# `python -m contact.point.fit_relaxation` (grid dx = a/12, dy = b/12, one element per step).
# Effective creepage y from creepage u over the rolled distance x: a2 y'' + a1 y' + y = u + b u',
# with b = beta a, a1 = alpha1 a, a2 = alpha2 a^2 (a: semi-axis along rolling).
# Columns: a/b, Poisson ratio nu, then per direction x (longitudinal creepage xi) and y (lateral
# creepage eta): beta, alpha1, alpha2 (-) and err = largest |ln(H_point / H_halfspace)| over
# omega a / V in [0.03, 15] (log amplitude ratio and phase in rad).
"""


def write_table(rows, path):
    """Write the rows as the package CSV (comment header + one line per (a/b, nu))."""
    with open(path, "w") as fh:
        fh.write(HEADER)
        fh.write(",".join(COLUMNS) + "\n")
        for row in rows:
            fh.write(",".join(f"{row[c]:.6g}" for c in COLUMNS) + "\n")


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    default = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))), "data", "point_relaxation.csv")
    parser.add_argument("--out", default=default, help="CSV file to write (default: the package table)")
    args = parser.parse_args(argv)
    logging.basicConfig(level=logging.INFO, format="%(message)s")
    write_table(fit_table(), args.out)
    log.info("wrote %s", args.out)


if __name__ == "__main__":
    main()
