"""Export of the wheel's mode shapes to ParaView (``pipeline.py export-modes``).

Writes ``wheel_modes.vtu``: the hex20 mesh with one point-data vector per mode
(``mode_001_396.4Hz_n2_axial``), whichever solver computed the modes; axisymmetric modes are
expanded on the 3D nodes with :func:`fe.axisymmetric.reconstruct`.
"""

from __future__ import annotations

import logging

import numpy as np

from fe.classify import ring_index
from squealcore.artefacts import atomic_output

logger = logging.getLogger(__name__)


def hex_node_shapes(mesh, modes, index):
    """Cartesian shape (N, 3) of mode ``index`` at the hex20 nodes, m/√kg."""
    if modes["solver"] == "hex20":
        return np.asarray(modes["shapes"][index], dtype=float)
    from fe.axisymmetric import reconstruct

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
    """
    import meshio

    from stages.wheel import read_mesh, read_modes

    mesh = read_mesh(out_dir / "wheel_mesh.h5")
    modes = read_modes(out_dir / "wheel_modes.h5", with_shapes=True)
    count = modes["frequency"].size
    chosen = range(count) if selection is None else [k - 1 for k in selection if 1 <= k <= count]
    point_data = {}
    for k in chosen:
        name = (f"mode_{k + 1:03d}_{modes['frequency'][k]:.1f}Hz_n{modes['nodal_diameters'][k]}"
                f"_{modes['family'][k]}")
        point_data[name] = hex_node_shapes(mesh, modes, k)
    out = meshio.Mesh(mesh["hex_nodes"], [("hexahedron20", mesh["hex_cells"])], point_data=point_data)
    with atomic_output(path) as tmp:
        meshio.write(str(tmp), out, file_format="vtu")
    logger.info("wrote %d mode shapes to %s", len(point_data), path)
    return len(point_data)
