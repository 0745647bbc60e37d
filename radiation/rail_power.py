r"""The rail's vibration under the contact force and its radiated sound power.

The rail's receptance along the track ``H(x, f)`` (3x3, m/N, at distances x ≥ 0 from the force;
rail_greens.h5, from the waveguide model, which holds the waves' decay) and the contact force
spectrum give the rail velocity ``v(x, f) = i ω H(x, f) (-F(f))`` (the rail receives -F). Its
vertical (z) and lateral (y) components radiate as line sources (radiation/efficiency.py):

``W'(x, f) = ρ c Σ_j σ_j(f) w_j |v_j(x, f)|²``, ``W(f) = ∫ W' dx`` over both sides of the contact
(the rail is symmetric about the load point: the moving load at 14 m/s ≪ the waves' speeds), by the
trapezoidal rule on the stored distances and, beyond the last one, the exponential decay of the
last interval continued to infinity. Longitudinal vibration and the rail's cross-section
deformation are not radiated (TWINS neglects them too, Thompson 2009 §6.4). The receptance is
zero outside its frequency grid: no rail power is computed there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radiation.acoustics import AIR_DENSITY, SOUND_SPEED
from radiation.efficiency import rail_efficiency

#: Rail directions that radiate: (index in the contact frame, name).
RAIL_DIRECTIONS = ((1, "lateral"), (2, "vertical"))


@dataclass(frozen=True)
class RailModel:
    """What the rail radiation needs from the rail artefacts.

    Attributes
    ----------
    frequency : (nf,) ndarray
        Hz.
    distance : (nx,) ndarray
        m, distance[0] = 0.
    receptance : (nx, nf, 3, 3) complex ndarray
        m/N.
    foot_width, height : float
        Section dimensions, m (radiating widths of vertical and lateral vibration).
    """

    frequency: np.ndarray
    distance: np.ndarray
    receptance: np.ndarray
    foot_width: float
    height: float

    def width(self, direction):
        """Radiating width (m) of a direction index: 2 (vertical) the foot width, 1 (lateral) the height."""
        return self.foot_width if direction == 2 else self.height


def interpolate_receptance(model, frequency):
    """Receptance (nx, nf', 3, 3) at other frequencies (linear in f, real and imaginary parts; 0 outside)."""
    f = np.asarray(frequency, dtype=float)
    h = model.receptance.reshape(len(model.distance), len(model.frequency), 9)
    out = np.zeros((len(model.distance), f.size, 9), dtype=complex)
    inside = (f >= model.frequency[0]) & (f <= model.frequency[-1])
    for x in range(h.shape[0]):
        for k in range(9):
            out[x, inside, k] = (np.interp(f[inside], model.frequency, h[x, :, k].real)
                                 + 1j * np.interp(f[inside], model.frequency, h[x, :, k].imag))
    return out.reshape(len(model.distance), f.size, 3, 3)


@dataclass(frozen=True)
class RailPower:
    """Radiated power of the rail.

    Attributes
    ----------
    frequency : (nf,) ndarray
        Hz.
    per_length : (nx, nf) ndarray
        W' at the stored distances, W/m (one side; the other side is the same).
    spectrum : (nf,) ndarray
        Total power per bin (both sides, with the tail), W.
    velocity : (2, nx, nf) complex ndarray
        Lateral and vertical rail velocity per bin (|.|² = mean square), m/s.
    """

    frequency: np.ndarray
    per_length: np.ndarray
    spectrum: np.ndarray
    velocity: np.ndarray

    @property
    def total(self):
        """Total radiated power, W."""
        return float(self.spectrum.sum())


def line_integral(distance, values):
    """``2 ∫_0^∞ values dx`` (values (nx, ...) at ``distance``): trapezoids, then the last interval's
    exponential decay continued to infinity (no tail if the values do not decay)."""
    inner = np.trapezoid(values, distance, axis=0)
    last, before = values[-1], values[-2]
    dx = distance[-1] - distance[-2]
    with np.errstate(divide="ignore", invalid="ignore"):
        rate = np.log(before / last) / dx
        tail = np.where((rate > 0) & np.isfinite(rate), last / rate, 0.0)
    return 2.0 * (inner + tail)


def rail_power(model, force_frequency, force_amplitude, rho=AIR_DENSITY, c=SOUND_SPEED):
    """Radiated power of the rail under a contact force spectrum.

    Parameters
    ----------
    model : RailModel
    force_frequency : (nf,) ndarray
        Hz.
    force_amplitude : (3, nf) complex ndarray
        One-sided force amplitudes (rail on wheel, |.|² = mean square), N.
    rho, c : float
        Air density (kg/m³), speed of sound (m/s).

    Returns
    -------
    RailPower
    """
    h = interpolate_receptance(model, force_frequency)
    omega = 2.0 * np.pi * np.asarray(force_frequency)
    f = np.maximum(force_frequency, 1e-9)
    per_length = np.zeros((len(model.distance), len(force_frequency)))
    velocity = []
    for direction, _ in RAIL_DIRECTIONS:
        v = 1j * omega[None, :] * np.einsum("xfj,jf->xf", h[:, :, direction, :], -np.asarray(force_amplitude))
        velocity.append(v)
        width = model.width(direction)
        per_length += rho * c * rail_efficiency(f, width, c)[None, :] * width * np.abs(v) ** 2
    spectrum = line_integral(model.distance, per_length)
    return RailPower(np.asarray(force_frequency), per_length, spectrum, np.array(velocity))
