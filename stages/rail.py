"""Rail stages: ``rail-mesh`` and ``rail-greens``.

Artefact layouts (every dataset has a ``units`` attribute):

``rail_mesh.h5`` (schema ``rail_mesh``)
    ``section/nodes`` (N, 2) (y lateral, z up; origin at the foot bottom centre) m,
    ``section/cells`` (E, 8 or 6; corner nodes first, counter-clockwise), attribute
    ``element_type``, ``section/boundary_edges``, ``density`` kg/m³, and the section properties
    from the mesh: ``properties/area`` m², ``properties/centroid`` m, ``properties/i_vertical``,
    ``properties/i_lateral`` m⁴, ``properties/torsion_constant`` m⁴,
    ``properties/mass_per_length`` kg/m.
``rail_greens.h5`` (schema ``rail_greens``, version 3)
    Attribute ``contact_geometry``: the contact it holds, the study's ``contact.geometry``;
    ``lateral_position`` m, the moving kernel's lateral position on the rail section;
    ``time_step`` s, ``speed`` m/s, ``frequency`` Hz, ``distance`` m (distance[0] = 0),
    ``receptance`` (n_x, nf, 3, 3) m/N (at ``track.contact_lateral_position``), ``wavenumbers``
    (nf, n) rad/m, ``decay`` (nf, n) dB/m, ``wave_label`` (nf, n), ``moving/kernel`` (nt, 3, 3) m/N, ``moving/time`` s,
    ``moving/frequency`` Hz, ``moving/receptance`` (nf', 3, 3) m/N (the kernel's spectrum over
    the first-order-hold factor: the moving receptance plus its aliases, see
    :func:`waveguide.greens.moving_kernel`), ``moving/static_compliance`` (3, 3) m/N.
"""

from __future__ import annotations

import logging

import numpy as np

from mesh.rail_mesh import RailMesh, mesh_rail_section
from profiles.rail_section import RailParams
from squealcore.artefacts import add_dataset, open_artefact, read_dataset
from stages.greens_layout import GEOMETRY_ATTRIBUTE, RAIL_GREENS_VERSION, held_geometry, study_geometry
from waveguide.api import moving_kernel, rail_greens
from waveguide.params import TrackParams
from waveguide.section import section_properties

logger = logging.getLogger(__name__)

GREENS_VERSION = RAIL_GREENS_VERSION
"""Schema version of ``rail_greens.h5`` (:data:`stages.greens_layout.RAIL_GREENS_VERSION`)."""


def build_mesh(ctx):
    """``rail-mesh``: the rail cross-section mesh and its properties from ``[rail]``."""
    params = RailParams.from_mapping(ctx.section("rail"), "rail")
    mesh = mesh_rail_section(params)
    props = section_properties(mesh, params.density)
    logger.info("rail section: %d %s elements, area %.1f mm^2, %.2f kg/m", len(mesh.cells), mesh.element_type,
                props.area * 1e6, props.mass_per_length)
    with ctx.writer() as f:
        add_dataset(f, "section/nodes", mesh.nodes, "m")
        cells = add_dataset(f, "section/cells", mesh.cells.astype(np.int64), "")
        cells.attrs["element_type"] = mesh.element_type
        add_dataset(f, "section/boundary_edges", mesh.boundary_edges.astype(np.int64), "")
        add_dataset(f, "density", float(mesh.density), "kg/m^3")
        add_dataset(f, "properties/area", props.area, "m^2")
        add_dataset(f, "properties/centroid", np.asarray(props.centroid, dtype=float), "m")
        add_dataset(f, "properties/i_vertical", props.i_vertical, "m^4")
        add_dataset(f, "properties/i_lateral", props.i_lateral, "m^4")
        add_dataset(f, "properties/torsion_constant", props.torsion_constant, "m^4")
        add_dataset(f, "properties/mass_per_length", props.mass_per_length, "kg/m")


def read_mesh(path):
    """``rail_mesh.h5`` as a :class:`mesh.rail_mesh.RailMesh`."""
    with open_artefact(path, "rail_mesh", 1) as f:
        cells = f["section/cells"]
        arrays = {
            "nodes": read_dataset(f, "section/nodes", "m", (None, 2)),
            "cells": read_dataset(f, "section/cells", ""),
            "element_type": str(cells.attrs["element_type"]),
            "boundary_edges": read_dataset(f, "section/boundary_edges", ""),
            "density": float(read_dataset(f, "density", "kg/m^3")),
        }
    return RailMesh.from_arrays(arrays)


