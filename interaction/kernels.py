"""Numba kernels of the interaction (compiled lazily on first call, cached on disk).

:func:`point_contact_loop` and :func:`halfspace_contact_loop` are the whole time stepping of
interaction/simulate.py for the point and the half-space contact model, with the wheel as a
pole-residue recursion and the rail as a convolution (the same algorithm as the Python loop,
which remains the reference and serves every other combination of models). Both share the
structural histories and commits below and the same signature,
``loop(structures, contact, coupling, excitation, state, out, start, stop) -> int``, on the
bundles of interaction/bundles.py and interaction/contact/bundles.py: they run the steps
``[start, stop)`` and carry everything to the next call in ``state``, so a run may be split
into chunks. Nothing is compiled at import time.
"""

from __future__ import annotations

import numba
import numpy as np

from interaction.contact.bundles import COMMITTED, DenseTangential, RollingInputs
from interaction.contact.influence_kernels import dense_product, same_list
from interaction.contact.kernels_linalg import cholesky_solve, inner_product
from interaction.contact.point_kernels import point_contact_law_jacobian
from interaction.contact.rolling_kernels import transient_rolling_step
from interaction.creepage import total_creepage

RUNAWAY = 4
"""``LoopState.failure``: the force is not finite or exceeds the runaway bound."""
NOT_CONVERGED = 5
"""``LoopState.failure``: the coupling iteration did not converge."""


@numba.njit(cache=True)
def _histories(structures, state, hist_w, hist_r, step):
    """Wheel and rail displacements (3,) at ``step`` due to all earlier forces (m), in place.

    The wheel's from its recursion states ``state.wheel`` (m, 3) and weights (m, 3, 3); the
    rail's from the force buffer ``state.rail``, which holds every force twice so that the
    last ``nk`` forces, newest first, are the contiguous slice ``rail[head:head + nk]``, plus
    the forces beyond the near kernel, ``state.far`` (summed per block by FFT; zero when the
    kernel has no far part).
    """
    weights = structures.wheel_weights
    rail_rows = structures.rail_rows
    h = state.wheel
    buffer = state.rail
    head = state.head[0]
    m = h.shape[0]
    nk = rail_rows.shape[1] // 3
    for i in range(3):
        acc = 0.0
        for r in range(m):
            for j in range(3):
                acc += 2.0 * (weights[r, i, j] * h[r, j]).real
        hist_w[i] = acc
    # the rail's sum: kernel row i against the last nk forces, both flat and contiguous
    forces = buffer.reshape(-1)[3 * head:3 * (head + nk)]  # forces[3 q + j] = buffer[head + q, j]
    for i in range(3):
        hist_r[i] = inner_product(rail_rows[i], forces, 3 * nk)
    k = step - state.far_start[0]
    if 0 <= k < state.far.shape[0]:
        for i in range(3):
            hist_r[i] += state.far[k, i]


@numba.njit(cache=True)
def _commit(structures, state, df):
    """Advance the structures by one step with the force deviation ``df`` (3,).

    Wheel recursion ``h[n+1] = z (h[n] + dF[n])``; the rail buffer gets ``df`` as its newest force.
    """
    z = structures.wheel_z
    h = state.wheel
    buffer = state.rail
    for r in range(h.shape[0]):
        for j in range(3):
            h[r, j] = z[r] * (h[r, j] + df[j])
    nk = buffer.shape[0] // 2
    if nk == 0:
        return
    head = (state.head[0] - 1) % nk
    for j in range(3):
        buffer[head, j] = df[j]
        buffer[head + nk, j] = df[j]
    state.head[0] = head


