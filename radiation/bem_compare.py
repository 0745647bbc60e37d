"""Fast model against the BEM for the wheel's axial modes with no nodal circle (n = 0…7).

For each n the cos partner of the axial mode with 0 nodal circles is given a unit modal velocity
(q̇ = 1 √kg m/s amplitude); the BEM (radiation/bem.py) solves its radiation on the surface of the
wheel's own hexahedral mesh (radiation/bem_wheel.py), and the fast model gives
``W = ρ c ½ (σ_ax I_ax + σ_rad I_rad)`` from the same mode's surface integrals. Both are reported
as power and as an effective efficiency ``σ = W / (ρ c ½ (I_ax + I_rad))``.
"""

from __future__ import annotations

import logging
import time

import numpy as np

from radiation import bem
from radiation.acoustics import AIR_DENSITY, SOUND_SPEED
from radiation.bem_wheel import section_mode_at_points, triangle_normal_velocity, wheel_surface
from radiation.efficiency import wheel_axial_efficiency, wheel_radial_efficiency
from radiation.surface import hex_mode_surfaces, section_mode_surfaces

logger = logging.getLogger(__name__)


def axial_mode_index(modes, n):
    """Index of the axial mode with n nodal diameters and no nodal circle (cos partner), or None."""
    for i in np.argsort(modes["frequency"]):
        if (modes["nodal_diameters"][i] == n and modes["nodal_circles"][i] == 0
                and _text(modes["family"][i]) == "axial"
                and (modes["solver"] != "axisymmetric" or _text(modes["orientation"][i]) == "cos")):
            return int(i)
    return None


def _text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def compare_axial_modes(mesh, modes, harmonics=range(2, 8), f_max=None, frequency_factor=1.0):
    """Fast model and BEM for the axial modes of a wheel.

    Parameters
    ----------
    mesh : dict
        The wheel mesh (``stages.wheel.read_mesh``): ``hex_nodes`` (m), ``hex_cells`` and, for the
        axisymmetric solver, ``section_nodes``, ``section_cells``.
    modes : dict
        The wheel modes with shapes (``stages.wheel.read_modes(..., with_shapes=True)``).
    harmonics : iterable of int
        Numbers of nodal diameters.
    f_max : float, optional
        Skip modes above this frequency (Hz): the mesh must resolve the acoustic wavelength.
    frequency_factor : float
        Solve each mode's shape at this multiple of its own frequency (1: at resonance; e.g. 0.5
        checks the fast model's low-frequency law away from the frequency it was compared at).

    Returns
    -------
    list of dict
        ``n``, ``frequency`` (Hz), ``power_bem``, ``power_fast`` (W), ``sigma_bem``,
        ``sigma_fast`` (-), ``difference_db`` (fast - BEM), ``seconds`` (BEM), ``triangles``, and what
        the fast model needs to be evaluated again without the BEM: ``ka`` (k a, -), ``radius`` and
        ``rim_width`` (m), ``axial_integral`` and ``radial_integral`` (the mode's I_ax, I_rad, m⁴/kg).
    """
    vertices, triangles, node_index = wheel_surface(mesh["hex_nodes"], mesh["hex_cells"])
    grid = bem.grid_from_triangles(vertices, triangles)
    axisymmetric = modes["shapes"].shape[1] != len(mesh["hex_nodes"])
    rows = []
    for n in harmonics:
        i = axial_mode_index(modes, n)
        if i is None or (f_max is not None and modes["frequency"][i] > f_max):
            continue
        f = float(modes["frequency"][i]) * frequency_factor
        if axisymmetric:
            surfaces = section_mode_surfaces(mesh["section_nodes"], mesh["section_cells"], modes["shapes"][i:i + 1],
                                             [n])
            shape = section_mode_at_points(vertices, mesh["section_nodes"], modes["shapes"][i], n)
        else:
            surfaces = hex_mode_surfaces(mesh["hex_nodes"], mesh["hex_cells"], modes["shapes"][i:i + 1])
            shape = np.asarray(modes["shapes"][i], dtype=float)[node_index]
        velocity = triangle_normal_velocity(vertices, triangles, shape)
        start = time.perf_counter()
        out = bem.radiated_power(grid, velocity, f)
        seconds = time.perf_counter() - start
        radius, width = surfaces.outer_radius, surfaces.rim_width
        fast = AIR_DENSITY * SOUND_SPEED * 0.5 * (wheel_axial_efficiency(f, n, radius) * surfaces.axial[0]
                                                  + wheel_radial_efficiency(f, n, radius, width) * surfaces.radial[0])
        reference = AIR_DENSITY * SOUND_SPEED * 0.5 * (surfaces.axial[0] + surfaces.radial[0])
        row = {"n": int(n), "frequency": f, "power_bem": out["power"], "power_fast": float(fast),
               "sigma_bem": out["power"] / reference, "sigma_fast": float(fast / reference),
               "difference_db": float(10 * np.log10(fast / out["power"])), "seconds": seconds,
               "triangles": int(len(triangles)), "ka": float(2 * np.pi * f * radius / SOUND_SPEED),
               "radius": float(radius), "rim_width": float(width), "axial_integral": float(surfaces.axial[0]),
               "radial_integral": float(surfaces.radial[0])}
        logger.info("n = %d at %.0f Hz: sigma BEM %.3g, fast %.3g (%+.1f dB), %.0f s", n, f, row["sigma_bem"],
                    row["sigma_fast"], row["difference_db"], seconds)
        rows.append(row)
    return rows
