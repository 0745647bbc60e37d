"""Point-contact model (``point``): Hertz normal spring and a transient creep-force law.

* Normal: Hertz, ``Fn = F_ref (delta / delta_ref)^(3/2)``; the semi-axes scale as Fn^(1/3)
  with a fixed ratio a/b (fixed curvatures).
* Tangential, steady: Kalker's linear theory (coefficients from Table E.3, see kalker.py),
  ``Fx = -G a b C11 xi``, ``Fy = -G a b C22 eta - G (ab)^1.5 C23 phi``, saturated with the
  Shen-Hedrick-Elkins (1983) law: with beta = |F_lin| / (mu Fn),
  ``|F| = mu Fn (beta - beta^2/3 + beta^3/27)`` for beta < 3, else ``mu Fn`` (mu = the
  kinetic coefficient), direction of F_lin.
* Transient: the linear law is applied to effective creepages y that follow each imposed
  creepage u through a second-order relaxation over the rolled distance x,

      alpha2 a^2 y'' + alpha1 a y' + y = u + beta a u'      (primes: d/dx),

  i.e. the rolling-distance transfer function ``H(s) = (1 + beta a s) / (1 + alpha1 a s +
  alpha2 a^2 s^2)`` of the frequency-dependent creep coefficients (Knothe & Gross-Thebing,
  Vehicle System Dynamics 15, 1986): H depends only on the non-dimensional frequency
  omega a / V and on a/b; H(0) = 1 (Kalker's steady theory) and at high frequency
  ``F ~ G a b C (beta / (alpha2 a)) V u / (i omega)``, a tangential contact stiffness. The
  constants are fitted once to the linear (no-slip) transient rolling of the ``halfspace``
  model (``python -m interaction.contact.fit_relaxation``; table ``data/point_relaxation.csv``
  over a/b and nu, interpolated linearly in ln(a/b) and nu, clamped with a warning outside).
  xi uses the longitudinal constants, eta and the spin phi the lateral ones (the spin's own
  transient is not fitted). The lengths scale with the semi-axis a, i.e. with Fn^(1/3); the
  states are kept when the load changes. Discretised exactly for creepages held constant
  over each step. This replaces the first-order relaxation ``L y' + y = u`` with Mindlin's
  stiffness (Zenzerovic, Kropp & Pieringer, JSV 2016), which misses the half-space response by
  up to -22 % in amplitude where the creepage wavelength is comparable to the contact length.
"""

from __future__ import annotations

import functools
import logging
import math
from typing import NamedTuple

import numpy as np

from squealcore.errors import InputError, require_range

from interaction.kernels import point_contact_loop

from .bundles import PointLaw
from .hertz import HertzSolution
from .kernels import compiled_entry, point_contact_law
from .kalker import creep_coefficients
from .model import CompiledPath, ContactResult, Diagnostics
from .params import Friction, Material
from .tables import read_table

log = logging.getLogger(__name__)

__all__ = ["PointState", "PointContact", "load_relaxation_table", "relaxation_coefficients"]


@functools.lru_cache(maxsize=1)
def load_relaxation_table():
    """Return the fitted relaxation table (``data/point_relaxation.csv``) as a dict of arrays."""
    return read_table("point_relaxation.csv")


def relaxation_coefficients(a_over_b: float, nu: float) -> np.ndarray:
    """Non-dimensional relaxation constants for semi-axis ratio a/b (-) and Poisson ratio nu (-).

    Interpolated bilinearly in (ln(a/b), nu) in the fitted table; outside the table the nearest
    edge is used and a warning logged.

    Returns
    -------
    ndarray (2, 3)
        Rows x (for xi) and y (for eta and phi): (beta, alpha1, alpha2) of
        ``alpha2 a^2 y'' + alpha1 a y' + y = u + beta a u'``.
    """
    a_over_b = require_range("geometry.a_over_b", a_over_b, 0.0, None, low_open=True)
    nu = require_range("material.poisson_ratio", nu, 0.0, 0.5)
    t = load_relaxation_table()
    ratios, nus = np.unique(t["a_over_b"]), np.unique(t["nu"])
    lr = float(np.clip(math.log(a_over_b), math.log(ratios[0]), math.log(ratios[-1])))
    nc = float(np.clip(nu, nus[0], nus[-1]))
    if not (math.isclose(lr, math.log(a_over_b)) and nc == nu):
        log.warning("point contact: a/b = %.3g, nu = %.3g outside the fitted relaxation table "
                    "(a/b %.3g-%.3g, nu %.3g-%.3g); using its edge", a_over_b, nu, ratios[0], ratios[-1],
                    nus[0], nus[-1])
    out = np.empty((2, 3))
    for row, d in enumerate("xy"):
        for col, name in enumerate(("beta", "alpha1", "alpha2")):
            grid = np.empty(nus.size)
            for k, n0 in enumerate(nus):
                m = np.isclose(t["nu"], n0)
                order = np.argsort(t["a_over_b"][m])
                grid[k] = np.interp(lr, np.log(t["a_over_b"][m][order]), t[f"{name}_{d}"][m][order])
            out[row, col] = np.interp(nc, nus, grid)
    return out