@numba.njit(cache=True)
def _store_step(n, f, hist_w, hist_r, structures, coupling, state, df, out):
    """Write step n's outputs for the converged force ``f`` and move the previous displacements on.

    ``df`` (out) receives the force deviation of the step.
    """
    k0_wheel = structures.wheel_k0
    k0_rail = structures.rail_k0
    uw_prev = state.wheel_previous
    ur_prev = state.rail_previous
    time_step = coupling.time_step
    speed = coupling.speed
    creepage = coupling.creepage
    force = out.force
    wheel_u = out.wheel_displacement
    rail_u = out.rail_displacement
    df[0] = f[0]
    df[1] = f[1]
    df[2] = f[2] - coupling.load
    for i in range(3):
        uw = hist_w[i] + k0_wheel[i, 0] * df[0] + k0_wheel[i, 1] * df[1] + k0_wheel[i, 2] * df[2]
        ur = -(hist_r[i] + k0_rail[i, 0] * df[0] + k0_rail[i, 1] * df[1] + k0_rail[i, 2] * df[2])
        force[n, i] = f[i]
        wheel_u[n, i] = uw
        rail_u[n, i] = ur
        out.wheel_velocity[n, i] = (uw - uw_prev[i]) / time_step
        out.rail_velocity[n, i] = (ur - ur_prev[i]) / time_step
    for i in range(2):
        out.creepage[n, i] = total_creepage(creepage[i], (wheel_u[n, i] - uw_prev[i]) - (rail_u[n, i] - ur_prev[i]),
                                            time_step, speed, True)
    out.creepage[n, 2] = creepage[2]
    for i in range(3):
        uw_prev[i] = wheel_u[n, i]
        ur_prev[i] = rail_u[n, i]


@numba.njit(cache=True)
def _point_at(f, hist_w, hist_r, structures, coupling, state, excitation, law, new_state, jac, scratch):
    """The point contact's forces and slip fraction for the inputs that the trial force ``f`` (3,) gives.

    The contact's state after the step goes to ``new_state``; ``jac`` (3, 3) receives the law's
    d(Fx, Fy, Fn)/d(approach, ξ, η) there (``point_kernels.point_contact_law_jacobian``;
    ``scratch``: room for its trial states).
    """
    k0_wheel = structures.wheel_k0
    k0_rail = structures.rail_k0
    uw_prev = state.wheel_previous
    ur_prev = state.rail_previous
    time_step = coupling.time_step
    speed = coupling.speed
    creepage = coupling.creepage
    e = state.contact
    d0 = f[0]
    d1 = f[1]
    d2 = f[2] - coupling.load
    rel = np.empty(3)  # u_wheel - u_rail, less their previous values for x and y
    for i in range(3):
        uw = hist_w[i] + k0_wheel[i, 0] * d0 + k0_wheel[i, 1] * d1 + k0_wheel[i, 2] * d2
        ur = -(hist_r[i] + k0_rail[i, 0] * d0 + k0_rail[i, 1] * d1 + k0_rail[i, 2] * d2)
        rel[i] = (uw - uw_prev[i]) - (ur - ur_prev[i]) if i < 2 else uw - ur
    approach = coupling.static_approach - rel[2] + excitation
    xi_t = total_creepage(creepage[0], rel[0], time_step, speed, True)
    eta_t = total_creepage(creepage[1], rel[1], time_step, speed, True)
    return point_contact_law_jacobian(law, approach, xi_t, eta_t, creepage[2], e, new_state, jac, scratch)


@numba.njit(cache=True)
def _input_sensitivity(structures, coupling):
    """d(approach, ξ, η)/dF (3, 3) of the contact's inputs to the trial force (m/N, 1/N, 1/N).

    Through the instantaneous compliance ``C = k_w[0] + k_r[0]`` of the relative displacement:
    the approach falls by ``C[2] dF``, the creepages rise by ``C[0:2] dF / (Δt v)``.
    """
    out = np.empty((3, 3))
    scale = 1.0 / (coupling.time_step * coupling.speed)
    for j in range(3):
        c0 = structures.wheel_k0[0, j] + structures.rail_k0[0, j]
        c1 = structures.wheel_k0[1, j] + structures.rail_k0[1, j]
        c2 = structures.wheel_k0[2, j] + structures.rail_k0[2, j]
        out[0, j] = -c2
        out[1, j] = c0 * scale
        out[2, j] = c1 * scale
    return out


