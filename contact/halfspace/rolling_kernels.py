"""The half-space model's transient rolling step, compiled (lazily, cached on disk).

:func:`transient_rolling_step` is the step of the interaction's compiled time loop
(contact/halfspace/loop.py): the normal problem, warm-started from a table of normal solutions of
the contact alone (:func:`normal_solution_table`) and solved by
:func:`~contact.halfspace.normal_kernels.normal_conjugate_gradient`, then the tangential
problem by Gauss-Seidel sweeps with a carried mixing memory
(:func:`~contact.halfspace.tangential_kernels.gauss_seidel_with_memory`), the states held as
lists of the elements in contact (the bundles of contact/halfspace/bundles.py). Nothing is
compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np

from contact.halfspace.anderson_kernels import continue_history
from contact.halfspace.bundles import NormalProblem, TangentialProblem, Tractions
from contact.halfspace.influence_kernels import build_upstream_rows, contact_rows, flat_tangential, same_list
from contact.kernels_linalg import inner_product
from contact.halfspace.normal_kernels import normal_conjugate_gradient
from contact.halfspace.tangential_kernels import gauss_seidel_with_memory


@numba.njit(cache=True)
def normal_solution_table(influence, grid, gap, approaches, tol):
    """Normal solutions of the contact alone at the given approaches (m), each warm-started from the last.

    The normal problem of quasi-identical bodies depends on the approach alone, so these
    solutions give any later solution a warm start with nearly the right contact area
    (:func:`transient_rolling_step`).

    Parameters
    ----------
    influence : Influence
        Influence coefficients of the grid (K33 is used), m/Pa.
    grid : GridGeometry
        The grid (nx, ny and the element area are used).
    gap : ndarray (nx ny,)
        Undeformed gap, m, flat in C order.
    approaches : ndarray (m,)
        Ascending approaches, m.
    tol : float
        Relative tolerance of the solutions (-).

    Returns
    -------
    pressure : ndarray (len(approaches), nx ny)
        Pa.
    displacement : ndarray (len(approaches), nx ny)
        Normal displacement difference ``A p`` on the whole grid, m.
    force : ndarray (len(approaches),)
        Normal forces, N.
    ok : bool
        Every solution converged.
    """
    area = grid.area
    n = grid.nx * grid.ny
    m = approaches.shape[0]
    pressure = np.zeros((m, n))
    displacement = np.zeros((m, n))
    force = np.zeros(m)
    p = np.zeros(n)
    ok = True
    for k in range(m):
        warm = False
        for i in range(n):
            if p[i] > 0.0:
                warm = True
                break
        if not warm:
            for i in range(n):
                if gap[i] < approaches[k]:
                    p[i] = 1.0
                    warm = True
        if warm:
            _, _, converged, u, _ = normal_conjugate_gradient(
                influence.K33, NormalProblem(gap, p, False, approaches[k], 0.0, area, tol, 1000, True), True)
            ok = ok and converged
            for i in range(n):
                displacement[k, i] = u[i]
        total = 0.0
        for i in range(n):
            pressure[k, i] = p[i]
            total += p[i]
        force[k] = total * area
    return pressure, displacement, force, ok


@numba.njit(cache=True)
def _table_warm_start(table, approach, series, out, out_displacement):
    """Warm start of the normal problem for a total ``approach`` (m) with series compliance ``series`` (m/N).

    Interpolates the tabulated solutions of the contact alone, pressure (Pa) into ``out`` and
    displacement (m) into ``out_displacement``, at the own approach d that solves
    ``d + series F(d) = approach`` (increasing in d; F interpolated linearly), from the
    :class:`~contact.halfspace.bundles.NormalTable` ``table``.
    """
    table_approach = table.approach
    table_force = table.force
    table_pressure = table.pressure
    table_displacement = table.displacement
    m = table_approach.shape[0]
    lo = 0
    hi = m - 1
    if table_approach[hi] + series * table_force[hi] <= approach:
        lo = hi - 1
    else:
        while hi - lo > 1:
            mid = (lo + hi) // 2
            if table_approach[mid] + series * table_force[mid] <= approach:
                lo = mid
            else:
                hi = mid
    g_lo = table_approach[lo] + series * table_force[lo] - approach
    g_hi = table_approach[lo + 1] + series * table_force[lo + 1] - approach
    theta = g_lo / (g_lo - g_hi) if g_hi != g_lo else 0.0
    theta = min(max(theta, 0.0), 1.0)
    for i in range(out.shape[0]):
        out[i] = (1.0 - theta) * table_pressure[lo, i] + theta * table_pressure[lo + 1, i]
        out_displacement[i] = (1.0 - theta) * table_displacement[lo, i] + theta * table_displacement[lo + 1, i]


@numba.njit(cache=True)
def _tangential_displacement_at(operator, ix, iy, src_ix, src_iy, src_tx, src_ty, sources):
    """Tangential displacement difference (m) at element (ix, iy) of the source tractions listed in ``sources``.

    ``operator`` (FlatTangential) holds the influence coefficients; the sources are the elements
    ``(src_ix[j], src_iy[j])`` with tractions ``(src_tx[j], src_ty[j])`` (Pa) for j in ``sources``.
    """
    f11 = operator.f11
    f12 = operator.f12
    f22 = operator.f22
    my = operator.row
    ox = operator.ox
    oy = operator.oy
    ux = 0.0
    uy = 0.0
    for jj in range(sources.shape[0]):
        j = sources[jj]
        k = (ix - src_ix[j] + ox) * my + (iy - src_iy[j] + oy)
        k12 = f12[k]
        ux += f11[k] * src_tx[j] + k12 * src_ty[j]
        uy += k12 * src_tx[j] + f22[k] * src_ty[j]
    return ux, uy


@numba.njit(cache=True)
def transient_rolling_step(inputs, step, states, committed, warm, out):
    """One transient rolling step of the half-space model, all compiled (the interaction's time loop).

    The same problem as :meth:`HalfspaceContact.solve` with ``kind="transient"``, a prescribed
    approach and series compliances (contact/halfspace/model.py documents it), with the
    states held as lists of the elements in contact instead of full-grid fields: for each, the
    tractions and the tangential displacement difference at those elements. The displacement
    of a state at other elements (the particles entering the contact, elements that join it) is
    summed directly from its tractions.

    Parameters
    ----------
    inputs : HalfspaceInputs
        The model (influence coefficients, grid, gap, friction, solver settings, table of normal
        solutions; contact/halfspace/bundles.py).
    step : RollingInputs
        Approach, creepages and series compliances of this solution.
    states : ElementStates
        Contact states; slot ``committed`` holds the committed state of the previous step,
        slot ``warm`` the warm start (the committed state or an earlier solution of this step),
        slot ``out`` receives the result (all but its ``count`` and ``threshold``, which the
        caller stores from the returned values once the solution is accepted).
    committed, warm, out : int
        Slots of ``states``.

    Returns
    -------
    (status, count, fx, fy, fz, n_slip, normal_iterations, sweeps, threshold) : tuple
        ``status`` 0 converged, 1 normal problem not converged, 2 tangential problem not
        converged, 3 the contact area reaches the grid edge; ``count`` elements in contact (the
        result's list length), forces on the wheel (N), elements in slip, the normal solver's
        iterations, the tangential sweeps, and the gap bound (m) below which the result's
        ``normal_u`` holds.
    """
    K33 = inputs.influence.K33
    nx = inputs.grid.nx
    ny = inputs.grid.ny
    x = inputs.grid.x
    y = inputs.grid.y
    dx = inputs.grid.dx
    area = inputs.grid.area
    gap = inputs.gap
    mu_static = inputs.friction.static
    mu_kinetic = inputs.friction.kinetic
    tol = inputs.solver.tol
    max_sweeps = inputs.solver.max_sweeps
    depth = inputs.solver.anderson_depth
    approach = step.approach
    creepage = step.creepage
    creepage_per_force = step.creepage_per_force
    force_reference = step.force_reference
    series = step.series
    use_table = step.use_table
    s_count = states.count[committed]
    s_ix = states.ix[committed]
    s_iy = states.iy[committed]
    s_tx = states.tx[committed]
    s_ty = states.ty[committed]
    s_ux = states.ux[committed]
    s_uy = states.uy[committed]
    s_lookup = states.lookup[committed]
    w_pressure = states.pressure[warm]
    w_normal_u = states.normal_u[warm]
    w_threshold = states.threshold[warm]
    w_count = states.count[warm]
    w_ix = states.ix[warm]
    w_iy = states.iy[warm]
    w_tx = states.tx[warm]
    w_ty = states.ty[warm]
    w_ux = states.ux[warm]
    w_uy = states.uy[warm]
    w_lookup = states.lookup[warm]
    r_pressure = states.pressure[out]
    r_normal_u = states.normal_u[out]
    r_ix = states.ix[out]
    r_iy = states.iy[out]
    r_tx = states.tx[out]
    r_ty = states.ty[out]
    r_ux = states.ux[out]
    r_uy = states.uy[out]
    r_status = states.status[out]
    r_lookup = states.lookup[out]
    n = nx * ny
    operator = flat_tangential(inputs.influence)
    u_warm = w_normal_u
    u_threshold = w_threshold
    if use_table and approach > 0.0:
        u_warm = np.empty(n)
        u_threshold = np.inf
        _table_warm_start(inputs.table, approach, series[2], r_pressure, u_warm)
    else:
        for i in range(n):
            r_pressure[i] = w_pressure[i]
    for i in range(n):
        r_lookup[i] = -1
    warm = False
    for i in range(n):
        if r_pressure[i] > 0.0:
            warm = True
            break
    if not warm and approach > 0.0:
        # cold start (after lift-off): unit pressure where the approach closes the gap, which the
        # solver first rescales to the approach
        for i in range(n):
            if gap[i] < approach:
                r_pressure[i] = 1.0
                warm = True
    iterations = 0
    threshold = np.inf  # r_normal_u is A p where the gap is below it
    if warm and approach > 0.0:
        if u_warm.shape[0] == n and not use_table:
            for i in range(n):
                if r_pressure[i] != w_pressure[i]:  # the cold start replaced the warm state
                    u_warm = np.empty(0)
                    break
        iterations, _, converged, u, threshold = normal_conjugate_gradient(
            K33, NormalProblem(gap, r_pressure, False, approach, series[2] * area, area, tol, 1000, warm), False,
            u_warm, u_threshold)
        if not converged:
            return 1, 0, 0.0, 0.0, 0.0, 0, iterations, 0, threshold
        for i in range(n):
            r_normal_u[i] = u[i]
    else:
        for i in range(n):
            r_pressure[i] = 0.0
            r_normal_u[i] = 0.0
    # elements in contact, in sweep order: leading edge (large x) first
    count = 0
    pmax = 0.0
    fz = 0.0
    for ix in range(nx - 1, -1, -1):
        for iy in range(ny):
            i = ix * ny + iy
            pz = r_pressure[i]
            if pz > 0.0:
                if ix == 0 or ix == nx - 1 or iy == 0 or iy == ny - 1:
                    return 3, 0, 0.0, 0.0, 0.0, 0, iterations, 0, threshold
                r_ix[count] = ix
                r_iy[count] = iy
                r_lookup[i] = count
                count += 1
                pmax = max(pmax, pz)
                fz += pz
    fz *= area
    if count == 0:
        return 0, 0, 0.0, 0.0, 0.0, 0, iterations, 0, threshold
    cix = r_ix[:count]
    ciy = r_iy[:count]
    wx = np.empty(count)
    wy = np.empty(count)
    upx = np.empty(count)
    upy = np.empty(count)
    gs = np.empty(count)
    gk = np.empty(count)
    every_s = np.arange(s_count)
    # warm-start elements out of contact now, and those still in contact
    n_dropped = 0
    for j in range(w_count):
        if r_lookup[w_ix[j] * ny + w_iy[j]] < 0:
            n_dropped += 1
    dropped = np.empty(n_dropped, np.int64)
    kept = np.empty(w_count - n_dropped, np.int64)
    a = 0
    b = 0
    for j in range(w_count):
        if r_lookup[w_ix[j] * ny + w_iy[j]] < 0:
            dropped[a] = j
            a += 1
        else:
            kept[b] = j
            b += 1
    # the last step's displacement upstream of the leading edge from rows, while its list is the cached one
    upstream = states.upstream
    rows_upstream = upstream.count[0] >= 0 and same_list(states.rows, s_ix[:s_count], s_iy[:s_count])
    xi = creepage[0] + creepage_per_force[0] * (fz - force_reference)
    eta = creepage[1] + creepage_per_force[1] * (fz - force_reference)
    phi = creepage[2]
    for c in range(count):
        ix = cix[c]
        iy = ciy[c]
        pz = r_pressure[ix * ny + iy]
        gs[c] = mu_static * pz
        gk[c] = mu_kinetic * pz
        wx[c] = (xi - phi * y[iy]) * dx
        wy[c] = (eta + phi * x[ix]) * dx
        # u': the previous displacement of the particle now here, one element upstream
        j = s_lookup[(ix + 1) * ny + iy]
        if j >= 0:
            upx[c] = s_ux[j]
            upy[c] = s_uy[j]
        else:
            row = -1
            if rows_upstream:
                j = s_lookup[ix * ny + iy]
                if j >= 0:
                    row = upstream.position[j]
            if row >= 0:
                base = row * s_count
                r11 = upstream.m11[base:base + s_count]
                r12 = upstream.m12[base:base + s_count]
                r22 = upstream.m22[base:base + s_count]
                upx[c] = inner_product(r11, s_tx, s_count) + inner_product(r12, s_ty, s_count)
                upy[c] = inner_product(r12, s_tx, s_count) + inner_product(r22, s_ty, s_count)
            else:
                upx[c], upy[c] = _tangential_displacement_at(operator, ix + 1, iy, s_ix, s_iy, s_tx, s_ty,
                                                             every_s)
        # warm start: the warm state's tractions where still in contact, with their displacement
        j = w_lookup[ix * ny + iy]
        if j >= 0:
            r_tx[c] = w_tx[j]
            r_ty[c] = w_ty[j]
            r_ux[c] = w_ux[j]
            r_uy[c] = w_uy[j]
            if n_dropped > 0:
                ax, ay = _tangential_displacement_at(operator, ix, iy, w_ix, w_iy, w_tx, w_ty, dropped)
                r_ux[c] -= ax
                r_uy[c] -= ay
        else:
            r_tx[c] = 0.0
            r_ty[c] = 0.0
            r_ux[c], r_uy[c] = _tangential_displacement_at(operator, ix, iy, w_ix, w_iy, w_tx, w_ty, kept)
    scale = pmax * min(max(mu_static, 1e-3), 1.0)
    px = r_tx[:count]
    py = r_ty[:count]
    ux = r_ux[:count]
    uy = r_uy[:count]
    # the mixing's memory and the dense rows belong to the last contact list: kept while it stays
    same = same_list(states.rows, cix, ciy)
    continue_history(states.mixing, same)
    rows = contact_rows(operator, cix, ciy, states.rows)
    if not same:
        if rows.count == count:
            build_upstream_rows(operator, cix, ciy, r_lookup, ny, upstream)
        else:
            upstream.count[0] = -1
    sweeps, change, status = gauss_seidel_with_memory(
        inputs.influence, TangentialProblem(cix, ciy, wx, wy, upx, upy, gs, gk, inputs.friction.law), Tractions(px, py, ux, uy), tol * scale,
        max_sweeps, (series[0] * area, series[1] * area), rows, states.mixing, depth)
    if change > tol * scale:
        return 2, count, 0.0, 0.0, 0.0, 0, iterations, sweeps, threshold
    fx = 0.0
    fy = 0.0
    n_slip = 0
    for c in range(count):
        fx += px[c]
        fy += py[c]
        r_status[c] = status[c]
        if status[c] == 2:
            n_slip += 1
    return 0, count, fx * area, fy * area, fz, n_slip, iterations, sweeps, threshold
