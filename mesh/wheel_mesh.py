"""gmsh meshes of the wheel: 8-node quadrilateral section and 20-node hexahedral 3D wheel.

The section outline (:mod:`mesh.wheel_section`) is meshed with quadrilaterals only
(Frontal-Delaunay triangles recombined by the Blossom algorithm; the number of boundary edges is
made even so that a full-quad recombination exists). The 3D wheel is the structured revolution of
that same quad mesh about the axle (gmsh ``geo.revolve`` with ``recombine=True`` in four pieces
of at most 180 deg), and both meshes are made quadratic with ``Mesh.SecondOrderIncomplete=1``.
The 3D corner nodes are exact rotations of the section corner nodes. gmsh's second-order nodes
on the revolved boundary surfaces can stray from the surface of revolution (seen: up to 0.4 mm on
the default mesh), so the 3D mid-edge nodes are then set exactly: in-plane ones at the rotated
section mid-side nodes, circumferential ones on the circles of the section corner nodes at the
mid angle (and the gmsh model is updated before a .msh is written). For outlines read from a
file and for tread profiles (``wheel.tread_profile``), the section mid-side nodes of boundary
edges are placed on the outline's polygon (the profile's points).

Coordinates follow ``docs/conventions.md``: section point (r, z) at angle theta sits at
``(X, Y, Z) = (r sin theta, z, -r cos theta)``; theta = 0 is the bottom (contact) of the wheel.
Element node orders are VTK's (``GMSH_QUAD8_TO_VTK``, ``GMSH_HEX20_TO_VTK``).
"""

from __future__ import annotations

import contextlib
import logging
import math
import time
from dataclasses import dataclass
from pathlib import Path

import gmsh
import meshio
import numpy as np
from scipy.spatial import cKDTree

from mesh.wheel_section import Outline, WheelParams, build_outline, outline_mass
from squealcore.errors import InputError
from squealcore.library_output import stdout_to_log

logger = logging.getLogger(__name__)

#: gmsh element type numbers.
GMSH_QUAD8 = 16
GMSH_HEX20 = 17

#: Column permutation from gmsh's 8-node quadrilateral to VTK's: ``vtk = gmsh[:, PERM]``.
#: Both list the 4 corners, then the mid-side nodes of edges 0-1, 1-2, 2-3, 3-0.
GMSH_QUAD8_TO_VTK = np.arange(8)

#: Column permutation from gmsh's 20-node hexahedron to VTK/Abaqus C3D20: ``vtk = gmsh[:, PERM]``.
#: Corners 0-7 agree. gmsh orders the mid-edge nodes by edges 0-1, 0-3, 0-4, 1-2, 1-5, 2-3,
#: 2-6, 3-7, 4-5, 4-7, 5-6, 6-7 (positions 8-19); VTK by 0-1, 1-2, 2-3, 3-0, 4-5, 5-6, 6-7,
#: 7-4, 0-4, 1-5, 2-6, 3-7.
GMSH_HEX20_TO_VTK = np.array([0, 1, 2, 3, 4, 5, 6, 7,
                              8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15])

#: VTK hex20 column permutation that mirrors an element (swaps the faces zeta = -1 and +1).
HEX20_FLIP = np.array([4, 5, 6, 7, 0, 1, 2, 3, 12, 13, 14, 15, 8, 9, 10, 11, 16, 17, 18, 19])
#: VTK quad8 column permutation that reverses the orientation (0, 3, 2, 1 and their mid-sides).
QUAD8_FLIP = np.array([0, 3, 2, 1, 7, 6, 5, 4])

#: Number of revolution pieces (each spans at most 180 deg for elements_around >= 4).
REVOLVE_PIECES = 4
#: 2D meshing algorithms tried in turn until the recombined mesh has no triangle
#: (6 = Frontal-Delaunay, 8 = Frontal-Delaunay for quads, 5 = Delaunay).
QUAD_ALGORITHMS = (6, 8, 5)
#: Relative changes of the section element size tried when no algorithm gives only quads.
SIZE_FACTORS = (1.0, 0.97, 1.03, 0.94, 1.06, 0.91, 1.09, 0.88, 0.85, 0.82, 0.8)
#: Fallback: size factors for gmsh's quasi-structured quad algorithm (11), which gives about
#: three times more elements than the recombined algorithms at the same size.
QQS_SIZE_FACTORS = (1.8, 1.7, 1.9, 1.6, 2.0)