def build_greens(ctx):
    """``rail-greens``: waves, receptances along the rail and the moving kernel.

    The moving kernel is computed at the contact ``contact.geometry`` selects, and only there:
    ``"manual"``, the hand-set position ``track.contact_lateral_position``; ``"profiles"``, the
    computed contact's ``rail_section_lateral`` of ``contact_geometry.h5``. The root attribute
    ``contact_geometry`` names it (:func:`stages.greens_layout.held_geometry`), ``lateral_position``
    gives the position. The waves and the receptances along the rail are at
    ``track.contact_lateral_position`` in both cases. In the rail section's upright frame; the case
    turns the kernel into the contact frame.
    """
    # Imported here: stages.geometry pulls in the contact package (numba, ~2 s to import), which
    # the engine, importing this module for GREENS_VERSION, should not pay.
    from stages.geometry import read_operating_contact  # lazy: ~2 s (numba)

    mesh = read_mesh(ctx.inputs["rail-mesh"])
    geometry = study_geometry(ctx.study)
    track = TrackParams.from_mapping(ctx.section("track"), "track")
    at_contact = track
    if geometry == "profiles":
        lateral = read_operating_contact(ctx.inputs["contact-geometry"]).rail_section_lateral
        if lateral != track.contact_lateral_position:
            moved = {**ctx.section("track"), "contact_lateral_position": lateral}
            at_contact = TrackParams.from_mapping(moved, "track")
        logger.info("rail moving kernel at the computed contact, %.2f mm from the centre line", 1e3 * lateral)
    speed = ctx.section("operating")["speed"]
    dt = ctx.section("time")["time_step"]
    out = rail_greens(mesh, track, speed, dt, moving=at_contact is track)
    moving = out["moving"] if at_contact is track else moving_kernel(mesh, at_contact, speed, dt)
    logger.info("rail moving kernel: %d samples (%.3f s), tail %.1e", moving["kernel"].shape[0],
                moving["kernel"].shape[0] * dt, moving["tail"])
    with ctx.writer() as f:
        f.attrs[GEOMETRY_ATTRIBUTE] = geometry
        add_dataset(f, "time_step", dt, "s")
        add_dataset(f, "speed", speed, "m/s")
        add_dataset(f, "lateral_position", float(at_contact.contact_lateral_position), "m")
        add_dataset(f, "frequency", out["frequency"], "Hz")
        add_dataset(f, "distance", out["distance"], "m")
        add_dataset(f, "receptance", out["receptance"], "m/N", compress=True)
        add_dataset(f, "wavenumbers", out["wavenumbers"], "rad/m")
        add_dataset(f, "decay", out["decay"], "dB/m")
        add_dataset(f, "wave_label", out["wave_label"], "")
        _write_moving(f, moving)


def _write_moving(group, moving):
    """The datasets ``moving/...`` of one moving kernel into ``group``."""
    add_dataset(group, "moving/kernel", moving["kernel"], "m/N", compress=True)
    add_dataset(group, "moving/time", moving["time"], "s")
    add_dataset(group, "moving/frequency", moving["frequency"], "Hz")
    add_dataset(group, "moving/receptance", moving["moving_receptance"], "m/N", compress=True)
    add_dataset(group, "moving/static_compliance", moving["static_compliance"], "m/N")


def read_rail_greens(path, geometry=None):
    """The moving kernel of ``rail_greens.h5``: dict with ``time_step`` (s), ``speed`` (m/s),
    ``kernel`` (nt, 3, 3) m/N, in the rail section's upright frame.

    ``geometry``: the contact the caller needs, ``"manual"`` (the kernel at
    ``track.contact_lateral_position``) or ``"profiles"`` (at the computed contact), see
    :func:`build_greens`; None: the one the artefact holds.

    Raises
    ------
    ArtefactError
        If the artefact is missing or damaged, or holds the other contact than ``geometry``.
    """
    with open_artefact(path, "rail_greens", GREENS_VERSION) as f:
        held_geometry(f, geometry)
        return {
            "time_step": float(read_dataset(f, "time_step", "s")),
            "speed": float(read_dataset(f, "speed", "m/s")),
            "kernel": read_dataset(f, "moving/kernel", "m/N", (None, 3, 3)),
        }
