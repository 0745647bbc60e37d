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
  model (``python -m contact.point.fit_relaxation``; table ``data/point_relaxation.csv``
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

from contact.point.loop import point_contact_loop
from stability.linearised_contact import LinearisedContact, sliding_speed, with_friction_slope

from contact.point.bundles import PointLaw
from contact.hertz import HertzSolution
from contact.halfspace.model import Grid
from contact.kernels_linalg import compiled_entry
from contact.kalker import creep_coefficients
from contact.model import CompiledPath, ContactResult, Diagnostics, freeze
from contact.friction_law import scaled
from contact.params import Friction, Material
from contact.point.kernels import RELAXATION, RELAXATION_STATES, STRIP, point_contact_law
from contact.tables import read_table

log = logging.getLogger(__name__)

__all__ = ["PointState", "PointContact", "TANGENTIAL_LAWS", "load_relaxation_table", "relaxation_coefficients",
           "linearise_point_contact", "for_study", "linearise_for_study", "for_command"]

STRIP_CREEP_FACTOR = 1.1
"""The strip model's creep coefficients are Kalker's times this. With Kalker's own (factor 1) every
strip reaches full slip at the Shen-Hedrick-Elkins creepage 3 mu Fn / (G a b C), but the exact
(half-space) theory is in full slip from about 0.85 of it on (measured on three contacts, a/b
0.62-2.18, grid-converged; docs/results.md), and squeal lives there: the factor 1.1 makes the
strips' steady force equal the half-space's on the study grid within 1e-3 of mu Fn from 0.8 of that
creepage on (``python -m benchmarks.strip_fit``), at the price of a linear force 10 % above
Kalker's (7 % above the half-space grid's)."""

STRIP_LOAD_FACTOR = 3.0
"""The strip grid covers the Hertz patch at this multiple of the reference load (plus 10 %), as the
half-space grid of a case does; a larger patch is cut at the grid's edge."""


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
    values : ndarray
        The carried state of :func:`~contact.point.kernels.point_contact_law`
        (read-only): the relaxation's effective creepages and auxiliary states of xi, eta and
        phi, then the strip model's elastic displacements (m).
    step : int
        Steps committed so far.
    """

    values: np.ndarray
    step: int = 0


TANGENTIAL_LAWS = {"strip": STRIP, "relaxation": RELAXATION}
"""The point model's tangential parts by name (``contact.point_tangential``)."""


class PointContact:
    """Point contact with Hertz normal spring and a transient tangential law.

    Parameters
    ----------
    material : Material
        Combined elastic constants.
    friction : Friction
        Friction; the kinetic coefficient sets the saturation mu Fn (with a characteristic of the
        sliding speed, mu at the contact's sliding speed ``speed * |(xi, eta)|``).
    hertz : HertzSolution
        Hertz solution at a reference load (fixes curvatures and a/b).
    kind : {"transient", "steady"}
        With the transient tangential law or the steady creep law.
    speed : float
        Rolling speed V (m/s), > 0.
    time_step : float
        Time step (s), > 0.
    tangential : {"strip", "relaxation"}
        Transient strip model (default) or the saturated creep law on relaxed creepages.
    strip_width : float
        Width of the strip model's strips (m), > 0; the elements along each strip are the
        rolled distance per step long.

    Attributes
    ----------
    c11, c22, c23 : float
        Kalker's creep coefficients for a/b and nu (-).
    relaxation : ndarray (2, 3)
        Rows x (xi) and y (eta, phi): non-dimensional (beta, alpha1, alpha2) of the relaxation,
        see :func:`relaxation_coefficients`.
    law : PointLaw
        The constants of :func:`~contact.point.kernels.point_contact_law` for this
        model, used by :meth:`solve` and by the compiled time loop alike.
    """

    def __init__(self, *, material: Material, friction: Friction, hertz: HertzSolution,
                 kind="transient", speed=30.0, time_step=1e-5, tangential="strip", strip_width=5e-4):
        if kind not in ("transient", "steady"):
            raise InputError("kind", f"point model supports 'transient' or 'steady', got {kind!r}")
        if tangential not in TANGENTIAL_LAWS:
            raise InputError("contact.point_tangential", f"must be one of {sorted(TANGENTIAL_LAWS)}, got {tangential!r}")
        self.material = material
        self.friction = friction
        self.hertz = hertz
        self.kind = kind
        self.tangential = tangential
        self.speed = require_range("rolling.speed", speed, 0.0, None, low_open=True, unit="m/s")
        self.time_step = require_range("rolling.time_step", time_step, 0.0, None, low_open=True, unit="s")
        self.strip_width = require_range("contact.grid_dy", strip_width, 0.0, None, low_open=True, unit="m")
        ratio = hertz.a / hertz.b
        self.c11, self.c22, self.c23 = creep_coefficients(ratio, material.poisson_ratio)
        # (2, 3): rows x, y of the non-dimensional (beta, alpha1, alpha2)
        self.relaxation = relaxation_coefficients(ratio, material.poisson_ratio)
        self.law = self.point_law()
        self._steady_law = self.point_law(steady=True)
        self._law_entry = None  # the compiled law without numba's argument dispatch, made on first use

    def with_friction(self, friction: Friction) -> "PointContact":
        """The same model with another :class:`~contact.params.Friction`."""
        return PointContact(material=self.material, friction=friction, hertz=self.hertz, kind=self.kind,
                            speed=self.speed, time_step=self.time_step, tangential=self.tangential,
                            strip_width=self.strip_width)

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
        """High-frequency limit of the relaxation as tangential stiffnesses (kx, ky) (N/m) at a force (N).

        ``k = G a b C b_relax / a2``: the force per unit rigid tangential displacement when the
        creepage wavelength is much shorter than the contact (compare Mindlin's no-slip
        stiffness ``4 G sqrt(ab) / (2 - nu)`` of a circular contact).
        """
        h = self.hertz.scaled(normal_force)
        gab = self.material.shear_modulus * h.a * h.b
        (bx, _, a2x), (by, _, a2y) = self.relaxation_constants(normal_force)
        return gab * self.c11 * bx / a2x, gab * self.c22 * by / a2y

    def initial_state(self) -> PointState:
        """Zero effective creepages, auxiliary states and strip displacements."""
        return PointState(freeze(np.zeros(self.state_size)), 0)

    @property
    def state_size(self) -> int:
        """Length of the carried state (6 relaxation states plus 2 per strip element)."""
        return RELAXATION_STATES + 2 * self.law.strip_x.size * self.law.strip_y.size

    def point_law(self, steady=None) -> PointLaw:
        """The bundle of :func:`contact.point.kernels.point_contact_law` for this model.

        ``steady`` (default: ``kind == "steady"``) gives the steady creep law. The strip model's
        grid covers the Hertz patch at :data:`STRIP_LOAD_FACTOR` times the reference load plus
        10 %, with elements of the rolled distance per step along x.
        """
        steady = self.kind == "steady" if steady is None else steady
        h = self.hertz
        distance = float(self.speed * self.time_step)
        strip = self.tangential == "strip" and not steady
        if strip:
            peak = h.scaled(STRIP_LOAD_FACTOR * h.normal_force)
            grid = Grid.covering(peak.a, peak.b, dx=distance, dy=self.strip_width, margin=0.1)
            xs, ys = np.ascontiguousarray(grid.x[::-1], dtype=float), np.ascontiguousarray(grid.y, dtype=float)
        else:
            xs = ys = np.zeros(0)
        return PointLaw(float(h.normal_force), float(h.approach), float(self.material.shear_modulus),
                        float(h.a * h.b), float(self.c11), float(self.c22), float(self.c23),
                        float(self.friction.kinetic), distance, 0.0 if steady else float(h.a), float(h.b),
                        np.ascontiguousarray(self.relaxation, dtype=float),
                        STRIP if strip else RELAXATION, xs, ys, float(self.strip_width), STRIP_CREEP_FACTOR,
                        float(self.speed), scaled(self.friction.law(), 1.0))

    def compiled_path(self, static: ContactResult) -> CompiledPath:
        """The compiled time loop of the interaction with this model's :class:`PointLaw`.

        ``static`` (the solution at static equilibrium) is not needed: the loop starts from
        zero states, as :meth:`solve` does from :meth:`initial_state`.
        """
        return CompiledPath(loop=point_contact_loop, contact=self.law, state=np.zeros(self.state_size),
                            snapshot=lambda state: None)

    def steady_force(self, normal_force, creepage) -> np.ndarray:
        """Saturated steady creep force (Fx, Fy) (N) for creepages (xi, eta, phi).

        The steady creep law (Kalker's linear theory saturated by the Shen-Hedrick-Elkins law).
        The strip model reaches the same law after rolling through its patch, for xi and eta
        alone, with its coefficients times :data:`STRIP_CREEP_FACTOR`.
        """
        fn = float(normal_force)
        if fn <= 0.0:
            return np.zeros(2)
        approach = self.hertz.approach * (fn / self.hertz.normal_force) ** (2.0 / 3.0)
        xi, eta, phi = (float(c) for c in creepage)
        out = point_contact_law(self._steady_law, approach, xi, eta, phi, np.zeros(RELAXATION_STATES),
                                np.zeros(RELAXATION_STATES))
        return np.array(out[:2])

    def solve(self, state: PointState, *, approach=None, normal_force=None, creepage=(0.0, 0.0, 0.0),
              shift=None) -> ContactResult:
        """One step from ``state``; see :class:`~contact.model.ContactModel`."""
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
        else:
            fn = max(float(normal_force), 0.0)
            delta = h0.approach * (fn / h0.normal_force) ** (2.0 / 3.0) if fn > 0 else 0.0
        values = np.asarray(state.values, dtype=float)
        new = np.empty(self.state_size)
        if self._law_entry is None:
            self._law_entry = compiled_entry(point_contact_law, self.law, delta, xi, eta, phi, values, new)
        fx, fy, fn, slip = self._law_entry(self.law, delta, xi, eta, phi, values, new)
        new_state = PointState(freeze(new), state.step + 1)
        if fn <= 0.0:
            return ContactResult(np.zeros(3), 0.0, new_state, Diagnostics(0, 0, 0, 0.0, 0, 0.0, 0.0, delta))
        s = (fn / h0.normal_force) ** (1.0 / 3.0)
        saturated = slip >= 1.0 - 1e-12
        diag = Diagnostics(1, 0 if saturated else 1, 1 if saturated else 0, slip, 1, 0.0, h0.p0 * s, delta)
        return ContactResult(np.array((fx, fy, fn)), 0.0, new_state, diag)


def linearise_point_contact(contact, wheel_load, creepage, relative_step=1e-4):
    """Linearise a point-contact model about steady rolling at the wheel load and creepages.

    The slopes of the steady creep-force law (:meth:`PointContact.steady_force`: Kalker's
    linear theory with the saturation) are central differences with steps ``relative_step``
    times the load and times ``max(|ξ|, |η|, 1e-3)``; the normal stiffness is Hertz's
    ``3 Q / (2 δ(Q))``. In full sliding ``μ_s = ∓μ``, ``c_y = 0`` and
    ``c_x = μ Q c11 / (c22 |η|)`` (a longitudinal creepage turns the saturated force); below
    saturation ``μ_s`` is the load dependence of the creep force and ``c`` Kalker's slopes.

    Parameters
    ----------
    contact : PointContact
    wheel_load : float
        Q, N, > 0.
    creepage : (3,) sequence of float
        (ξ, η, φ), -, -, 1/m.
    relative_step : float
        Finite-difference step, -.

    Returns
    -------
    stability.linearised_contact.LinearisedContact
    """
    q = require_range("operating.wheel_load", wheel_load, 0.0, None, low_open=True, unit="N")
    friction = contact.friction
    if friction.characteristic != "constant":  # μ held at the operating point, then the slope term
        v = sliding_speed(contact.speed, creepage)
        mu = float(friction.coefficient(v))
        step = relative_step * mu
        force_per_friction = (contact.with_friction(Friction(mu + step)).steady_force(q, creepage)
                              - contact.with_friction(Friction(mu - step)).steady_force(q, creepage)) / (2 * step)
        frozen = linearise_point_contact(contact.with_friction(friction.frozen(v)), q, creepage, relative_step)
        return with_friction_slope(frozen, friction, contact.speed, creepage, force_per_friction)
    xi, eta, phi = (float(c) for c in creepage)
    k_n = 1.5 * q / contact.hertz.scaled(q).approach
    dq = relative_step * q
    law = contact.steady_force
    mu_s = (law(q + dq, (xi, eta, phi))[1] - law(q - dq, (xi, eta, phi))[1]) / (2 * dq)
    h = relative_step * max(abs(xi), abs(eta), 1e-3)
    c_x = -(law(q, (xi + h, eta, phi))[0] - law(q, (xi - h, eta, phi))[0]) / (2 * h)
    c_y = -(law(q, (xi, eta + h, phi))[1] - law(q, (xi, eta - h, phi))[1]) / (2 * h)
    force = law(q, (xi, eta, phi))
    bound = contact.friction.kinetic * q
    # a saturated law is flat: its differences are round-off, of either sign
    c_x, c_y = (max(c, 0.0) if c > -1e-6 * bound / h else c for c in (c_x, c_y))
    relaxation = contact.relaxation_constants(q) if contact.kind == "transient" else None
    return LinearisedContact(float(k_n), float(mu_s), (float(c_x), float(c_y)), relaxation,
                             float(np.hypot(*force) / bound) if bound > 0 else 1.0)


# --------------------------------------------------------------------------- registry hooks
# (contact/registry.py: how a study, the screen and the contact command use this model)

def for_study(setup) -> PointContact:
    """The transient point model of a case (:class:`~contact.registry.ContactSetup`),
    with the study's tangential law (``contact.point_tangential``) and strip width (``contact.grid_dy``)."""
    return PointContact(material=setup.material, friction=setup.friction, hertz=setup.hertz, kind="transient",
                        speed=setup.speed, time_step=setup.time_step, tangential=setup.options.point_tangential,
                        strip_width=setup.options.grid_dy)


def linearise_for_study(setup, normal_force, creepage):
    """The screen's linearisation: the steady creep law's slopes and the relaxation constants
    (:func:`linearise_point_contact`)."""
    model = PointContact(material=setup.material, friction=setup.friction, hertz=setup.hertz, kind="transient",
                         speed=setup.speed, time_step=setup.time_step)
    return linearise_point_contact(model, normal_force, creepage)


def for_command(setup, grid, gap, kind) -> PointContact:
    """The contact command's point model; its time step is the grid's rolled step unless the case gives one."""
    dt = grid.dx / setup.speed if setup.time_step is None else setup.time_step
    return PointContact(material=setup.material, friction=setup.friction, hertz=setup.hertz, kind=kind,
                        speed=setup.speed, time_step=dt)

