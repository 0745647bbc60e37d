"""What the radiation of one case reads from the artefacts, and the call that computes it.

The physics is in the ``radiation`` package (:func:`radiation.case_radiation.radiate`), which takes
arrays; this module reads the case (``cases/<id>.h5``) and its variant's structural artefacts
(wheel mesh, modes and Green's functions, rail mesh and Green's functions) and passes them on.
"""

from __future__ import annotations

import functools
import os
from pathlib import Path

import numpy as np

from interaction.frame import to_contact_frame, vectors_to_contact_frame
from radiation.case_radiation import radiate
from radiation.rail_power import RailModel
from radiation.surface import hex_mode_surfaces, section_mode_surfaces
from squealcore.artefacts import open_artefact, read_dataset
from stages.rail import GREENS_VERSION
from stages.wheel import read_greens, read_mesh, read_modes


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

    :func:`stages.wheel.read_greens` without the receptance and kernel.

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
    wheel = read_greens(path, model, geometry, response=False)
    return {key: wheel[key] for key in ("poles", "residues", "spin", "contact_shape", "time_step")}


def read_rail_model(greens_path, mesh_path):
    """Read the receptance along the rail (``rail_greens.h5``) and the section size (``rail_mesh.h5``).

    Returns
    -------
    radiation.rail_power.RailModel
    """
    with open_artefact(greens_path, "rail_greens", GREENS_VERSION) as f:
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        distance = read_dataset(f, "distance", "m", (None,))
        receptance = read_dataset(f, "receptance", "m/N", (distance.size, frequency.size, 3, 3))
    with open_artefact(mesh_path, "rail_mesh", 1) as f:
        nodes = read_dataset(f, "section/nodes", "m", (None, 2))
    return RailModel(frequency, distance, receptance, float(np.ptp(nodes[:, 0])), float(np.ptp(nodes[:, 1])))


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
    radiation.case_radiation.CaseRadiation
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
    rail = read_rail_model(variant_dir / "rail_greens.h5", variant_dir / "rail_mesh.h5")
    return radiate(model_name, wheel, modes, surfaces, rail, force, normal_force, rail_velocity, rms_window,
                   name=Path(case_path).stem)
