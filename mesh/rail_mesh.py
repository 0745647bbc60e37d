"""Mesh a rail cross-section with gmsh (8-node quadrilaterals or 6-node triangles).

The mesh is returned as plain arrays in the section coordinates of
:mod:`profiles.rail_section` (y lateral to the field side, z up, origin at the foot-bottom
centre, m). Cells list corner nodes first, counter-clockwise, then mid-side nodes
(docs/conventions.md).
"""

from __future__ import annotations

import dataclasses
import logging

import gmsh
import numpy as np

from profiles.rail_section import RailParams, rail_outline, validate_outline
from squealcore.library_output import stdout_to_log

logger = logging.getLogger(__name__)

__all__ = ["RailMesh", "mesh_rail_section", "mesh_outline", "edge_table"]

# gmsh element type ids -> (our name, number of nodes); gmsh node orders for these two
# types coincide with the VTK order used here.
_GMSH_TYPES = {16: ("quad8", 8), 9: ("tri6", 6)}


@dataclasses.dataclass(frozen=True)
class RailMesh:
    """A meshed rail cross-section.

    Attributes
    ----------
    nodes : ndarray (N, 2)
        Node coordinates (y, z) in m.
    cells : ndarray (E, 8) or (E, 6)
        Connectivity, corners counter-clockwise first, then mid-side nodes.
    element_type : str
        ``"quad8"`` or ``"tri6"``.
    boundary_edges : ndarray (B, 3)
        Outer boundary edges as (corner, corner, mid-side) node ids, oriented so that the
        material lies on the left (counter-clockwise outline).
    density : float
        Steel density (kg/m^3).
    """

    nodes: np.ndarray
    cells: np.ndarray
    element_type: str
    boundary_edges: np.ndarray
    density: float = 7850.0

    @property
    def n_nodes(self) -> int:
        return len(self.nodes)

    @property
    def height(self) -> float:
        """Top of the section (m)."""
        return float(self.nodes[:, 1].max())

    def to_arrays(self) -> dict:
        """Plain arrays for an HDF5 artefact (nodes m, cells, boundary_edges)."""
        return {"nodes": self.nodes, "cells": self.cells, "boundary_edges": self.boundary_edges,
                "element_type": self.element_type, "density": self.density}

    @classmethod
    def from_arrays(cls, d) -> "RailMesh":
        """Inverse of :meth:`to_arrays`."""
        return cls(np.asarray(d["nodes"], float), np.asarray(d["cells"], np.int64),
                   str(d["element_type"]), np.asarray(d["boundary_edges"], np.int64),
                   float(d["density"]))


def edge_table(element_type):
    """Local node triples (corner, corner, mid-side) of the element edges, (n_edges, 3) int array."""
    if element_type == "quad8":
        return np.array([[0, 1, 4], [1, 2, 5], [2, 3, 6], [3, 0, 7]])
    return np.array([[0, 1, 3], [1, 2, 4], [2, 0, 5]])


def _boundary_edges(cells, element_type):
    tab = edge_table(element_type)
    edges = cells[:, tab].reshape(-1, 3)
    key = np.sort(edges[:, :2], axis=1)
    _, inv, cnt = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    return edges[cnt[inv.ravel()] == 1]


def mesh_outline(outline, element_size: float, element_type: str = "quad8",
                 density: float = 7850.0) -> RailMesh:
    """Mesh a closed polygon with gmsh.

    Parameters
    ----------
    outline : ndarray (n, 2)
        Counter-clockwise closed outline (y, z) in m (last point joins the first).
    element_size : float
        Target element size (m).
    element_type : {"quad8", "tri6"}
    density : float
        Density stored with the mesh (kg/m^3).

    Returns
    -------
    RailMesh
    """
    outline = np.asarray(outline, float)
    validate_outline(outline)
    initialised_here = not gmsh.isInitialized()
    if initialised_here:
        gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("rail_section")
        geo = gmsh.model.geo
        # quads: recombine a mesh of twice the size, then split every element into quads
        # (gmsh's subdivision), which guarantees an all-quad mesh of about element_size
        lc = 2 * element_size if element_type == "quad8" else element_size
        tags = [geo.addPoint(y, z, 0.0, lc) for y, z in outline]
        lines = [geo.addLine(tags[i], tags[(i + 1) % len(tags)]) for i in range(len(tags))]
        loop = geo.addCurveLoop(lines)
        surf = geo.addPlaneSurface([loop])
        geo.synchronize()
        if element_type == "quad8":
            gmsh.model.mesh.setRecombine(2, surf)
            gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)
            gmsh.option.setNumber("Mesh.SubdivisionAlgorithm", 1)
            gmsh.option.setNumber("Mesh.Algorithm", 8)
            gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
        else:
            gmsh.option.setNumber("Mesh.Algorithm", 6)
        gmsh.option.setNumber("Mesh.MeshSizeMax", lc)
        with stdout_to_log(logger, "gmsh"):  # past General.Terminal: to the log (INFO)
            gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(2)
        node_tags, coords, _ = gmsh.model.mesh.getNodes()
        etypes, _, enodes = gmsh.model.mesh.getElements(2)
    finally:
        gmsh.model.remove()
        if initialised_here:
            gmsh.finalize()
    want = 16 if element_type == "quad8" else 9
    if want not in list(etypes):
        raise RuntimeError(f"gmsh produced element types {list(etypes)}, expected {want}")
    if len(etypes) != 1:
        raise RuntimeError(f"gmsh produced mixed element types {list(etypes)}")
    nn = _GMSH_TYPES[want][1]
    conn_tags = np.asarray(enodes[list(etypes).index(want)], np.int64).reshape(-1, nn)
    xyz = np.asarray(coords).reshape(-1, 3)[:, :2]
    used, conn = np.unique(conn_tags, return_inverse=True)
    conn = conn.reshape(-1, nn)
    lookup = {int(t): i for i, t in enumerate(node_tags)}
    nodes = xyz[[lookup[int(t)] for t in used]]
    conn = _orient_ccw(nodes, conn, element_type)
    bnd = _boundary_edges(conn, element_type)
    logger.info("rail section mesh: %d %s elements, %d nodes", len(conn), element_type, len(nodes))
    return RailMesh(nodes=nodes, cells=conn, element_type=element_type, boundary_edges=bnd,
                    density=float(density))


def _orient_ccw(nodes, conn, element_type):
    """Reverse clockwise elements so that corners run counter-clockwise."""
    nc = 4 if element_type == "quad8" else 3
    c = nodes[conn[:, :nc]]
    area = 0.5 * np.sum(c[:, :, 0] * np.roll(c[:, :, 1], -1, 1) - np.roll(c[:, :, 0], -1, 1) * c[:, :, 1], 1)
    flip = area < 0
    if np.any(flip):
        if element_type == "quad8":
            perm = [0, 3, 2, 1, 7, 6, 5, 4]
        else:
            perm = [0, 2, 1, 5, 4, 3]
        conn = conn.copy()
        conn[flip] = conn[flip][:, perm]
    return conn


def mesh_rail_section(params: RailParams) -> RailMesh:
    """Mesh the rail section described by the ``[rail]`` parameters.

    Parameters
    ----------
    params : RailParams

    Returns
    -------
    RailMesh
    """
    outline = rail_outline(params.profile, size=params.element_size)
    return mesh_outline(outline, params.element_size, params.element_type, params.density)
