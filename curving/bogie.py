"""Quasi-static steady curving of a two-axle bogie: equilibrium, flange contacts, solution.

Unknowns (track frame of :mod:`curving.kinematics`; wheelset 1 leading at x = +b, wheelset 2
trailing at x = -b, b half the wheelbase):

* **rigid bogie**: the frame's lateral position y_b (mean of the wheelsets') and yaw ψ_b
  (relative to the radial direction at the bogie centre), and each wheelset's rotation ω_i;
  the wheelsets follow the frame, ``y_i = y_b + x_i ψ_b``, ``ψ_i = ψ_b + x_i / R``
  (so ``ψ_1 - ψ_2 = 2b / R`` exactly). Equations: the bogie's lateral force
  ``Σ F_y,i + 2 F_u = 0``, yaw moment about its centre ``Σ (M_z,i + x_i F_y,i) = 0`` and each
  wheelset's torque ``T_i = 0``;
* **primary suspension** (k_x, k_y per axle box, boxes at ±d): each wheelset's y_i, ψ_i, ω_i and
  the frame's y_b, ψ_b; the boxes pull wheelset i by ``-2 k_y (y_i - y_b - x_i ψ_b)`` and turn it by
  ``-2 k_x d² (ψ_i - ψ_b - x_i / R)``; equations: each wheelset's lateral force, yaw moment and
  torque, and the frame's lateral force (``2 F_u`` acts on the frame) and yaw moment (no yaw
  restraint from the body: the secondary suspension's yaw stiffness is neglected).

**Flange contact** (an active set): when a wheelset's displacement would pass the flangeway
clearance (``±y_f``), the flange's normal force N_f becomes an unknown and ``y_i = ±y_f`` an
equation; a flange whose N_f comes out negative is released. Solved by scipy's MINPACK hybrid
method on scaled unknowns (mm, mrad, 1e-3 of ω, 10 kN), with a continuation over the curvature
from straight track when the direct solve fails. The residuals in N and N m are reported.
"""

from __future__ import annotations

import logging
import math
from dataclasses import replace

import numpy as np
from scipy.optimize import root

from squealcore.errors import InputError

from .creep import CreepLaw
from .loads import axle_loads
from .params import CurvingParams
from .wheelset import SIDES, contact_record, wheelset_forces

logger = logging.getLogger(__name__)

__all__ = ["solve_bogie", "solve_wheelset", "RESIDUAL_TOLERANCE", "CurvingError"]

#: Largest residual accepted, relative to the axle load (forces) and to the axle load times l0 (moments).
RESIDUAL_TOLERANCE = 1e-8
_SCALE = (1e-3, 1e-3, 1e-3, 1e4)  # y (m), ψ (rad), ω - 1, N_f (N)
_MAX_ACTIVE_SET_ROUNDS = 8
_CONTINUATION_STEPS = (0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 0.85, 1.0)
WHEELSETS = ("leading", "trailing")


class CurvingError(RuntimeError):
    """The equilibrium was not found (the message says where)."""


