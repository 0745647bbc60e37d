"""Numba kernels of the contact solvers (compiled lazily on first call, cached on disk).

:func:`tangential_gauss_seidel` is the element-by-element (Gauss-Seidel) solution of the
tangential problem with Coulomb friction, in the spirit of Kalker's ConvexGS / SteadyGS;
:func:`point_contact_law` is the whole point-contact model of one step (used by
:class:`~interaction.contact.point.PointContact` and by the interaction's compiled time loop).
Nothing is compiled at import time.
"""

from __future__ import annotations

import math

import numba
import numpy as np


@numba.njit(cache=True)
def _local_slip(cx, cy, dxx, dyy, g):
    """Traction of one slipping element.

    Solve s = c + D p with p = -g s/|s| (D = diag(dxx, dyy) > 0). With sigma = |s|:
    s_k = c_k sigma / (sigma + g d_k), and sigma solves sum c_k^2/(sigma + g d_k)^2 = 1
    (monotone, Newton from the equal-diagonal solution).
    """
    cn = math.sqrt(cx * cx + cy * cy)
    if g <= 0.0 or cn == 0.0:
        return 0.0, 0.0
    dm = 0.5 * (dxx + dyy)
    sig = max(cn - g * dm, 0.0)
    for _ in range(30):
        ax = sig + g * dxx
        ay = sig + g * dyy
        f = cx * cx / (ax * ax) + cy * cy / (ay * ay) - 1.0
        df = -2.0 * (cx * cx / (ax * ax * ax) + cy * cy / (ay * ay * ay))
        step = f / df
        new = sig - step
        if new < 0.0:
            new = 0.5 * sig
        if abs(new - sig) <= 1e-14 * (cn + g * dm):
            sig = new
            break
        sig = new
    return -g * cx / (sig + g * dxx), -g * cy / (sig + g * dyy)


