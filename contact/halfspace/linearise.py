r"""The half-space contact linearised about steady rolling, for the linear stability screen.

The screen (:func:`stability.screen.screen`) takes the contact as a
:class:`stability.linearised_contact.LinearisedContact`: normal stiffness ``k_n = dF_z/dδ``, the
load dependence of the lateral force at constant creepage ``μ_s = ∂F_y/∂F_z``, the creep
slopes ``c_x = -∂F_x/∂ξ``, ``c_y = -∂F_y/∂η``, the saturation ``|F_t| / (μ F_z)`` and the
creep relaxation. :func:`linearise_halfspace_contact` takes them from the half-space model
(:class:`contact.halfspace.model.HalfspaceContact`) on the grid it is given:

* ``k_n``: central difference of the normal solver's force against the approach
  (:func:`contact.halfspace.normal.solve_normal`) about the approach at the wheel load; for a
  Hertzian gap it equals Hertz's ``3 Q / (2 δ)`` to within the grid's discretisation error
  (tests/test_linearise_halfspace.py);
* ``c_x``, ``c_y`` and the saturation: central differences of the STEADY rolling solution
  (:mod:`contact.halfspace.steady`, through ``HalfspaceContact(kind="steady")``) in ξ and η,
  steps ``relative_step`` times ``max(|ξ|, |η|, 1e-3)``; ``μ_s`` from them and the force by
  Hertz's similarity (:func:`steady_jacobian`: load steps on a fixed grid are dominated by the
  contact edge crossing elements). In partial slip the discrete solution switches
  elements between stick and slip as the creepage changes, so the differences are of
  a piecewise smooth function: the step must span a few such switches (the default 1e-2 was
  chosen from the step study in ``benchmarks/halfspace_screen.py``);
* relaxation: the caller passes the point model's relaxation constants of the same semi-axes
  (:meth:`contact.point.model.PointContact.relaxation_constants`), fitted to this model's
  linear (no-slip) transient rolling (:mod:`contact.point.fit_relaxation`); in partial
  slip their lengths are shortened to the stick area's (:func:`stick_scaled_relaxation`): the
  no-slip relaxation would take the creep damping away where the partial-slip contact keeps it
  (measured with :func:`transient_creep_response`, docs/results.md).

The closed loop uses no cross slopes (∂F_x/∂η, ∂F_y/∂ξ, the spin's slopes) and no change of
the tangential force's direction; :func:`steady_jacobian` gives the full 2 × 3 Jacobian of the
steady law for diagnostics.
"""

from __future__ import annotations

import hashlib
import logging
import math
from dataclasses import replace
from typing import NamedTuple

import numpy as np

from squealcore.errors import InputError, require_range
from stability.linearised_contact import LinearisedContact, sliding_speed, with_friction_slope

from contact.halfspace.model import HalfspaceContact, for_study
from contact.model import freeze
from contact.halfspace.normal import solve_normal
from contact.params import Friction
from contact.point.model import PointContact

logger = logging.getLogger(__name__)

__all__ = [
    "DEFAULT_RELATIVE_STEP",
    "SteadyJacobian",
    "cached_linearisation",
    "check_hertzian",
    "linearise_halfspace_contact",
    "no_slip_slopes",
    "normal_stiffness",
    "steady_jacobian",
    "steady_twin",
    "stick_scaled_relaxation",
    "transient_creep_response",
]

#: Relative finite-difference step of the creepages and the approach (see the module docstring).
DEFAULT_RELATIVE_STEP = 1e-2
#: Smallest creepage scale of the creepage steps, -.
MIN_CREEPAGE_SCALE = 1e-3
#: Relative tolerance of the steady solutions the slopes are differences of (the solver's error
#: then enters a slope at about 1e-9 / (2 relative_step), far below the grid's error).
STEADY_TOLERANCE = 1e-9


def steady_twin(model: HalfspaceContact, tol=STEADY_TOLERANCE) -> HalfspaceContact:
    """The steady-rolling model on the grid, gap, material and friction of ``model``.

    Parameters
    ----------
    model : HalfspaceContact
        Any kind (the time domain's is transient).
    tol : float
        Relative tolerance of its solvers, -.

    Returns
    -------
    HalfspaceContact
        ``kind="steady"`` (``model`` itself when it is steady with that tolerance).
    """
    if not isinstance(model, HalfspaceContact):
        raise InputError("contact.model", f"the half-space linearisation takes a HalfspaceContact, "
                                          f"got {type(model).__name__}")
    if model.kind == "steady" and model.tol == tol:
        return model
    return HalfspaceContact(material=model.material, friction=model.friction, grid=model.grid, gap=model.gap,
                            kind="steady", speed=model.speed, tol=tol, max_sweeps=model.max_sweeps)


