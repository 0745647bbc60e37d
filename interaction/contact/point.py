"""Point-contact model (``point``): Hertz normal spring and a transient creep-force law.

* Normal: Hertz, ``Fn = F_ref (delta / delta_ref)^(3/2)``; the semi-axes scale as Fn^(1/3)
  with a fixed ratio a/b (fixed curvatures).
* Tangential, steady: Kalker's linear theory (coefficients from Table E.3, see kalker.py),
  ``Fx = -G a b C11 xi``, ``Fy = -G a b C22 eta - G (ab)^1.5 C23 phi``, saturated with the
  Shen-Hedrick-Elkins (1983) law: with beta = |F_lin| / (mu Fn),
  ``|F| = mu Fn (beta - beta^2/3 + beta^3/27)`` for beta < 3, else ``mu Fn`` (mu = the
  kinetic coefficient), direction of F_lin.
* Transient: the creepages entering the law lag the imposed ones by a first-order
  relaxation over a rolling distance L, ``L dxi_e/dx + xi_e = xi`` (the linear creep
  damper of the contact in series with its tangential stiffness k, so that
  ``L = G a b C / k``), as in the point-contact models of Zenzerovic, Kropp & Pieringer
  (JSV 2016) and the relaxation-length models of Knothe & Gross-Thebing. The stiffness is
  Mindlin's no-slip tangential stiffness of two identical bodies with a circular contact,
  ``k = 4 G c / (2 - nu)``, with the equivalent radius c = sqrt(ab) (an approximation for
  elliptic contacts). Discretised exactly for creepages held constant over each step.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from squealcore.errors import InputError, require_range

from .hertz import HertzSolution
from .kernels import point_contact_law
from .kalker import creep_coefficients
from .model import ContactResult, Diagnostics
from .params import Friction, Material

__all__ = ["PointState", "PointContact"]


class PointState(NamedTuple):
    """State of the point model.

    Attributes
    ----------
    creepage : tuple of 3 float
        Relaxed (effective) creepages (xi, eta (-), phi (1/m)).
    step : int
        Steps committed so far.
    """

    creepage: tuple
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
    """

    def __init__(self, *, material: Material, friction: Friction, hertz: HertzSolution,
                 kind="transient", speed=30.0, time_step=1e-5, relaxation_factor=1.0):
        if kind not in ("transient", "steady"):
            raise InputError("kind", f"point model supports 'transient' or 'steady', got {kind!r}")
        self.material = material
        self.friction = friction
        self.hertz = hertz
        self.kind = kind
        self.speed = require_range("rolling.speed", speed, 0.0, None, low_open=True, unit="m/s")
        self.time_step = require_range("rolling.time_step", time_step, 0.0, None, low_open=True, unit="s")
        self.relaxation_factor = require_range("relaxation_factor", relaxation_factor, 0.0, None, low_open=True)
        ratio = hertz.a / hertz.b
        self.c11, self.c22, self.c23 = creep_coefficients(ratio, material.poisson_ratio)
        self._ab0 = hertz.a * hertz.b
        self._gab0 = material.shear_modulus * self._ab0
        self._lx0, self._ly0 = self.relaxation_lengths(hertz.normal_force)
        self._dist = self.speed * self.time_step
        self._constants = self.kernel_constants()

    def relaxation_lengths(self, normal_force) -> tuple[float, float]:
        """Relaxation lengths (Lx, Ly) (m) at a normal force (N): L = G a b C / k."""
        h = self.hertz.scaled(normal_force)
        G, nu = self.material.shear_modulus, self.material.poisson_ratio
        k = 4.0 * G * math.sqrt(h.a * h.b) / (2.0 - nu)
        f = self.relaxation_factor
        return f * G * h.a * h.b * self.c11 / k, f * G * h.a * h.b * self.c22 / k

    def initial_state(self) -> PointState:
        """Zero effective creepages."""
        return PointState((0.0, 0.0, 0.0), 0)

    def kernel_constants(self, steady=None) -> np.ndarray:
        """Constants of :func:`interaction.contact.kernels.point_contact_law` for this model."""
        steady = self.kind == "steady" if steady is None else steady
        h = self.hertz
        lx, ly = (0.0, 0.0) if steady else (self._lx0, self._ly0)
        return np.array([h.normal_force, h.approach, self._gab0, self._ab0, self.c11, self.c22, self.c23,
                         self.friction.kinetic, self._dist, lx, ly])

    def steady_force(self, normal_force, creepage) -> np.ndarray:
        """Saturated steady creep force (Fx, Fy) (N) for creepages (xi, eta, phi)."""
        fn = float(normal_force)
        if fn <= 0.0:
            return np.zeros(2)
        approach = self.hertz.approach * (fn / self.hertz.normal_force) ** (2.0 / 3.0)
        out = point_contact_law(approach, *(float(c) for c in creepage), 0.0, 0.0, 0.0,
                                self.kernel_constants(steady=True))
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
            return ContactResult(np.zeros(3), 0.0, PointState((0.0, 0.0, 0.0), state.step + 1), diag)
        s = (fn / h0.normal_force) ** (1.0 / 3.0)
        c = state.creepage
        fx, fy, _, ex, ey, ep = point_contact_law(delta, xi, eta, phi, c[0], c[1], c[2], self._constants)
        bound = self.friction.kinetic * fn
        ratio = math.hypot(fx, fy) / bound if bound > 0 else 1.0
        saturated = ratio >= 1.0 - 1e-12
        diag = Diagnostics(1, 0 if saturated else 1, 1 if saturated else 0, min(ratio, 1.0), 1, 0.0,
                           h0.p0 * s, delta)
        return ContactResult(np.array((fx, fy, fn)), 0.0, PointState((ex, ey, ep), state.step + 1), diag)