class _Problem:
    """The equations of one bogie for one set of flanges in contact."""

    def __init__(self, params: CurvingParams, law: CreepLaw, active: tuple, single: bool = False):
        self.p = params
        self.law = law
        self.active = tuple(active)  # ((wheelset index, side), ...)
        self.loads = axle_loads(params)
        self.single = single
        self.b = params.semi_wheelbase
        self.x = (0.0,) if single else (self.b, -self.b)
        self.n = len(self.x)
        self.rigid = params.rigid and not single
        self.n_base = 3 if single else 4 if self.rigid else 8
        g = params.geometry
        self.force_scale = params.axle_load
        self.moment_scale = params.axle_load * g.contact_half_spacing

    # unknowns -> physical state -------------------------------------------------------------
    def unpack(self, u):
        y_s, a_s, w_s, f_s = _SCALE
        k = self.p.curvature
        if self.single:
            ys, psis, omega = (u[0] * y_s,), (u[1] * a_s,), (1.0 + u[2] * w_s,)
            yb, pb = ys[0], psis[0]
        elif self.rigid:
            yb, pb = u[0] * y_s, u[1] * a_s
            omega = (1.0 + u[2] * w_s, 1.0 + u[3] * w_s)
            ys = tuple(yb + xi * pb for xi in self.x)
            psis = tuple(pb + xi * k for xi in self.x)
        else:
            ys = (u[0] * y_s, u[3] * y_s)
            psis = (u[1] * a_s, u[4] * a_s)
            omega = (1.0 + u[2] * w_s, 1.0 + u[5] * w_s)
            yb, pb = u[6] * y_s, u[7] * a_s
        flange = [dict() for _ in range(self.n)]
        for j, (i, side) in enumerate(self.active):
            flange[i][side] = u[self.n_base + j] * f_s
        return ys, psis, omega, yb, pb, flange

    def pack(self, ys, psis, omega, yb, pb, flange):
        y_s, a_s, w_s, f_s = _SCALE
        if self.single:
            u = [ys[0] / y_s, psis[0] / a_s, (omega[0] - 1.0) / w_s]
        elif self.rigid:
            u = [yb / y_s, pb / a_s, (omega[0] - 1.0) / w_s, (omega[1] - 1.0) / w_s]
        else:
            u = [ys[0] / y_s, psis[0] / a_s, (omega[0] - 1.0) / w_s, ys[1] / y_s, psis[1] / a_s,
                 (omega[1] - 1.0) / w_s, yb / y_s, pb / a_s]
        for i, side in self.active:
            u.append(flange[i].get(side, 0.3 * self.p.axle_load) / f_s)
        return np.array(u, dtype=float)

    # forces ---------------------------------------------------------------------------------
    def wheelsets(self, u):
        ys, psis, omega, yb, pb, flange = self.unpack(u)
        p = self.p
        loads = (self.loads.outer, self.loads.inner)
        return [wheelset_forces(p.geometry, self.law, ys[i], psis[i], omega[i], p.curvature, loads, flange[i],
                                p.friction, p.flange_mu, p.spin) for i in range(self.n)], (ys, psis, omega, yb, pb, flange)

    def suspension(self, ys, psis, yb, pb):
        """Forces and moments of the primary suspension on each wheelset (N, N m)."""
        p = self.p
        if self.rigid:
            return (0.0, 0.0), (0.0, 0.0)
        ky, kpsi = 2.0 * p.lateral_stiffness, 2.0 * p.longitudinal_stiffness * p.axlebox_half_spacing ** 2
        f = tuple(-ky * (ys[i] - yb - self.x[i] * pb) for i in range(2))
        m = tuple(-kpsi * (psis[i] - pb - self.x[i] * p.curvature) for i in range(2))
        return f, m

    def residuals_physical(self, u):
        """(lateral forces (N), moments (N m), torques (N m), constraint gaps (m)) of the equations."""
        ws, (ys, psis, omega, yb, pb, flange) = self.wheelsets(u)
        fu2 = 2.0 * self.loads.unbalanced_force
        torques = [w.torque for w in ws]
        if self.single:
            forces = [ws[0].lateral_force + self.loads.unbalanced_force]
            moments = [ws[0].yaw_moment]
        elif self.rigid:
            forces = [ws[0].lateral_force + ws[1].lateral_force + fu2]
            moments = [sum(ws[i].yaw_moment + self.x[i] * ws[i].lateral_force for i in range(2))]
        else:
            fs, ms = self.suspension(ys, psis, yb, pb)
            forces = [ws[i].lateral_force + fs[i] for i in range(2)] + [fu2 - fs[0] - fs[1]]
            moments = [ws[i].yaw_moment + ms[i] for i in range(2)] + [
                -sum(ms[i] + self.x[i] * fs[i] for i in range(2))]
        gaps = [side * ys[i] - self.p.geometry.flange_limit for i, side in self.active]
        return forces, moments, torques, gaps

    def __call__(self, u):
        forces, moments, torques, gaps = self.residuals_physical(u)
        return np.array([f / self.force_scale for f in forces] + [m / self.moment_scale for m in moments]
                        + [t / self.moment_scale for t in torques] + [g / _SCALE[0] for g in gaps])


def _solve(params, law, active, start, single):
    """Solve for a fixed active set from ``start`` (physical state tuple); returns (problem, u, ok)."""
    prob = _Problem(params, law, active, single)
    u0 = prob.pack(*start)
    sol = root(prob, u0, method="hybr", options={"xtol": 1e-13, "maxfev": 4000})
    u = sol.x
    r = prob(u)
    ok = bool(np.all(np.isfinite(r)) and np.max(np.abs(r), initial=0.0) <= RESIDUAL_TOLERANCE)
    if not ok:
        sol2 = root(prob, u, method="lm", options={"xtol": 1e-14, "ftol": 1e-14, "maxiter": 4000})
        r2 = prob(sol2.x)
        if np.all(np.isfinite(r2)) and np.max(np.abs(r2)) < np.max(np.abs(r)):
            u, r = sol2.x, r2
        ok = bool(np.max(np.abs(r)) <= RESIDUAL_TOLERANCE)
    return prob, u, ok


