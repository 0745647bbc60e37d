"""Numba kernels of the interaction (compiled lazily on first call, cached on disk).

:func:`point_contact_loop` and :func:`halfspace_contact_loop` are the whole time stepping of
interaction/simulate.py for the point and the half-space contact model, with the wheel as a
pole-residue recursion and the rail as a convolution (the same algorithm as the Python loop,
which remains the reference and serves every other combination of models). Both share the
structural histories and commits below. Nothing is compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np

from interaction.contact.kernels import point_contact_law, transient_rolling_step


@numba.njit(cache=True)
def _histories(weights, h, rail_tail, buffer, head, hist_w, hist_r):
    """Wheel and rail displacements (3,) at the current step due to all earlier forces (m), in place.

    The wheel's from its recursion states ``h`` (m, 3) and weights (m, 3, 3); the rail's from
    the force buffer, which holds every force twice so that the last ``nk`` forces, newest
    first, are the contiguous slice ``buffer[head:head + nk]``.
    """
    m = h.shape[0]
    nk = rail_tail.shape[0]
    for i in range(3):
        acc = 0.0
        for r in range(m):
            for j in range(3):
                acc += 2.0 * (weights[r, i, j] * h[r, j]).real
        hist_w[i] = acc
    for i in range(3):
        hist_r[i] = 0.0
    for q in range(nk):
        b0 = buffer[head + q, 0]
        b1 = buffer[head + q, 1]
        b2 = buffer[head + q, 2]
        for i in range(3):
            hist_r[i] += rail_tail[q, i, 0] * b0 + rail_tail[q, i, 1] * b1 + rail_tail[q, i, 2] * b2


@numba.njit(cache=True)
def _commit(z, h, df, buffer, head):
    """Advance the structures by one step with the force deviation ``df`` (3,); returns the new head.

    Wheel recursion ``h[n+1] = z (h[n] + dF[n])``; the rail buffer gets ``df`` as its newest force.
    """
    for r in range(h.shape[0]):
        for j in range(3):
            h[r, j] = z[r] * (h[r, j] + df[j])
    nk = buffer.shape[0] // 2
    if nk == 0:
        return head
    head = (head - 1) % nk
    for j in range(3):
        buffer[head, j] = df[j]
        buffer[head + nk, j] = df[j]
    return head


@numba.njit(cache=True)
def _store_step(n, f, load, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, time_step, speed, creepage, df,
                force, creep_out, wheel_u, rail_u, wheel_v, rail_v):
    """Write step n's outputs for the converged force ``f`` and move the previous displacements on."""
    df[0] = f[0]
    df[1] = f[1]
    df[2] = f[2] - load
    for i in range(3):
        uw = hist_w[i] + k0_wheel[i, 0] * df[0] + k0_wheel[i, 1] * df[1] + k0_wheel[i, 2] * df[2]
        ur = -(hist_r[i] + k0_rail[i, 0] * df[0] + k0_rail[i, 1] * df[1] + k0_rail[i, 2] * df[2])
        force[n, i] = f[i]
        wheel_u[n, i] = uw
        rail_u[n, i] = ur
        wheel_v[n, i] = (uw - uw_prev[i]) / time_step
        rail_v[n, i] = (ur - ur_prev[i]) / time_step
    for i in range(2):
        creep_out[n, i] = creepage[i] + ((wheel_u[n, i] - uw_prev[i]) - (rail_u[n, i] - ur_prev[i])) / time_step / speed
    creep_out[n, 2] = creepage[2]
    for i in range(3):
        uw_prev[i] = wheel_u[n, i]
        ur_prev[i] = rail_u[n, i]


