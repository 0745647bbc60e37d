"""Linear theory of steady curving by creep forces: the reference of the solver's creep-controlled regime.

The theory of Boocock (*Steady-state motion of railway vehicles on curved track*, J. Mech. Eng.
Sci. 11 (1969) 556–566; also in Wickens, *Fundamentals of Rail Vehicle Dynamics*, and in Iwnicki
(ed.), *Handbook of Railway Vehicle Dynamics*, the curving chapter), derived here for the
conical wheelset of :class:`curving.geometry.ConicalGeometry` in the frames of
:mod:`curving.kinematics` (x along the track, y towards the outer rail, ψ > 0 the heading turned
towards the outer rail; wheel s = +1 outer, -1 inner). It is independent of the solver
(:mod:`curving.bogie`): Kalker's linear law without saturation, linearised kinematics, and a
small linear system solved by :func:`numpy.linalg.solve` (or the closed forms below). Spin is
left out (``CurvingParams.spin = False`` in the comparisons).

**Wheelset.** Cone of conicity λ (contact angle δ = atan λ on both wheels), rolling radius r0,
contacts at ±l0, wheel loads Q_o, Q_i normal to the track plane and Kalker's coefficients per
wheel ``f11 = G a b C11``, ``f22 = G a b C22`` (Hertz semi-axes a, b at ``N = Q / cos δ``). The
wheelset turns at V / R about the curve's centre and rotates at ``(1 + w) V / r0``; to first order

* longitudinal creepage of wheel s: ``ξ_s = s (l0 / R - λ y / r0) - w`` (its contact, at s l0,
  is carried forward at V (1 + s l0 / R), its rolling surface moves back at V (1 + w)(1 + s λ y / r0));
* lateral creepage (wheel frame, y towards its field side): ``η_s = -s ψ cos δ`` (the yawed
  wheelset rolls along its heading, its material slips sideways at -V ψ).

The creep forces on wheel s are ``T_s = -f11 ξ_s`` (longitudinal) and ``F_s = -f22 η_s`` (in the
contact plane, towards its field side); the normal force N_s follows from the load,
``N_s cos δ + F_s sin δ = Q_s``. The rail's lateral force on the wheelset (track plane, towards the
outer rail) is ``Σ s (F_s cos δ - N_s sin δ) = Σ s (F_s / cos δ - Q_s tan δ)``, so

    F_lat = F22 ψ - (Q_o - Q_i) tan δ,        F22 = f22_o + f22_i,

exactly in the linear law (the normal forces' share of the lateral creep force makes cos² δ +
sin² δ = 1; on a cone of constant δ there is no gravitational stiffness, only the load
transfer's term). No axle torque, ``Σ T_s r0 = 0``, gives ``w = a (f11_o - f11_i) / (f11_o + f11_i)``
with ``a = l0 / R - λ y / r0``; the yaw moment of the longitudinal forces (a forward force on the
inner wheel turns the heading outwards), ``M = -l0 Σ s T_s``, is then

    M = K (l0 / R - λ y / r0),        K = l0 F11,  F11 = 4 f11_o f11_i / (f11_o + f11_i)

(F11 = 2 f11 for equal loads).

**Bogie.** Wheelsets at x_1 = +b (leading), x_2 = -b; per axle the unbalanced force
``F_u = P (V² / (g R) cos θ - sin θ)`` on the frame and the load transfer ``Q_o - Q_i = F_u h / l0``.

* *Rigid* (``y_i = y_b + x_i ψ_b``, ``ψ_i = ψ_b + x_i / R``): the lateral balance
  ``Σ F_lat,i + 2 F_u = 0`` and the yaw balance ``Σ (M_i + x_i F_lat,i) = 0`` give

      ψ_b = -(F_u - (Q_o - Q_i) tan δ) / F22,
      y_b = (r0 l0 / (λ R)) (1 + F22 b² / (F11 l0²)),

  Boocock's result: the wheelsets take ±b / R (plus ψ_b) and run outside the pure-rolling line
  by the factor ``1 + (f22 / f11)(b / l0)²``, so that the longitudinal creep forces balance the
  moment of the lateral ones.
* *Primary yaw and lateral stiffness* (per axle box k_x, k_y; ``k_ψ = 2 k_x d²``, ``k_l = 2 k_y``):
  each wheelset ``F_lat,i - k_l (y_i - y_b - x_i ψ_b) = 0`` and ``M_i - k_ψ (ψ_i - ψ_b - x_i / R) = 0``,
  the frame ``2 F_u + Σ k_l (y_i - y_b - x_i ψ_b) = 0`` and
  ``Σ [k_ψ (ψ_i - ψ_b - x_i / R) + x_i k_l (y_i - y_b - x_i ψ_b)] = 0`` (no yaw restraint from the
  body): six linear equations. Without a cant deficiency (F_u = 0, equal loads) the lateral
  balance makes ``ψ_2 = -ψ_1 = -α`` and eliminating the rest gives the closed form

      α = (b / R) / (1 + (K λ F22 / (r0 k_ψ)) (b² / k_ψ + 1 / k_l)),
      ψ_b = b F22 α / k_ψ,    y_b = r0 l0 / (λ R) + r0 b F22 α / (K λ),
      y_{1,2} = y_b ± (b ψ_b + F22 α / k_l),

  with the limits k_ψ → ∞: α → b / R, the rigid bogie's angle of attack; k_ψ → 0: α → 0 and
  y_i → r0 l0 / (λ R), each wheelset radial at its pure-rolling offset.

Second-order terms left out (against the solver): ψ², y / l0 in the arms, w λ y, the creep
forces' change of the normal forces in Kalker's coefficients (N^(2/3)); the solver's saturated
law departs from Kalker's linear one by the factor ``1 - β/3 + β²/27`` of the
Shen–Hedrick–Elkins/Johnson–Vermeulen cubic, β = |F_linear| / (μ N), so by β/3 at first order.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from contact.hertz import hertz_from_curvatures
from contact.kalker import creep_coefficients

from .geometry import ConicalGeometry

__all__ = ["LinearCurving", "linear_coefficients", "linear_bogie", "rigid_bogie_closed_form",
           "flexible_bogie_closed_form", "STEEL_YOUNG", "STEEL_POISSON", "GRAVITY"]

#: Steel: Young's modulus (Pa) and Poisson's ratio (-).
STEEL_YOUNG = 210e9
STEEL_POISSON = 0.3
#: Standard gravity (m/s²).
GRAVITY = 9.81


@dataclass(frozen=True)
class LinearCurving:
    """The linear theory's steady curving of a two-axle bogie (SI units).

    Attributes
    ----------
    lateral_displacement : (float, float)
        y_1, y_2 of the leading and trailing wheelsets towards the outer rail (m).
    angle_of_attack : (float, float)
        ψ_1, ψ_2 (rad).
    frame_displacement, frame_yaw : float
        y_b (m), ψ_b (rad).
    f11, f22 : (float, float)
        Kalker's coefficients of the outer and inner wheel (N).
    unbalanced_force : float
        F_u per axle (N).
    wheel_loads : (float, float)
        Q_o, Q_i (N).
    force_ratio : float
        The largest ratio of a wheel's linear creep force to its normal force,
        ``max |(f11 ξ, f22 η)| / N`` over the four wheels (-): the saturated law's
        β = force_ratio / μ.
    """

    lateral_displacement: tuple
    angle_of_attack: tuple
    frame_displacement: float
    frame_yaw: float
    f11: tuple
    f22: tuple
    unbalanced_force: float
    wheel_loads: tuple
    force_ratio: float


def linear_coefficients(geometry: ConicalGeometry, normal_force: float, young: float = STEEL_YOUNG,
                        poisson: float = STEEL_POISSON) -> tuple[float, float]:
    """Kalker's linear creep coefficients (f11, f22) = G a b (C11, C22) of a conical tread (N).

    Parameters
    ----------
    geometry : ConicalGeometry
        Its tread contact: wheel radius r0 along the track, the rail crown across (a straight cone).
    normal_force : float
        N (N), > 0.
    young, poisson : float
        Young's modulus (Pa) and Poisson's ratio (-) of both bodies.
    """
    contact_modulus = young / (2.0 * (1.0 - poisson ** 2))
    hz = hertz_from_curvatures(0.5 / geometry.wheel_radius, 0.5 / geometry.rail_crown_radius, normal_force,
                               contact_modulus)
    c11, c22, _ = creep_coefficients(hz.a / hz.b, poisson)
    gab = young / (2.0 * (1.0 + poisson)) * hz.a * hz.b
    return gab * c11, gab * c22


def _loads(geometry, radius, speed, cant, axle_load, cg_height):
    """F_u per axle and the wheel loads (Q_o, Q_i) normal to the track plane (N)."""
    l0 = geometry.contact_half_spacing
    theta = math.asin(cant / (2.0 * l0))
    ratio = speed ** 2 / (GRAVITY * radius)
    fu = axle_load * (ratio * math.cos(theta) - math.sin(theta))
    pn = axle_load * (math.cos(theta) + ratio * math.sin(theta))
    transfer = fu * cg_height / (2.0 * l0)
    return fu, (0.5 * pn + transfer, 0.5 * pn - transfer)


def linear_bogie(geometry: ConicalGeometry, radius: float, speed: float, *, cant: float = 0.0,
                 wheelbase: float = 2.5, axle_load: float = 100e3, centre_of_gravity_height: float = 1.2,
                 longitudinal_stiffness: float = math.inf, lateral_stiffness: float = math.inf,
                 axlebox_half_spacing: float = 1.0) -> LinearCurving:
    """Solve the linear steady-curving equations of the module docstring with :func:`numpy.linalg.solve`.

    Parameters
    ----------
    geometry : ConicalGeometry
    radius : float
        R (m), finite.
    speed : float
        V (m/s).
    cant : float
        h (m).
    wheelbase : float
        2b (m).
    axle_load : float
        P (N).
    centre_of_gravity_height : float
        h_cg (m): the load transfer F_u h_cg / (2 l0) per wheel.
    longitudinal_stiffness, lateral_stiffness : float
        k_x, k_y per axle box (N/m); ``math.inf`` (both) for the rigid bogie.
    axlebox_half_spacing : float
        d (m): k_ψ = 2 k_x d².

    Returns
    -------
    LinearCurving
    """
    g = geometry
    r0, l0, lam = g.wheel_radius, g.contact_half_spacing, g.conicity
    b = 0.5 * wheelbase
    x = (b, -b)
    fu, (qo, qi) = _loads(g, radius, speed, cant, axle_load, centre_of_gravity_height)
    cos_d, tan_d = 1.0 / math.hypot(1.0, lam), lam
    (f11o, f22o), (f11i, f22i) = (linear_coefficients(g, q / cos_d) for q in (qo, qi))
    f22 = f22o + f22i
    k = l0 * 4.0 * f11o * f11i / (f11o + f11i)
    t = (qo - qi) * tan_d  # lateral force of the load transfer on a cone, towards the inner rail
    if math.isinf(longitudinal_stiffness):
        # unknowns (y_b, ψ_b): lateral and yaw balance of the bogie
        # (in the yaw balance ψ_b drops out: Σ x_i = 0)
        a = np.array([[0.0, 2.0 * f22],
                      [-2.0 * k * lam / r0, 0.0]])
        c = np.array([2.0 * t - 2.0 * fu,
                      -2.0 * k * l0 / radius - f22 * sum(xi * xi for xi in x) / radius])
        yb, pb = np.linalg.solve(a, c)
        ys = tuple(float(yb + xi * pb) for xi in x)
        psis = tuple(float(pb + xi / radius) for xi in x)
    else:
        kl = 2.0 * lateral_stiffness
        kpsi = 2.0 * longitudinal_stiffness * axlebox_half_spacing ** 2
        # unknowns u = (y_1, ψ_1, y_2, ψ_2, y_b, ψ_b)
        a = np.zeros((6, 6))
        c = np.zeros(6)
        for i, xi in enumerate(x):
            iy, ip = 2 * i, 2 * i + 1
            # wheelset lateral: F22 ψ_i - t - kl (y_i - y_b - x_i ψ_b) = 0
            a[iy, ip], a[iy, iy], a[iy, 4], a[iy, 5] = f22, -kl, kl, kl * xi
            c[iy] = t
            # wheelset yaw: K (l0/R - λ y_i / r0) - kψ (ψ_i - ψ_b - x_i / R) = 0
            a[ip, iy], a[ip, ip], a[ip, 5] = -k * lam / r0, -kpsi, kpsi
            c[ip] = -k * l0 / radius - kpsi * xi / radius
            # frame lateral: 2 F_u + Σ kl (y_i - y_b - x_i ψ_b) = 0
            a[4, iy] += kl
            a[4, 4] -= kl
            a[4, 5] -= kl * xi
            # frame yaw: Σ kψ (ψ_i - ψ_b - x_i / R) + x_i kl (y_i - y_b - x_i ψ_b) = 0
            a[5, ip] += kpsi
            a[5, 5] -= kpsi + kl * xi * xi
            a[5, iy] += kl * xi
            a[5, 4] -= kl * xi
            c[5] += kpsi * xi / radius
        c[4] = -2.0 * fu
        u = np.linalg.solve(a, c)
        ys, psis = (float(u[0]), float(u[2])), (float(u[1]), float(u[3]))
        yb, pb = u[4], u[5]
    ratio = 0.0
    for y, psi in zip(ys, psis):
        a_ = l0 / radius - lam * y / r0
        w = a_ * (f11o - f11i) / (f11o + f11i)
        for s, f11, f22s, q in ((1, f11o, f22o, qo), (-1, f11i, f22i, qi)):
            force = math.hypot(f11 * (s * a_ - w), f22s * psi * cos_d)
            ratio = max(ratio, force * cos_d / q)
    return LinearCurving(ys, psis, float(yb), float(pb), (f11o, f11i), (f22o, f22i), fu, (qo, qi), ratio)


def rigid_bogie_closed_form(r0: float, l0: float, conicity: float, radius: float, semi_wheelbase: float,
                            f11: float, f22: float, lateral_force: float = 0.0) -> tuple[float, float]:
    """Boocock's rigid bogie: (y_b, ψ_b) (m, rad) for equal wheel loads (module docstring).

    Parameters
    ----------
    r0, l0 : float
        Rolling radius and half contact spacing (m).
    conicity : float
        λ (-).
    radius : float
        R (m).
    semi_wheelbase : float
        b (m).
    f11, f22 : float
        Kalker's coefficients of one wheel (N).
    lateral_force : float
        Net lateral force per axle on the wheelsets towards the outer rail, F_u minus the load
        transfer's term (N).
    """
    yb = r0 * l0 / (conicity * radius) * (1.0 + f22 * semi_wheelbase ** 2 / (f11 * l0 ** 2))
    return yb, -lateral_force / (2.0 * f22)


def flexible_bogie_closed_form(r0: float, l0: float, conicity: float, radius: float, semi_wheelbase: float,
                               f11: float, f22: float, yaw_stiffness: float, lateral_stiffness: float) -> dict:
    """The bogie with primary yaw and lateral stiffness, no cant deficiency, equal wheel loads.

    Parameters
    ----------
    r0, l0, conicity, radius, semi_wheelbase, f11, f22
        As :func:`rigid_bogie_closed_form`.
    yaw_stiffness : float
        k_ψ = 2 k_x d² per wheelset (N m/rad).
    lateral_stiffness : float
        k_l = 2 k_y per wheelset (N/m).

    Returns
    -------
    dict
        ``angle_of_attack`` (ψ_1, ψ_2) = (α, -α), ``lateral_displacement`` (y_1, y_2),
        ``frame_displacement`` y_b, ``frame_yaw`` ψ_b (m, rad).
    """
    b = semi_wheelbase
    k, big_f22 = 2.0 * f11 * l0, 2.0 * f22
    alpha = (b / radius) / (1.0 + k * conicity * big_f22 / (r0 * yaw_stiffness)
                            * (b * b / yaw_stiffness + 1.0 / lateral_stiffness))
    pb = b * big_f22 * alpha / yaw_stiffness
    yb = r0 * l0 / (conicity * radius) + r0 * b * big_f22 * alpha / (k * conicity)
    dy = b * pb + big_f22 * alpha / lateral_stiffness
    return {"angle_of_attack": (alpha, -alpha), "lateral_displacement": (yb + dy, yb - dy),
            "frame_displacement": yb, "frame_yaw": pb}