def _active_set_solve(params, law, start, active=(), single=False):
    """Solve with flanges entering and leaving contact; returns (problem, u, ok).

    ``ok`` only for a consistent solution: residuals within tolerance, every flange in contact
    pressed (N_f >= 0) and no wheelset past a flange. A failed solve (e.g. a cylindrical wheelset
    without a flange in contact has no lateral stiffness) is retried with the leading wheelset's
    outer flange in contact, the usual state in a curve, and then with the flange of any wheelset
    it left past its flangeway clearance.
    """
    active = tuple(sorted(active))
    yf = params.geometry.flange_limit
    prob = u = None
    ok = False
    for _ in range(_MAX_ACTIVE_SET_ROUNDS):
        prob, u, ok = _solve(params, law, active, start, single)
        ys, psis, omega, yb, pb, flange = prob.unpack(u)
        if ok:
            new = [a for a in active if flange[a[0]][a[1]] >= 0.0]
            for i in range(prob.n):
                for side in (1, -1):
                    if (i, side) not in new and side * ys[i] > yf * (1.0 + 1e-9):
                        new.append((i, side))
            new = tuple(sorted(new))
            if new == active:
                return prob, u, True
            start = _clamped(prob, ys, psis, omega, yb, pb, flange)
        elif (0, 1) not in active:
            new = tuple(sorted(active + ((0, 1),)))
            start = _initial(params, single, flanging=True)
        else:
            # unconverged with a wheelset run past a flange (off the contact table, e.g. the trailing
            # wheelset under a large cant deficiency): put that flange in contact too and retry
            past = tuple((i, side) for i in range(prob.n) for side in (1, -1)
                         if (i, side) not in active and side * ys[i] > yf * (1.0 + 1e-9))
            if not past:
                break
            new = tuple(sorted(active + past))
            start = _clamped(prob, ys, psis, omega, yb, pb, flange)
        active = new
    return prob, u, False


def _clamped(prob, ys, psis, omega, yb, pb, flange):
    """A start for the next active set: the wheelsets moved back within their flanges (a moved one
    rolling at ω = 1 again: its rotation off the table is meaningless); for a rigid bogie the frame's
    position and yaw recomputed from them (its unknowns), the yaw ψ_b = (y_1 - y_2) / 2b."""
    yf = prob.p.geometry.flange_limit
    moved = tuple(abs(y) > yf for y in ys)
    ys = tuple(max(-yf, min(yf, y)) for y in ys)
    omega = tuple(1.0 if m else w for m, w in zip(moved, omega))
    if prob.rigid:
        yb, pb = 0.5 * (ys[0] + ys[1]), (ys[0] - ys[1]) / (2.0 * prob.b)
    return ys, psis, omega, yb, pb, flange


def _initial(params, single, flanging=False):
    """A first guess: centred and radial, or (``flanging``) the leading wheelset at its outer flange
    with the trailing one radial (leading angle of attack 2b / R), the usual flanging position."""
    yf = params.geometry.flange_limit
    if single:
        return ((yf if flanging else 0.0),), (0.0,), (1.0,), 0.0, 0.0, [dict()]
    b, k = params.semi_wheelbase, params.curvature
    if flanging:
        return (yf, yf - 2.0 * b * b * k), (2.0 * b * k, 0.0), (1.0, 1.0), yf - b * b * k, b * k, [dict(), dict()]
    return (0.0, 0.0), (b * k, -b * k), (1.0, 1.0), 0.0, 0.0, [dict(), dict()]


def _solve_bogie(params: CurvingParams, law: CreepLaw, single: bool = False):
    prob, u, ok = _active_set_solve(params, law, _initial(params, single), single=single)
    if ok:
        return prob, u
    logger.info("steady curving at R = %g m: direct solve failed, continuing over the curvature", params.radius)
    start, active = _initial(params, single), ()
    for frac in _CONTINUATION_STEPS:
        step = replace(params, radius=params.radius / frac) if frac < 1.0 else params
        prob, u, ok = _active_set_solve(step, law, start, active, single)
        if not ok:
            break
        ys, psis, omega, yb, pb, flange = prob.unpack(u)
        start, active = (ys, psis, omega, yb, pb, flange), prob.active
    if not ok:
        r = prob(u)
        raise CurvingError(f"no steady-curving equilibrium found at R = {params.radius:g} m, V = {params.speed:g} "
                           f"m/s (largest scaled residual {np.max(np.abs(r)):.3g})")
    return prob, u


def _num(v):
    v = float(v)
    return None if not math.isfinite(v) else v