@numba.njit(cache=True)
def _point_at(f, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, load, delta_static, excitation, creepage,
              time_step, speed, e, consts):
    """The point contact's forces and new state for the inputs that the trial force ``f`` (3,) gives."""
    d0 = f[0]
    d1 = f[1]
    d2 = f[2] - load
    uw = np.empty(3)
    ur = np.empty(3)
    for i in range(3):
        uw[i] = hist_w[i] + k0_wheel[i, 0] * d0 + k0_wheel[i, 1] * d1 + k0_wheel[i, 2] * d2
        ur[i] = -(hist_r[i] + k0_rail[i, 0] * d0 + k0_rail[i, 1] * d1 + k0_rail[i, 2] * d2)
    approach = delta_static - (uw[2] - ur[2]) + excitation
    xi_t = creepage[0] + ((uw[0] - uw_prev[0]) - (ur[0] - ur_prev[0])) / time_step / speed
    eta_t = creepage[1] + ((uw[1] - uw_prev[1]) - (ur[1] - ur_prev[1])) / time_step / speed
    return point_contact_law(approach, xi_t, eta_t, creepage[2], e[0], e[1], e[2], e[3], e[4], e[5], consts)


@numba.njit(cache=True)
def _point_newton_step(f, image, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, load, delta_static, excitation,
                       creepage, time_step, speed, e, consts):
    """One Newton step on ``R(F) = G(F) - F`` from ``f`` (in place; ``image = G(f)``).

    The algorithm of ``interaction.simulate._newton_step``: forward-difference Jacobian with the
    step 1e-6 of the load, step halved (up to 12 times) until the largest residual drops;
    ``f`` becomes ``image`` if the Jacobian is singular or no halving helps.
    """
    h = 1e-6 * load
    jac = np.zeros((3, 3))
    trial = np.empty(3)
    for k in range(3):
        for i in range(3):
            trial[i] = f[i]
        trial[k] += h
        gx, gy, gn, _, _, _, _, _, _ = _point_at(trial, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, load,
                                                 delta_static, excitation, creepage, time_step, speed, e, consts)
        jac[0, k] = (gx - image[0]) / h
        jac[1, k] = (gy - image[1]) / h
        jac[2, k] = (gn - image[2]) / h
        jac[k, k] -= 1.0
    rhs = np.empty(3)
    size = 0.0
    for i in range(3):
        rhs[i] = f[i] - image[i]
        size = max(size, abs(rhs[i]))
    if abs(np.linalg.det(jac)) == 0.0:
        for i in range(3):
            f[i] = image[i]
        return
    step = np.linalg.solve(jac, rhs)
    for _ in range(12):
        for i in range(3):
            trial[i] = f[i] + step[i]
        gx, gy, gn, _, _, _, _, _, _ = _point_at(trial, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, load,
                                                 delta_static, excitation, creepage, time_step, speed, e, consts)
        if max(abs(gx - trial[0]), abs(gy - trial[1]), abs(gn - trial[2])) < size:
            for i in range(3):
                f[i] = trial[i]
            return
        for i in range(3):
            step[i] *= 0.5
    for i in range(3):
        f[i] = image[i]


