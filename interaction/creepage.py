"""The total creepage of a time step: the imposed one plus the structural part.

The contact sees the imposed creepages (ξ, η, φ) of the case (:func:`stages.cases.imposed_creepage`:
the study's ξ and η, and the hand-set or the computed contact's geometric spin) plus the
structural creepages that the motion of wheel and rail adds: the relative displacement
``Δu = u_wheel - u_rail`` along x and y changes by ``slip`` over the step, a relative velocity
``slip / Δt`` (backward difference), which over the rolling speed ``v`` is a creepage
(docs/design.md §4.5). The spin has no structural part here.

:func:`total_creepage` is the one place that formula is written: the Python time loop
(:mod:`interaction.simulate`, the contact's inputs and the stored creepages) calls it from
Python, the compiled loops (``contact/*/loop.py``: the stored creepages, the point
contact's and the half-space contact's inputs) from their kernels.
"""

from __future__ import annotations

import numba

__all__ = ["total_creepage"]


@numba.njit(cache=True)
def total_creepage(imposed, slip, time_step, speed, velocity_first=False):
    """ξ or η of one step: ``imposed + slip / (Δt v)``.

    Parameters
    ----------
    imposed : float
        The imposed creepage (-).
    slip : float
        Change of the relative displacement ``u_wheel - u_rail`` over the step, m.
    time_step, speed : float
        Δt (s) and the rolling speed v (m/s).
    velocity_first : bool
        Divide by Δt first (the relative velocity), then by v, instead of by the distance
        rolled in the step ``Δt v``. The same quantity, rounded differently in the last bit:
        the compiled point loop and the stored creepages of the compiled loops have always
        done so, the Python loop and the half-space loop's contact inputs not; both kept so
        that results stay the same bit for bit.

    Returns
    -------
    float
    """
    if velocity_first:
        return imposed + slip / time_step / speed
    return imposed + slip / (time_step * speed)
