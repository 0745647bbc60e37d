r"""Radiation efficiencies of the fast model: wheel modes by type and nodal diameters, rail section.

Wheel (TWINS-type, after Thompson & Jones, *Sound radiation from a vibrating railway wheel*,
JSV 253(2), 2002, 401–419). The wheel's axial surface velocity radiates with an efficiency
σ_ax(n, f), its radial surface velocity with σ_rad(n, f), each a function of the number of nodal
diameters n and of the wheel radius a (and, radial, the rim width b):

.. math::

    σ_{ax} = \frac{1}{1 + (f_{ax}/f)^{p_{ax}}},\qquad
    σ_{rad} = \frac{1}{1 + (f_{rad}/f)^{p_{rad}}}\,\frac{1}{1 + (f_b/f)^2}

The exponents are those of the multipole each motion is at low frequency: an axially moving free
disc with n nodal diameters is a multipole of order n + 1 (σ ∝ (ka)^{2n+4}: n = 0 a dipole, n = 1
a quadrupole; the wheel's n = 1, 2, 3 are of order n, (ka)^{2n+2}, below), a radially moving ring
of order max(n, 0) with a breathing monopole for n = 0 (σ ∝ (ka)² for n = 0, (ka)⁴ for n = 1,
(ka)^{2n+2} for n ≥ 2). The corner frequencies are where the acoustic wavenumber k reaches the
circumferential wavenumber of the pattern at the rim, k a = n + 1 (axial, n ≥ 4; n = 0…3 fitted
to the BEM, below) and k a = max(n, 1) (radial), and where half a wavelength spans the rim width,
f_b = c / (2 b).

This is the structure of the published simplified formulae (power laws below a
corner, unity above); the fitted coefficients of the paper were not available to this
implementation, so the curves are checked against this package's own boundary-element results
(radiation/bem.py, tests/test_radiation_bem.py) and the agreement is stated in
docs/verification.md.

The axial laws of n = 0…3 are set from this package's boundary-element solution of the default
wheel's axial modes with no nodal circle, each at its own frequency and at half of it (n = 0:
204.5 / 102.3 Hz, ka = 1.57 / 0.78; n = 1: 137.9 / 68.9 Hz, ka = 1.06 / 0.53; n = 2: 396.4 /
198.2 Hz, ka = 3.03 / 1.52; n = 3: 1115 / 557 Hz, ka = 8.53 / 4.27; the solves and the fit are in
radiation/bem_wheel_solves.py, the agreement in docs/verification.md#radiation). The wheel is not
symmetric about its mid-plane (the web offset, the flange), so an axial pattern with n ≥ 1 nodal
diameters can radiate as the lowest multipole its cos nθ allows, of degree n, σ ∝ (ka)^{2n+2}
(the free thin disc's degree n + 1, (ka)^{2n+4}, needs that symmetry): the n = 1 mode rises by
10.5 dB per octave in the BEM, like a dipole, not a quadrupole's 18. So the axial exponent is 4
for n = 0 (a dipole: the umbrella mode moves no net volume) and 2n + 2 for n = 1, 2, 3, and the
corners k a = κ_0 = 2.04, κ_1 = 5.09, κ_2 = 5.28 and κ_3 = 8.13 are the minimax fits in dB of the
fast model (this axial law plus the radial one, unchanged, over the mode's own I_ax and I_rad) to
the two frequencies; residual ±1.3, ±1.0, ±1.2 and ±1.8 dB (with the free disc's 2n + 4 for
n = 2 and 3: ±0.1 and ±2.1 dB; 2n + 2 has the smaller worst case and the same physics as n = 1).
The rim's corners k a = n + 1 with
the thin disc's slopes had put the fast model 3.9 dB (n = 0), 10.6 dB (n = 1), 9.0 dB (n = 2)
and 3.7 dB (n = 3) above the BEM at the modes' own frequencies and 8.8 dB (n = 3) at half of it.
From n = 4 on the rim's corners k a = n + 1 and the exponent 2n + 4 are kept: well above their
corners both models give σ near 1 (n = 4 at 2012 Hz within 1 dB of the BEM). For comparison, a
thin rigid disc of radius a in free space, whose low-frequency efficiencies follow from its
entrained mass 8ρa³/3 (n = 0, a dipole) and entrained moment of inertia 16ρa⁵/45 (n = 1, rocking
about a diameter: a lateral quadrupole) (Lamb, *Hydrodynamics*, 6th ed., 1932, §108),

.. math::

    σ_0 → \frac{8 (ka)^4}{27 π^2},\qquad σ_1 → \frac{1024\,(ka)^6}{243000\,π^2}

relative to the mean-square normal velocity over both faces, radiates less than the wheel
(corner κ = 2.40 for n = 0).

Rail: per unit length, a rail vibrating as a rigid section with velocity v radiates
``W' = ρ c σ w <v²>`` with a radiating width w (vertical: the foot width; lateral: the rail
height, as in TWINS: Thompson, *Railway Noise and Vibration*, 2009, §6.4). σ is taken as that of
a circular cylinder oscillating as a rigid body (a 2D dipole) whose half perimeter π a equals w,
in closed form ``σ = 2 / (π k a |H_1'(k a)|²)`` (exact for the cylinder; Junger & Feit,
*Sound, Structures and their Interaction*, 1986, §2.8).
"""