@numba.njit(cache=True)
def _solve3(m, r, x):
    """``x = -m^-1 r`` for a 3 x 3 ``m`` by Cramer's rule, in place; False (x untouched) if singular."""
    c00 = m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1]
    c01 = m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2]
    c02 = m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0]
    det = m[0, 0] * c00 + m[0, 1] * c01 + m[0, 2] * c02
    if not (det != 0.0 and np.isfinite(det)):
        return False
    inv = -1.0 / det
    x0 = inv * (c00 * r[0] + (m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2]) * r[1]
                + (m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]) * r[2])
    x1 = inv * (c01 * r[0] + (m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0]) * r[1]
                + (m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]) * r[2])
    x2 = inv * (c02 * r[0] + (m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1]) * r[1]
                + (m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]) * r[2])
    if not (np.isfinite(x0) and np.isfinite(x1) and np.isfinite(x2)):
        return False
    x[0] = x0
    x[1] = x1
    x[2] = x2
    return True


#: Halvings of a Newton step of the point loop's coupling before it is taken as it is.
MAX_HALVINGS = 12


@numba.njit(cache=True)
def point_contact_loop(structures, law, coupling, excitation, state, out, start, stop):
    """Time stepping with the point contact model over the steps ``[start, stop)``; fills ``out``.

    The coupling ``F = G(F)`` of each step (``G``: the contact's force for the inputs that the
    trial force gives) is solved by Newton's method from the linear extrapolation of the last two
    forces, with the Jacobian ``J_law D - I`` from the law's own derivatives ``J_law``
    (``point_kernels.point_contact_law_jacobian``, from the same evaluation) and the inputs'
    sensitivity ``D`` (:func:`_input_sensitivity`). A step after which the residual grows is
    halved (up to :data:`MAX_HALVINGS` times); a singular Jacobian gives a fixed-point step.
    The strip model's force is piecewise smooth in the trial force (elements switch between
    stick and slip), so the steps are those of a semismooth Newton method.

    Parameters
    ----------
    structures : Structures
        Wheel recursion and rail convolution (interaction/bundles.py).
    law : PointLaw
        The point-contact law (interaction/contact/bundles.py).
    coupling : Coupling
        Imposed creepages, speed, time step, load, static approach and the coupling settings.
    excitation : (nt,) ndarray
        Extra approach per step, m.
    state : LoopState
        Carried state (in and out); its ``contact`` is the point law's state
        (``point_kernels.point_contact_law``: relaxation states, then strip displacements).
    out : Histories
        Outputs; ``slip_fraction`` as the point law gives it; ``iterations`` counts the law's
        evaluations of each step.
    start, stop : int
        Steps to run.

    Returns
    -------
    int
        -1 when every step converged, else the failing step (``state.failure[0]`` holds the
        reason, :data:`RUNAWAY` or :data:`NOT_CONVERGED`; the outputs hold the values up to
        that step).
    """
    load = coupling.load
    tolerance = coupling.tolerance
    runaway_factor = coupling.runaway_factor
    max_iterations = coupling.max_iterations
    f = state.force
    e = state.contact
    trial_state = np.zeros(e.shape[0])
    scratch = np.zeros(e.shape[0])
    iterations = out.iterations
    hist_w = np.zeros(3)
    hist_r = np.zeros(3)
    df = np.zeros(3)
    jac_law = np.zeros((3, 3))
    jac = np.zeros((3, 3))
    sensitivity = _input_sensitivity(structures, coupling)
    base = np.zeros(3)
    step = np.zeros(3)
    residual = np.zeros(3)
    coef = np.zeros((3, PREDICTION_ORDER))
    mean = np.zeros(3)
    use = np.zeros(3, np.int64)
    fitted_at = -1
    for n in range(start, stop):
        _histories(structures, state, hist_w, hist_r, n)
        if n >= 2:  # start from the linear extrapolation of the last two forces, or the prediction
            for i in range(3):
                f[i] = 2.0 * out.force[n - 1, i] - out.force[n - 2, i]
        fitted_at = _predict_force(out.force, n, f, coef, mean, use, fitted_at)
        converged = False
        it = 0
        last = np.inf
        halvings = 0
        fx = fy = fn = slip = 0.0
        for it in range(1, max_iterations + 1):
            fx, fy, fn, slip = _point_at(f, hist_w, hist_r, structures, coupling, state, excitation[n], law,
                                         trial_state, jac_law, scratch)
            if not (np.isfinite(fx) and np.isfinite(fy) and np.isfinite(fn)) or max(abs(fx), abs(fy), abs(fn)) > runaway_factor * load:
                iterations[n] = it
                state.failure[0] = RUNAWAY
                return n
            residual[0] = fx - f[0]
            residual[1] = fy - f[1]
            residual[2] = fn - f[2]
            size = max(abs(residual[0]), abs(residual[1]), abs(residual[2]))
            if size <= tolerance * load:
                f[0], f[1], f[2] = fx, fy, fn
                converged = True
                break
            if size >= last and halvings < MAX_HALVINGS:  # the last step overshot: back along it
                halvings += 1
                for i in range(3):
                    step[i] *= 0.5
                    f[i] = base[i] + step[i]
                continue
            halvings = 0
            last = size
            # Newton: (J_law D - I) step = -(G(f) - f)
            for i in range(3):
                for j in range(3):
                    acc = -1.0 if i == j else 0.0
                    for k in range(3):
                        acc += jac_law[i, k] * sensitivity[k, j]
                    jac[i, j] = acc
            if not _solve3(jac, residual, step):  # singular: a fixed-point step
                for i in range(3):
                    step[i] = residual[i]
            for i in range(3):
                base[i] = f[i]
                f[i] += step[i]
        iterations[n] = it
        if not converged:
            state.failure[0] = NOT_CONVERGED
            return n
        _store_step(n, f, hist_w, hist_r, structures, coupling, state, df, out)
        out.slip_fraction[n] = slip if fn > 0.0 else 0.0
        e[:] = trial_state
        _commit(structures, state, df)
    return -1