@numba.njit(cache=True)
def tangential_gauss_seidel(K11, K12, K22, nx, ny, cix, ciy, tix, tiy, nb, steady,
                            wx, wy, upx, upy, gs, gk, px, py, ux, uy, tol, max_sweeps, omega,
                            series_x=0.0, series_y=0.0):
    """Gauss-Seidel sweeps for the tangential tractions of the contact elements.

    Parameters
    ----------
    K11, K12, K22 : ndarray (2 nx - 1, 2 ny - 1)
        Influence kernels (m/Pa).
    nx, ny : int
        Grid size.
    cix, ciy : int ndarray (nc,)
        Grid indices of the contact elements, in sweep order. They are also the first nc
        entries of the tracked set (tix, tiy).
    tix, tiy : int ndarray (nt,)
        Grid indices of the tracked elements whose displacement is kept up to date.
    nb : int ndarray (nc,)
        Steady rolling: index in the tracked set of the element upstream (ix + 1) of each
        contact element.
    steady : bool
        Steady rolling (u' = current u upstream) or transient/shift (u' given).
    wx, wy : ndarray (nc,)
        Rigid slip over the step (m).
    upx, upy : ndarray (nc,)
        Previous displacement u' of the same particle (m) (unused when steady).
    gs, gk : ndarray (nc,)
        Traction bounds mu_s p_z and mu_k p_z (Pa). ``gs`` is lowered to ``gk`` in place
        where an element slides (hysteresis: this keeps the iteration monotone, and
        convergent, when mu_s > mu_k).
    px, py : ndarray (nc,)
        Tractions (Pa); initial guess in, solution out.
    ux, uy : ndarray (nt,)
        Displacement differences of the tracked elements (m), consistent with px, py on
        entry; updated in place.
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps : int
        Limit of sweeps.
    omega : float
        Over-relaxation factor of stick updates (1 = plain Gauss-Seidel).
    series_x, series_y : float
        Compliance of springs in series with the contact (e.g. the structures' instantaneous
        compliance) times the element area (m/Pa): every element's slip gains
        ``series * sum(p)``, the displacement of the springs under the total force. Zero
        for the contact alone.

    Returns
    -------
    sweeps : int
        Sweeps done.
    change : float
        Largest traction change (Pa) in the last sweep.
    status : int8 ndarray (nc,)
        1 stick, 2 slip.
    """
    nc = cix.shape[0]
    nt = tix.shape[0]
    ox = nx - 1
    oy = ny - 1
    status = np.ones(nc, np.int8)
    my = K11.shape[1]
    f11 = K11.ravel()
    f12 = K12.ravel()
    f22 = K22.ravel()
    tflat = tix * my + tiy  # flat kernel index of offset (t - c) is tflat[t] + off(c)
    d0x = K11[ox, oy]
    d0y = K22[ox, oy]
    if steady:
        dxx = d0x - K11[ox + 1, oy]
        dyy = d0y - K22[ox + 1, oy]
    else:
        dxx = d0x
        dyy = d0y
    dxx += series_x
    dyy += series_y
    total_x = 0.0  # sum of the tractions (Pa): the series springs' displacement is series * total
    total_y = 0.0
    for c in range(nc):
        total_x += px[c]
        total_y += py[c]
    change = 0.0
    sweeps = 0
    skip = 1e-3 * tol  # changes this small are not propagated (far below the tolerance)
    for sweep in range(max_sweeps):
        change = 0.0
        for c in range(nc):
            if steady:
                sx = wx[c] + ux[c] - ux[nb[c]]
                sy = wy[c] + uy[c] - uy[nb[c]]
            else:
                sx = wx[c] + ux[c] - upx[c]
                sy = wy[c] + uy[c] - upy[c]
            sx += series_x * total_x
            sy += series_y * total_y
            cx = sx - dxx * px[c]
            cy = sy - dyy * py[c]
            qx = -cx / dxx
            qy = -cy / dyy
            if qx * qx + qy * qy <= gs[c] * gs[c]:
                status[c] = 1
                if omega != 1.0:  # over-relaxation of the stick update, projected on the bound
                    qx = px[c] + omega * (qx - px[c])
                    qy = py[c] + omega * (qy - py[c])
                    qn = math.sqrt(qx * qx + qy * qy)
                    if qn > gs[c]:
                        qx *= gs[c] / qn
                        qy *= gs[c] / qn
            else:
                qx, qy = _local_slip(cx, cy, dxx, dyy, gk[c])
                status[c] = 2
                gs[c] = gk[c]  # once sliding, kinetic friction bounds a return to stick
            dpx = qx - px[c]
            dpy = qy - py[c]
            if abs(dpx) > skip or abs(dpy) > skip:
                px[c] = qx
                py[c] = qy
                total_x += dpx
                total_y += dpy
                off = (ox - cix[c]) * my + (oy - ciy[c])
                for t in range(nt):
                    k = tflat[t] + off
                    k12 = f12[k]
                    ux[t] += f11[k] * dpx + k12 * dpy
                    uy[t] += k12 * dpx + f22[k] * dpy
                m = max(abs(dpx), abs(dpy))
                if m > change:
                    change = m
        sweeps = sweep + 1
        if change <= tol:
            break
    return sweeps, change, status


