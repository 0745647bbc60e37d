"""Numba kernels of the point-contact model (contact/point/model.py describes the model).

:func:`point_contact_law` is the whole point-contact model of one step, used by
:class:`~contact.point.model.PointContact` and by the interaction's compiled time loop
(contact/point/loop.py). Its tangential part is either the transient strip model
(:func:`strip_tractions`, the default) or the relaxed creepages of the saturated creep law
(:func:`relax`). A friction characteristic of the sliding speed (contact/friction_law.py) sets
the saturation bound at the contact's sliding speed ``V |(xi, eta)|`` (:func:`_sliding_coefficient`).
Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from contact.friction_kernels import sliding_factor, sliding_factor_slope
from contact.friction_law import CONSTANT

#: ``PointLaw.tangential``: saturated creep law on relaxed creepages (the former model).
RELAXATION = 0
#: ``PointLaw.tangential``: transient strip model (elastic displacements carried through the patch).
STRIP = 1
#: Entries of the carried state before the strip's displacements: (y, w) of xi, eta and phi.
RELAXATION_STATES = 6


@numba.njit(cache=True)
def relax(u, y, w, h, beta, alpha1, alpha2):
    """One exact step of ``alpha2 y'' + alpha1 y' + y = u + beta u'`` for u held constant.

    The rolled distance h and the constants are in units of the current semi-axis a. States:
    observable canonical form, ``y' = -(alpha1/alpha2) y + w + (beta/alpha2) u``,
    ``w' = (u - y) / alpha2``; y is the effective creepage. Returns the new (y, w).
    """
    p = alpha1 / alpha2  # -trace of the state matrix
    g = 1.0 / alpha2  # its determinant
    # deviation from the steady state (y, w) = (u, (alpha1 - beta) u / alpha2) decays as exp(A h)
    dy = y - u
    dw = w - (alpha1 - beta) * g * u
    m = -0.5 * p
    q2 = m * m - g
    if q2 > 1e-12:
        q = math.sqrt(q2)
        c = math.cosh(q * h)
        sq = math.sinh(q * h) / q
    elif q2 < -1e-12:
        q = math.sqrt(-q2)
        c = math.cos(q * h)
        sq = math.sin(q * h) / q
    else:
        c = 1.0
        sq = h
    e = math.exp(m * h)
    # exp(A h) = e^{m h} (c I + sq (A - m I)), A - m I = [[m, 1], [-g, -m]] (m = -p/2)
    ny = e * ((c + sq * m) * dy + sq * dw)
    nw = e * (-sq * g * dy + (c - sq * m) * dw)
    return u + ny, (alpha1 - beta) * g * u + nw


@numba.njit(cache=True)
def _sliding_coefficient(law, xi, eta):
    """The friction coefficient at the contact's sliding speed ``v = V |(xi, eta)|`` and its
    relative change per unit creepage: ``(mu, dmu/dxi / mu, dmu/deta / mu)`` (-, -, -)."""
    c = math.sqrt(xi * xi + eta * eta)
    v = law.rolling_speed * c
    phi = sliding_factor(law.friction_law, v)
    mu = law.kinetic_friction * phi
    if phi <= 0.0 or c == 0.0:
        return mu, 0.0, 0.0
    r = sliding_factor_slope(law.friction_law, v) * law.rolling_speed / (phi * c)
    return mu, r * xi, r * eta


@numba.njit(cache=True)
def _strip_range(xs, dx, a, ry):
    """The elements ``[i0, i1)`` of a strip inside the ellipse, ``ry - (x / a)^2 > 0``.

    ``xs`` descends from ``xs[0]`` by ``dx`` (m); ``a`` is the current semi-axis (m) and
    ``ry = 1 - (y / b)^2 > 0`` the strip's share of it, so that its half-length is ``a sqrt(ry)``.
    """
    nx = xs.shape[0]
    half = a * math.sqrt(ry)
    i0 = max(int(math.floor((xs[0] - half) / dx)), 0)
    i1 = min(int(math.ceil((xs[0] + half) / dx)) + 1, nx)
    while i0 < i1 and ry - (xs[i0] / a) ** 2 <= 0.0:
        i0 += 1
    while i1 > i0 and ry - (xs[i1 - 1] / a) ** 2 <= 0.0:
        i1 -= 1
    return i0, i1


@numba.njit(cache=True)
def _parabola_sum(x0, dx, a, ry, i0, i1):
    """``sum(ry - (x_i / a)^2 for i in [i0, i1))`` with ``x_i = x0 - i dx``, in closed form (-)."""
    n = i1 - i0
    if n <= 0:
        return 0.0
    s1 = 0.5 * (i0 + i1 - 1) * n  # sum of i
    s2 = ((i1 - 1) * i1 * (2 * i1 - 1) - (i0 - 1) * i0 * (2 * i0 - 1)) / 6.0  # sum of i^2
    squares = n * x0 * x0 - 2.0 * x0 * dx * s1 + dx * dx * s2
    return n * ry - squares / (a * a)


@numba.njit(cache=True)
def strip_tractions(law, fn, s, xi, eta, phi, state, new_state, jac):
    """Tangential force of the transient strip model for one step; the new displacements in place.

    The contact ellipse (semi-axes ``a = a0 s``, ``b = b0 s``) is cut into the strips of the
    grid ``law.strip_y`` (m, spacing ``law.strip_dy``) and each strip into elements at
    ``law.strip_x`` (m, descending: element 0 at the leading edge, spacing the rolled distance
    per step, ``law.distance``), so that in one step the material moves on by exactly one
    element. Each element carries the elastic tangential displacement ``u`` (m) of the material
    passing through it; the traction is ``u / L`` with the strip's flexibility
    ``L(y) = c a^2 / a(y)`` (m/Pa; ``c = 3 pi / (4 G k C)`` for xi and eta with Kalker's C
    and the factor ``k = law.strip_creep_factor``, so that the linear force is k times
    Kalker's, and every strip reaches full slip at the same creepage, that of the
    Shen-Hedrick-Elkins law with those coefficients), bounded by ``mu p`` (mu at the contact's
    sliding speed for a friction characteristic) with the parabolic pressure
    ``p ∝ 1 - x^2/a^2 - y^2/b^2`` summed to ``fn``. Stick: ``u`` advances by minus the rigid
    slip over the rolled distance (``xi - phi y``, ``eta + phi x``; the spin term scaled by the
    spin's flexibility, so that the linear spin force is k times Kalker's C23 term); slip: the traction
    is put back on the bound in its own direction (the displacement with it). Material entering
    at the leading edge is undeformed.

    Parameters
    ----------
    law : PointLaw
    fn : float
        Normal force, N (> 0).
    s : float
        Scale of the semi-axes, ``(fn / reference_force)^(1/3)`` (-).
    xi, eta, phi : float
        Creepages of this step (-, -, 1/m).
    state, new_state : ndarray
        Carried state before and after the step; the strip's displacements (x, y per element,
        strip by strip) follow the first :data:`RELAXATION_STATES` entries.
    jac : ndarray (>= 2, 3)
        Its first two rows receive the derivatives of (fx, fy) with respect to (fn, xi, eta) (N/N, N, N) for the
        elements' stick/slip states of this step: a sticking element's traction moves with the
        creepage by its rolled distance over its flexibility; a slipping one's only across its
        direction (the bound holds its size), and its size with the bound, which is taken
        proportional to ``fn`` (the patch's change of shape with ``fn`` is left out, so this is
        the exact derivative in full slip and an approximation otherwise: the coupling's Newton
        steps need its direction, not its last digit).

    Returns
    -------
    (fx, fy, slip_fraction) : tuple of float
        Tangential force on the wheel (N) and the share of the elements in contact that slip.
    """
    xs = law.strip_x
    ys = law.strip_y
    nx = xs.shape[0]
    ny = ys.shape[0]
    dx = law.distance
    dy = law.strip_dy
    a = law.semi_axis * s
    b = law.semi_axis_b * s
    g = law.shear_modulus
    mu = law.kinetic_friction
    # a friction characteristic: mu at the contact's sliding speed V |(xi, eta)|, and the relative
    # change of the bound per unit creepage (the Jacobian's term of the sliding elements)
    characteristic = law.friction_law.kind != CONSTANT
    r_xi = r_eta = 0.0
    if characteristic:
        mu, r_xi, r_eta = _sliding_coefficient(law, xi, eta)
    gc = g * law.strip_creep_factor
    cx = 3.0 * math.pi / (4.0 * gc * law.c11)
    cy = 3.0 * math.pi / (4.0 * gc * law.c22)
    # spin: sum over the patch of (a(y)^2 - x^2) / (2 L_s) equals G C23 (ab)^1.5 with L_s = cs a^2 / a(y)
    cs = 32.0 * math.sqrt(a / b) / (45.0 * gc * law.c23) if law.c23 != 0.0 else 0.0
    base = RELAXATION_STATES
    for k in range(base, new_state.shape[0]):
        new_state[k] = 0.0
    for r in range(2):
        for c in range(3):
            jac[r, c] = 0.0
    total = 0.0  # the parabolic shape summed over the elements in contact
    for j in range(ny):
        ry = 1.0 - (ys[j] / b) ** 2
        if ry <= 0.0:
            continue
        i0, i1 = _strip_range(xs, dx, a, ry)
        total += _parabola_sum(xs[0], dx, a, ry, i0, i1)
    if total <= 0.0:
        return 0.0, 0.0, 1.0
    pressure_scale = fn / (total * dx * dy)
    inv_a2 = 1.0 / (a * a)
    fx = 0.0
    fy = 0.0
    n_contact = 0
    n_slip = 0
    # the Jacobian's entries, summed as scalars: d(fx, fy)/dfn, d/dxi, d/deta
    jx_fn = jy_fn = jx_xi = jy_xi = jx_eta = jy_eta = 0.0
    for j in range(ny):
        y = ys[j]
        ry = 1.0 - (y / b) ** 2
        if ry <= 0.0:
            continue
        i0, i1 = _strip_range(xs, dx, a, ry)
        row = base + 2 * nx * j
        half = a * math.sqrt(ry)  # the strip's half-length a(y)
        lx = cx * a * a / half
        ly = cy * a * a / half
        inv_lx = 1.0 / lx
        inv_ly = 1.0 / ly
        spin_scale = half / (cs * a * a) if cs > 0.0 else 0.0  # 1 / L_s(y)
        spin_x = phi * y * lx * spin_scale
        spin_y = phi * ly * spin_scale
        bound_scale = mu * pressure_scale
        for i in range(i0, i1):
            x = xs[i]
            k = row + 2 * i
            q = ry - x * x * inv_a2
            if i > i0:  # the material comes from the element upstream, one step earlier
                ux = state[k - 2]
                uy = state[k - 1]
                rolled = dx
            else:  # it entered the patch at the leading edge, undeformed
                ux = 0.0
                uy = 0.0
                rolled = half - x
            ux -= (xi - spin_x) * rolled
            uy -= (eta + spin_y * (x + 0.5 * rolled)) * rolled  # spin at the rolled interval's middle
            tx = ux * inv_lx
            ty = uy * inv_ly
            bound = bound_scale * q
            t2 = tx * tx + ty * ty
            n_contact += 1
            # d(tx, ty)/d(xi, eta) of the element before the bound: -rolled / L on the diagonal
            gx = -rolled * inv_lx
            gy = -rolled * inv_ly
            if t2 > bound * bound:
                # on the bound: the size follows the bound (∝ fn), the direction the trial traction
                inv_t = 1.0 / math.sqrt(t2)
                ex = tx * inv_t
                ey = ty * inv_t
                scale = bound * inv_t
                tx = bound * ex
                ty = bound * ey
                ux = tx * lx
                uy = ty * ly
                n_slip += 1
                jx_fn += tx
                jy_fn += ty
                jx_xi += scale * (1.0 - ex * ex) * gx
                jy_xi -= scale * ey * ex * gx
                jx_eta -= scale * ex * ey * gy
                jy_eta += scale * (1.0 - ey * ey) * gy
            else:
                jx_xi += gx
                jy_eta += gy
            new_state[k] = ux
            new_state[k + 1] = uy
            fx += tx
            fy += ty
    if characteristic:  # the sliding elements' bound moves with the sliding speed
        jx_xi += r_xi * jx_fn
        jy_xi += r_xi * jy_fn
        jx_eta += r_eta * jx_fn
        jy_eta += r_eta * jy_fn
    slip = n_slip / n_contact if n_contact > 0 else 1.0
    area = dx * dy
    jac[0, 0] = jx_fn * area / fn
    jac[1, 0] = jy_fn * area / fn
    jac[0, 1] = jx_xi * area
    jac[1, 1] = jy_xi * area
    jac[0, 2] = jx_eta * area
    jac[1, 2] = jy_eta * area
    return fx * area, fy * area, slip


@numba.njit(cache=True)
def point_contact_law(law, approach, xi, eta, phi, state, new_state):
    """One step of the point-contact model (contact/point/model.py holds its description).

    The body is :func:`_point_law`; :func:`point_contact_law_jacobian` gives its derivatives too.

    Parameters
    ----------
    law : PointLaw
        The model's constants (contact/halfspace/bundles.py).
    approach : float
        Approach of the bodies, m (<= 0: lift-off).
    xi, eta, phi : float
        Creepages of this step (-, -, 1/m), held over the step.
    state : ndarray
        Carried state of the previous step: ``(e_xi, w_xi, e_eta, w_eta, e_phi, w_phi)``, the
        effective creepage and the auxiliary state of each creepage's relaxation, then (strip
        model) the strip's displacements (m).
    new_state : ndarray
        Receives the state after this step (same length; all zero at lift-off).

    Returns
    -------
    (Fx, Fy, Fn, slip_fraction) : tuple of float
        Forces on the wheel (N) and the slip fraction: |F_t| / (mu Fn) for the creep law, the
        share of the elements that slip for the strip model (1 at lift-off).
    """
    return _point_law(law, approach, xi, eta, phi, state, new_state, np.empty((3, 3)))


@numba.njit(cache=True)
def _point_law(law, approach, xi, eta, phi, state, new_state, jac):
    """:func:`point_contact_law`; the strip model also fills ``jac[:2]`` with d(Fx, Fy)/d(Fn, xi, eta)
    (N/N, N, N, see :func:`strip_tractions`)."""
    f_ref = law.reference_force
    d_ref = law.reference_approach
    a0 = law.semi_axis
    if approach <= 0.0:
        for k in range(new_state.shape[0]):
            new_state[k] = 0.0
        return 0.0, 0.0, 0.0, 1.0
    fn = f_ref * (approach / d_ref) ** 1.5
    s = (fn / f_ref) ** (1.0 / 3.0)  # semi-axes scale as Fn^(1/3)
    if law.tangential == STRIP and a0 > 0.0:
        for k in range(RELAXATION_STATES):
            new_state[k] = 0.0
        fx, fy, slip = strip_tractions(law, fn, s, xi, eta, phi, state, new_state, jac)
        return fx, fy, fn, slip
    if a0 > 0.0:
        h = law.distance / (a0 * s)  # rolled distance of the step in current semi-axes
        rx = law.relaxation[0]
        ry = law.relaxation[1]
        e_xi, w_xi = relax(xi, state[0], state[1], h, rx[0], rx[1], rx[2])
        e_eta, w_eta = relax(eta, state[2], state[3], h, ry[0], ry[1], ry[2])
        e_phi, w_phi = relax(phi, state[4], state[5], h, ry[0], ry[1], ry[2])
    else:
        e_xi, w_xi, e_eta, w_eta, e_phi, w_phi = xi, 0.0, eta, 0.0, phi, 0.0
    new_state[0] = e_xi
    new_state[1] = w_xi
    new_state[2] = e_eta
    new_state[3] = w_eta
    new_state[4] = e_phi
    new_state[5] = w_phi
    for k in range(RELAXATION_STATES, new_state.shape[0]):
        new_state[k] = 0.0
    gab = law.shear_modulus * law.ab * s * s
    fx = -gab * law.c11 * e_xi
    fy = -gab * law.c22 * e_eta - gab * math.sqrt(law.ab) * s * law.c23 * e_phi
    norm = math.sqrt(fx * fx + fy * fy)
    bound = law.kinetic_friction * fn
    if law.friction_law.kind != CONSTANT:
        bound = _sliding_coefficient(law, xi, eta)[0] * fn
    if norm > 0.0:
        if bound == 0.0:
            fx, fy = 0.0, 0.0
        else:
            beta = norm / bound
            factor = 1.0 - beta / 3.0 + beta * beta / 27.0 if beta < 3.0 else 1.0 / beta
            fx *= factor
            fy *= factor
    slip = min(math.sqrt(fx * fx + fy * fy) / bound, 1.0) if bound > 0.0 else 1.0
    return fx, fy, fn, slip


#: Forward-difference steps of :func:`point_contact_law_jacobian` for the creep law: of the
#: approach relative to it, and of the creepages (absolute; creepages are 1e-4 to 1e-2).
APPROACH_STEP = 1e-7
CREEPAGE_STEP = 1e-9


@numba.njit(cache=True)
def point_contact_law_jacobian(law, approach, xi, eta, phi, state, new_state, jac, scratch):
    """:func:`point_contact_law` and its derivatives, for the coupling's Newton steps.

    Parameters
    ----------
    law, approach, xi, eta, phi, state, new_state
        As for :func:`point_contact_law`.
    jac : (3, 3) ndarray
        Receives d(Fx, Fy, Fn)/d(approach, xi, eta) (N/m, N, N): for the strip model from the
        same pass over the elements (:func:`strip_tractions`; Hertz's dFn/d(approach) =
        1.5 Fn / approach), for the creep law by forward differences (three more evaluations).
        Zero at lift-off.
    scratch : ndarray
        Room for a trial state (same length as ``state``).

    Returns
    -------
    (Fx, Fy, Fn, slip_fraction) : tuple of float
        As :func:`point_contact_law`.
    """
    for r in range(3):
        for c in range(3):
            jac[r, c] = 0.0
    fx, fy, fn, slip = _point_law(law, approach, xi, eta, phi, state, new_state, jac)
    if fn <= 0.0:
        for r in range(3):
            for c in range(3):
                jac[r, c] = 0.0
        return fx, fy, fn, slip
    dfn = 1.5 * fn / approach
    if law.tangential == STRIP and law.semi_axis > 0.0:
        jac[0, 0] *= dfn  # d/dFn -> d/d(approach)
        jac[1, 0] *= dfn
        jac[2, 0] = dfn
        return fx, fy, fn, slip
    h = APPROACH_STEP * approach
    gx, gy, gn, _ = _point_law(law, approach + h, xi, eta, phi, state, scratch, jac)
    jac[0, 0] = (gx - fx) / h
    jac[1, 0] = (gy - fy) / h
    jac[2, 0] = dfn
    gx, gy, gn, _ = _point_law(law, approach, xi + CREEPAGE_STEP, eta, phi, state, scratch, jac)
    d0x, d0y = (gx - fx) / CREEPAGE_STEP, (gy - fy) / CREEPAGE_STEP
    gx, gy, gn, _ = _point_law(law, approach, xi, eta + CREEPAGE_STEP, phi, state, scratch, jac)
    jac[0, 1], jac[1, 1] = d0x, d0y
    jac[0, 2], jac[1, 2] = (gx - fx) / CREEPAGE_STEP, (gy - fy) / CREEPAGE_STEP
    jac[2, 1] = 0.0
    jac[2, 2] = 0.0
    return fx, fy, fn, slip
