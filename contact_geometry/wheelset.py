"""Rolling radius difference and equivalent conicity of a wheelset with the same profile both sides.

For a lateral wheelset displacement ``y`` (m, towards the right rail) the right wheel moves
towards its flange (wheel displacement ``+y``) and the left wheel away from it (``-y``); with
identical wheel/rail pairs on both sides

    ``dr(y) = r(+y) - r(-y)``

(r from slot 0 of :func:`geometry.contact_search.contact_table`). The wheelset roll angle is
neglected (each wheel is lowered onto its rail independently), a first-order approximation.

**Equivalent conicity** (variant implemented): the harmonic linearisation of ``dr`` for a
sinusoidal lateral motion ``y = A sin(phi)`` of amplitude A,

    ``gamma_e(A) = c1 / (2 A)``,  ``c1 = (1 / pi) * integral_0^2pi dr(A sin phi) sin phi dphi``,

i.e. the conicity of the cone pair whose dr has the same first harmonic. For a pure cone of
conicity gamma, dr = 2 gamma y and gamma_e = gamma for every amplitude. EN 15302 states several
methods (regression of dr, numerical integration of the wheelset's kinematic motion); this is the
linearisation idea common to them, not a transcription of the standard's text, which was not
available. It is commonly reported at A = 3 mm.
"""

from __future__ import annotations

import numpy as np

from squealcore.errors import require_range

from .contact_search import WheelRailPair, contact_table

__all__ = ["rolling_radius_difference", "equivalent_conicity"]


def rolling_radius_difference(pair: WheelRailPair, displacement, **kwargs) -> np.ndarray:
    """Rolling radius difference dr(y) = r(+y) - r(-y) (m) of a symmetric wheelset.

    Parameters
    ----------
    pair : WheelRailPair
        The wheel/rail pair of each side.
    displacement : array_like
        Wheelset lateral displacements y (m).
    **kwargs
        Passed to :func:`~geometry.contact_search.contact_table`.
    """
    y = np.atleast_1d(np.asarray(displacement, dtype=float))
    table = contact_table(pair, np.concatenate([y, -y]), **kwargs)
    r = table.rolling_radius[:, 0]
    return r[:y.size] - r[y.size:]


def equivalent_conicity(pair: WheelRailPair, amplitude: float = 0.003, n_phase: int = 256,
                        **kwargs) -> float:
    """Equivalent conicity (-) by harmonic linearisation of dr over an amplitude (module docstring).

    Parameters
    ----------
    pair : WheelRailPair
    amplitude : float
        Amplitude A of the lateral wheelset motion (m), in (0, 0.02].
    n_phase : int
        Number of phase samples of the period (trapezoidal rule).
    **kwargs
        Passed to :func:`~geometry.contact_search.contact_table`.
    """
    amplitude = require_range("geometry.conicity_amplitude", amplitude, 0.0, 0.02, low_open=True, unit="m")
    phi = 2.0 * np.pi * np.arange(n_phase) / n_phase
    dr = rolling_radius_difference(pair, amplitude * np.sin(phi), **kwargs)
    c1 = 2.0 * np.mean(dr * np.sin(phi))
    return float(c1 / (2.0 * amplitude))
