"""Radiated sound of one interaction case: wheel and rail power, receiver pressure, WAV signal.

Ties the pieces together: the case's force history drives the wheel model's poles
(radiation/wheel_vibration.py) and the rail's receptance (radiation/rail_power.py); the limit
cycle (the last ``rms_window`` seconds, as for L_F2) gives the spectra; the efficiencies
(radiation/efficiency.py) the powers; radiation/receiver.py the pressure at the pass-by position.
"""

from __future__ import annotations

import functools
import logging
import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from interaction.frame import to_contact_frame, vectors_to_contact_frame
from radiation.acoustics import AIR_DENSITY, REFERENCE_POWER, REFERENCE_PRESSURE, SOUND_SPEED
from radiation.bands import a_weighting_db, band_sum, level_db, third_octave_centres
from radiation.efficiency import rail_efficiency, wheel_axial_efficiency, wheel_radial_efficiency
from radiation.rail_power import RAIL_DIRECTIONS, interpolate_receptance, rail_power, read_rail_model
from radiation.receiver import (NEAR_RAIL, RAIL_HEIGHT_OFFSET, geometric_factor, rail_pressure_squared,
                                wheel_pressure_squared)
from radiation.spectra import one_sided_spectrum, window_slice
from radiation.surface import hex_mode_surfaces, section_mode_surfaces
from radiation.wheel_power import wheel_power
from radiation.wheel_vibration import wheel_vibration
from squealcore.artefacts import open_artefact, read_dataset
from stages.greens_layout import WHEEL_GREENS_VERSION, held_geometry
from stages.wheel import read_mesh, read_modes

logger = logging.getLogger(__name__)

ROTATING_MODELS = ("moving_load", "eulerian")


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


@functools.lru_cache(maxsize=4)
def _surfaces_cached(modes_path, mesh_path, stamp):
    modes = read_modes(modes_path, with_shapes=True)
    mesh = read_mesh(mesh_path)
    if modes["shapes"].shape[1] == len(mesh["hex_nodes"]):
        surfaces = hex_mode_surfaces(mesh["hex_nodes"], mesh["hex_cells"], modes["shapes"])
    else:
        surfaces = section_mode_surfaces(mesh["section_nodes"], mesh["section_cells"], modes["shapes"],
                                         modes["nodal_diameters"])
    modes.pop("shapes")
    return modes, surfaces


def wheel_modes_and_surfaces(variant_dir):
    """Modes (without shapes) and their surface integrals, cached per file version in this process."""
    modes_path = Path(variant_dir) / "wheel_modes.h5"
    mesh_path = Path(variant_dir) / "wheel_mesh.h5"
    stamp = tuple(os.stat(p).st_mtime_ns for p in (modes_path, mesh_path))
    return _surfaces_cached(str(modes_path), str(mesh_path), stamp)


def read_wheel_model(path, model, geometry="manual"):
    """Poles, residues, spin and contact shapes of one wheel model of ``wheel_greens.h5``.

    Parameters
    ----------
    path : path-like
        ``wheel_greens.h5``.
    model : str
        Wheel model name.
    geometry : {"manual", "profiles"}
        The contact the case used (its ``contact_geometry`` attribute): the mesh's contact node
        or the computed contact; the artefact must hold it (``stages.greens_layout``); residues
        and shapes in the track frame, as stored.
    """
    with open_artefact(path, "wheel_greens", WHEEL_GREENS_VERSION) as f:
        held_geometry(f, geometry)  # the models at the root are those of the contact held
        if model not in f:
            raise ValueError(f"{path}: no wheel model {model!r} at the {geometry} contact")
        shape_path = "modal/contact_shape" if geometry == "manual" else "profiles/contact_shape"
        return {"poles": read_dataset(f[model], "poles", "rad/s", (None,)),
                "residues": read_dataset(f[model], "residues", "m/(N*s)", (None, 3, 3)),
                "spin": float(read_dataset(f, "spin", "rad/s")),
                "contact_shape": read_dataset(f, shape_path, "m/sqrt(kg)", (None, 3)),
                "time_step": float(read_dataset(f, "time_step", "s"))}


def radiate_case(case_path, variant_dir, wheel_load, rms_window):
    """Radiated sound of one case.

    Parameters
    ----------
    case_path : path
        ``cases/<id>.h5``.
    variant_dir : path
        Folder of the structural artefacts the case was run with.
    wheel_load : float
        Static wheel load Q (N); the force deviation is ``F - (0, 0, N)`` in the case's contact
        frame, with N its static normal force (Q for cases without the attribute).
    rms_window : float
        Length of the limit-cycle window at the end of the history, s.

    Returns
    -------
    CaseRadiation
    """
    variant_dir = Path(variant_dir)
    with open_artefact(case_path, "case") as f:
        model_name = str(f.attrs["wheel_model"])
        # the contact the case ran with: forces are in its contact frame, inclined by its angle,
        # with the static normal force Q / cos(angle) along the normal
        geometry = str(f.attrs.get("contact_geometry", "manual"))
        angle = float(f.attrs.get("contact_angle", 0.0))
        normal_force = float(f.attrs.get("normal_force", wheel_load))
        force = read_dataset(f, "force", "N", (None, 3))
        rail_velocity = read_dataset(f, "rail/velocity", "m/s", (None, 3))
    modes, surfaces = wheel_modes_and_surfaces(variant_dir)
    wheel = read_wheel_model(variant_dir / "wheel_greens.h5", model_name, geometry)
    # the wheel at the case's contact point, in its contact frame (identity at angle 0)
    modes = {**modes, "contact_shape": vectors_to_contact_frame(wheel["contact_shape"], angle)}
    wheel["residues"] = to_contact_frame(wheel["residues"], angle)
    dt = wheel["time_step"]
    deviation = force - np.array([0.0, 0.0, normal_force])
    travelling = model_name in ROTATING_MODELS
    window = window_slice(len(force), dt, rms_window)
    vibration = wheel_vibration(wheel["poles"], wheel["residues"], modes, surfaces, deviation, dt, travelling,
                                wheel["spin"], window)
    radius, rim = surfaces.outer_radius, surfaces.rim_width
    power = wheel_power(vibration, window, dt, radius, rim)
    frequency, force_amplitude = one_sided_spectrum(deviation[window].T, dt)
    rail = read_rail_model(variant_dir / "rail_greens.h5", variant_dir / "rail_mesh.h5")
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
    logger.info("radiation of %s: L_W = %.1f dB (wheel %.1f, rail %.1f), L_pA = %.1f dB(A)", Path(case_path).stem,
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
