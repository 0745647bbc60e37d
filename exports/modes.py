"""Export of the wheel's mode shapes to ParaView (``pipeline.py export modes`` / ``export-modes``).

Writes one VTU file: the hex20 mesh with one point-data vector per mode
(``mode_001_396.4Hz_n2_axial``), whichever solver computed the modes; axisymmetric modes are
expanded on the 3D nodes with :func:`fe.axisymmetric.reconstruct`.
"""

from __future__ import annotations

import logging
from pathlib import Path

import meshio
import numpy as np

from fe.axisymmetric import reconstruct
from fe.classify import ring_index
from squealcore.artefacts import atomic_output
from squealcore.errors import InputError
from stages.wheel import read_mesh, read_modes

logger = logging.getLogger(__name__)


def mode_name(modes, index):
    """Name of mode ``index`` (0-based) in exported files, e.g. ``mode_003_396.4Hz_n2_axial``."""
    return (f"mode_{index + 1:03d}_{modes['frequency'][index]:.1f}Hz_n{modes['nodal_diameters'][index]}"
            f"_{modes['family'][index]}")


def hex_node_shapes(mesh, modes, index):
    """Cartesian shape (N, 3) of mode ``index`` at the hex20 nodes, m/√kg."""
    if modes["solver"] == "hex20":
        return np.asarray(modes["shapes"][index], dtype=float)
    nodes = mesh["hex_nodes"]
    section = mesh["section_nodes"]
    r = np.hypot(nodes[:, 0], nodes[:, 2])
    theta = np.arctan2(nodes[:, 0], -nodes[:, 2])
    # section node of each 3D node: match (r, z) rings
    ring, ring_rz = ring_index(np.concatenate([section[:, 0], r]), np.concatenate([section[:, 1], nodes[:, 1]]))
    section_of_ring = np.full(ring_rz.shape[0], -1)
    section_of_ring[ring[: len(section)]] = np.arange(len(section))
    node_section = section_of_ring[ring[len(section):]]
    if np.any(node_section < 0):
        raise ValueError("3D nodes that are not on a section node's circle")
    angles, angle_index = np.unique(np.round(theta, 12), return_inverse=True)
    full = reconstruct(modes["shapes"][index], int(modes["nodal_diameters"][index]), str(modes["orientation"][index]),
                       section, angles)
    return full[angle_index.ravel(), node_section]


def chosen_modes(selection, count):
    """0-based indices of the 1-based mode numbers ``selection`` (all if None).

    Raises
    ------
    InputError
        (field ``--modes``) if the selection is empty or a number is not an integer in 1..count.
    """
    if selection is None:
        return list(range(count))
    selection = list(selection)
    if not selection:
        raise InputError("--modes", f"give at least one mode number in 1..{count} (or none for all)")
    bad = [k for k in selection
           if isinstance(k, bool) or not isinstance(k, (int, np.integer)) or not 1 <= k <= count]
    if bad:
        raise InputError("--modes", f"mode numbers must be integers in 1..{count} (the study has {count} modes), "
                                    f"got {', '.join(map(repr, bad))}")
    return [int(k) - 1 for k in selection]


def export_modes(out_dir, path, selection=None):
    """Write the mode shapes of ``out_dir``'s wheel artefacts to a VTU file.

    Parameters
    ----------
    out_dir : Path
        Folder with ``wheel_mesh.h5`` and ``wheel_modes.h5``.
    path : Path
        Output ``.vtu``.
    selection : sequence of int, optional
        Mode numbers (1-based); default all.

    Returns
    -------
    int
        Number of modes written.

    Raises
    ------
    InputError
        If a selected mode number is outside 1..(number of modes); nothing is written.
    """
    out_dir = Path(out_dir)
    modes = read_modes(out_dir / "wheel_modes.h5", with_shapes=True)
    chosen = chosen_modes(selection, modes["frequency"].size)
    mesh = read_mesh(out_dir / "wheel_mesh.h5")
    point_data = {mode_name(modes, k): hex_node_shapes(mesh, modes, k) for k in chosen}
    out = meshio.Mesh(mesh["hex_nodes"], [("hexahedron20", mesh["hex_cells"])], point_data=point_data)
    with atomic_output(path) as tmp:
        meshio.write(str(tmp), out, file_format="vtu")
    logger.info("wrote %d mode shapes to %s", len(point_data), path)
    return len(point_data)
