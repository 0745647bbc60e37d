"""The compiled time loop of the interaction with the point model (numba, compiled lazily, cached on disk).

:func:`point_contact_loop` is the whole time stepping of interaction/simulate.py for the point
contact (the Python loop remains the reference): the wheel as a pole-residue recursion, the rail
as a convolution, and each step's coupling solved by Newton's method with the law's own Jacobian.
Signature and bundles as every compiled loop (interaction/loop_steps.py, whose shared steps it
calls): ``loop(structures, law, coupling, excitation, state, out, start, stop) -> int``.
"""

from __future__ import annotations

import numba
import numpy as np

from contact.point.kernels import point_contact_law_jacobian
from interaction.creepage import total_creepage
from interaction.loop_steps import (NOT_CONVERGED, PREDICTION_ORDER, RUNAWAY, commit_step, input_sensitivity,
                                    predict_force, solve3, store_step, structural_histories)


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


MAX_HALVINGS = 12


@numba.njit(cache=True)
def point_contact_loop(structures, law, coupling, excitation, state, out, start, stop):
    """Time stepping with the point contact model over the steps ``[start, stop)``; fills ``out``.

    The coupling ``F = G(F)`` of each step (``G``: the contact's force for the inputs that the
    trial force gives) is solved by Newton's method from the linear extrapolation of the last two
    forces, with the Jacobian ``J_law D - I`` from the law's own derivatives ``J_law``
    (``point_kernels.point_contact_law_jacobian``, from the same evaluation) and the inputs'
    sensitivity ``D`` (:func:`input_sensitivity`). A step after which the residual grows is
    halved (up to :data:`MAX_HALVINGS` times); a singular Jacobian gives a fixed-point step.
    The strip model's force is piecewise smooth in the trial force (elements switch between
    stick and slip), so the steps are those of a semismooth Newton method.

    Parameters
    ----------
    structures : Structures
        Wheel recursion and rail convolution (interaction/bundles.py).
    law : PointLaw
        The point-contact law (contact/halfspace/bundles.py).
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
    sensitivity = input_sensitivity(structures, coupling)
    base = np.zeros(3)
    step = np.zeros(3)
    residual = np.zeros(3)
    coef = np.zeros((3, PREDICTION_ORDER))
    mean = np.zeros(3)
    use = np.zeros(3, np.int64)
    fitted_at = -1
    for n in range(start, stop):
        structural_histories(structures, state, hist_w, hist_r, n)
        if n >= 2:  # start from the linear extrapolation of the last two forces, or the prediction
            for i in range(3):
                f[i] = 2.0 * out.force[n - 1, i] - out.force[n - 2, i]
        fitted_at = predict_force(out.force, n, f, coef, mean, use, fitted_at)
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
            if not solve3(jac, residual, step):  # singular: a fixed-point step
                for i in range(3):
                    step[i] = residual[i]
            for i in range(3):
                base[i] = f[i]
                f[i] += step[i]
        iterations[n] = it
        if not converged:
            state.failure[0] = NOT_CONVERGED
            return n
        store_step(n, f, hist_w, hist_r, structures, coupling, state, df, out)
        out.slip_fraction[n] = slip if fn > 0.0 else 0.0
        e[:] = trial_state
        commit_step(structures, state, df)
    return -1
