"""Air properties and reference values of the radiation models (SI units).

The values are the usual ones for air at 20 °C and 101.3 kPa (ISO 9613-1 conditions); every
radiation model of this package reads them from here.
"""

AIR_DENSITY = 1.204
"""Density of air, kg/m³ (20 °C, 101.325 kPa)."""

SOUND_SPEED = 343.2
"""Speed of sound in air, m/s (20 °C)."""

REFERENCE_POWER = 1e-12
"""Reference sound power of L_W, W (ISO 80000-8)."""

REFERENCE_PRESSURE = 2e-5
"""Reference sound pressure of L_p, Pa (ISO 80000-8)."""