class PointState(NamedTuple):
    """State of the point model.

    Attributes
    ----------
    creepage : tuple of 3 float
        Effective creepages (xi, eta (-), phi (1/m)) of the relaxation.
    auxiliary : tuple of 3 float
        Second state of each creepage's relaxation (units of that creepage).
    step : int
        Steps committed so far.
    """

    creepage: tuple
    auxiliary: tuple = (0.0, 0.0, 0.0)
    step: int = 0


class PointContact:
    """Point contact with Hertz normal spring and transient saturated creep forces.

    Parameters
    ----------
    material : Material
        Combined elastic constants.
    friction : Friction
        Friction; the kinetic coefficient sets the saturation mu Fn.
    hertz : HertzSolution
        Hertz solution at a reference load (fixes curvatures and a/b).
    kind : {"transient", "steady"}
        With relaxation or without.
    speed : float
        Rolling speed V (m/s), > 0.
    time_step : float
        Time step (s), > 0.

    Attributes
    ----------
    c11, c22, c23 : float
        Kalker's creep coefficients for a/b and nu (-).
    relaxation : ndarray (2, 3)
        Rows x (xi) and y (eta, phi): non-dimensional (beta, alpha1, alpha2) of the relaxation,
        see :func:`relaxation_coefficients`.
    law : PointLaw
        The constants of :func:`~interaction.contact.kernels.point_contact_law` for this model,
        used by :meth:`solve` and by the compiled time loop alike.
    """

    def __init__(self, *, material: Material, friction: Friction, hertz: HertzSolution,
                 kind="transient", speed=30.0, time_step=1e-5):
        if kind not in ("transient", "steady"):
            raise InputError("kind", f"point model supports 'transient' or 'steady', got {kind!r}")
        self.material = material
        self.friction = friction
        self.hertz = hertz
        self.kind = kind
        self.speed = require_range("rolling.speed", speed, 0.0, None, low_open=True, unit="m/s")
        self.time_step = require_range("rolling.time_step", time_step, 0.0, None, low_open=True, unit="s")
        ratio = hertz.a / hertz.b
        self.c11, self.c22, self.c23 = creep_coefficients(ratio, material.poisson_ratio)
        # (2, 3): rows x, y of the non-dimensional (beta, alpha1, alpha2)
        self.relaxation = relaxation_coefficients(ratio, material.poisson_ratio)
        self.law = self.point_law()
        self._steady_law = self.point_law(steady=True)
        self._law_entry = None  # the compiled law without numba's argument dispatch, made on first use

    def relaxation_constants(self, normal_force) -> np.ndarray:
        """Dimensional relaxation constants at a normal force (N).

        Returns
        -------
        ndarray (2, 3)
            Rows x (xi) and y (eta, phi): (b (m), a1 (m), a2 (m²)) of ``a2 y'' + a1 y' + y = u + b u'``.
        """
        a = self.hertz.scaled(normal_force).a
        return self.relaxation * np.array([a, a, a * a])

    def contact_stiffness(self, normal_force) -> tuple[float, float]:
        """High-frequency limit of the law as tangential stiffnesses (kx, ky) (N/m) at a force (N).

        ``k = G a b C b_relax / a2``: the force per unit rigid tangential displacement when the
        creepage wavelength is much shorter than the contact (compare Mindlin's no-slip
        stiffness ``4 G sqrt(ab) / (2 - nu)`` of a circular contact).
        """
        h = self.hertz.scaled(normal_force)
        gab = self.material.shear_modulus * h.a * h.b
        (bx, _, a2x), (by, _, a2y) = self.relaxation_constants(normal_force)
        return gab * self.c11 * bx / a2x, gab * self.c22 * by / a2y

    def initial_state(self) -> PointState:
        """Zero effective creepages and auxiliary states."""
        return PointState((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), 0)

    def point_law(self, steady=None) -> PointLaw:
        """The bundle of :func:`interaction.contact.kernels.point_contact_law` for this model.

        ``steady`` (default: ``kind == "steady"``) gives the law without relaxation.
        """
        steady = self.kind == "steady" if steady is None else steady
        h = self.hertz
        ab = h.a * h.b
        return PointLaw(float(h.normal_force), float(h.approach), float(self.material.shear_modulus * ab),
                        float(ab), float(self.c11), float(self.c22), float(self.c23), float(self.friction.kinetic),
                        float(self.speed * self.time_step), 0.0 if steady else float(h.a),
                        np.ascontiguousarray(self.relaxation, dtype=float))

    def compiled_path(self, static: ContactResult) -> CompiledPath:
        """The compiled time loop of the interaction with this model's :class:`PointLaw`.

        ``static`` (the solution at static equilibrium) is not needed: the loop starts from
        zero relaxation states, as :meth:`solve` does from :meth:`initial_state`.
        """
        return CompiledPath(loop=point_contact_loop, contact=self.law, state=np.zeros(6),
                            snapshot=lambda state: None)

    def steady_force(self, normal_force, creepage) -> np.ndarray:
        """Saturated steady creep force (Fx, Fy) (N) for creepages (xi, eta, phi)."""
        fn = float(normal_force)
        if fn <= 0.0:
            return np.zeros(2)
        approach = self.hertz.approach * (fn / self.hertz.normal_force) ** (2.0 / 3.0)
        xi, eta, phi = (float(c) for c in creepage)
        out = point_contact_law(self._steady_law, approach, xi, eta, phi, (0.0, 0.0, 0.0, 0.0, 0.0, 0.0))
        return np.array(out[:2])

    def solve(self, state: PointState, *, approach=None, normal_force=None, creepage=(0.0, 0.0, 0.0),
              shift=None) -> ContactResult:
        """One step from ``state``; see :class:`~interaction.contact.model.ContactModel`.

        Scalar code (no arrays but the returned force) to keep a step at a few microseconds.
        """
        if (approach is None) == (normal_force is None):
            raise InputError("load", "give exactly one of normal_force and approach")
        if shift is not None:
            raise InputError("kind", "the point model does not solve shift problems")
        try:
            xi, eta, phi = (float(c) for c in creepage)
        except (TypeError, ValueError):
            raise InputError("rolling.creepage", f"must be [xi, eta, phi], got {creepage!r}") from None
        if not (math.isfinite(xi) and math.isfinite(eta) and math.isfinite(phi)):
            raise InputError("rolling.creepage", f"must be finite, got {creepage!r}")
        h0 = self.hertz
        if approach is not None:
            delta = float(approach)
            fn = h0.normal_force * (delta / h0.approach) ** 1.5 if delta > 0 else 0.0
        else:
            fn = max(float(normal_force), 0.0)
            delta = h0.approach * (fn / h0.normal_force) ** (2.0 / 3.0) if fn > 0 else 0.0
        if fn <= 0.0:
            diag = Diagnostics(0, 0, 0, 0.0, 0, 0.0, 0.0, delta)
            return ContactResult(np.zeros(3), 0.0, PointState((0.0, 0.0, 0.0), (0.0, 0.0, 0.0), state.step + 1),
                                 diag)
        s = (fn / h0.normal_force) ** (1.0 / 3.0)
        c, w = state.creepage, state.auxiliary
        relaxed = (float(c[0]), float(w[0]), float(c[1]), float(w[1]), float(c[2]), float(w[2]))
        if self._law_entry is None:
            self._law_entry = compiled_entry(point_contact_law, self.law, delta, xi, eta, phi, relaxed)
        fx, fy, _, ex, wx, ey, wy, ep, wp = self._law_entry(self.law, delta, xi, eta, phi, relaxed)
        bound = self.friction.kinetic * fn
        ratio = math.hypot(fx, fy) / bound if bound > 0 else 1.0
        saturated = ratio >= 1.0 - 1e-12
        diag = Diagnostics(1, 0 if saturated else 1, 1 if saturated else 0, min(ratio, 1.0), 1, 0.0,
                           h0.p0 * s, delta)
        return ContactResult(np.array((fx, fy, fn)), 0.0, PointState((ex, ey, ep), (wx, wy, wp), state.step + 1),
                             diag)
