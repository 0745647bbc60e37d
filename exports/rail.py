"""The rail for ParaView (``pipeline.py export rail``): section mesh and wave shapes as VTU.

Files written into the target folder:

``rail_section.vtu``
    the cross-section mesh of ``rail_mesh.h5`` (quad8 or tri6 cells) in the plane x = 0 of the
    track frame (x along the rail, y lateral towards the field side, z up; m).
``rail_waves_<f>Hz.vtu``
    the same mesh with, per wave travelling or decaying towards +x at frequency f, its
    cross-section shape U(y, z) as two point vectors, real and imaginary part, named after the
    wave's rank (01 decays least), dominant motion and wavenumber kappa (rad/m, 4 digits),
    e.g. ``w01_vertical_kappa=2.31-0.0497j_re`` / ``..._im``. The displacement of the wave is
    ``u(x, y, z, t) = Re[U(y, z) exp(i (omega t - kappa x))]``; U is dimensionless, scaled to
    a largest nodal amplitude |U| of 1 with that component real and positive.
``rail_waves.csv``
    the exported waves with their exact wavenumbers and decay rates (CSV, ``#`` comments).

The waves are recomputed from ``rail_mesh.h5`` and the study's ``[track]`` with the waveguide
model of the ``rail-greens`` stage (:func:`waveguide.api.build_waveguide`, the same reduced
basis when the frequencies lie within its range): their wavenumbers are those of
:meth:`waveguide.waves.RailWaveguide.waves`, and each shape is the null vector of the dynamic
stiffness ``D(kappa, omega)`` (:meth:`~waveguide.waves.RailWaveguide.dynamic_matrix`), taken
from its singular value decomposition.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import meshio
import numpy as np

from squealcore.artefacts import atomic_output
from squealcore.errors import InputError
from squealcore.study import get_section
from squealcore.csv_tables import write_csv
from stages.rail import read_mesh
from waveguide.api import build_waveguide
from waveguide.params import TrackParams
from waveguide.waves import LABELS

logger = logging.getLogger(__name__)

DEFAULT_FREQUENCIES = (500.0, 1000.0, 2000.0, 5000.0)
"""Hz, frequencies of the exported wave shapes unless the caller chooses."""

WAVES_PER_FREQUENCY = 10
"""Waves exported per frequency: the ones that decay least (the others are near fields that die
out within centimetres)."""

MAX_FREQUENCY = 50e3
"""Hz, upper limit of an exported frequency."""

MESHIO_CELL_TYPE = {"quad8": "quad8", "tri6": "triangle6"}


def check_frequencies(frequencies):
    """Validated export frequencies (Hz) as a sorted float array without duplicates.

    Raises
    ------
    InputError
        (field ``--frequencies``) if empty or a value is not a number in (0, 50000] Hz.
    """
    values = list(DEFAULT_FREQUENCIES if frequencies is None else frequencies)
    if not values:
        raise InputError("--frequencies", f"give at least one frequency in (0, {MAX_FREQUENCY:g}] Hz")
    for value in values:
        if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)) \
                or not math.isfinite(value) or not 0.0 < value <= MAX_FREQUENCY:
            raise InputError("--frequencies", f"must be numbers in (0, {MAX_FREQUENCY:g}] Hz, got {value!r}")
    return np.unique(np.asarray(values, dtype=float))


def section_points(nodes):
    """3D points (N, 3) of the section nodes (y, z) in the plane x = 0, m."""
    nodes = np.asarray(nodes, dtype=float)
    return np.column_stack([np.zeros(len(nodes)), nodes])


def wave_shape(waveguide, kappa, omega):
    """Cross-section shape of the wave with wavenumber ``kappa`` at ``omega``.

    Parameters
    ----------
    waveguide : waveguide.waves.RailWaveguide
    kappa : complex
        Wavenumber (rad/m), an eigenvalue of the waveguide at ``omega``.
    omega : float
        rad/s.

    Returns
    -------
    shape : (n_nodes, 3) complex ndarray
        Physical displacements (u_x, u_y, u_z) per node, largest nodal amplitude 1 with that
        component real and positive (-).
    residual : float
        ``|D v| / (|D| |v|)`` of the reduced null vector v (2-norms): small when ``kappa`` is a
        wavenumber of the model.
    """
    d = waveguide.dynamic_matrix(kappa, omega)
    _, sigma, vh = np.linalg.svd(d)
    v = vh[-1].conj()
    residual = float(sigma[-1] / sigma[0])
    u = (waveguide.basis @ v).reshape(-1, 3)
    u[:, 0] *= 1j  # symmetric form -> physical axial displacement (U = T V, T = diag(i, 1, 1))
    node, component = np.unravel_index(np.argmax(np.abs(u)), u.shape)
    peak = u[node, component]
    return u * (abs(peak) / peak) / abs(peak), residual


def rail_waves(waveguide, frequency, count=WAVES_PER_FREQUENCY):
    """The ``count`` least-decaying waves towards +x at ``frequency`` (Hz) with their shapes.

    Returns
    -------
    list of dict
        Sorted by decay: ``kappa`` (complex, rad/m), ``decay`` (dB/m), ``label`` (str, one of
        :data:`waveguide.waves.LABELS`), ``shape`` ((n_nodes, 3) complex, -), ``residual`` (-).
    """
    omega = 2.0 * np.pi * float(frequency)
    waves = waveguide.waves(omega)
    order = np.argsort(np.abs(waves.kappa.imag), kind="stable")[:count]
    out = []
    for n in order:
        kappa = complex(waves.kappa[n])
        shape, residual = wave_shape(waveguide, kappa, omega)
        out.append({"kappa": kappa, "decay": float(waves.decay_db_per_m[n]), "label": LABELS[int(waves.label[n])],
                    "label_index": int(waves.label[n]), "shape": shape, "residual": residual})
    return out


def rail_model_frequency(study, frequencies):
    """Frequency (Hz) up to which the exported waveguide model is built: the ``rail-greens``
    stage's ``min(track.max_frequency, 1 / time_step)``, raised to the highest export frequency."""
    track = get_section(study, "track")
    return max(min(track["max_frequency"], 1.0 / study["time"]["time_step"]), float(np.max(frequencies)))