PREDICTION_ORDER = 30
"""Past forces that the linear prediction of the half-space loop's first coupling pass combines."""
PREDICTION_WINDOW = 300
"""Steps over which the prediction's coefficients are fitted (least squares)."""
PREDICTION_REFIT = 32
"""Steps between fits of the prediction: its coefficients at step n are fitted on the forces
before the last multiple of this at or below n (the same for any split of a run into chunks)."""


@numba.njit(cache=True)
def _fit_prediction(force, end, coef, mean, use):
    """Fit the linear prediction of each force direction on the forces ``force[:end]`` (N).

    Per direction j, the model ``y[n] - c = sum_k a_k (y[n - k] - c)`` (k = 1 ..
    :data:`PREDICTION_ORDER`, c the mean of the forces used) is fitted by least squares (normal
    equations, Cholesky, regularised by 1e-12 of their trace) to the targets of the last
    :data:`PREDICTION_WINDOW` steps before ``end``. A constant plus h sinusoids obeys such a
    recursion exactly for an order of at least 2 h + 1, so a limit cycle of a few harmonics is predicted far
    better than by linear extrapolation ``2 y[n - 1] - y[n - 2]``. ``coef[j]`` receives a_k,
    ``mean[j]`` c, and ``use[j]`` 1 where the model's root-mean-square one-step error over the
    window is below the extrapolation's (0: extrapolate). Needs ``end >= window + order``.
    """
    order = coef.shape[1]
    window = PREDICTION_WINDOW
    gram = np.empty((order, order))
    rhs = np.empty(order)
    y = np.empty(window + order)  # y[k]: the force at step end - window - order + k, less the mean
    base = end - window - order
    for j in range(3):
        use[j] = 0
        c = 0.0
        for n in range(base, end):
            c += force[n, j]
        c /= window + order
        mean[j] = c
        for k in range(window + order):
            y[k] = force[base + k, j] - c
        # the targets are y[order:], lag a the same window shifted back by 1 + a: rhs and the first
        # column of the normal matrix are inner products of shifted windows, and each further entry
        # follows from its upper-left neighbour by one product in and one out (the window slides)
        target = y[order:]
        first = y[order - 1:order - 1 + window]
        for a in range(order):
            lagged = y[order - 1 - a:order - 1 - a + window]
            rhs[a] = inner_product(lagged, target, window)
            gram[a, 0] = inner_product(lagged, first, window)
        for b in range(order - 1):
            for a in range(b, order - 1):
                gram[a + 1, b + 1] = (gram[a, b] + y[order - 2 - a] * y[order - 2 - b]
                                      - y[order + window - 2 - a] * y[order + window - 2 - b])
        trace = 0.0
        for a in range(order):
            trace += gram[a, a]
        if not trace > 0.0:
            continue
        for a in range(order):  # regularised normal equations
            gram[a, a] += 1e-12 * trace
        if not cholesky_solve(gram, rhs, order):
            continue
        fit_error = 0.0
        extrapolation_error = 0.0
        for k in range(order, order + window):
            model = 0.0
            for a in range(order):
                model += rhs[a] * y[k - 1 - a]
            fit_error += (y[k] - model) ** 2
            extrapolation_error += (y[k] - 2.0 * y[k - 1] + y[k - 2]) ** 2
        for a in range(order):
            coef[j, a] = rhs[a]
        if fit_error < extrapolation_error:
            use[j] = 1