def normal_stiffness(model: HalfspaceContact, wheel_load, relative_step=DEFAULT_RELATIVE_STEP):
    """``dF_z/dδ`` (N/m) of the half-space normal problem at the wheel load.

    The approach δ0 at ``wheel_load`` is solved for, then the force at ``δ0 (1 ± relative_step)``
    (prescribed approach, FFT products on grids of at least
    :data:`~contact.halfspace.normal.FFT_MIN_ELEMENTS`: the direct products' solution to the
    tolerance); the slope is their central difference. Computed once per normal problem (grid,
    gap, material, tolerance), load and step in this process (:func:`_load_cached`): it does not
    depend on the friction or the creepage.

    Parameters
    ----------
    model : HalfspaceContact
    wheel_load : float
        Q, N, > 0.
    relative_step : float
        Step of the approach relative to δ0, in (0, 0.5).

    Returns
    -------
    stiffness : float
        N/m.
    approach : float
        δ0, m.
    """
    q = require_range("operating.wheel_load", wheel_load, 0.0, None, low_open=True, unit="N")
    step = require_range("relative_step", relative_step, 0.0, 0.5, low_open=True, high_open=True)
    return _load_cached("normal", model, q, step, lambda: _normal_stiffness(model, q, step))


def _normal_stiffness(model, q, step):
    tol = min(model.tol, STEADY_TOLERANCE)
    at_load = _normal_at_load(model, q)
    delta = float(at_load.approach)
    up, down = (solve_normal(model.kernels, model.gap, approach=delta * (1.0 + s), p_init=at_load.pressure,
                             tol=tol, full_displacement=False, fft=True) for s in (step, -step))
    return float((up.normal_force - down.normal_force) / (2.0 * step * delta)), delta


def _normal_at_load(model, q):
    """The normal solution at the load ``q`` (N) of the steady solutions' normal problem (the model's
    grid, gap and material at :data:`STEADY_TOLERANCE`), solved once per normal problem and load
    (:func:`_load_cached`): the normal stiffness, the steady Jacobian and the no-slip slopes start
    from it instead of each solving it again (the same call, so the same solution to the bit)."""
    tol = min(model.tol, STEADY_TOLERANCE)

    def solve():
        at_load = solve_normal(model.kernels, model.gap, normal_force=q, tol=tol, full_displacement=False)
        return replace(at_load, pressure=freeze(at_load.pressure), displacement=freeze(at_load.displacement))

    return _load_cached("normal solution", model, q, 0.0, solve, tol=tol)


def _loaded_start(model: HalfspaceContact, q):
    """The unloaded :meth:`~HalfspaceContact.initial_state` of a steady ``model`` but carrying its
    normal solution at the load ``q`` (:func:`_normal_at_load`), which its :meth:`solve` at that
    load then takes instead of solving the normal problem."""
    start = model.initial_state()
    at_load = _normal_at_load(model, q)
    return replace(start, pressure=at_load.pressure, normal=((model.normal_problem_key, q, None, 0.0), at_load))


#: Results of :func:`normal_stiffness` and :func:`no_slip_slopes` kept by :func:`_load_cached`.
LOAD_CACHE_SIZE = 512
_LOAD_CACHE = {}


def _load_cached(kind, model, load, step, compute, tol=None):
    """``compute()`` once per ``kind``, normal problem of ``model`` (material, grid, gap, tolerance:
    the model's, or ``tol`` when the computation uses another), load and step in this process:
    what depends on neither the friction nor the creepage (a map's configurations of one contact
    and load, at several friction coefficients or creepages, share it)."""
    gap = hashlib.sha256(np.ascontiguousarray(model.gap).tobytes()).hexdigest()
    key = (kind, model.material, model.grid, gap, float(model.tol if tol is None else tol), float(load), float(step))
    if key not in _LOAD_CACHE:
        if len(_LOAD_CACHE) >= LOAD_CACHE_SIZE:
            _LOAD_CACHE.pop(next(iter(_LOAD_CACHE)))
        _LOAD_CACHE[key] = compute()
    return _LOAD_CACHE[key]