from __future__ import annotations

import numpy as np
from scipy.special import h1vp

from radiation.acoustics import SOUND_SPEED


def axial_exponent(n):
    """Low-frequency slope of σ_ax: 2n + 4 (an axially moving free disc: multipole of degree n + 1),
    but 2n + 2 for n = 1, 2, 3 (the wheel's asymmetry allows degree n; fitted to the BEM with
    these slopes: module notes)."""
    n = np.asarray(n, dtype=float)
    return np.where((n >= 1) & (n <= 3), 2.0 * n + 2.0, 2.0 * n + 4.0)


def radial_exponent(n):
    """Low-frequency slope of σ_rad: 2 (n = 0, monopole), 4 (n = 1, dipole), 2n + 2 (n ≥ 2)."""
    n = np.asarray(n, dtype=float)
    return np.where(n == 0, 2.0, 2.0 * n + 2.0)


#: k a of the axial corner for n = 0…3, fitted to the BEM of the default wheel (module notes,
#: radiation/bem_wheel_solves.py); n ≥ 4: k a = n + 1.
LOW_ORDER_AXIAL_CORNER_KA = {0: 2.04, 1: 5.09, 2: 5.28, 3: 8.13}


def axial_corner(n, radius, sound_speed=SOUND_SPEED):
    """Corner frequency of σ_ax, Hz: k a = κ_n for n = 0…3 (fitted to the BEM: LOW_ORDER_AXIAL_CORNER_KA),
    n + 1 for n ≥ 4."""
    n = np.asarray(n, dtype=float)
    ka = np.select([n == m for m in LOW_ORDER_AXIAL_CORNER_KA], list(LOW_ORDER_AXIAL_CORNER_KA.values()), n + 1.0)
    return sound_speed * ka / (2.0 * np.pi * radius)


def radial_corner(n, radius, sound_speed=SOUND_SPEED):
    """Corner frequency of σ_rad, Hz: k a = max(n, 1)."""
    return sound_speed * np.maximum(np.asarray(n, dtype=float), 1.0) / (2.0 * np.pi * radius)


def wheel_axial_efficiency(frequency, n, radius, sound_speed=SOUND_SPEED):
    """σ_ax (-) of an axial wheel vibration pattern with n nodal diameters.

    Parameters
    ----------
    frequency : array_like
        Hz (> 0).
    n : int or array_like
        Nodal diameters (broadcast with ``frequency``).
    radius : float
        Wheel (tread) radius a, m.
    """
    f = np.asarray(frequency, dtype=float)
    ratio = axial_corner(n, radius, sound_speed) / f
    return 1.0 / (1.0 + ratio ** axial_exponent(n))


def wheel_radial_efficiency(frequency, n, radius, rim_width, sound_speed=SOUND_SPEED):
    """σ_rad (-) of a radial wheel vibration pattern with n nodal diameters.

    Parameters
    ----------
    frequency : array_like
        Hz (> 0).
    n : int or array_like
        Nodal diameters.
    radius : float
        Wheel radius a, m.
    rim_width : float
        Axial width b of the tread and flange, m.
    """
    f = np.asarray(frequency, dtype=float)
    ratio = radial_corner(n, radius, sound_speed) / f
    width = 1.0 / (1.0 + (sound_speed / (2.0 * rim_width) / f) ** 2)
    return width / (1.0 + ratio ** radial_exponent(n))


def cylinder_dipole_efficiency(ka):
    """σ (-) of an infinitely long circular cylinder oscillating as a rigid body, closed form.

    ``σ = 2 / (π ka |H_1'(ka)|²)``, relative to the perimeter-averaged mean-square normal
    velocity (half the mean square of the translation). Tends to (π²/4)(ka)³/... → 1 for ka → ∞.
    """
    ka = np.asarray(ka, dtype=float)
    return 2.0 / (np.pi * ka * np.abs(h1vp(1, ka)) ** 2)


def rail_efficiency(frequency, radiating_width, sound_speed=SOUND_SPEED):
    """σ (-) of a rail direction with radiating width w: the cylinder with π a = w.

    Parameters
    ----------
    frequency : array_like
        Hz (> 0).
    radiating_width : float
        m (foot width for vertical, rail height for lateral vibration).
    """
    radius = radiating_width / np.pi
    return cylinder_dipole_efficiency(2.0 * np.pi * np.asarray(frequency, dtype=float) * radius / sound_speed)