@numba.njit(cache=True)
def _predicted(force, step, j, coef, mean):
    """Force of direction ``j`` at ``step`` (N) predicted from ``force[:step]`` (:func:`_fit_prediction`)."""
    acc = mean[j]
    for a in range(coef.shape[1]):
        acc += coef[j, a] * (force[step - 1 - a, j] - mean[j])
    return acc


@numba.njit(cache=True)
def _predict_force(force, step, f, coef, mean, use, fitted_at):
    """The trial force ``f`` (3,) of ``step``'s first coupling pass from the linear prediction, in place.

    Refits the prediction (:func:`_fit_prediction`) on the forces before the last multiple of
    :data:`PREDICTION_REFIT` at or below ``step`` when that differs from ``fitted_at`` and enough
    steps exist; then replaces ``f[j]`` by the prediction in the directions where it is in use
    (elsewhere ``f`` keeps the caller's linear extrapolation). Returns the step the coefficients
    were fitted at (-1: not yet).
    """
    fit_end = step - step % PREDICTION_REFIT
    if fit_end < PREDICTION_WINDOW + PREDICTION_ORDER:
        return fitted_at
    if fitted_at != fit_end:
        _fit_prediction(force, fit_end, coef, mean, use)
        fitted_at = fit_end
    for i in range(3):
        if use[i]:
            f[i] = _predicted(force, step, i, coef, mean)
    return fitted_at


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
    ``P(m) = sum_a coef[j, a] y[m - a]``: the force's linear recursion (:func:`_fit_prediction`)
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
    problem (:func:`~interaction.contact.rolling_kernels.transient_rolling_step`); so does the
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
    a linear prediction of order :data:`PREDICTION_ORDER` (:func:`_fit_prediction`): in a
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
        The half-space model (interaction/contact/bundles.py); its table of normal solutions of
        the contact alone warm-starts the first normal solution of each step (later passes start
        from the pass before).
    coupling : Coupling
        As for :func:`point_contact_loop`.
    excitation : (nt,) ndarray
        Extra approach per step, m.
    state : LoopState
        Carried state (in and out); its ``contact`` is an
        :class:`~interaction.contact.bundles.ElementStates` whose committed slot holds the state
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
        _histories(structures, state, hist_w, hist_r, step)
        for i in range(3):
            hist[i] = hist_w[i] + hist_r[i]  # u_r = -(rail history + k0_r dF)
        if step >= 2:
            for i in range(3):
                f[i] = 2.0 * f[i] - f_before[i]
        fitted_at = _predict_force(force, step, f, coef, mean, use, fitted_at)
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
        _store_step(step, f, hist_w, hist_r, structures, coupling, state, df, out)
        out.slip_fraction[step] = n_slip / n_contact if n_contact > 0 else 0.0
        # dFy/dFz for the next step: mu Fy/|Ft| = Fy/Fz in full sliding, none in stick
        gamma = f[1] / f[2] * out.slip_fraction[step] if f[2] > 0.0 else 0.0
        _commit(structures, state, df)
    state.gamma[0] = gamma
    return -1