@dataclass(frozen=True)
class WheelMesh:
    """Section and 3D meshes of a wheel (SI units, VTK node orders).

    Attributes
    ----------
    params : WheelParams
        The parameters the mesh was built from.
    section_nodes : ndarray, shape (Ns, 2)
        Section node coordinates (r, z) (m).
    section_cells : ndarray of int, shape (Es, 8)
        8-node quadrilaterals, VTK order, counter-clockwise in (r, z).
    section_clamped_nodes : ndarray of int
        Section nodes on the hub bore edge (clamped), sorted.
    hex_nodes : ndarray, shape (N, 3)
        3D node coordinates (X, Y, Z) (m).
    hex_cells : ndarray of int, shape (E, 20)
        20-node hexahedra, VTK/Abaqus C3D20 order, positive volume.
    hex_clamped_nodes : ndarray of int
        3D nodes on the bore surface (clamped), sorted.
    contact_section_node : int
        Section node at the contact point (r_c, z_c).
    contact_hex_node : int
        3D node at the contact point (theta = 0).
    contact_position : ndarray, shape (3,)
        Contact point (X, Y, Z) = (0, z_c, -r_c) (m).
    mass : float
        Mass from the outline by Pappus' theorem (kg).
    """

    params: WheelParams
    section_nodes: np.ndarray
    section_cells: np.ndarray
    section_clamped_nodes: np.ndarray
    hex_nodes: np.ndarray
    hex_cells: np.ndarray
    hex_clamped_nodes: np.ndarray
    contact_section_node: int
    contact_hex_node: int
    contact_position: np.ndarray
    mass: float


@contextlib.contextmanager
def gmsh_model(name: str):
    """Initialise gmsh if needed, add a model, route gmsh messages to logging, clean up (every
    gmsh-built geometry of the project: wheel section, wheel, the BEM's thin disc)."""
    own = not gmsh.isInitialized()
    if own:
        gmsh.initialize(readConfigFiles=False, interruptible=False)
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    gmsh.logger.start()
    gmsh.model.add(name)
    try:
        # its embedded mesh optimisers print on stdout past General.Terminal: to the log (INFO)
        with stdout_to_log(logger, "gmsh"):
            yield
    finally:
        messages = gmsh.logger.get()
        for message in messages:
            level = logging.WARNING if message.startswith("Error") else logging.DEBUG
            logger.log(level, "gmsh: %s", message)
        n_warn = sum(m.startswith("Warning") for m in messages)
        if n_warn:
            logger.info("gmsh issued %d warnings (logged at DEBUG)", n_warn)
        gmsh.logger.stop()
        gmsh.model.remove()
        if own:
            gmsh.finalize()


def _segment_length(segment) -> float:
    """Length of an outline segment (m), from its fine discretisation."""
    pts = np.vstack([segment.discretise(), segment.points[-1]])
    return float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum())


def _curve_divisions(outline: Outline, size: float) -> list[int]:
    """Number of mesh edges on each outline segment, with an even total (full-quad meshes)."""
    lengths = [_segment_length(s) for s in outline.segments]
    counts = [max(1, int(round(length / size))) for length in lengths]
    if sum(counts) % 2:
        k = int(np.argmax([length / c for length, c in zip(lengths, counts)]))
        counts[k] += 1
    return counts


def _add_section(outline: Outline, size: float) -> tuple[int, int, int]:
    """Create the section surface in the plane theta = 0 with the gmsh geo kernel.

    Returns the surface tag, the tag of the bore curve and the tag of the contact point.
    """
    geo = gmsh.model.geo

    def point(rz):
        return geo.addPoint(0.0, float(rz[1]), -float(rz[0]), size)

    n = len(outline.segments)
    starts = [point(s.points[0]) for s in outline.segments]
    counts = _curve_divisions(outline, size)
    curves = []
    for i, seg in enumerate(outline.segments):
        a, b = starts[i], starts[(i + 1) % n]
        if seg.kind == "line":
            tag = geo.addLine(a, b)
        elif seg.kind == "arc":
            tag = geo.addCircleArc(a, point(seg.points[1]), b)
        else:
            tag = geo.addSpline([a] + [point(q) for q in seg.points[1:-1]] + [b])
        geo.mesh.setTransfiniteCurve(tag, counts[i] + 1)
        curves.append(tag)
    surface = geo.addPlaneSurface([geo.addCurveLoop(curves)])
    geo.mesh.setRecombine(2, surface)
    return surface, curves[outline.bore_segment], starts[outline.contact_vertex]


