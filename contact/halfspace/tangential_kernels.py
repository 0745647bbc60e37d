"""Gauss-Seidel solution of the tangential contact problem, compiled (lazily, cached on disk).

:func:`tangential_gauss_seidel` is the element-by-element (Gauss-Seidel) solution of the
tangential problem with Coulomb friction, in the spirit of Kalker's ConvexGS, accelerated by
Anderson mixing (anderson_kernels.py; :func:`gauss_seidel_with_memory` the same with a given
mixing memory, which the time loop carries from step to step). One sweep is
:func:`tangential_sweep`: the friction law of each element (friction_kernels.py), its traction
change applied to the displacements of the others, exactly (from dense rows of the influence
coefficients for contact lists of up to ``bundles.DENSE_MAX_CONTACT`` elements,
influence_kernels.py) or to its neighbours only (local_sweep_kernels.py). Also the gather of a
stand-alone problem from grid fields (:func:`gather_tangential_problem`) and the scatter of its
solution. The kernels take the bundles of contact/halfspace/bundles.py
(:class:`~contact.halfspace.bundles.TangentialProblem`,
:class:`~contact.halfspace.bundles.Tractions`,
:class:`~contact.halfspace.bundles.FlatTangential`). Nothing is compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np

from contact.halfspace.anderson_kernels import anderson_history, anderson_input, anderson_mix
from contact.halfspace.bundles import LocalUpdates, SweepCompliance, TangentialProblem, Tractions
from contact.friction_kernels import element_law, element_law_characteristic
from contact.friction_law import CONSTANT
from contact.halfspace.influence_kernels import add_dense_row, flat_tangential


SWEEP_SKIP = 0.1
"""A Gauss-Seidel sweep of :func:`gauss_seidel_with_memory` leaves an element's traction as it is
when its update would change it by at most this many tolerances (so its O(n) update of the
other elements' displacements is saved). The stopping test is unchanged: a sweep whose applied
changes are all within the tolerance ends the iteration, and a skipped update is smaller still,
so the solution satisfies the friction law to the tolerance either way. It matters in the sweep
that confirms a mixed one, whose updates are mostly a small fraction of the tolerance
(docs/benchmarks.md, *The half-space time loop*, measures the time saved)."""


CARRY_LIMIT = 1e4
"""A memory carried into a solution (:func:`continue_history`) is dropped if the first sweep
changes a traction by more than this many tolerances: the carried differences were taken near
the last solution and extrapolate a much larger residual badly (from a zero start, a carried
memory stopped 60-1000 tolerances from the solution, against one for a fresh memory)."""


@numba.njit(cache=True)
def tangential_sweep(operator, problem, flat, tractions, compliance, total, skip, status, updates, rows):
    """One Gauss-Seidel sweep over the contact elements (see :func:`tangential_gauss_seidel`).

    Parameters
    ----------
    operator : FlatTangential
        The tangential influence coefficients (m/Pa).
    problem : TangentialProblem
        The contact elements; ``static_bound`` is lowered in place where an element slides.
    flat : (nc,) int64 ndarray
        ``problem.ix * operator.row + problem.iy``.
    tractions : Tractions
        Tractions (Pa) and displacement differences (m), updated in place.
    compliance : SweepCompliance
        Own and series compliances, m/Pa.
    total : (2,) ndarray
        Summed tractions (Pa), updated in place.
    skip : float
        Traction changes up to this (Pa) are not applied.
    status : (nc,) int8 ndarray
        Out: 1 stick, 2 slip.
    updates : LocalUpdates
        Empty (:func:`no_local_updates`): after a traction change the displacement of every
        contact element is updated (the exact sweep). Else (:func:`local_updates`) only at the
        contact elements within a few grid lines of the changed one, the rest of the coupling
        being left to an exact product after the sweep (contact/halfspace/transient_fft.py);
        the series springs' term is global and stays exact.
    rows : DenseTangential
        With exact updates and ``rows.count == nc``: the exact updates read these dense rows
        (the same coefficients as ``operator``; bit-identical results, faster). Else
        :func:`no_dense_rows`.

    Returns
    -------
    float
        The largest traction change of the sweep, Pa.
    """
    f11 = operator.f11
    f12 = operator.f12
    f22 = operator.f22
    my = operator.row
    ox = operator.ox
    oy = operator.oy
    cix = problem.ix
    wx = problem.slip_x
    wy = problem.slip_y
    upx = problem.previous_x
    upy = problem.previous_y
    gs = problem.static_bound
    gk = problem.kinetic_bound
    law = problem.law
    coulomb = law.kind == CONSTANT
    px = tractions.px
    py = tractions.py
    ux = tractions.ux
    uy = tractions.uy
    dxx = compliance.dxx
    dyy = compliance.dyy
    series_x = compliance.series_x
    series_y = compliance.series_y
    nc = cix.shape[0]
    neighbours = updates.neighbours
    exact = neighbours.shape[0] == 0
    s11 = updates.stencil[0]
    s12 = updates.stencil[1]
    s22 = updates.stencil[2]
    change = 0.0
    total_x = total[0]
    total_y = total[1]
    for c in range(nc):
        sx = wx[c] + ux[c] - upx[c] + series_x * total_x
        sy = wy[c] + uy[c] - upy[c] + series_y * total_y
        if coulomb:
            qx, qy, sliding = element_law(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c])
        else:  # a characteristic of the slip: a continuous law, the stick bound stays at rest's
            qx, qy, sliding = element_law_characteristic(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c], law)
        status[c] = 2 if sliding else 1
        if sliding and coulomb:
            gs[c] = gk[c]  # once sliding, kinetic friction bounds a return to stick
        dpx = qx - px[c]
        dpy = qy - py[c]
        if abs(dpx) > skip or abs(dpy) > skip:
            px[c] = qx
            py[c] = qy
            total_x += dpx
            total_y += dpy
            if exact and rows.count == nc:
                add_dense_row(rows, c, dpx, dpy, ux, uy)
            elif exact:
                off = np.uint64(ox * my + oy - flat[c])  # unsigned indices: no wraparound test, the loop vectorises
                for t in range(nc):
                    k = np.uint64(flat[t]) + off
                    k12 = f12[k]
                    ux[t] += f11[k] * dpx + k12 * dpy
                    uy[t] += k12 * dpx + f22[k] * dpy
            else:
                near = neighbours[c]
                for q in range(near.shape[0]):
                    t = near[q]
                    if t >= 0:
                        ux[t] += s11[q] * dpx + s12[q] * dpy
                        uy[t] += s12[q] * dpx + s22[q] * dpy
            m = max(abs(dpx), abs(dpy))
            if m > change:
                change = m
    total[0] = total_x
    total[1] = total_y
    return change


@numba.njit(cache=True)
def no_local_updates():
    """Empty :class:`~contact.halfspace.bundles.LocalUpdates`: the sweep updates every contact element (exact)."""
    return LocalUpdates(np.empty((0, 0), np.int64), np.empty((3, 0)))


@numba.njit(cache=True)
def gather_tangential_problem(pressure, rigid_slip, previous, upstream, warm, warm_displacement, static, kinetic,
                              law):
    """A transient or shift tangential problem gathered from grid fields, its contact elements in sweep order.

    The sweep order is the exact sweeps': lines of constant x from the leading edge (large x)
    to the trailing edge, each along increasing y.

    Parameters
    ----------
    pressure : (nx, ny) ndarray
        Pressure (Pa); the contact is where it is > 0.
    rigid_slip : (nx, ny, 2) ndarray
        Rigid slip over the step (m).
    previous : (nx, ny, 2) ndarray
        Previous displacement field (m); an empty (0, 0, 2) array for zero.
    upstream : int
        1 (transient rolling): an element's previous displacement is that of the element
        upstream (``ix + 1``); 0 (shift): its own.
    warm, warm_displacement : (nx, ny, 2) ndarray
        Warm-start tractions (Pa) and their displacement (m); empty (0, 0, 2) arrays for none.
    static, kinetic : float
        Friction coefficients.
    law : FrictionLaw
        The kinetic coefficient's factor of the slip (``TangentialProblem.law``).

    Returns
    -------
    problem : TangentialProblem
        Empty lists with ``status`` 1 if the contact reaches the grid's leading line in
        transient rolling (no element upstream there).
    tractions : Tractions
        The warm start at the contact elements; its displacements are ``warm_displacement``'s,
        valid only if ``status`` is 0 (given, and the warm tractions are zero outside the
        contact, so they are those of the contact's tractions).
    status : int
        0 the warm displacements hold, 2 they must be computed from the tractions, 1 as above.
    """
    nx, ny = pressure.shape
    count = 0
    for ix in range(nx):
        for iy in range(ny):
            if pressure[ix, iy] > 0.0:
                count += 1
                if upstream == 1 and ix == nx - 1:
                    empty = np.empty(0)
                    index = np.empty(0, np.int64)
                    return (TangentialProblem(index, index, empty, empty, empty, empty, empty, empty, law),
                            Tractions(empty, empty, empty, empty), 1)
    cix = np.empty(count, np.int64)
    ciy = np.empty(count, np.int64)
    wx = np.empty(count)
    wy = np.empty(count)
    upx = np.zeros(count)
    upy = np.zeros(count)
    gs = np.empty(count)
    gk = np.empty(count)
    px = np.zeros(count)
    py = np.zeros(count)
    ux = np.zeros(count)
    uy = np.zeros(count)
    have_previous = previous.shape[0] > 0
    have_warm = warm.shape[0] > 0
    c = 0
    for ix in range(nx - 1, -1, -1):
        for iy in range(ny):
            pz = pressure[ix, iy]
            if pz > 0.0:
                cix[c] = ix
                ciy[c] = iy
                wx[c] = rigid_slip[ix, iy, 0]
                wy[c] = rigid_slip[ix, iy, 1]
                if have_previous:
                    upx[c] = previous[ix + upstream, iy, 0]
                    upy[c] = previous[ix + upstream, iy, 1]
                gs[c] = static * pz
                gk[c] = kinetic * pz
                if have_warm:
                    px[c] = warm[ix, iy, 0]
                    py[c] = warm[ix, iy, 1]
                c += 1
    status = 2
    if have_warm and warm_displacement.shape[0] > 0:
        status = 0
        for ix in range(nx):
            for iy in range(ny):
                if pressure[ix, iy] <= 0.0 and (warm[ix, iy, 0] != 0.0 or warm[ix, iy, 1] != 0.0):
                    status = 2
        if status == 0:
            for c in range(count):
                ux[c] = warm_displacement[cix[c], ciy[c], 0]
                uy[c] = warm_displacement[cix[c], ciy[c], 1]
    return TangentialProblem(cix, ciy, wx, wy, upx, upy, gs, gk, law), Tractions(px, py, ux, uy), status


@numba.njit(cache=True)
def gather_pair_at(field, cix, ciy, a, b):
    """``a, b <- field[cix, ciy, 0], field[cix, ciy, 1]`` for a (nx, ny, 2) field."""
    for c in range(cix.shape[0]):
        a[c] = field[cix[c], ciy[c], 0]
        b[c] = field[cix[c], ciy[c], 1]


@numba.njit(cache=True)
def scatter_pair_at(field, cix, ciy, a, b):
    """``field[cix, ciy, 0], field[cix, ciy, 1] <- a, b`` for a (nx, ny, 2) field (the rest left as it is)."""
    for c in range(cix.shape[0]):
        field[cix[c], ciy[c], 0] = a[c]
        field[cix[c], ciy[c], 1] = b[c]


@numba.njit(cache=True)
def scatter_solution(cix, ciy, px, py, status, traction, grid_status):
    """``traction[cix, ciy] <- (px, py)`` and ``grid_status[cix, ciy] <- status`` (the rest left as it is)."""
    scatter_pair_at(traction, cix, ciy, px, py)
    for c in range(cix.shape[0]):
        grid_status[cix[c], ciy[c]] = status[c]


@numba.njit(cache=True)
def sum_tractions(px, py, total):
    """``total <- (sum px, sum py)`` (Pa): the summed tractions that the series springs see."""
    total[0] = 0.0
    total[1] = 0.0
    for c in range(px.shape[0]):
        total[0] += px[c]
        total[1] += py[c]


@numba.njit(cache=True)
def tangential_gauss_seidel(influence, problem, tractions, tol, max_sweeps, series, depth, rows):
    """Gauss-Seidel sweeps, Anderson-accelerated, for the tangential tractions of the contact elements.

    :func:`gauss_seidel_with_memory` with a fresh Anderson memory (its documentation holds the
    parameters and returns).
    """
    nc = problem.ix.shape[0]
    return gauss_seidel_with_memory(influence, problem, tractions, tol, max_sweeps, series, rows,
                                    anderson_history(depth, nc, nc), depth)


@numba.njit(cache=True)
def gauss_seidel_with_memory(influence, problem, tractions, tol, max_sweeps, series, rows, history, depth):
    """Gauss-Seidel sweeps, Anderson-accelerated, for the tangential tractions of the contact elements.

    Each sweep visits the contact elements in order and solves each one's local problem with the
    others fixed: stick if the traction that cancels its slip is within the static bound, else
    the slip traction on the kinetic bound (Kalker's / Vollebregt's ConvexGS idea). The sweep is
    a fixed-point map ``x -> G(x)`` of the tractions; type-II Anderson mixing over the last
    ``depth`` sweeps (``x <- G(x_k) - sum_j gamma_j (G(x_j+1) - G(x_j))``, gamma the least-squares
    fit of the residuals ``G(x) - x``) cuts the sweeps (by how much: docs/benchmarks.md, *The
    half-space time loop*). The displacements are affine in
    the tractions, so they are mixed with the same coefficients and stay consistent. The result
    is always the output of a plain sweep, so it satisfies the friction bounds, and convergence
    is judged on that sweep's change. A mixing step that makes the next change grow restarts
    the history.

    Parameters
    ----------
    influence : Influence
        Influence coefficients of the grid (contact/halfspace/bundles.py); K11, K12, K22
        (2 nx - 1, 2 ny - 1), m/Pa.
    problem : TangentialProblem
        The contact elements in sweep order (leading edge first), their rigid slip, previous
        displacements and traction bounds. The static bound is lowered to the kinetic one in
        place where an element slides (hysteresis: this keeps the iteration monotone, and
        convergent, when mu_s > mu_k).
    tractions : Tractions
        Tractions (Pa), initial guess in, solution out, and the displacement differences (m) of
        the contact elements, consistent with the tractions on entry; updated in place.
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps : int
        Limit of sweeps.
    series : (float, float)
        Compliances of springs in series with the contact along x and y (e.g. the structures'
        instantaneous compliance) times the element area (m/Pa): every element's slip gains
        ``series * sum(p)``, the displacement of the springs under the total force. Zero for the
        contact alone.
    rows : DenseTangential
        The influence coefficients between the contact elements as dense rows
        (:func:`contact_rows`; the same numbers, faster), or :func:`no_dense_rows`: the sweeps
        then index the kernels directly.
    history : AndersonHistory
        The mixing's memory (:func:`anderson_history` for at least nc elements), empty or carried
        from an earlier solution of the same contact list (:func:`carried_anderson_history`,
        :func:`continue_history`); updated in place. A carried memory is dropped if the first
        sweep changes a traction by more than :data:`CARRY_LIMIT` tolerances.
    depth : int
        0: plain Gauss-Seidel sweeps, no mixing; else the memory's ring holds its own number of
        sweeps.

    Returns
    -------
    sweeps : int
        Sweeps done.
    change : float
        Largest traction change (Pa) in the last sweep.
    status : int8 ndarray (nc,)
        1 stick, 2 slip.
    """
    K11 = influence.K11
    K22 = influence.K22
    cix = problem.ix
    ciy = problem.iy
    px = tractions.px
    py = tractions.py
    ux = tractions.ux
    uy = tractions.uy
    series_x, series_y = series
    nc = cix.shape[0]
    status = np.ones(nc, np.int8)
    operator = flat_tangential(influence)
    ox = operator.ox
    oy = operator.oy
    my = operator.row
    compliance = SweepCompliance(K11[ox, oy] + series_x, K22[ox, oy] + series_y, series_x, series_y)
    total = np.zeros(2)  # sum of the tractions (Pa): the series springs' displacement is series * total
    sum_tractions(px, py, total)
    skip = SWEEP_SKIP * tol  # changes this small are not applied (below the tolerance)
    flat = cix * my + ciy
    exact = no_local_updates()
    change = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        anderson_input(history, px, py)
        change = tangential_sweep(operator, problem, flat, tractions, compliance, total, skip, status, exact, rows)
        sweeps = sweep + 1
        if change <= tol:
            break
        if depth == 0:
            continue
        if sweep == 0 and change > CARRY_LIMIT * tol:
            # far from the solution: the carried differences (taken near the last one) would
            # extrapolate the much larger residual, so they are dropped
            history.counters[0] = 0
            history.counters[1] = -1
        if anderson_mix(history, change, px, py, ux, uy):
            sum_tractions(px, py, total)
    return sweeps, change, status