@numba.njit(cache=True)
def _relax(u, y, w, h, beta, alpha1, alpha2):
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
def point_contact_law(approach, xi, eta, phi, e_xi, w_xi, e_eta, w_eta, e_phi, w_phi, consts):
    """One step of the point-contact model (interaction/contact/point.py holds its description).

    Parameters
    ----------
    approach : float
        Approach of the bodies, m (<= 0: lift-off).
    xi, eta, phi : float
        Creepages of this step (-, -, 1/m), held over the step.
    e_xi, w_xi, e_eta, w_eta, e_phi, w_phi : float
        Relaxation state of the previous step: effective creepage and auxiliary state of each
        creepage (same units as the creepage).
    consts : (16,) ndarray
        ``[F_ref, delta_ref, G a b, a b, C11, C22, C23, mu_k, distance, a, beta_x, alpha1_x,
        alpha2_x, beta_y, alpha1_y, alpha2_y]`` at the Hertz reference load (N, m, N, m², -,
        -, -, -, m per step, m, then the non-dimensional relaxation constants of
        ``alpha2 a² y'' + alpha1 a y' + y = u + beta a u'`` for xi (x) and for eta and phi (y));
        ``a <= 0`` selects the steady model (no relaxation).

    Returns
    -------
    (Fx, Fy, Fn, e_xi, w_xi, e_eta, w_eta, e_phi, w_phi) : tuple of float
        Forces on the wheel (N) and the new state; all zero at lift-off.
    """
    f_ref, d_ref, gab0, ab0, c11, c22, c23, mu, dist, a0 = consts[:10]
    if approach <= 0.0:
        return 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0
    fn = f_ref * (approach / d_ref) ** 1.5
    s = (fn / f_ref) ** (1.0 / 3.0)  # semi-axes scale as Fn^(1/3)
    if a0 > 0.0:
        h = dist / (a0 * s)  # rolled distance of the step in current semi-axes
        e_xi, w_xi = _relax(xi, e_xi, w_xi, h, consts[10], consts[11], consts[12])
        e_eta, w_eta = _relax(eta, e_eta, w_eta, h, consts[13], consts[14], consts[15])
        e_phi, w_phi = _relax(phi, e_phi, w_phi, h, consts[13], consts[14], consts[15])
    else:
        e_xi, w_xi, e_eta, w_eta, e_phi, w_phi = xi, 0.0, eta, 0.0, phi, 0.0
    gab = gab0 * s * s
    fx = -gab * c11 * e_xi
    fy = -gab * c22 * e_eta - gab * math.sqrt(ab0) * s * c23 * e_phi
    norm = math.sqrt(fx * fx + fy * fy)
    bound = mu * fn
    if norm > 0.0:
        if bound == 0.0:
            fx, fy = 0.0, 0.0
        else:
            beta = norm / bound
            factor = 1.0 - beta / 3.0 + beta * beta / 27.0 if beta < 3.0 else 1.0 / beta
            fx *= factor
            fy *= factor
    return fx, fy, fn, e_xi, w_xi, e_eta, w_eta, e_phi, w_phi


@numba.njit(cache=True)
def _influence_add(f33, base, offset, x, rows, out, scale):
    """``out[rows] += scale * A x`` for the Toeplitz influence matrix of the flat kernel ``f33``.

    ``A[i, j] = f33[base[i] + offset[j]]``; only the non-zero entries of ``x`` are visited.
    """
    for j in range(x.shape[0]):
        xj = x[j]
        if xj != 0.0:
            o = offset[j]
            c = scale * xj
            for r in range(rows.shape[0]):
                i = rows[r]
                out[i] += f33[base[i] + o] * c


