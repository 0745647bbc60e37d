"""The compiled time loop of the interaction with the half-space model (numba, compiled lazily, cached on disk).

:func:`halfspace_contact_loop` is the whole time stepping of interaction/simulate.py for the
half-space contact (the Python loop remains the reference): each pass of a step is the model's
transient rolling step (``rolling_kernels.transient_rolling_step``), warm-started from the last
committed element states or, where it pays, from tractions predicted with the force's
recursion. Signature and bundles as every compiled loop (interaction/loop_steps.py, whose shared
steps it calls): ``loop(structures, inputs, coupling, excitation, state, out, start, stop) -> int``.
"""

from __future__ import annotations

import numba
import numpy as np

from contact.halfspace.bundles import COMMITTED, DenseTangential, RollingInputs
from contact.halfspace.influence_kernels import dense_product, same_list
from contact.halfspace.rolling_kernels import transient_rolling_step
from interaction.creepage import total_creepage
from interaction.loop_steps import (NOT_CONVERGED, PREDICTION_ORDER, PREDICTION_REFIT, RUNAWAY,
                                    commit_step, predict_force, store_step, structural_histories)


PREDICTION_GAIN = 0.01
"""The first pass's starting tractions are predicted in a window of :data:`PREDICTION_REFIT`
steps only where, at its start, the prediction's squared error one step earlier is below this share
of the last step's tractions' (:func:`_traction_prediction_pays`): a limit cycle, not a steady
or noisy contact, where the prediction's cost would not be repaid by fewer sweeps."""


PREDICTION_MIN_SWEEPS = 4.0
"""Tangential sweeps per step (all passes) that the last window must have taken for the starting
tractions of the next to be predicted (:func:`_traction_prediction_pays`): with the mixing memory
carried (a steady contact list) a step takes two or three sweeps, too few for a start that costs
about one product over the list to pay."""


@numba.njit(cache=True)
def _record_tractions(states, step, ny):
    """Store the committed tangential tractions (Pa) of ``step`` in row ``step % TRACTION_HISTORY`` of ``states.history``."""
    row = states.history[step % states.history.shape[0]]
    n = row.shape[0] // 2
    for i in range(2 * n):
        row[i] = 0.0
    ix = states.ix[COMMITTED]
    iy = states.iy[COMMITTED]
    tx = states.tx[COMMITTED]
    ty = states.ty[COMMITTED]
    for k in range(states.count[COMMITTED]):
        i = ix[k] * ny + iy[k]
        row[i] = tx[k]
        row[n + i] = ty[k]


@numba.njit(cache=True)
def _lagged_sum(history, coef, newest, offset, flat, count, out):
    """``out[k] = sum_a coef[a] y[newest - a]`` at history entry ``offset + flat[k]``, for k < count (Pa)."""
    depth = history.shape[0]
    for k in range(count):
        out[k] = 0.0
    for a in range(coef.shape[0]):
        row = history[(newest - a) % depth]
        ca = coef[a]
        for k in range(count):
            out[k] += ca * row[offset + flat[k]]