def solve_bogie(params: CurvingParams) -> dict:
    """Quasi-static steady curving of a two-axle bogie (module docstring).

    Parameters
    ----------
    params : CurvingParams

    Returns
    -------
    dict
        JSON-ready, SI units: ``inputs``; ``loads`` (unbalanced force, cant deficiency, wheel
        loads); ``bogie`` (lateral displacement y_b, yaw ψ_b, rigid or not); ``wheelsets`` (per
        wheelset: position, lateral displacement, angle of attack, rotation ω, flanges in contact);
        ``wheels`` (per wheel: ``wheelset``, ``side``, wheel load, lateral force towards the field side,
        vertical force, flange force, derailment quotient, ``creepage`` of its main tread contact and
        ``contacts``: kind, load share, creepages [ξ, η, φ], contact angle, rolling radius, lateral
        arm, positions on wheel and rail, normal force, creep force [Fx, Fy] in the wheel's contact
        frame, Hertz semi-axes, friction use |F| / (μ N)); ``residuals`` (the largest lateral force,
        yaw moment and axle torque left, N and N m) and ``tolerance``.

    Raises
    ------
    InputError
        If ``params`` is not a :class:`CurvingParams`.
    CurvingError
        If no equilibrium is found.
    """
    return _report(params, single=False)


def solve_wheelset(params: CurvingParams) -> dict:
    """Quasi-static steady curving of one free wheelset (no suspension, no frame).

    Its lateral force (with the unbalanced force ``F_u`` of one axle), yaw moment and axle torque
    vanish; ``params``' wheelbase and stiffnesses are not used. Returns the dict of
    :func:`solve_bogie` with one wheelset, ``"single"``, and two wheels.
    """
    return _report(params, single=True)


def _report(params: CurvingParams, single: bool) -> dict:
    if not isinstance(params, CurvingParams):
        raise InputError("curving", f"expected CurvingParams, got {type(params).__name__}")
    law = CreepLaw()
    prob, u = _solve_bogie(params, law, single)
    labels = ("single",) if single else WHEELSETS
    ws, (ys, psis, omega, yb, pb, flange) = prob.wheelsets(u)
    forces, moments, torques, gaps = prob.residuals_physical(u)
    loads = prob.loads
    wheels = []
    for i, w in enumerate(ws):
        for wheel in w.wheels:
            treads = [c for c in wheel.contacts if c.geometry.kind == "tread"]
            main = max(treads, key=lambda c: c.share)
            vertical = wheel.vertical_force
            wheels.append({
                "wheelset": labels[i], "side": SIDES[wheel.side], "wheel_load": wheel.load,
                "lateral_force": wheel.field_force, "vertical_force": vertical,
                "flange_force": wheel.flange_force,
                "derailment_quotient": -wheel.field_force / vertical if vertical > 0 else None,
                "creepage": list(main.creepage), "contact_angle": main.geometry.contact_angle,
                "contacts": [contact_record(c, law) for c in wheel.contacts]})
    p = params
    out = {
        "inputs": {"radius": _num(p.radius), "speed": p.speed, "cant": p.cant, "cant_angle": p.cant_angle,
                   "wheelbase": p.wheelbase, "axle_load": p.axle_load,
                   "centre_of_gravity_height": p.centre_of_gravity_height,
                   "longitudinal_stiffness": _num(p.longitudinal_stiffness),
                   "lateral_stiffness": _num(p.lateral_stiffness), "axlebox_half_spacing": p.axlebox_half_spacing,
                   "friction": p.friction, "flange_friction": p.flange_mu, "spin": p.spin,
                   "geometry": p.geometry.describe(),
                   "creep_law": "contact.point.model.PointContact.steady_force (Kalker linear theory "
                                "saturated by Shen-Hedrick-Elkins)"},
        "loads": {"unbalanced_force": loads.unbalanced_force, "lateral_acceleration": loads.lateral_acceleration,
                  "cant_deficiency": loads.cant_deficiency, "normal_load": loads.normal_load,
                  "outer_wheel_load": loads.outer, "inner_wheel_load": loads.inner},
        "bogie": None if single else {"rigid": p.rigid, "lateral_displacement": yb, "yaw": pb},
        "wheelsets": [{"position": labels[i], "lateral_displacement": ys[i], "angle_of_attack": psis[i],
                       "rotation": omega[i], "flange_contact": [SIDES[s] for s in sorted(flange[i], reverse=True)],
                       "flange_normal_force": {SIDES[s]: n for s, n in flange[i].items()}} for i in range(prob.n)],
        "wheels": wheels,
        "residuals": {"lateral_force": max(abs(f) for f in forces), "yaw_moment": max(abs(m) for m in moments),
                      "axle_torque": max(abs(t) for t in torques),
                      "flange_gap": max((abs(g) for g in gaps), default=0.0)},
        "tolerance": {"force": RESIDUAL_TOLERANCE * prob.force_scale,
                      "moment": RESIDUAL_TOLERANCE * prob.moment_scale},
    }
    return out