def wave_field_name(rank, wave):
    """Point-data name prefix of a wave: rank, dominant motion and wavenumber (rad/m)."""
    kappa = wave["kappa"]
    return f"w{rank:02d}_{wave['label']}_kappa={kappa.real:.4g}{kappa.imag:+.4g}j"


def _write_vtu(path, points, cell_type, cells, point_data=None):
    mesh = meshio.Mesh(points, [(cell_type, cells)], point_data=point_data or {})
    with atomic_output(path) as tmp:
        meshio.write(str(tmp), mesh, file_format="vtu")
    return Path(path)


def export_rail(study, out_dir, target_dir, frequencies=None):
    """Write the rail section mesh and the wave shapes at chosen frequencies as VTU files.

    Parameters
    ----------
    study : dict
        The validated study (its ``[track]`` and ``[time]`` sections are used).
    out_dir : Path
        Folder with ``rail_mesh.h5``.
    target_dir : Path
        Folder for the VTU files (created if needed).
    frequencies : sequence of float, optional
        Hz; default :data:`DEFAULT_FREQUENCIES`.

    Returns
    -------
    list of Path
        ``rail_section.vtu``, one ``rail_waves_<f>Hz.vtu`` per frequency and ``rail_waves.csv``.

    Raises
    ------
    InputError
        If a frequency is not in (0, 50000] Hz (nothing is written).
    """
    freqs = check_frequencies(frequencies)
    out_dir, target_dir = Path(out_dir), Path(target_dir)
    mesh = read_mesh(out_dir / "rail_mesh.h5")
    track = TrackParams.from_mapping(get_section(study, "track"), "track")
    waveguide = build_waveguide(mesh, track, rail_model_frequency(study, freqs))
    points = section_points(mesh.nodes)
    cell_type = MESHIO_CELL_TYPE[mesh.element_type]
    written = [_write_vtu(target_dir / "rail_section.vtu", points, cell_type, mesh.cells)]
    table = []
    for frequency in freqs:
        point_data = {}
        for rank, wave in enumerate(rail_waves(waveguide, frequency), start=1):
            name = wave_field_name(rank, wave)
            point_data[f"{name}_re"] = wave["shape"].real
            point_data[f"{name}_im"] = wave["shape"].imag
            table.append((frequency, rank, wave["label_index"], wave["kappa"].real, wave["kappa"].imag,
                          wave["decay"]))
            logger.info("rail wave %s at %g Hz: %.3g dB/m (residual %.1e)", name, frequency, wave["decay"],
                        wave["residual"])
        written.append(_write_vtu(target_dir / f"rail_waves_{frequency:g}Hz.vtu", points, cell_type, mesh.cells,
                                  point_data))
    names = ("frequency_Hz", "wave_rank", "label_index", "kappa_re_rad_per_m", "kappa_im_rad_per_m",
             "decay_dB_per_m")
    comments = ("curve-squeal rail waves towards +x exported with their shapes (rail_waves_<f>Hz.vtu)",
                "wave displacement u(x, t) = Re[U exp(i (omega t - kappa x))], Im kappa <= 0; "
                "decay_dB_per_m = -20 log10(e) Im kappa",
                "label_index: " + ", ".join(f"{k} {label}" for k, label in enumerate(LABELS)),
                "wave_rank: 1 decays least at its frequency; numbers: shortest exact binary64 text")
    written.append(write_csv(target_dir / "rail_waves.csv", list(zip(names, np.array(table).T)), comments))
    logger.info("wrote the rail section and wave shapes at %s Hz to %s", ", ".join(f"{f:g}" for f in freqs),
                target_dir)
    return written