@numba.njit(cache=True)
def _traction_prediction_pays(states, step, coef, use, ny, sweeps):
    """Decide, at the start of a window of steps, in which directions to predict the starting tractions.

    The starting tractions of ``step`` would be predicted per element of the committed list and
    direction j (x, y) with the force's coefficients ``coef[j]`` (:func:`_predicted_start`). The
    same prediction one step earlier, ``y[s-2] + P(s-2) - P(s-3)`` with ``P(m) = sum_a coef[a]
    y[m - a]``, is compared with the committed tractions ``y[s-1]`` (sum of squares over the list)
    and so is the last step's start, ``y[s-2]``: direction j is predicted in this window where the
    force's prediction is in use (``use[j]``) and the first error is below :data:`PREDICTION_GAIN`
    times the second, and where the last :data:`PREDICTION_REFIT` steps took at least
    :data:`PREDICTION_MIN_SWEEPS` tangential sweeps per step (``sweeps``: per step, all passes).
    Writes ``states.prediction[1:]`` (x, y; the caller stores the window in ``states.prediction[0]``).
    """
    history = states.history
    n = history.shape[1] // 2
    depth = history.shape[0]
    count = states.count[COMMITTED]
    states.prediction[1] = 0
    states.prediction[2] = 0
    if count == 0 or step < max(depth, PREDICTION_REFIT) or coef.shape[1] + 2 > depth:
        return
    recent = 0.0
    for m in range(step - PREDICTION_REFIT, step):
        recent += sweeps[m]
    if recent < PREDICTION_MIN_SWEEPS * PREDICTION_REFIT:
        return
    flat = states.ix[COMMITTED, :count] * ny + states.iy[COMMITTED, :count]
    before = np.empty(count)
    older = np.empty(count)
    last = history[(step - 1) % depth]
    previous = history[(step - 2) % depth]
    for j in range(2):
        if not use[j]:
            continue
        _lagged_sum(history, coef[j], step - 2, j * n, flat, count, before)
        _lagged_sum(history, coef[j], step - 3, j * n, flat, count, older)
        error = 0.0
        warm_error = 0.0
        for k in range(count):
            i = j * n + flat[k]
            error += (previous[i] + before[k] - older[k] - last[i]) ** 2
            warm_error += (previous[i] - last[i]) ** 2
        if error < PREDICTION_GAIN * warm_error:
            states.prediction[1 + j] = 1


@numba.njit(cache=True)
def _predicted_start(states, step, coef, ny, slot):
    """Write into ``slot`` of ``states`` the committed state with predicted tangential tractions; True if done.

    In each direction j that :func:`_traction_prediction_pays` chose, the traction y of each
    element of the committed list is predicted as ``y[s] = y[s-1] + P(s-1) - P(s-2)``,
    ``P(m) = sum_a coef[j, a] y[m - a]``: the force's linear recursion (:func:`fit_prediction`)
    applied to the element's traction, whose own constant cancels (a limit cycle's traction at a
    grid element, which stays under the contact while the material rolls through, is a constant
    plus the same harmonics as the force). The displacement differences of the predicted tractions
    are the dense product over the list, so the start is consistent. Needs the dense rows of the
    committed list in ``states.rows`` (else nothing is written and False returned).
    """
    count = states.count[COMMITTED]
    s_ix = states.ix[COMMITTED, :count]
    s_iy = states.iy[COMMITTED, :count]
    if count == 0 or not same_list(states.rows, s_ix, s_iy):
        return False
    history = states.history
    n = history.shape[1] // 2
    flat = s_ix * ny + s_iy
    now = np.empty(count)
    before = np.empty(count)
    for j in range(2):
        target = states.tx[slot] if j == 0 else states.ty[slot]
        committed = states.tx[COMMITTED] if j == 0 else states.ty[COMMITTED]
        if states.prediction[1 + j]:
            _lagged_sum(history, coef[j], step - 1, j * n, flat, count, now)
            _lagged_sum(history, coef[j], step - 2, j * n, flat, count, before)
            for k in range(count):
                target[k] = committed[k] + now[k] - before[k]
        else:
            for k in range(count):
                target[k] = committed[k]
    cache = states.rows
    dense_product(DenseTangential(cache.m11, cache.m12, cache.m22, count), states.tx[slot], states.ty[slot],
                  states.ux[slot], states.uy[slot])
    for k in range(count):
        states.ix[slot, k] = s_ix[k]
        states.iy[slot, k] = s_iy[k]
        states.status[slot, k] = states.status[COMMITTED, k]
    states.count[slot] = count
    states.threshold[slot] = states.threshold[COMMITTED]
    lookup = states.lookup[slot]
    pressure = states.pressure[slot]
    normal_u = states.normal_u[slot]
    for i in range(lookup.shape[0]):
        lookup[i] = states.lookup[COMMITTED, i]
        pressure[i] = states.pressure[COMMITTED, i]
        normal_u[i] = states.normal_u[COMMITTED, i]
    return True