def _revolve(surface: int, elements_around: int) -> list[int]:
    """Revolve the section by 2 pi about the axle (Y) in pieces; returns the volume tags."""
    n = elements_around
    counts = [n // REVOLVE_PIECES + (1 if i < n % REVOLVE_PIECES else 0) for i in range(REVOLVE_PIECES)]
    current = [(2, surface)]
    volumes = []
    for count in counts:
        # Rotation about -Y by +angle maps (0, z, -r) to (r sin a, z, -r cos a): theta = angle.
        out = gmsh.model.geo.revolve(current, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0,
                                     2.0 * math.pi * count / n, numElements=[count], recombine=True)
        current = [out[0]]
        volumes.append(out[1][1])
    return volumes


def _set_2d_options(algorithm: int, size: float, linear_midnodes: bool) -> None:
    """gmsh options for the quadrilateral section mesh and the second-order conversion."""
    gmsh.option.setNumber("Mesh.Algorithm", algorithm)
    gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 1)  # Blossom
    gmsh.option.setNumber("Mesh.RecombineAll", 0)
    gmsh.option.setNumber("Mesh.MeshSizeMax", size)
    gmsh.option.setNumber("Mesh.ElementOrder", 1)
    gmsh.option.setNumber("Mesh.SecondOrderIncomplete", 1)
    # File outlines: mid-side nodes are placed by this module, gmsh's spline projection is slow.
    gmsh.option.setNumber("Mesh.SecondOrderLinear", 1 if linear_midnodes else 0)


def _quad_candidates(outline: Outline, size: float):
    """Algorithms and sizes for which the section mesh has valid quadrilaterals only, in turn.

    Tries the Blossom-recombined ``QUAD_ALGORITHMS`` at ``size`` times ``SIZE_FACTORS``
    (recombination occasionally leaves a triangle), then gmsh's quasi-structured quad
    algorithm (11) at ``size`` times ``QQS_SIZE_FACTORS``. A candidate is accepted if it has
    quadrilaterals only and all of them are valid (minimum scaled Jacobian > 0).

    Yields
    ------
    (algorithm, size)
        Each accepted candidate, in the order tried.
    """
    candidates = [(alg, f) for f in SIZE_FACTORS for alg in QUAD_ALGORITHMS]
    candidates += [(11, f) for f in QQS_SIZE_FACTORS]
    for algorithm, factor in candidates:
        with gmsh_model("wheel_section"):
            surface, _, _ = _add_section(outline, size * factor)
            gmsh.model.geo.synchronize()
            _set_2d_options(algorithm, size * factor, False)
            try:
                gmsh.model.mesh.generate(2)
            except Exception as exc:  # gmsh raises a bare Exception on meshing failures
                logger.debug("2D algorithm %d failed: %s", algorithm, exc)
                continue
            if list(gmsh.model.mesh.getElementTypes(2, surface)) != [3]:  # 4-node quads only
                continue
            _, tags, _ = gmsh.model.mesh.getElements(2, surface)
            if gmsh.model.mesh.getElementQualities(tags[0], "minSICN").min() <= 0.0:
                continue
        if (algorithm, factor) != candidates[0]:
            logger.info("all-quad section mesh with algorithm %d and size %.4g m", algorithm, size * factor)
        yield algorithm, size * factor


def _quad_settings(outline: Outline, size: float) -> tuple[int, float] | None:
    """The first of :func:`_quad_candidates`, or None if every candidate fails."""
    return next(_quad_candidates(outline, size), None)


class _TrialMismatch(RuntimeError):
    """The section mesh of the revolved model is not the all-quad mesh of the trial."""


def _mesh_model(params: WheelParams, outline: Outline, algorithm: int, size: float):
    """Build geometry and meshes (section and 3D, second order) in the current gmsh model."""
    surface, bore_curve, contact_point = _add_section(outline, size)
    volumes = _revolve(surface, params.elements_around)
    gmsh.model.geo.synchronize()
    _set_2d_options(algorithm, size, outline.polygon is not None)
    gmsh.model.mesh.generate(2)
    if list(gmsh.model.mesh.getElementTypes(2, surface)) != [3]:
        raise _TrialMismatch("section mesh of the revolved model differs from the trial mesh")
    gmsh.model.mesh.generate(3)
    gmsh.model.mesh.setOrder(2)
    gmsh.model.addPhysicalGroup(3, volumes, name="wheel")
    gmsh.model.addPhysicalGroup(2, [surface], name="section")
    gmsh.model.addPhysicalGroup(1, [bore_curve], name="bore")
    gmsh.model.addPhysicalGroup(0, [contact_point], name="contact")
    return surface, bore_curve, contact_point