def check_hertzian(model: HalfspaceContact, tolerance=1e-9):
    """Raise :class:`InputError` (``contact.gap``) unless the model's gap is ``A x² + B y²`` (to
    ``tolerance`` of its largest value): the load slope's similarity law (:func:`steady_jacobian`)
    holds for such a gap only."""
    x, y = np.meshgrid(model.grid.x, model.grid.y, indexing="ij")
    basis = np.column_stack([(x**2).ravel(), (y**2).ravel()])
    gap = np.asarray(model.gap, float).ravel()
    coef, *_ = np.linalg.lstsq(basis, gap, rcond=None)
    if np.abs(basis @ coef - gap).max() > tolerance * np.abs(gap).max():
        raise InputError("contact.gap", "the half-space linearisation needs a Hertzian gap A x^2 + B y^2 "
                                        "(its load slope uses Hertz's similarity)")


class SteadyJacobian(NamedTuple):
    """The steady creep-force law of a contact about one operating point.

    Attributes
    ----------
    force : (3,) ndarray
        (F_x, F_y, F_z) at the operating point, N.
    load_slope : (2,) ndarray
        ∂(F_x, F_y)/∂F_z at constant creepage, -, from Hertz's similarity (:func:`steady_jacobian`).
    creep_slope : (2, 3) ndarray
        ∂(F_x, F_y)/∂(ξ, η, φ), N, N, N m.
    slip_fraction : float
        Elements in slip over elements in contact at the operating point, -.
    """

    force: np.ndarray
    load_slope: np.ndarray
    creep_slope: np.ndarray
    slip_fraction: float


def steady_jacobian(model: HalfspaceContact, wheel_load, creepage, relative_step=DEFAULT_RELATIVE_STEP,
                    spin=True):
    r"""Central differences of the steady half-space creep forces about ``(wheel_load, creepage)``.

    The load slope at constant creepage is not a difference in the load: on a fixed grid a load
    step moves the contact's edge across elements, and such differences scatter by ±20 % about
    the slope (measured on 30 × 30 and 40 × 40 grids, steps 1-10 %). It follows instead from the
    similarity of the Hertzian problem: with lengths scaled by ``s = (Q'/Q)^{1/3}`` the pressure
    scales by s, the elastic displacement by s², the rigid slip ``(ξ - φ y, η + φ x)`` by 1 when
    ξ, η are divided by s (φ unchanged), so ``F(Q', ξ, η, φ) = (Q'/Q) F(Q, ξ/s, η/s, φ)`` and

    .. math::

        \frac{\partial F}{\partial Q} = \frac{F}{Q}
            - \frac{ξ\, ∂F/∂ξ + η\, ∂F/∂η}{3 Q}

    (exact for a quadratic gap, which :func:`check_hertzian` asks for; tested on grids scaled
    by s in tests/test_linearise_halfspace.py). No slip: ``(2/3) F / Q``; full sliding: ``F / Q``.

    Parameters
    ----------
    model : HalfspaceContact
        Solved as :func:`steady_twin` of it.
    wheel_load : float
        Q, N, > 0 (the normal force).
    creepage : (3,) sequence of float
        (ξ, η, φ), -, -, 1/m.
    relative_step : float
        Steps: ``relative_step max(|ξ|, |η|, 1e-3)`` for ξ and η,
        ``relative_step max(|φ|, 1e-3 / a_x)`` for φ (a_x: half the grid's length), in (0, 0.5).
    spin : bool
        Whether to difference in φ too (two solutions more); else the φ column is NaN.

    Returns
    -------
    SteadyJacobian
    """
    q = require_range("operating.wheel_load", wheel_load, 0.0, None, low_open=True, unit="N")
    step = require_range("relative_step", relative_step, 0.0, 0.5, low_open=True, high_open=True)
    try:
        xi, eta, phi = (float(c) for c in creepage)
    except (TypeError, ValueError):
        raise InputError("contact.creepage", f"must be (xi, eta, phi), got {creepage!r}") from None
    check_hertzian(model)
    steady = steady_twin(model)
    start = _loaded_start(steady, q)
    centre = steady.solve(start, normal_force=q, creepage=(xi, eta, phi))

    def force(load, c):
        return steady.solve(start, normal_force=load, creepage=c, initial=centre.new_state).force[:2]

    creep_slope = np.full((2, 3), np.nan)
    scale = step * max(abs(xi), abs(eta), MIN_CREEPAGE_SCALE)
    half_length = 0.5 * steady.grid.nx * steady.grid.dx
    steps = (scale, scale, step * max(abs(phi), MIN_CREEPAGE_SCALE / half_length))
    for j in range(3 if spin else 2):
        plus, minus = [xi, eta, phi], [xi, eta, phi]
        plus[j] += steps[j]
        minus[j] -= steps[j]
        creep_slope[:, j] = (force(q, tuple(plus)) - force(q, tuple(minus))) / (2.0 * steps[j])
    total = np.asarray(centre.force, float)
    load_slope = total[:2] / q - (xi * creep_slope[:, 0] + eta * creep_slope[:, 1]) / (3.0 * q)
    return SteadyJacobian(total, load_slope, creep_slope,
                          float(centre.diagnostics.slip_fraction))


