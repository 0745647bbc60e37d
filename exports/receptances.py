"""Receptances as CSV tables (``pipeline.py export receptances``), the way TWINS users exchange them.

Files written into the target folder:

``wheel_<model>_receptance.csv``
    one per wheel model of ``wheel_greens.h5`` (``stationary``, ``moving_load``, ``eulerian``),
    on that artefact's frequency grid (refined around every peak);
``rail_point_receptance.csv``
    the rail at the load point (``rail_greens.h5``, distance 0);
``rail_moving_receptance.csv``
    the rail seen by the moving contact point (``rail_greens.h5:/moving``): the spectrum of the
    moving kernel over the first-order-hold factor, i.e. the moving receptance plus its aliases
    (:func:`waveguide.greens.moving_kernel`), up to the Nyquist frequency of the time step.

Columns: ``frequency_Hz``, then for each component ij of the 3 x 3 matrix (i the response, j the
force, both in x, y, z of the contact frame) ``H_ij_re_m_per_N``, ``H_ij_im_m_per_N``,
``H_ij_dB_re_1m_per_N`` (20 log10 |H|) and ``H_ij_phase_deg`` (atan2(Im, Re), -180 to 180).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from squealcore.artefacts import ArtefactError, open_artefact, read_dataset
from squealcore.csv_tables import artefact_provenance, write_csv
from stages.greens_layout import WHEEL_GREENS_VERSION
from stages.rail import GREENS_VERSION as RAIL_GREENS_VERSION
from interaction.wheel_models import wheel_model_names

logger = logging.getLogger(__name__)

"""Wheel models written by the ``wheel-greens`` stage."""

AXES = "xyz"
"""Component letters of the contact frame."""

CONVENTIONS = (
    "H[i,j] = displacement i per unit force j (complex, m/N), time dependence exp(+i omega t)",
    "frame: contact frame, x longitudinal (rolling direction), y lateral (flange towards field side), "
    "z vertical (up)",
    "columns: frequency_Hz, then per component ij (i response, j force): H_ij_re_m_per_N, H_ij_im_m_per_N, "
    "H_ij_dB_re_1m_per_N = 20 log10(|H| / (1 m/N)) (-inf where H is exactly 0), H_ij_phase_deg = atan2(Im H, Re H) in degrees",
    "numbers: shortest decimal text that reads back to the same binary64 value",
)


def receptance_columns(frequency, receptance):
    """The CSV columns of a receptance.

    Parameters
    ----------
    frequency : (nf,) array_like
        Hz.
    receptance : (nf, 3, 3) complex array_like
        m/N.

    Returns
    -------
    list of (str, ndarray)
        ``frequency_Hz`` and, per component ij, real and imaginary part (m/N), level (dB re
        1 m/N; ``-inf`` where H is exactly zero) and phase (deg).
    """
    h = np.asarray(receptance)
    columns = [("frequency_Hz", np.asarray(frequency, dtype=float))]
    with np.errstate(divide="ignore"):
        level = 20.0 * np.log10(np.abs(h))
    phase = np.degrees(np.angle(h))
    for i, a in enumerate(AXES):
        for j, b in enumerate(AXES):
            columns += [(f"H_{a}{b}_re_m_per_N", h[:, i, j].real), (f"H_{a}{b}_im_m_per_N", h[:, i, j].imag),
                        (f"H_{a}{b}_dB_re_1m_per_N", level[:, i, j]), (f"H_{a}{b}_phase_deg", phase[:, i, j])]
    return columns


def export_receptances(out_dir, target_dir):
    """Write the wheel and rail receptances of a study folder as CSV files.

    Parameters
    ----------
    out_dir : Path
        Folder with ``wheel_greens.h5`` and ``rail_greens.h5``.
    target_dir : Path
        Folder for the CSV files (created if needed).

    Returns
    -------
    list of Path
        The files written: ``wheel_<model>_receptance.csv`` per wheel model,
        ``rail_point_receptance.csv``, ``rail_moving_receptance.csv``.

    Raises
    ------
    ArtefactError
        If an artefact is missing or not of the expected layout.
    """
    out_dir, target_dir = Path(out_dir), Path(target_dir)
    written = []
    with open_artefact(out_dir / "wheel_greens.h5", "wheel_greens", WHEEL_GREENS_VERSION) as f:
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        speed = float(read_dataset(f, "speed", "m/s"))
        for model in wheel_model_names():
            if model not in f:
                raise ArtefactError(f"{f.filename}: no wheel model {model!r}")
            receptance = read_dataset(f[model], "receptance", "m/N", (frequency.size, 3, 3))
            comments = (f"curve-squeal wheel receptance at the contact point, wheel model {model!r} "
                        f"(speed {speed!r} m/s)", artefact_provenance(f),
                        "force: exerted by the rail on the wheel; response: wheel displacement at the contact point",
                        *CONVENTIONS)
            written.append(write_csv(target_dir / f"wheel_{model}_receptance.csv",
                                     receptance_columns(frequency, receptance), comments))
    with open_artefact(out_dir / "rail_greens.h5", "rail_greens", RAIL_GREENS_VERSION) as f:
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        distance = read_dataset(f, "distance", "m", (None,))
        if distance[0] != 0.0:
            raise ArtefactError(f"{f.filename}: distance[0] = {distance[0]} m, expected 0 (the load point)")
        point = read_dataset(f, "receptance", "m/N", (distance.size, frequency.size, 3, 3))[0]
        moving_frequency = read_dataset(f, "moving/frequency", "Hz", (None,))
        moving = read_dataset(f, "moving/receptance", "m/N", (moving_frequency.size, 3, 3))
        speed = float(read_dataset(f, "speed", "m/s"))
        time_step = float(read_dataset(f, "time_step", "s"))
        source = artefact_provenance(f)
    rail_force = "force: applied to the rail head (spread over the load patch); response: rail displacement there"
    written.append(write_csv(target_dir / "rail_point_receptance.csv", receptance_columns(frequency, point),
                             ("curve-squeal rail point receptance at the load point (distance 0 m)", source,
                              rail_force, *CONVENTIONS)))
    written.append(write_csv(
        target_dir / "rail_moving_receptance.csv", receptance_columns(moving_frequency, moving),
        (f"curve-squeal rail moving receptance: the load and the response point move together at {speed!r} m/s; "
         f"spectrum of the moving kernel (time step {time_step!r} s) over the first-order-hold factor, "
         "i.e. the moving receptance plus its aliases (waveguide.greens.moving_kernel)", source, rail_force,
         *CONVENTIONS)))
    logger.info("wrote %d receptance tables to %s", len(written), target_dir)
    return written