@numba.njit(cache=True)
def normal_conjugate_gradient(K33, nx, ny, h, p, force_mode, target, series, area, tol, max_iter, warm):
    """Polonsky-Keer constrained conjugate gradients for the normal contact problem.

    The algorithm of interaction/contact/normal.py (which documents it), with direct products of
    the influence matrix restricted to the elements in contact, so that a small grid needs no FFT.

    Parameters
    ----------
    K33 : ndarray (2 nx - 1, 2 ny - 1)
        Normal influence kernel (m/Pa).
    nx, ny : int
        Grid size.
    h : ndarray (nx ny,)
        Undeformed gap (m), flat in C order.
    p : ndarray (nx ny,)
        Pressure (Pa): initial guess in, solution out.
    force_mode : bool
        Prescribed normal force ``target`` (N), else prescribed approach ``target`` (m).
    series : float
        Series compliance times element area (m/Pa), added to every influence coefficient
        (approach mode only).
    area : float
        Element area (m²).
    tol : float
        Relative tolerance (pressure change and gap residual).
    max_iter : int
        Iteration limit.
    warm : bool
        ``p`` is a warm start: exit at once if it already solves the problem and, with a
        prescribed approach, first rescale it to the approach (mean gap closed on its area).

    Returns
    -------
    iterations : int
    residual : float
        Final relative pressure change (-).
    converged : bool
    u : ndarray (nx ny,)
        Normal displacement difference including the series term (m).
    """
    n = nx * ny
    my = K33.shape[1]
    ox = nx - 1
    oy = ny - 1
    f33 = K33.ravel()
    base = np.empty(n, np.int64)
    offset = np.empty(n, np.int64)
    for i in range(n):
        ix = i // ny
        iy = i - ix * ny
        base[i] = ix * my + iy
        offset[i] = (ox - ix) * my + (oy - iy)
    everything = np.arange(n)
    hmin = h[0]
    hmax = h[0]
    for i in range(n):
        hmin = min(hmin, h[i])
        hmax = max(hmax, h[i])
    hscale = max(hmax - hmin, 1e-300)
    u = np.zeros(n)
    _influence_add(f33, base, offset, p, everything, u, 1.0)
    total = 0.0
    for i in range(n):
        total += p[i]
    for i in range(n):
        u[i] += series * total
    if warm and not force_mode:
        # rescale the warm start to the new approach: u is linear in p
        num = 0.0
        den = 0.0
        for i in range(n):
            if p[i] > 0.0:
                num += target - h[i]
                den += u[i]
        if den > 0.0 and num > 0.0:
            factor = num / den
            if abs(factor - 1.0) > tol:
                for i in range(n):
                    p[i] *= factor
                    u[i] *= factor
    g = np.empty(n)
    t = np.zeros(n)
    r = np.zeros(n)
    p_old = np.empty(n)
    g_old = 1.0
    conjugate = False
    residual = np.inf
    converged = False
    it = 0
    for it in range(1, max_iter + 1):
        n_active = 0
        gsum = 0.0
        for i in range(n):
            if p[i] > 0.0:
                n_active += 1
                gsum += h[i] + u[i]
        if n_active == 0:
            break
        gbar = gsum / n_active if force_mode else target
        G = 0.0
        ginactive = 0.0
        for i in range(n):
            g[i] = h[i] + u[i] - gbar
            if p[i] > 0.0:
                G += g[i] * g[i]
            elif g[i] < ginactive:
                ginactive = g[i]
        gap_res = math.sqrt(G / n_active) / hscale
        if it == 1 and warm and gap_res < 10.0 * tol and ginactive > -tol * hscale:
            residual = 0.0
            converged = True
            break
        beta = G / g_old if conjugate else 0.0
        for i in range(n):
            t[i] = g[i] + beta * t[i] if p[i] > 0.0 else 0.0
        g_old = G
        # r = A t on the elements in contact (only those enter the step length)
        active = np.empty(n_active, np.int64)
        k = 0
        for i in range(n):
            if p[i] > 0.0:
                active[k] = i
                k += 1
        for i in range(n):
            r[i] = 0.0
        _influence_add(f33, base, offset, t, active, r, 1.0)
        tsum = 0.0
        for i in range(n):
            tsum += t[i]
        rbar = 0.0
        if force_mode:
            for i in range(n):
                if p[i] > 0.0:
                    rbar += r[i]
            rbar /= n_active
        num = 0.0
        den = 0.0
        for i in range(n):
            if p[i] > 0.0:
                ri = r[i] + series * tsum - rbar
                num += g[i] * t[i]
                den += ri * t[i]
        tau = num / den if den != 0.0 else 0.0
        overlap = False
        psum = 0.0
        for i in range(n):
            p_old[i] = p[i]
            q = p[i] - tau * t[i]
            if q < 0.0:
                q = 0.0
            if q == 0.0 and g[i] < 0.0:
                q = -tau * g[i]
                overlap = True
            p[i] = q
            psum += q
        conjugate = not overlap
        if force_mode and psum > 0.0:
            scale = target / (psum * area)
            for i in range(n):
                p[i] *= scale
            psum *= scale
        change = 0.0
        for i in range(n):
            change += abs(p[i] - p_old[i])
        residual = change / psum if psum > 0.0 else 0.0
        # u = A p, recomputed (exact; the cost equals that of an incremental update)
        for i in range(n):
            u[i] = 0.0
        _influence_add(f33, base, offset, p, everything, u, 1.0)
        for i in range(n):
            u[i] += series * psum
        if residual < tol and gap_res < 10.0 * tol and not overlap:
            converged = True
            break
    return it, residual, converged, u