#: Smallest scale of the relaxation lengths (:func:`stick_scaled_relaxation`), -.
MIN_RELAXATION_SCALE = 1e-3
#: Friction coefficient of the no-slip (linear) solutions, as contact/point/fit_relaxation.py.
NO_SLIP_FRICTION = 1e3


def no_slip_slopes(model: HalfspaceContact, wheel_load):
    """Kalker's linear creep slopes ``(c_x0, c_y0) = (-F_x/ξ, -F_y/η)`` (N) of the steady half-space
    without slip (friction :data:`NO_SLIP_FRICTION`) at the wheel load, on the model's grid
    (once per normal problem and load in this process, :func:`_load_cached`)."""
    q = require_range("operating.wheel_load", wheel_load, 0.0, None, low_open=True, unit="N")
    return _load_cached("no slip", model, q, 0.0, lambda: _no_slip_slopes(model, q))


def _no_slip_slopes(model, q):
    twin = steady_twin(model)
    linear = HalfspaceContact(material=twin.material, friction=Friction(NO_SLIP_FRICTION), grid=twin.grid,
                              gap=twin.gap, kind="steady", speed=twin.speed, tol=twin.tol, max_sweeps=twin.max_sweeps)
    h = MIN_CREEPAGE_SCALE
    start = _loaded_start(linear, q)
    fx = linear.solve(start, normal_force=q, creepage=(h, 0.0, 0.0)).force[0]
    fy = linear.solve(start, normal_force=q, creepage=(0.0, h, 0.0)).force[1]
    return -float(fx) / h, -float(fy) / h


def stick_scaled_relaxation(relaxation, creep_stiffness, no_slip_stiffness):
    r"""The no-slip relaxation shortened to the stick area of a contact in partial slip.

    In partial slip only the stick area (at the leading edge) responds elastically to a small
    change of creepage; the slip area's tractions stay on the friction bound. In the theory of
    Vermeulen and Johnson (J. Appl. Mech. 31, 1964; the saturation law of the point model) the
    stick area is an ellipse similar to the contact's, of relative size ``1 - ψ``, and the creep
    slope is the no-slip one times ``(1 - ψ)²``. So a direction j whose slope is ``κ_j = c_j /
    c_j0`` of the no-slip slope responds like a no-slip contact of semi-axes ``√κ_j`` times the
    contact's: its relaxation lengths are scaled by ``s_j = √min(κ_j, 1)`` (b, a1 by s_j, a2 by
    s_j²). No slip: unchanged; full sliding: no relaxation left (the force follows the slip).

    Parameters
    ----------
    relaxation : (2, 3) array_like
        Rows x, y: (b (m), a1 (m), a2 (m²)) of the no-slip contact.
    creep_stiffness, no_slip_stiffness : (2,) sequence of float
        (c_x, c_y) at the operating point and without slip, N.

    Returns
    -------
    (2, 3) ndarray
    """
    out = np.array(relaxation, float)
    for j in range(2):
        kappa = creep_stiffness[j] / no_slip_stiffness[j] if no_slip_stiffness[j] > 0 else 1.0
        scale = math.sqrt(min(max(kappa, 0.0), 1.0))
        # the loop needs a2 > 0: at least MIN_RELAXATION_SCALE, whose relaxation poles (~ V / (s a1))
        # lie far above any band of the screen
        scale = max(scale, MIN_RELAXATION_SCALE)
        out[j] *= (scale, scale, scale * scale)
    return out


