r"""Sound pressure at the standard pass-by position from the sound powers.

Receiver: 7.5 m from the track centre line, 1.2 m above the rail head (ISO 3095), level with the
wheel (the instant of closest approach; not the pass-by L_Aeq). Sources, in the cross-section
plane (lateral distance from the track centre, height above the rail head):

* the wheel on the near rail: an **omnidirectional** point source at the wheel centre
  (lateral ``NEAR_RAIL``, height = wheel radius). Thompson & Jones (2002) find dipole-like
  directivity for the axial modes; omnidirectional is the TWINS default for the total
  (stated assumption);
* the near rail: a line of incoherent omnidirectional sources along the track at rail mid-height,
  with the power per length of radiation/rail_power.py.

Ground: **hard** (reflection coefficient 1), at ``GROUND_HEIGHT`` below the rail head, added
incoherently as an image source: ``p² = ρ c W / (4π) (1/r² + 1/r_image²)`` (≈ +3 dB at these
distances). No air absorption (< 0.1 dB at 5 kHz over 7 m).
"""

from __future__ import annotations

import numpy as np

from radiation.acoustics import AIR_DENSITY, SOUND_SPEED

RECEIVER_DISTANCE = 7.5
"""m from the track centre line (ISO 3095)."""
RECEIVER_HEIGHT = 1.2
"""m above the rail head (ISO 3095)."""
NEAR_RAIL = 0.75
"""Lateral position of the near rail and wheel, m from the track centre (standard gauge)."""
RAIL_HEIGHT_OFFSET = -0.08
"""Height of the rail's acoustic centre relative to the rail head, m (mid-height of a 150 mm rail)."""
GROUND_HEIGHT = -0.25
"""Ground (hard) plane relative to the rail head, m (sleeper top under a 150 mm rail and pad)."""


def geometric_factor(lateral, height, along=0.0):
    """``1/r² + 1/r_image²`` (1/m²) from a source at (along, lateral, height) to the receiver."""
    dy = RECEIVER_DISTANCE - lateral
    direct = along**2 + dy**2 + (RECEIVER_HEIGHT - height) ** 2
    image = along**2 + dy**2 + (RECEIVER_HEIGHT + height - 2.0 * GROUND_HEIGHT) ** 2
    return 1.0 / direct + 1.0 / image


def wheel_pressure_squared(power, wheel_radius, rho=AIR_DENSITY, c=SOUND_SPEED):
    """Mean-square pressure (Pa²) at the receiver of a wheel radiating ``power`` (W, any shape)."""
    return rho * c * np.asarray(power) / (4.0 * np.pi) * geometric_factor(NEAR_RAIL, wheel_radius)


def rail_pressure_squared(distance, per_length, rho=AIR_DENSITY, c=SOUND_SPEED):
    """Mean-square pressure (Pa²) at the receiver of the rail.

    Parameters
    ----------
    distance : (nx,) ndarray
        m from the contact along the rail (one side; the other side is its mirror).
    per_length : (nx, ...) ndarray
        Radiated power per length, W/m.
    """
    g = geometric_factor(NEAR_RAIL, RAIL_HEIGHT_OFFSET, np.asarray(distance))
    shape = (-1,) + (1,) * (np.ndim(per_length) - 1)
    return rho * c / (4.0 * np.pi) * 2.0 * np.trapezoid(per_length * g.reshape(shape), distance, axis=0)


def pressure_gain(power_per_mean_square, wheel_radius, rho=AIR_DENSITY, c=SOUND_SPEED):
    """Pa per unit of a signal whose mean square radiates ``power_per_mean_square`` W (for the WAV)."""
    return np.sqrt(wheel_pressure_squared(power_per_mean_square, wheel_radius, rho, c))