@numba.njit(cache=True)
def halfspace_contact_loop(structures, inputs, coupling, excitation, state, out, start, stop):
    """Time stepping with the half-space contact model (transient rolling) over ``[start, stop)``; fills ``out``.

    The algorithm of interaction/simulate.py for a model that takes series compliances: the
    diagonal of the instantaneous compliance ``C = k0_wheel + k0_rail`` enters the contact
    problem (:func:`~contact.halfspace.rolling_kernels.transient_rolling_step`); so does the
    dependence of the tangential inputs on the normal force (``C[0:2, 2]``), because each step
    solves the normal problem first. The remaining off-diagonal terms (the normal input's
    dependence on the tangential force) are iterated on from a predicted force, each pass
    warm-started from the last, until they move the contact inputs by less than
    ``tolerance * load`` divided by the bound ``3 load / delta_static`` on the contact
    stiffness, or the force itself changes by less than ``tolerance * load``. The lateral force
    that the normal input needs is linearised about the iterate, ``Fy ~ fy + gamma (Fz - fz)``
    with ``gamma = Fy/Fz`` times the slip share of the previous step (exact in full sliding), and
    the part in Fz joins the normal problem's series compliance, so that in full sliding one pass
    usually suffices. The predicted force is the linear extrapolation from the last two steps
    (as in the Python loop) or, where it fits the last :data:`PREDICTION_WINDOW` steps better,
    a linear prediction of order :data:`PREDICTION_ORDER` (:func:`fit_prediction`): in a
    5 kHz limit cycle (5.5 steps per period) the extrapolation misses the lateral force by about
    its amplitude and a second pass was needed in most steps, the prediction by about 1 N. It
    changes the first trial only, not the stopping test. In windows of :data:`PREDICTION_REFIT`
    steps where the contact is in a limit cycle, the first pass's tangential solution also starts
    from tractions predicted per element with the same recursion (:func:`_predicted_start`,
    decided by :func:`_traction_prediction_pays`); the committed tractions of the last
    ``TRACTION_HISTORY`` steps are recorded in the element states for it. The fixed point is
    that of the Python loop, which lags every off-diagonal term (tests compare the two).

    Parameters
    ----------
    structures : Structures
        As for :func:`point_contact_loop`.
    inputs : HalfspaceInputs
        The half-space model (contact/halfspace/bundles.py); its table of normal solutions of
        the contact alone warm-starts the first normal solution of each step (later passes start
        from the pass before).
    coupling : Coupling
        As for :func:`point_contact_loop`.
    excitation : (nt,) ndarray
        Extra approach per step, m.
    state : LoopState
        Carried state (in and out); its ``contact`` is an
        :class:`~contact.halfspace.bundles.ElementStates` whose committed slot holds the state
        of the last step (at the start of a run: the pressure at static equilibrium under the
        load, no tractions).
    out : Histories
        Outputs as for :func:`point_contact_loop`; ``slip_fraction`` is the share of the contact
        elements in slip, ``work`` the normal-solver iterations and tangential sweeps of each
        step (all passes).
    start, stop : int
        Steps to run.

    Returns
    -------
    int
        -1 when every step converged, else the failing step; ``state.failure[0]`` holds the
        reason: 1 normal problem, 2 tangential problem not converged, 3 contact at the grid
        edge (``transient_rolling_step``), :data:`RUNAWAY`, :data:`NOT_CONVERGED`.
    """
    load = coupling.load
    time_step = coupling.time_step
    speed = coupling.speed
    creepage = coupling.creepage
    delta_static = coupling.static_approach
    tolerance = coupling.tolerance
    max_iterations = coupling.max_iterations
    runaway_factor = coupling.runaway_factor
    states = state.contact
    count = states.count
    u_threshold = states.threshold
    pressure = states.pressure
    lookup = states.lookup
    work = out.work
    iterations = out.iterations
    force = out.force
    n = inputs.grid.nx * inputs.grid.ny
    ny = inputs.grid.ny
    uw_prev = state.wheel_previous
    ur_prev = state.rail_previous
    compliance = structures.wheel_k0 + structures.rail_k0
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
    f = state.force
    f_before = state.force_before
    hist = np.zeros(3)
    hist_w = np.zeros(3)
    hist_r = np.zeros(3)
    df = np.zeros(3)
    rel = np.zeros(3)
    imposed = np.zeros(3)
    imposed[2] = creepage[2]
    gamma = state.gamma[0]
    step_series = series.copy()
    new = np.zeros(3)
    # linear prediction of the force (the first pass's trial force), refitted every PREDICTION_REFIT steps
    coef = np.zeros((3, PREDICTION_ORDER))
    mean = np.zeros(3)
    use = np.zeros(3, np.int64)
    fitted_at = -1
    for step in range(start, stop):
        structural_histories(structures, state, hist_w, hist_r, step)
        for i in range(3):
            hist[i] = hist_w[i] + hist_r[i]  # u_r = -(rail history + k0_r dF)
        if step >= 2:
            for i in range(3):
                f[i] = 2.0 * f[i] - f_before[i]
        fitted_at = predict_force(force, step, f, coef, mean, use, fitted_at)
        fit_end = step - step % PREDICTION_REFIT
        warm = COMMITTED
        result = 1
        if fitted_at >= 0:
            # the first pass's starting tractions: predicted in the windows where that pays (a limit cycle)
            if states.prediction[0] != fit_end:
                _traction_prediction_pays(states, step, coef, use, ny, work[:, 1])
                states.prediction[0] = fit_end
            if (states.prediction[1] or states.prediction[2]) and _predicted_start(states, step, coef, ny, 2):
                warm = 2
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
            imposed[0] = total_creepage(creepage[0], rel[0] - (uw_prev[0] - ur_prev[0]), time_step, speed, False)
            imposed[1] = total_creepage(creepage[1], rel[1] - (uw_prev[1] - ur_prev[1]), time_step, speed, False)
            # the first pass starts the normal problem from the table, later ones from the pass before
            status, c, fx, fy, fz, ns, normal_its, sweeps, threshold = transient_rolling_step(
                inputs, RollingInputs(approach, imposed, per_force, load, step_series, it == 1), states, COMMITTED,
                warm, result)
            u_threshold[result] = threshold
            work[step, 0] += normal_its
            work[step, 1] += sweeps
            if status != 0:
                iterations[step] = it
                state.failure[0] = status
                state.gamma[0] = gamma
                return step
            count[result] = c
            n_contact = c
            n_slip = ns
            new[0] = fx
            new[1] = fy
            new[2] = fz
            if not (np.isfinite(fx) and np.isfinite(fy) and np.isfinite(fz)) or \
                    max(abs(fx), abs(fy), abs(fz)) > runaway_factor * load:
                iterations[step] = it
                state.failure[0] = RUNAWAY
                state.gamma[0] = gamma
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
            warm = result
            result = 3 - result
            if change <= tolerance * load or input_change <= tolerance * load:
                converged = True
                break
        iterations[step] = it
        if not converged:
            state.failure[0] = NOT_CONVERGED
            state.gamma[0] = gamma
            return step
        # commit: the last pass becomes the state (slot ``warm`` holds it)
        for i in range(n):
            pressure[COMMITTED, i] = pressure[warm, i]
            lookup[COMMITTED, i] = lookup[warm, i]
        c = count[warm]
        count[COMMITTED] = c
        for k in range(c):
            states.ix[COMMITTED, k] = states.ix[warm, k]
            states.iy[COMMITTED, k] = states.iy[warm, k]
            states.tx[COMMITTED, k] = states.tx[warm, k]
            states.ty[COMMITTED, k] = states.ty[warm, k]
            states.ux[COMMITTED, k] = states.ux[warm, k]
            states.uy[COMMITTED, k] = states.uy[warm, k]
            states.status[COMMITTED, k] = states.status[warm, k]
        for k in range(3):
            f_before[k] = force[step - 1, k] if step >= 1 else f_static[k]
        _record_tractions(states, step, ny)
        store_step(step, f, hist_w, hist_r, structures, coupling, state, df, out)
        out.slip_fraction[step] = n_slip / n_contact if n_contact > 0 else 0.0
        # dFy/dFz for the next step: mu Fy/|Ft| = Fy/Fz in full sliding, none in stick
        gamma = f[1] / f[2] * out.slip_fraction[step] if f[2] > 0.0 else 0.0
        commit_step(structures, state, df)
    state.gamma[0] = gamma
    return -1