@numba.njit(cache=True)
def point_contact_loop(z, weights, k0_wheel, rail_tail, k0_rail, consts, creepage, speed, time_step, load,
                       delta_static, excitation, tolerance, max_iterations, runaway_factor, newton_after,
                       force, creep_out, slip, wheel_u, rail_u, wheel_v, rail_v, iterations):
    """Time stepping with the point contact model; fills the output arrays.

    The coupling of each step is iterated by fixed point, and by Newton steps
    (:func:`_point_newton_step`, the algorithm of ``interaction.simulate._newton_step``) from
    iteration ``newton_after`` on.

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
    newton_after : int
        Fixed-point iterations before Newton steps take over.
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
    buffer = np.zeros((2 * nk, 3))
    head = 0
    f = np.array([0.0, 0.0, load])
    e = np.zeros(6)  # relaxation state: (y, w) of xi, eta, phi (point_contact_law)
    uw_prev = np.zeros(3)
    ur_prev = np.zeros(3)
    hist_w = np.zeros(3)
    hist_r = np.zeros(3)
    df = np.zeros(3)
    image = np.zeros(3)
    for n in range(nt):
        _histories(weights, h, rail_tail, buffer, head, hist_w, hist_r)
        converged = False
        it = 0
        fx = fy = fn = 0.0
        r0 = r1 = r2 = r3 = r4 = r5 = 0.0
        for it in range(1, max_iterations + 1):
            fx, fy, fn, r0, r1, r2, r3, r4, r5 = _point_at(f, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev,
                                                           load, delta_static, excitation[n], creepage, time_step,
                                                           speed, e, consts)
            if not (np.isfinite(fx) and np.isfinite(fy) and np.isfinite(fn)) or max(abs(fx), abs(fy), abs(fn)) > runaway_factor * load:
                iterations[n] = it
                return n
            change = max(abs(fx - f[0]), abs(fy - f[1]), abs(fn - f[2]))
            if change <= tolerance * load:
                f[0], f[1], f[2] = fx, fy, fn
                converged = True
                break
            image[0], image[1], image[2] = fx, fy, fn
            if it >= newton_after:
                _point_newton_step(f, image, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, load, delta_static,
                                   excitation[n], creepage, time_step, speed, e, consts)
            else:
                f[0], f[1], f[2] = fx, fy, fn
        iterations[n] = it
        if not converged:
            return n
        _store_step(n, f, load, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, time_step, speed, creepage, df,
                    force, creep_out, wheel_u, rail_u, wheel_v, rail_v)
        bound = mu * fn
        slip[n] = min((fx * fx + fy * fy) ** 0.5 / bound, 1.0) if bound > 0.0 else 0.0
        e[0], e[1], e[2], e[3], e[4], e[5] = r0, r1, r2, r3, r4, r5
        head = _commit(z, h, df, buffer, head)
    return -1


@numba.njit(cache=True)
def halfspace_contact_loop(z, weights, k0_wheel, rail_tail, k0_rail, K11, K12, K22, K33, nx, ny, gap, x, y, dx, area,
                           mu_static, mu_kinetic, contact_tol, max_sweeps, depth, table_approach, table_force,
                           table_pressure, table_displacement, static_pressure, creepage, speed,
                           time_step, load, delta_static, excitation, tolerance, max_iterations, runaway_factor,
                           force, creep_out, slip, wheel_u, rail_u, wheel_v, rail_v, iterations, work, failure):
    """Time stepping with the half-space contact model (transient rolling); fills the output arrays.

    The algorithm of interaction/simulate.py for a model that takes series compliances: the
    diagonal of the instantaneous compliance ``C = k0_wheel + k0_rail`` enters the contact
    problem (:func:`~interaction.contact.kernels.transient_rolling_step`); so does the
    dependence of the tangential inputs on the normal force (``C[0:2, 2]``), because each step
    solves the normal problem first. The remaining off-diagonal terms (the normal input's
    dependence on the tangential force) are iterated on from a linearly extrapolated force, each
    pass warm-started from the last, until they move the contact inputs by less than
    ``tolerance * load`` divided by the bound ``3 load / delta_static`` on the contact
    stiffness, or the force itself changes by less than ``tolerance * load``. The lateral force
    that the normal input needs is linearised about the iterate, ``Fy ~ fy + gamma (Fz - fz)``
    with ``gamma = Fy/Fz`` times the slip share of the previous step (exact in full sliding), and
    the part in Fz joins the normal problem's series compliance, so that in full sliding one pass
    usually suffices. The fixed point is that of the Python loop, which lags every off-diagonal
    term (tests compare the two).

    Parameters
    ----------
    z, weights, k0_wheel, rail_tail, k0_rail
        Structures, as for :func:`point_contact_loop`.
    K11, K12, K22, K33, nx, ny, gap, x, y, dx, area, mu_static, mu_kinetic
        The half-space model (see ``transient_rolling_step``); ``gap`` flat (nx ny,).
    contact_tol : float
        Relative tolerance of the contact solvers.
    max_sweeps, depth : int
        Tangential sweep limit and Anderson depth.
    table_approach, table_force, table_pressure, table_displacement : ndarray
        Normal solutions of the contact alone (``normal_solution_table``): the warm start of the
        first normal solution of each step (later passes start from the pass before).
    static_pressure : (nx ny,) ndarray
        Pressure at static equilibrium under the load (Pa), the state before the first step.
    creepage, speed, time_step, load, delta_static, excitation, tolerance, max_iterations, runaway_factor
        As for :func:`point_contact_loop`.
    force, creep_out, slip, wheel_u, rail_u, wheel_v, rail_v, iterations
        Outputs as for :func:`point_contact_loop`; ``slip`` is the share of the contact elements
        in slip.
    work : (nt, 2) int ndarray
        Output: normal-solver iterations and tangential sweeps of each step (all passes).
    failure : (1,) int ndarray
        Output: the reason of a failure (1 normal problem, 2 tangential problem not converged,
        3 contact at the grid edge, 4 force not finite or runaway, 5 coupling not converged).

    Returns
    -------
    int
        -1 when every step converged, else the failing step.
    """
    nt = force.shape[0]
    m = z.shape[0]
    nk = rail_tail.shape[0]
    n = nx * ny
    h = np.zeros((m, 3), dtype=np.complex128)
    buffer = np.zeros((2 * nk, 3))
    head = 0
    # contact states: slot 0 the committed state, slots 1 and 2 the passes of a step (alternating)
    pressure = np.zeros((3, n))
    normal_u = np.zeros((3, n))  # A p of the pressure, known where the gap is below u_threshold
    u_threshold = np.zeros(3)
    count = np.zeros(3, np.int64)
    cix = np.zeros((3, n), np.int64)
    ciy = np.zeros((3, n), np.int64)
    tx = np.zeros((3, n))
    ty = np.zeros((3, n))
    ux = np.zeros((3, n))
    uy = np.zeros((3, n))
    lookup = -np.ones((3, n), np.int64)
    for i in range(n):
        pressure[0, i] = static_pressure[i]
    compliance = k0_wheel + k0_rail
    series = np.zeros(3)
    rest = compliance.copy()
    for i in range(3):
        series[i] = compliance[i, i]
        rest[i, i] = 0.0
    # tangential inputs per newton of normal force, taken into the contact step (not iterated)
    per_force = np.array([rest[0, 2], rest[1, 2]]) / (time_step * speed)
    lagged = rest.copy()
    lagged[0, 2] = 0.0
    lagged[1, 2] = 0.0
    stiffness_bound = 3.0 * load / delta_static
    f_static = np.array([0.0, 0.0, load])
    f = f_static.copy()
    f_before = f_static.copy()
    uw_prev = np.zeros(3)
    ur_prev = np.zeros(3)
    hist = np.zeros(3)
    hist_w = np.zeros(3)
    hist_r = np.zeros(3)
    df = np.zeros(3)
    rel = np.zeros(3)
    imposed = np.zeros(3)
    imposed[2] = creepage[2]
    gamma = 0.0
    step_series = series.copy()
    new = np.zeros(3)
    for step in range(nt):
        _histories(weights, h, rail_tail, buffer, head, hist_w, hist_r)
        for i in range(3):
            hist[i] = hist_w[i] + hist_r[i]  # u_r = -(rail history + k0_r dF)
        if step >= 2:
            for i in range(3):
                f[i] = 2.0 * f[i] - f_before[i]
        warm = 0
        out = 1
        converged = False
        it = 0
        n_contact = 0
        n_slip = 0
        # the normal input's dependence on the lateral force, linearised with Fy ~ fy + gamma (Fz - fz):
        # its part in Fz joins the series compliance, the rest is iterated on
        step_series[2] = series[2] + lagged[2, 1] * gamma
        for it in range(1, max_iterations + 1):
            for i in range(3):
                acc = hist[i]
                for j in range(3):
                    acc += lagged[i, j] * (f[j] - f_static[j])
                rel[i] = acc  # x, y: at the normal force Q (the step adds per_force (Fz - Q))
            rel[2] -= lagged[2, 1] * gamma * f[2]
            approach = delta_static - rel[2] + series[2] * load + excitation[step]
            imposed[0] = creepage[0] + (rel[0] - (uw_prev[0] - ur_prev[0])) / (time_step * speed)
            imposed[1] = creepage[1] + (rel[1] - (uw_prev[1] - ur_prev[1])) / (time_step * speed)
            # the first pass starts the normal problem from the table, later ones from the pass before
            status, c, fx, fy, fz, ns, normal_its, sweeps, threshold = transient_rolling_step(
                K11, K12, K22, K33, nx, ny, gap, x, y, dx, area, mu_static, mu_kinetic, contact_tol, max_sweeps,
                depth, approach, imposed, per_force, load, step_series, table_approach, table_force, table_pressure,
                table_displacement, it == 1,
                count[0], cix[0], ciy[0], tx[0], ty[0], ux[0], uy[0], lookup[0],
                pressure[warm], normal_u[warm], u_threshold[warm], count[warm], cix[warm], ciy[warm], tx[warm],
                ty[warm], ux[warm], uy[warm], lookup[warm],
                pressure[out], normal_u[out], cix[out], ciy[out], tx[out], ty[out], ux[out], uy[out], lookup[out])
            u_threshold[out] = threshold
            work[step, 0] += normal_its
            work[step, 1] += sweeps
            if status != 0:
                iterations[step] = it
                failure[0] = status
                return step
            count[out] = c
            n_contact = c
            n_slip = ns
            new[0] = fx
            new[1] = fy
            new[2] = fz
            if not (np.isfinite(fx) and np.isfinite(fy) and np.isfinite(fz)) or \
                    max(abs(fx), abs(fy), abs(fz)) > runaway_factor * load:
                iterations[step] = it
                failure[0] = 4
                return step
            change = 0.0
            input_change = 0.0
            for i in range(3):
                change = max(change, abs(new[i] - f[i]))
                acc = 0.0
                for j in range(3):
                    acc += lagged[i, j] * (new[j] - f[j])
                if i == 2:
                    acc -= lagged[2, 1] * gamma * (new[2] - f[2])
                input_change = max(input_change, abs(acc) * stiffness_bound)
            for i in range(3):
                f[i] = new[i]
            warm = out
            out = 3 - out
            if change <= tolerance * load or input_change <= tolerance * load:
                converged = True
                break
        iterations[step] = it
        if not converged:
            failure[0] = 5
            return step
        # commit: the last pass becomes the state (slot ``warm`` holds it)
        for i in range(n):
            pressure[0, i] = pressure[warm, i]
            lookup[0, i] = lookup[warm, i]
        c = count[warm]
        count[0] = c
        for k in range(c):
            cix[0, k] = cix[warm, k]
            ciy[0, k] = ciy[warm, k]
            tx[0, k] = tx[warm, k]
            ty[0, k] = ty[warm, k]
            ux[0, k] = ux[warm, k]
            uy[0, k] = uy[warm, k]
        for k in range(3):
            f_before[k] = force[step - 1, k] if step >= 1 else f_static[k]
        _store_step(step, f, load, hist_w, hist_r, k0_wheel, k0_rail, uw_prev, ur_prev, time_step, speed, creepage,
                    df, force, creep_out, wheel_u, rail_u, wheel_v, rail_v)
        slip[step] = n_slip / n_contact if n_contact > 0 else 0.0
        # dFy/dFz for the next step: mu Fy/|Ft| = Fy/Fz in full sliding, none in stick
        gamma = f[1] / f[2] * slip[step] if f[2] > 0.0 else 0.0
        head = _commit(z, h, df, buffer, head)
    return -1
