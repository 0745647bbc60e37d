r"""Friction characteristics: a friction coefficient constant, or falling or rising with the sliding speed.

Three characteristics (:data:`CHARACTERISTICS`), each a function ``μ(v)`` of the sliding speed
``v >= 0`` (m/s):

- ``constant``: Coulomb friction, ``μ = μ_k`` in sliding and the static bound ``μ_s`` in stick
  (the models' law before issue 35 item 4, unchanged bit for bit);
- ``exponential``: the falling law ``μ(v) = μ_k + (μ_s - μ_k) exp(-v / v_ref)``, i.e.
  ``μ_s [(1 - λ) e^{-κ v} + λ]`` with ``λ = μ_k / μ_s`` and ``κ = 1 / v_ref``, the form of the
  squeal models of Huang, Thompson and Jones and of their followers (a static coefficient at
  rest decaying to the kinetic one over the reference speed);
- ``linear``: ``μ(v) = max(μ_0 (1 + s v), 0)`` with the slope ``s`` (s/m): positive for a
  friction modifier (a rising characteristic), negative for a linearly falling one.

Every characteristic is written as a base coefficient times a factor of the speed,
``μ(v) = μ_base φ(v)`` (:meth:`~contact.params.Friction.law`): ``μ_base = μ_k`` and
``φ = 1 + (μ_s/μ_k - 1) e^{-v/v_ref}`` (exponential), ``μ_base = μ_0`` and ``φ = max(1 + s v, 0)``
(linear), ``φ = 1`` (constant). The compiled laws take ``φ`` as a :class:`FrictionLaw` bundle
whose rate is per unit of the quantity they measure the sliding with: per m/s in the point model
(the contact's sliding speed), per metre of slip over one time step in the half-space model
(the element's slip ``σ`` over ``Δt``: ``v = σ / Δt``). The kernels are in
:mod:`contact.friction_kernels`. This module imports numpy only.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

__all__ = ["CHARACTERISTICS", "CONSTANT", "EXPONENTIAL", "LINEAR", "FrictionLaw", "CONSTANT_LAW",
           "sliding_factor", "sliding_factor_slope", "scaled"]

#: The friction characteristics, in the order of their codes.
CHARACTERISTICS = ("constant", "exponential", "linear")
#: :attr:`FrictionLaw.kind` codes.
CONSTANT, EXPONENTIAL, LINEAR = 0, 1, 2


class FrictionLaw(NamedTuple):
    """The speed dependence of a friction characteristic, ``φ`` of ``μ = μ_base φ`` (numba bundle).

    Attributes
    ----------
    kind : int
        :data:`CONSTANT` (``φ = 1``), :data:`EXPONENTIAL` (``φ = 1 + amplitude e^{-rate x}``) or
        :data:`LINEAR` (``φ = max(1 + rate x, 0)``).
    amplitude : float
        ``μ_s / μ_k - 1`` of the exponential law (-); 0 otherwise.
    rate : float
        ``1 / v_ref`` (exponential) or the slope ``s`` (linear), per unit of the sliding measure
        ``x``: s/m for a speed, 1/m for a slip over one time step.
    """

    kind: int
    amplitude: float
    rate: float


#: The law of a constant characteristic.
CONSTANT_LAW = FrictionLaw(CONSTANT, 0.0, 0.0)


def sliding_factor(law: FrictionLaw, x):
    """``φ(x)`` of a :class:`FrictionLaw` at sliding measures ``x >= 0`` (numpy; the kernels' twin).

    Parameters
    ----------
    law : FrictionLaw
    x : float or ndarray
        Sliding speed (m/s) or slip (m), in the unit of ``law.rate``'s inverse.

    Returns
    -------
    float or ndarray
        The factor (-).
    """
    x = np.abs(np.asarray(x, dtype=float))
    if law.kind == EXPONENTIAL:
        return 1.0 + law.amplitude * np.exp(-law.rate * x)
    if law.kind == LINEAR:
        return np.maximum(1.0 + law.rate * x, 0.0)
    return np.ones_like(x)


def sliding_factor_slope(law: FrictionLaw, x):
    """``dφ/dx`` at sliding measures ``x >= 0`` (per unit of ``x``; 0 where the linear law is clipped).

    Parameters
    ----------
    law : FrictionLaw
    x : float or ndarray
        Sliding speed (m/s) or slip (m).

    Returns
    -------
    float or ndarray
        The slope, s/m or 1/m.
    """
    x = np.abs(np.asarray(x, dtype=float))
    if law.kind == EXPONENTIAL:
        return -law.amplitude * law.rate * np.exp(-law.rate * x)
    if law.kind == LINEAR:
        return np.where(1.0 + law.rate * x > 0.0, law.rate, 0.0)
    return np.zeros_like(x)


def scaled(law: FrictionLaw, per_unit: float) -> FrictionLaw:
    """The same law with its rate per another measure: ``x_new = x / per_unit``.

    E.g. ``scaled(law, 1 / Δt)`` measures the sliding by the slip over a time step ``Δt``
    (``v = σ / Δt``) instead of the speed.
    """
    rate = float(law.rate) * float(per_unit)
    if not math.isfinite(rate):
        raise ValueError(f"friction law rate {rate} is not finite")
    return FrictionLaw(int(law.kind), float(law.amplitude), rate)
