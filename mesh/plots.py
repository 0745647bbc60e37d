"""PNG pictures of the meshes: wheel section, 3D wheel surface, rail section (matplotlib, Agg canvas,
no pyplot global state)."""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.collections import LineCollection, PolyCollection
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from mesh.rail_mesh import RailMesh, edge_table
from mesh.wheel_mesh import WheelMesh

logger = logging.getLogger(__name__)

#: Boundary walk of a VTK quad8: corner, mid-side, corner, ...
_QUAD8_WALK = [0, 4, 1, 5, 2, 6, 3, 7]
#: Corner nodes of the six faces of a VTK hexahedron, outward normals.
_HEX_FACES = np.array([[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4],
                       [1, 2, 6, 5], [2, 3, 7, 6], [3, 0, 4, 7]])


def plot_section_mesh(mesh: WheelMesh, path: str | Path) -> None:
    """Save a PNG of the section mesh.

    The axial position z is drawn horizontally and the radius r vertically, both in mm, with
    equal axes; clamped (bore) nodes and the contact node are marked.

    Parameters
    ----------
    mesh : WheelMesh
    path : str or Path
        Output PNG file.
    """
    mm = 1e3 * mesh.section_nodes[:, ::-1]          # (z, r) in mm
    fig = Figure(figsize=(7, 8))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    polys = mm[mesh.section_cells[:, _QUAD8_WALK]]
    ax.add_collection(PolyCollection(polys, facecolors="#d9e6f2", edgecolors="k", linewidths=0.6))
    ax.plot(mm[:, 0], mm[:, 1], ".", color="0.3", ms=2)
    clamped = mm[mesh.section_clamped_nodes]
    ax.plot(clamped[:, 0], clamped[:, 1], "s", color="tab:red", ms=4, label="clamped (bore)")
    c = mm[mesh.contact_section_node]
    ax.plot(c[0], c[1], "*", color="tab:orange", ms=14, mec="k", label="contact point")
    ax.set_aspect("equal")
    ax.autoscale_view()
    ax.set_xlabel("z, axial from flange back (mm)")
    ax.set_ylabel("r, radius (mm)")
    ax.set_title(f"Wheel section: {len(mesh.section_cells)} quad8, {len(mm)} nodes, "
                 f"{mesh.mass:.1f} kg")
    ax.legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.savefig(str(path), dpi=120, bbox_inches="tight")
    logger.info("wrote %s", path)


def boundary_faces(cells: np.ndarray) -> np.ndarray:
    """Corner nodes of the hexahedron faces that belong to one element only, shape (F, 4)."""
    faces = cells[:, _HEX_FACES].reshape(-1, 4)
    key = np.sort(faces, axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    return faces[first[counts == 1]]


def plot_wheel_3d(mesh: WheelMesh, path: str | Path) -> None:
    """Save a PNG view of the surface mesh of the 3D wheel (corner nodes of boundary faces).

    Parameters
    ----------
    mesh : WheelMesh
    path : str or Path
        Output PNG file.
    """
    elev, azim = np.radians(20.0), np.radians(-60.0)
    faces = boundary_faces(mesh.hex_cells)
    # Plot axes: X (tangential), Y (axle) and Z (up), in mm.
    polys = 1e3 * mesh.hex_nodes[faces]
    normals = np.cross(polys[:, 2] - polys[:, 0], polys[:, 3] - polys[:, 1])
    normals /= np.linalg.norm(normals, axis=1, keepdims=True)
    # Back-face culling (outward normals) avoids matplotlib's depth-sorting artefacts.
    eye = np.array([np.cos(elev) * np.cos(azim), np.cos(elev) * np.sin(azim), np.sin(elev)])
    front = normals @ eye > 0.0
    polys, normals = polys[front], normals[front]
    light = np.array([0.4, -0.6, 0.7]) / np.linalg.norm([0.4, -0.6, 0.7])
    shade = 0.35 + 0.65 * np.clip(normals @ light, 0.0, 1.0)
    colours = np.column_stack([0.55 * shade, 0.65 * shade, 0.8 * shade, np.ones_like(shade)])
    fig = Figure(figsize=(8, 8))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1, projection="3d")
    ax.add_collection3d(Poly3DCollection(polys, facecolors=colours, edgecolors="k", linewidths=0.1))
    c = 1e3 * mesh.hex_nodes[mesh.contact_hex_node]
    ax.scatter([c[0]], [c[1]], [c[2]], color="tab:orange", s=60, depthshade=False)
    lim = 1e3 * np.abs(mesh.hex_nodes).max()
    ax.set_xlim(-lim, lim)
    ax.set_ylim(-lim, lim)
    ax.set_zlim(-lim, lim)
    ax.set_box_aspect((1, 1, 1))
    ax.set_xlabel("X (mm)")
    ax.set_ylabel("Y, axle (mm)")
    ax.set_zlabel("Z, up (mm)")
    ax.view_init(elev=np.degrees(elev), azim=np.degrees(azim))
    ax.set_title(f"3D wheel: {len(mesh.hex_cells)} hex20, {len(mesh.hex_nodes)} nodes")
    fig.savefig(str(path), dpi=110, bbox_inches="tight")
    logger.info("wrote %s", path)


def plot_rail_mesh(mesh: RailMesh, path, title: str | None = None):
    """Write a PNG of the section mesh (element edges drawn with their mid-side nodes).

    Parameters
    ----------
    mesh : RailMesh
    path : str or path-like
        Output PNG file.
    title : str, optional
    """
    tab = edge_table(mesh.element_type)
    edges = mesh.cells[:, tab].reshape(-1, 3)
    segs = np.concatenate([mesh.nodes[edges[:, [0, 2]]], mesh.nodes[edges[:, [2, 1]]]]) * 1e3
    fig = Figure(figsize=(5, 6))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 1, 1)
    ax.add_collection(LineCollection(segs, linewidths=0.5, colors="k"))
    ax.plot(*(mesh.nodes.T * 1e3), ".", ms=1.5, color="tab:blue")
    ax.set_aspect("equal")
    ax.autoscale()
    ax.set_xlabel("y (mm), field side ->")
    ax.set_ylabel("z (mm)")
    ax.set_title(title or f"{len(mesh.cells)} {mesh.element_type} elements, {mesh.n_nodes} nodes")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