def _element_nodes(dim: int, tag: int, etype: int, nnodes: int) -> np.ndarray:
    """Node tags (n, nnodes) of the elements of one type on an entity (tag -1: all)."""
    _, node_tags = gmsh.model.mesh.getElementsByType(etype, tag)
    return np.asarray(node_tags, dtype=np.int64).reshape(-1, nnodes)


def _corner_jacobian_sign(nodes: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Determinant of the trilinear corner map at the element centre, shape (E,) (m^3/8)."""
    sign = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                     [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], dtype=float)
    corners = nodes[cells[:, :8]]                       # (E, 8, 3)
    jac = np.einsum("eai,aj->eij", corners, sign) / 8.0  # dX_i / dxi_j at the centre
    return np.linalg.det(jac)


def mesh_wheel(params: WheelParams, msh_path: str | Path | None = None) -> WheelMesh:
    """Mesh the wheel section (8-node quads) and the 3D wheel (20-node hexahedra).

    Parameters
    ----------
    params : WheelParams
        Validated wheel parameters (``section_element_size``, ``elements_around`` control
        the resolution).
    msh_path : str or Path, optional
        If given, the gmsh model (physical groups ``wheel``, ``section``, ``bore``,
        ``contact``; gmsh node orders) is written there.

    Returns
    -------
    WheelMesh

    Raises
    ------
    InputError
        If the outline is invalid or cannot be meshed with quadrilaterals only.

    Notes
    -----
    gmsh is not thread-safe: call from one thread per process. If gmsh is already initialised
    the caller's session is reused (a temporary model is added and removed).
    """
    outline = build_outline(params)
    start = time.perf_counter()
    # The revolved model occasionally recombines the section differently from the trial (seen:
    # a triangle left by Blossom once the revolved surfaces exist): take the next candidate.
    result = None
    for settings in _quad_candidates(outline, params.section_element_size):
        with gmsh_model("wheel"):
            try:
                tags = _mesh_model(params, outline, *settings)
            except _TrialMismatch:
                logger.info("revolved section mesh differs from the trial with algorithm %d and size %.4g m; "
                            "trying the next candidate", *settings)
                continue
            result = _extract(params, outline, *tags, update_gmsh=msh_path is not None)
            if msh_path is not None:
                gmsh.write(str(msh_path))
        break
    if result is None:
        raise InputError("wheel.section_element_size",
                         f"no all-quadrilateral mesh of the section found near the size "
                         f"{params.section_element_size:g} m; must be changed slightly")
    logger.info("wheel mesh: %d section quads, %d section nodes, %d hexahedra, %d nodes (%.2f s)",
                len(result.section_cells), len(result.section_nodes), len(result.hex_cells),
                len(result.hex_nodes), time.perf_counter() - start)
    return result


def _extract(params: WheelParams, outline: Outline, surface: int, bore_curve: int,
             contact_point: int, update_gmsh: bool = False) -> WheelMesh:
    """Read the meshes from the current gmsh model and convert them to VTK order."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    coords = coords.reshape(-1, 3)
    lookup = np.full(int(tags.max()) + 1, -1, dtype=np.int64)
    lookup[tags] = np.arange(len(tags))

    # 3D: 20-node hexahedra only.
    types3 = list(gmsh.model.mesh.getElementTypes(3))
    if types3 != [GMSH_HEX20]:
        raise RuntimeError(f"3D wheel mesh has element types {types3}, expected only hex20")
    hex_tags = _element_nodes(3, -1, GMSH_HEX20, 20)[:, GMSH_HEX20_TO_VTK]
    used, hex_cells = np.unique(hex_tags, return_inverse=True)
    hex_cells = hex_cells.reshape(hex_tags.shape)
    hex_nodes = coords[lookup[used]]
    flip = _corner_jacobian_sign(hex_nodes, hex_cells) < 0.0
    hex_cells[flip] = hex_cells[flip][:, HEX20_FLIP]

    # Section: the quads on the source surface (theta = 0), (r, z) = (-Z, Y).
    quad_tags = _element_nodes(2, surface, GMSH_QUAD8, 8)[:, GMSH_QUAD8_TO_VTK]
    sec_used, section_cells = np.unique(quad_tags, return_inverse=True)
    section_cells = section_cells.reshape(quad_tags.shape)
    xyz = coords[lookup[sec_used]]
    section_nodes = np.column_stack([-xyz[:, 2], xyz[:, 1]])
    rc, zc = section_nodes[section_cells[:, :4]].transpose(2, 0, 1)
    area2 = (rc * np.roll(zc, -1, axis=1) - np.roll(rc, -1, axis=1) * zc).sum(axis=1)
    flip = area2 < 0.0
    section_cells[flip] = section_cells[flip][:, QUAD8_FLIP]

    # Mid-side nodes on a file outline: on the outline polygon (gmsh's spline mid-nodes can
    # fold elements); then all 3D mid-edge nodes are placed on the exact revolution.
    if outline.polygon is not None:
        _project_boundary_midnodes(section_nodes, section_cells, outline.polygon)
    moved = _snap_revolution(hex_nodes, hex_cells, section_nodes, section_cells)
    logger.debug("snapped 3D mid-edge nodes to the revolution: max move %.3g m", moved)
    if update_gmsh:  # keep the gmsh model (and the .msh file) identical to the arrays
        for tag, xyz in zip(used, hex_nodes):
            gmsh.model.mesh.setNode(int(tag), xyz.tolist(), [])

    # Expected node count of a closed revolution: N (Ns + Nc).
    n_corner = len(np.unique(section_cells[:, :4]))
    expected = params.elements_around * (len(section_nodes) + n_corner)
    if len(hex_nodes) != expected or len(hex_cells) != params.elements_around * len(section_cells):
        raise RuntimeError(f"revolved mesh is not closed: {len(hex_nodes)} nodes, expected {expected}")

    # Clamped nodes: the section nodes on the bore curve; in 3D all nodes at the bore radius.
    bore_tags, _, _ = gmsh.model.mesh.getNodes(1, bore_curve, includeBoundary=True)
    section_clamped = np.sort(np.searchsorted(sec_used, bore_tags))
    r_bore = section_nodes[section_clamped, 0].mean()
    scale = np.ptp(section_nodes, axis=0).max()
    radius = np.hypot(hex_nodes[:, 0], hex_nodes[:, 2])
    hex_clamped = np.flatnonzero(np.abs(radius - r_bore) <= 1e-9 * scale)

    # Contact: the geometry point at (r_c, z_c).
    contact_tag, _, _ = gmsh.model.mesh.getNodes(0, contact_point)
    contact_section = int(np.searchsorted(sec_used, contact_tag[0]))
    contact_hex = int(np.searchsorted(used, contact_tag[0]))
    contact_position = np.array([0.0, outline.contact_point[1], -outline.contact_point[0]])
    return WheelMesh(
        params=params,
        section_nodes=section_nodes,
        section_cells=section_cells,
        section_clamped_nodes=section_clamped,
        hex_nodes=hex_nodes,
        hex_cells=hex_cells,
        hex_clamped_nodes=hex_clamped,
        contact_section_node=contact_section,
        contact_hex_node=contact_hex,
        contact_position=contact_position,
        mass=outline_mass(params),
    )


def _project_boundary_midnodes(nodes: np.ndarray, cells: np.ndarray, polygon: np.ndarray) -> None:
    """Move the mid-side nodes of boundary edges to the outline polygon (in place).

    Parameters
    ----------
    nodes : ndarray, shape (Ns, 2)
        Section nodes (r, z) (m); modified in place.
    cells : ndarray, shape (Es, 8)
        VTK quad8 cells.
    polygon : ndarray, shape (P, 2)
        Closed outline polygon (m).
    """
    corner_pairs = cells[:, [[0, 1], [1, 2], [2, 3], [3, 0]]].reshape(-1, 2)
    mids = cells[:, 4:].reshape(-1)
    key = np.sort(corner_pairs, axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    boundary = counts[inverse.reshape(-1)] == 1
    chord_mid = 0.5 * (nodes[corner_pairs[boundary, 0]] + nodes[corner_pairs[boundary, 1]])
    a = polygon
    d = np.roll(polygon, -1, axis=0) - a                                   # (P, 2)
    t = np.einsum("mpi,pi->mp", chord_mid[:, None, :] - a[None], d) / np.einsum("pi,pi->p", d, d)
    foot = a[None] + np.clip(t, 0.0, 1.0)[..., None] * d[None]            # (M, P, 2)
    dist = np.linalg.norm(foot - chord_mid[:, None, :], axis=-1)
    nodes[mids[boundary]] = foot[np.arange(len(chord_mid)), np.argmin(dist, axis=1)]


def _snap_revolution(hex_nodes: np.ndarray, hex_cells: np.ndarray, section_nodes: np.ndarray,
                     section_cells: np.ndarray) -> float:
    """Place the 3D mid-edge nodes exactly on the revolution of the section mesh (in place).

    gmsh's second-order nodes on the revolved boundary surfaces are placed through the surface
    parametrisation and can leave the circles of the section nodes. The corner nodes (exact
    rotations of section corners) define, per element, the plane angle of each face and the
    section corners: in-plane mid-edge nodes (VTK 8-15) become the rotated section mid-side
    nodes, circumferential ones (16-19) the points of the corner circles at the mid angle.

    Returns
    -------
    float
        Largest node displacement (m).
    """
    corners = np.unique(hex_cells[:, :8])
    xyz = hex_nodes[corners]
    rz = np.column_stack([np.hypot(xyz[:, 0], xyz[:, 2]), xyz[:, 1]])
    dist, sec_of = cKDTree(section_nodes).query(rz)
    scale = np.ptp(section_nodes, axis=0).max()
    if dist.max() > 1e-9 * scale:
        raise RuntimeError(f"3D corner nodes off the section circles by {dist.max():.3g} m")
    sec = np.full(len(hex_nodes), -1)
    sec[corners] = sec_of
    theta = np.arctan2(hex_nodes[:, 0], -hex_nodes[:, 2])
    # Section edge (corner a, corner b) -> mid-side node.
    ns = len(section_nodes)
    pairs = section_cells[:, [[0, 1], [1, 2], [2, 3], [3, 0]]].reshape(-1, 2)
    keys = np.concatenate([pairs[:, 0] * ns + pairs[:, 1], pairs[:, 1] * ns + pairs[:, 0]])
    vals = np.concatenate([section_cells[:, 4:].reshape(-1)] * 2)
    order = np.argsort(keys)
    keys, vals = keys[order], vals[order]
    new = hex_nodes.copy()
    edges = np.array([[0, 1], [1, 2], [2, 3], [3, 0], [4, 5], [5, 6], [6, 7], [7, 4],
                      [0, 4], [1, 5], [2, 6], [3, 7]])
    a, b = hex_cells[:, edges[:, 0]], hex_cells[:, edges[:, 1]]            # (E, 12)
    mid = hex_cells[:, 8:]
    # In-plane edges: rotated section mid-side node.
    key = sec[a[:, :8]] * ns + sec[b[:, :8]]
    pos = np.searchsorted(keys, key)
    if np.any(keys[np.minimum(pos, len(keys) - 1)] != key):
        raise RuntimeError("3D element edge without a matching section edge")
    s_mid = vals[pos]
    t = theta[a[:, :8]]
    r, z = section_nodes[s_mid, 0], section_nodes[s_mid, 1]
    new[mid[:, :8]] = np.stack([r * np.sin(t), z, -r * np.cos(t)], axis=-1)
    # Circumferential edges: on the corner circle at the mid angle.
    if np.any(sec[a[:, 8:]] != sec[b[:, 8:]]):
        raise RuntimeError("circumferential 3D edge joining different section nodes")
    ta, tb = theta[a[:, 8:]], theta[b[:, 8:]]
    t = ta + 0.5 * np.angle(np.exp(1j * (tb - ta)))
    r, z = section_nodes[sec[a[:, 8:]], 0], section_nodes[sec[a[:, 8:]], 1]
    new[mid[:, 8:]] = np.stack([r * np.sin(t), z, -r * np.cos(t)], axis=-1)
    moved = float(np.linalg.norm(new - hex_nodes, axis=1).max())
    hex_nodes[:] = new
    return moved


def write_vtu(mesh: WheelMesh, path: str | Path) -> None:
    """Write the 3D wheel mesh as VTU (``hexahedron20`` cells, point data ``clamped``).

    Parameters
    ----------
    mesh : WheelMesh
    path : str or Path
        Output file (``.vtu``).
    """
    clamped = np.zeros(len(mesh.hex_nodes), dtype=np.uint8)
    clamped[mesh.hex_clamped_nodes] = 1
    contact = np.zeros(len(mesh.hex_nodes), dtype=np.uint8)
    contact[mesh.contact_hex_node] = 1
    meshio.Mesh(points=mesh.hex_nodes, cells=[("hexahedron20", mesh.hex_cells)],
                point_data={"clamped": clamped, "contact": contact}).write(str(path))
