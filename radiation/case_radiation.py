"""Radiated sound of one interaction case: wheel and rail power, receiver pressure, WAV signal.

Ties the pieces together: the case's force history drives the wheel model's poles
(radiation/wheel_vibration.py) and the rail's receptance (radiation/rail_power.py); the limit
cycle (the last ``rms_window`` seconds, as for L_F2) gives the spectra; the efficiencies
(radiation/efficiency.py) the powers; radiation/receiver.py the pressure at the pass-by position.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from interaction.wheel_models import wheel_model
from radiation.acoustics import AIR_DENSITY, REFERENCE_POWER, REFERENCE_PRESSURE, SOUND_SPEED
from radiation.bands import a_weighting_db, band_sum, level_db, third_octave_centres
from radiation.efficiency import rail_efficiency, wheel_axial_efficiency, wheel_radial_efficiency
from radiation.rail_power import RAIL_DIRECTIONS, interpolate_receptance, rail_power
from radiation.receiver import (NEAR_RAIL, RAIL_HEIGHT_OFFSET, geometric_factor, rail_pressure_squared,
                                wheel_pressure_squared)
from radiation.spectra import one_sided_spectrum, window_slice
from radiation.wheel_power import wheel_power
from radiation.wheel_vibration import wheel_vibration

logger = logging.getLogger(__name__)

@dataclass(frozen=True)
class CaseRadiation:
    """Radiation results of one case (SI units; levels in dB).

    Attributes
    ----------
    band_centres : (nb,) ndarray
        One-third octave mid-band frequencies, Hz.
    wheel_band_power, rail_band_power : (nb,) ndarray
        W per band.
    wheel_band_pressure2, rail_band_pressure2 : (nb,) ndarray
        Mean-square pressure per band at the receiver, Pa².
    input_power : float
        Mean power the contact force puts into the wheel, ``<F·v>`` over the window, W.
    pole_frequency, pole_power : (k,) ndarray
        Per pole of the wheel model: frequency (Hz) and radiated power (W).
    pole_harmonic, pole_mode : (k,) int ndarray
        Nodal diameters and matched mode index per pole.
    pole_input_power : (k,) ndarray
        Power the force puts into each pole's vibration, W.
    wheel_pressure, rail_pressure : (nt,) ndarray
        Pressure signals at the receiver over the whole history (for the WAV), Pa.
    time_step : float
        s.
    """

    band_centres: np.ndarray
    wheel_band_power: np.ndarray
    rail_band_power: np.ndarray
    wheel_band_pressure2: np.ndarray
    rail_band_pressure2: np.ndarray
    input_power: float
    pole_frequency: np.ndarray
    pole_power: np.ndarray
    pole_harmonic: np.ndarray
    pole_mode: np.ndarray
    pole_input_power: np.ndarray
    wheel_pressure: np.ndarray
    rail_pressure: np.ndarray
    time_step: float

    @property
    def wheel_power(self):
        """W."""
        return float(self.wheel_band_power.sum())

    @property
    def rail_power(self):
        """W."""
        return float(self.rail_band_power.sum())

    @property
    def L_W(self):
        """Sound power level of wheel + rail, dB re 1 pW."""
        return float(level_db(self.wheel_power + self.rail_power, REFERENCE_POWER))

    @property
    def L_W_wheel(self):
        return float(level_db(self.wheel_power, REFERENCE_POWER))

    @property
    def L_W_rail(self):
        return float(level_db(self.rail_power, REFERENCE_POWER))

    def band_pressure_level(self, a_weighted=True):
        """L_p per band at the receiver (wheel + rail), dB re 20 µPa (A-weighted if asked)."""
        level = level_db(self.wheel_band_pressure2 + self.rail_band_pressure2, REFERENCE_PRESSURE**2)
        return level + (a_weighting_db(self.band_centres) if a_weighted else 0.0)

    @property
    def L_pA(self):
        """A-weighted sound pressure level at the receiver, dB(A) re 20 µPa."""
        weights = 10.0 ** (a_weighting_db(self.band_centres) / 10.0)
        total = np.sum((self.wheel_band_pressure2 + self.rail_band_pressure2) * weights)
        return float(level_db(total, REFERENCE_PRESSURE**2))


def radiate(model_name, wheel, modes, surfaces, rail, force, normal_force, rail_velocity, rms_window, name="case"):
    """Radiated sound of one case from its force history and its structures.

    Parameters
    ----------
    model_name : str
        Wheel model of the case (the rotating models radiate travelling waves).
    wheel : dict
        The wheel model at the case's contact, in its contact frame: ``poles`` (rad/s), ``residues``
        (m/(N s)), ``spin`` (rad/s), ``time_step`` (s).
    modes : dict
        Wheel modes (``frequency``, ``nodal_diameters``, ...) with ``contact_shape`` in the contact frame.
    surfaces : radiation.surface.ModeSurfaces
        The modes' surface integrals.
    rail : radiation.rail_power.RailModel
        Receptance along the rail and the section's size.
    force : (nt, 3) ndarray
        Contact force history in the case's contact frame, N.
    normal_force : float
        Static normal force N of the case, N (the deviation is ``force - (0, 0, N)``).
    rail_velocity : (nt, 3) ndarray
        Rail velocity at the contact, m/s.
    rms_window : float
        Length of the limit-cycle window at the end of the history, s.
    name : str
        Case name for the log.

    Returns
    -------
    CaseRadiation
    """
    dt = wheel["time_step"]
    deviation = force - np.array([0.0, 0.0, normal_force])
    travelling = wheel_model(model_name).rotating  # the load travels round the wheel's modes
    window = window_slice(len(force), dt, rms_window)
    vibration = wheel_vibration(wheel["poles"], wheel["residues"], modes, surfaces, deviation, dt, travelling,
                                wheel["spin"], window)
    radius, rim = surfaces.outer_radius, surfaces.rim_width
    power = wheel_power(vibration, window, dt, radius, rim)
    frequency, force_amplitude = one_sided_spectrum(deviation[window].T, dt)
    rail_out = rail_power(rail, frequency, force_amplitude)
    centres = third_octave_centres()
    wheel_p2 = wheel_pressure_squared(power.spectrum, radius)
    rail_p2 = rail_pressure_squared(rail.distance, rail_out.per_length)
    result = CaseRadiation(
        band_centres=centres,
        wheel_band_power=band_sum(frequency, power.spectrum, centres),
        rail_band_power=band_sum(frequency, rail_out.spectrum, centres),
        wheel_band_pressure2=band_sum(frequency, wheel_p2, centres),
        rail_band_pressure2=band_sum(frequency, rail_p2, centres),
        input_power=float(vibration.input_power.sum()),
        pole_frequency=vibration.frequency, pole_power=power.per_pole.sum(axis=1),
        pole_harmonic=vibration.harmonic, pole_mode=vibration.mode, pole_input_power=vibration.input_power,
        wheel_pressure=_wheel_pressure_signal(vibration, radius, rim),
        rail_pressure=_rail_pressure_signal(rail, rail_velocity, frequency, force_amplitude),
        time_step=dt)
    logger.info("radiation of %s: L_W = %.1f dB (wheel %.1f, rail %.1f), L_pA = %.1f dB(A)", name,
                result.L_W, result.L_W_wheel, result.L_W_rail, result.L_pA)
    return result


def _wheel_pressure_signal(vibration, radius, rim_width):
    """Receiver pressure (Pa) of the wheel: each pole's modal velocity times its gain at its own
    frequency (the efficiencies vary slowly across a resonance); all in phase at emission (the
    common propagation delay is omitted)."""
    f = np.maximum(vibration.frequency, 1e-9)
    per_ms = (wheel_axial_efficiency(f, vibration.harmonic, radius) * vibration.axial
              + wheel_radial_efficiency(f, vibration.harmonic, radius, rim_width) * vibration.radial)
    gain = np.sqrt(wheel_pressure_squared(AIR_DENSITY * SOUND_SPEED * per_ms, radius))
    return gain @ vibration.velocity


def _rail_pressure_signal(rail, rail_velocity, frequency, force_amplitude):
    """Receiver pressure (Pa) of the rail: its lateral and vertical contact velocities times a gain
    evaluated at the dominant frequency of the force (the rail's transfer varies slowly)."""
    dominant = frequency[np.argmax(np.sum(np.abs(force_amplitude) ** 2, axis=0))]
    f = np.array([max(dominant, 1e-9)])
    h = interpolate_receptance(rail, f)[:, 0]
    g = geometric_factor(NEAR_RAIL, RAIL_HEIGHT_OFFSET, rail.distance)
    signal = np.zeros(len(rail_velocity))
    for direction, _ in RAIL_DIRECTIONS:
        decay = np.sum(np.abs(h[:, direction, :]) ** 2, axis=1)
        if decay[0] <= 0:
            continue
        shape = decay / decay[0]
        width = rail.width(direction)
        gain2 = AIR_DENSITY * SOUND_SPEED / (4.0 * np.pi) * rail_efficiency(f, width)[0] * width \
            * 2.0 * np.trapezoid(shape * g, rail.distance)
        signal += np.sqrt(gain2) * rail_velocity[:, direction]
    return signal
