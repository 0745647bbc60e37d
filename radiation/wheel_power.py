r"""Sound power of the wheel per pole, per frequency bin and per one-third octave band.

``W = ρ c Σ_r Σ_f [σ_ax(n_r, f) I_ax,r + σ_rad(n_r, f) I_rad,r] <q̇_r²>(f)`` with the pole
vibrations of radiation/wheel_vibration.py and the efficiencies of radiation/efficiency.py: the
TWINS form ``W = ρ c S σ <v_n²>`` applied to the axial and radial surfaces of every mode.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from radiation.acoustics import AIR_DENSITY, SOUND_SPEED
from radiation.efficiency import wheel_axial_efficiency, wheel_radial_efficiency
from radiation.spectra import one_sided_spectrum


@dataclass(frozen=True)
class WheelPower:
    """Radiated power of the wheel.

    Attributes
    ----------
    frequency : (nf,) ndarray
        Bin frequencies, Hz.
    per_pole : (k, nf) ndarray
        Power per pole and bin, W.
    amplitude : (k, nf) complex ndarray
        Modal velocity per pole and bin (one-sided, |.|² = mean square), √kg m/s.
    sigma_axial, sigma_radial : (k, nf) ndarray
        Radiation efficiencies used, -.
    """

    frequency: np.ndarray
    per_pole: np.ndarray
    amplitude: np.ndarray
    sigma_axial: np.ndarray
    sigma_radial: np.ndarray

    @property
    def spectrum(self):
        """Power per bin, W (sum over poles)."""
        return self.per_pole.sum(axis=0)

    @property
    def total(self):
        """Total radiated power, W."""
        return float(self.per_pole.sum())


def wheel_power(vibration, window, time_step, radius, rim_width, rho=AIR_DENSITY, c=SOUND_SPEED):
    """Radiated power of a wheel vibration over a window of its history.

    Parameters
    ----------
    vibration : radiation.wheel_vibration.PoleVibration
    window : slice
        Samples of the history used (the limit cycle).
    time_step : float
        s.
    radius, rim_width : float
        Wheel radius and rim width for the efficiencies, m.
    rho, c : float
        Air density (kg/m³) and speed of sound (m/s).

    Returns
    -------
    WheelPower
    """
    frequency, amplitude = one_sided_spectrum(vibration.velocity[:, window], time_step)
    f = np.maximum(frequency, 1e-9)[None, :]
    n = vibration.harmonic[:, None]
    sigma_ax = wheel_axial_efficiency(f, n, radius, c)
    sigma_rad = wheel_radial_efficiency(f, n, radius, rim_width, c)
    per_pole = rho * c * (sigma_ax * vibration.axial[:, None] + sigma_rad * vibration.radial[:, None]) \
        * np.abs(amplitude) ** 2
    return WheelPower(frequency, per_pole, amplitude, sigma_ax, sigma_rad)