def linearise_halfspace_contact(model: HalfspaceContact, wheel_load, creepage, relaxation=None,
                                relative_step=DEFAULT_RELATIVE_STEP, stick_relaxation=True) -> LinearisedContact:
    """Linearise the half-space contact about steady rolling at the wheel load and creepages.

    Parameters
    ----------
    model : HalfspaceContact
        The contact on its grid (any kind; its steady twin is solved, :func:`steady_twin`).
    wheel_load : float
        Q, N, > 0: the normal force.
    creepage : (3,) sequence of float
        (ξ, η, φ), -, -, 1/m.
    relaxation : (2, 3) array_like, optional
        Rows x, y: (b (m), a1 (m), a2 (m²)) of the creep relaxation (the point model's of the
        same semi-axes); None: a steady law.
    relative_step : float
        Finite-difference step, - (:func:`steady_jacobian`, :func:`normal_stiffness`).
    stick_relaxation : bool
        Shorten the relaxation to the stick area (:func:`stick_scaled_relaxation`, with the
        no-slip slopes of :func:`no_slip_slopes`); False: the no-slip relaxation as given.

    Returns
    -------
    LinearisedContact
        ``normal_stiffness`` from :func:`normal_stiffness`; ``sliding_coefficient`` ∂F_y/∂F_z,
        ``creep_stiffness`` (-∂F_x/∂ξ, -∂F_y/∂η) and ``saturation`` |F_t| / (μ_k F_z) from
        :func:`steady_jacobian`. A slope of a saturated law is round-off of either sign: a
        negative creep slope smaller than ``1e-6 μ Q / step`` is set to 0 (as
        :func:`contact.point.model.linearise_point_contact` does). A friction characteristic of
        the sliding speed: μ held at its value at ``V |(ξ, η)|`` and the slope term of
        :func:`~stability.linearised_contact.with_friction_slope` added, with ``∂F/∂μ = F/μ``
        (exact in full sliding; an upper bound of its size in partial slip).
    """
    friction = model.friction  # a characteristic: μ held at the operating point, its slope term added at the end
    if friction.characteristic != "constant":
        model = model.with_friction(friction.frozen(sliding_speed(model.speed, creepage)))
    jac = steady_jacobian(model, wheel_load, creepage, relative_step, spin=False)
    k_n, _ = normal_stiffness(model, wheel_load, relative_step)
    q = float(wheel_load)
    xi, eta, _ = (float(c) for c in creepage)
    h = relative_step * max(abs(xi), abs(eta), MIN_CREEPAGE_SCALE)
    bound = model.friction.kinetic * q
    slopes = (-jac.creep_slope[0, 0], -jac.creep_slope[1, 1])
    c_x, c_y = (max(c, 0.0) if c > -1e-6 * bound / h else c for c in slopes)
    if relaxation is not None:
        relaxation = np.asarray(relaxation, float)
        if relaxation.shape != (2, 3):
            raise InputError("contact.relaxation", f"must have shape (2, 3), got {relaxation.shape}")
        if stick_relaxation:
            relaxation = stick_scaled_relaxation(relaxation, (c_x, c_y), no_slip_slopes(model, q))
    saturation = float(np.hypot(*jac.force[:2]) / bound) if bound > 0 else 1.0
    logger.debug("half-space linearised at Q = %.6g N, creepage %s: k_n %.6g N/m, mu_s %.6g, c %.6g, %.6g N, "
                 "saturation %.4f, slip fraction %.3f", q, tuple(creepage), k_n, jac.load_slope[1], c_x, c_y,
                 saturation, jac.slip_fraction)
    return with_friction_slope(LinearisedContact(float(k_n), float(jac.load_slope[1]), (float(c_x), float(c_y)),
                                                 relaxation, saturation),
                               friction, model.speed, creepage, jac.force[:2] / model.friction.kinetic)


#: Linearisations kept by :func:`cached_linearisation` (a map has a few distinct contacts).
CACHE_SIZE = 256
_CACHE = {}


def _model_key(model: HalfspaceContact):
    gap = hashlib.sha256(np.ascontiguousarray(model.gap).tobytes()).hexdigest()
    return (model.material, model.friction, model.grid, gap)


