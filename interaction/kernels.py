"""Numba kernels of the interaction (compiled lazily on first call, cached on disk).

:func:`point_contact_loop` is the whole time stepping of interaction/simulate.py for the point
contact model, with the wheel as a pole-residue recursion and the rail as a convolution (the
same algorithm as the Python loop, which remains the reference and serves every other
combination of models). Nothing is compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np

from interaction.contact.kernels import point_contact_law


@numba.njit(cache=True)
def point_contact_loop(z, weights, k0_wheel, rail_tail, k0_rail, consts, creepage, speed, time_step, load,
                       delta_static, excitation, tolerance, max_iterations, runaway_factor,
                       force, creep_out, slip, wheel_u, rail_u, wheel_v, rail_v, iterations):
    """Time stepping with the point contact model; fills the output arrays.

    Parameters
    ----------
    z : (m,) complex ndarray
        ``exp(p Δt)`` of the wheel's poles.
    weights : (m, 3, 3) complex ndarray
        Recursion weights of the wheel (fe.greens.recursion_coefficients), m/N.
    k0_wheel, k0_rail : (3, 3) ndarray
        Instantaneous compliances, m/N.
    rail_tail : (nk, 3, 3) ndarray
        Rail kernel samples 1..nk, m/N.
    consts : ndarray
        Point-contact constants (PointContact.kernel_constants).
    creepage : (3,) ndarray
        Imposed creepages (ξ, η, φ).
    speed, time_step, load, delta_static : float
        m/s, s, N, m.
    excitation : (nt,) ndarray
        Extra approach per step, m.
    tolerance : float
        Coupling convergence relative to the load.
    max_iterations : int
    runaway_factor : float
    force, creep_out, wheel_u, rail_u, wheel_v, rail_v : (nt, 3) ndarray
        Outputs.
    slip : (nt,) ndarray
        Output: |F_t| / μF_n.
    iterations : (nt,) int ndarray
        Output.

    Returns
    -------
    int
        -1 when every step converged, else the failing step (runaway or no convergence: the
        outputs hold the values up to that step).
    """
    nt = force.shape[0]
    m = z.shape[0]
    nk = rail_tail.shape[0]
    mu = consts[7]
    h = np.zeros((m, 3), dtype=np.complex128)
    buffer = np.zeros((max(nk, 1), 3))
    head = 0
    f = np.array([0.0, 0.0, load])
    e = np.zeros(6)  # relaxation state: (y, w) of xi, eta, phi (point_contact_law)
    uw_prev = np.zeros(3)
    ur_prev = np.zeros(3)
    hist_w = np.zeros(3)
    hist_r = np.zeros(3)
    df = np.zeros(3)
    uw = np.zeros(3)
    ur = np.zeros(3)
    for n in range(nt):
        for i in range(3):
            acc = 0.0
            for r in range(m):
                for j in range(3):
                    acc += 2.0 * (weights[r, i, j] * h[r, j]).real
            hist_w[i] = acc
            acc = 0.0
            for q in range(nk):
                slot = (head - q) % nk
                for j in range(3):
                    acc += rail_tail[q, i, j] * buffer[slot, j]
            hist_r[i] = acc
        converged = False
        it = 0
        fx = fy = fn = 0.0
        r0 = r1 = r2 = r3 = r4 = r5 = 0.0
        xi_t = eta_t = 0.0
        for it in range(1, max_iterations + 1):
            df[0] = f[0]
            df[1] = f[1]
            df[2] = f[2] - load
            for i in range(3):
                uw[i] = hist_w[i] + k0_wheel[i, 0] * df[0] + k0_wheel[i, 1] * df[1] + k0_wheel[i, 2] * df[2]
                ur[i] = -(hist_r[i] + k0_rail[i, 0] * df[0] + k0_rail[i, 1] * df[1] + k0_rail[i, 2] * df[2])
            approach = delta_static - (uw[2] - ur[2]) + excitation[n]
            xi_t = creepage[0] + ((uw[0] - uw_prev[0]) - (ur[0] - ur_prev[0])) / time_step / speed
            eta_t = creepage[1] + ((uw[1] - uw_prev[1]) - (ur[1] - ur_prev[1])) / time_step / speed
            fx, fy, fn, r0, r1, r2, r3, r4, r5 = point_contact_law(approach, xi_t, eta_t, creepage[2], e[0], e[1],
                                                                   e[2], e[3], e[4], e[5], consts)
            change = max(abs(fx - f[0]), abs(fy - f[1]), abs(fn - f[2]))
            f[0], f[1], f[2] = fx, fy, fn
            if not (np.isfinite(fx) and np.isfinite(fy) and np.isfinite(fn)) or max(abs(fx), abs(fy), abs(fn)) > runaway_factor * load:
                iterations[n] = it
                return n
            if change <= tolerance * load:
                converged = True
                break
        iterations[n] = it
        if not converged:
            return n
        df[0] = f[0]
        df[1] = f[1]
        df[2] = f[2] - load
        for i in range(3):
            uw[i] = hist_w[i] + k0_wheel[i, 0] * df[0] + k0_wheel[i, 1] * df[1] + k0_wheel[i, 2] * df[2]
            ur[i] = -(hist_r[i] + k0_rail[i, 0] * df[0] + k0_rail[i, 1] * df[1] + k0_rail[i, 2] * df[2])
            force[n, i] = f[i]
            wheel_u[n, i] = uw[i]
            rail_u[n, i] = ur[i]
            wheel_v[n, i] = (uw[i] - uw_prev[i]) / time_step
            rail_v[n, i] = (ur[i] - ur_prev[i]) / time_step
            uw_prev[i] = uw[i]
            ur_prev[i] = ur[i]
        creep_out[n, 0] = xi_t
        creep_out[n, 1] = eta_t
        creep_out[n, 2] = creepage[2]
        bound = mu * fn
        slip[n] = min((fx * fx + fy * fy) ** 0.5 / bound, 1.0) if bound > 0.0 else 0.0
        e[0], e[1], e[2], e[3], e[4], e[5] = r0, r1, r2, r3, r4, r5
        # commit: wheel recursion h[n+1] = z (h[n] + dF[n]); rail buffer newest first
        for r in range(m):
            for j in range(3):
                h[r, j] = z[r] * (h[r, j] + df[j])
        if nk > 0:
            head = (head + 1) % nk
            for j in range(3):
                buffer[head, j] = df[j]
    return -1