def cached_linearisation(model: HalfspaceContact, wheel_load, creepage, relaxation=None,
                         relative_step=DEFAULT_RELATIVE_STEP, stick_relaxation=True) -> LinearisedContact:
    """:func:`linearise_halfspace_contact`, computed once per distinct model (grid, gap, material,
    friction), load, creepage, relaxation and step in this process (the screen of a map meets
    few distinct ones: the steady solution does not depend on the speed but through the grid)."""
    rel = None if relaxation is None else np.asarray(relaxation, float).tobytes()
    key = (_model_key(model), float(wheel_load), tuple(float(c) for c in creepage), rel, float(relative_step),
           bool(stick_relaxation))
    if key not in _CACHE:
        if len(_CACHE) >= CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
        _CACHE[key] = linearise_halfspace_contact(model, wheel_load, creepage, relaxation, relative_step,
                                                  stick_relaxation)
    return _CACHE[key]


def transient_creep_response(model: HalfspaceContact, wheel_load, creepage, frequency, component=1,
                             amplitude=1e-5, periods=8, settle=3.0):
    """The small-signal creep force of the transient half-space at one frequency, about steady rolling.

    The contact rolls from its steady solution (:func:`steady_twin` of the model, tolerance
    :data:`STEADY_TOLERANCE`) with the creepage ``component`` modulated by
    ``amplitude sin(2π f t)`` (one element rolled per step, ``t = n dx / V``); the force
    component's response over the last ``periods`` whole periods (after ``settle`` grid lengths
    of rolling) is fitted by a sinusoid. The ratio is the measured counterpart of the screen's
    ``-c W(iω)`` (creep slope times the relaxation's transfer function).

    Parameters
    ----------
    model : HalfspaceContact
        Transient (its grid's dx and speed set the step).
    wheel_load : float
        Normal force, N, > 0.
    creepage : (3,) sequence of float
        (ξ, η, φ) of the steady state, -, -, 1/m.
    frequency : float
        Hz, > 0.
    component : {0, 1}
        The creepage and force component (0: ξ and F_x, 1: η and F_y).
    amplitude : float
        Creepage amplitude, -.
    periods : int
        Periods fitted.
    settle : float
        Grid lengths rolled before the fit window.

    Returns
    -------
    complex
        ``ΔF / Δγ`` (N per unit creepage): output ``Im(r ε e^{iωt})`` for input ``Im(ε e^{iωt})``.
    """
    if model.kind != "transient":
        raise InputError("contact.kind", f"the response is of the transient model, got {model.kind!r}")
    f = require_range("frequency", frequency, 0.0, None, low_open=True, unit="Hz")
    base = [float(c) for c in creepage]
    steady = steady_twin(model)
    state = steady.solve(steady.initial_state(), normal_force=wheel_load, creepage=tuple(base)).new_state
    transient = HalfspaceContact(material=model.material, friction=model.friction, grid=model.grid, gap=model.gap,
                                 kind="transient", speed=model.speed, tol=STEADY_TOLERANCE,
                                 max_sweeps=model.max_sweeps)
    dt = transient.time_step
    per_period = 1.0 / (f * dt)
    first = int(np.ceil(settle * model.grid.nx))
    count = int(np.ceil(periods * per_period))
    n = np.arange(first + count)
    # step n rolls over t in (n dt, (n + 1) dt]: its creepage is the input at the middle of the
    # step (the step's mean to O((ω dt)²)), its force the output at the end
    phase_in = 2.0 * np.pi * f * dt * (n + 0.5)
    phase_out = 2.0 * np.pi * f * dt * (n + 1.0)
    force = np.empty(n.size)
    for k in n:
        c = list(base)
        c[component] += amplitude * np.sin(phase_in[k])
        result = transient.solve(state, normal_force=wheel_load, creepage=tuple(c))
        state = result.new_state
        force[k] = result.force[component]
    window = slice(first, first + count)
    design = np.column_stack([np.sin(phase_out[window]), np.cos(phase_out[window]), np.ones(count)])
    (s, c, _), *_ = np.linalg.lstsq(design, force[window], rcond=None)
    return complex(s, c) / amplitude


def linearise_for_study(setup, normal_force, creepage) -> LinearisedContact:
    """The screen's linearisation of the half-space model (registry hook): the steady half-space
    on the case's grid (:func:`cached_linearisation`, once per distinct contact), with the point
    model's relaxation constants for the creep dynamics."""
    relaxation = PointContact(material=setup.material, friction=setup.friction, hertz=setup.hertz, kind="transient",
                              speed=setup.speed, time_step=setup.time_step).relaxation_constants(normal_force)
    return cached_linearisation(for_study(setup), normal_force, creepage, relaxation)

