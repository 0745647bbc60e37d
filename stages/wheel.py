"""Wheel stages: ``wheel-mesh``, ``wheel-modes`` and ``wheel-greens``.

Artefact layouts (all datasets carry a ``units`` attribute):

``wheel_mesh.h5`` (schema ``wheel_mesh``)
    ``hex20/nodes`` (N, 3) m, ``hex20/cells`` (E, 20) VTK/C3D20 order, ``hex20/clamped_nodes``,
    ``section/nodes`` (Ns, 2) (r, z) m, ``section/cells`` (Es, 8) VTK quad8 order,
    ``section/clamped_nodes``, ``contact/hex_node``, ``contact/section_node``,
    ``contact/position`` (3,) m, ``mass`` (kg, from the hex20 mesh volume),
    ``mass_outline`` (kg, Pappus on the outline), ``density`` (kg/m³).
``wheel_modes.h5`` (schema ``wheel_modes``)
    ``frequency`` Hz, ``damping_ratio``, ``nodal_diameters``, ``nodal_circles``, ``family``,
    ``orientation``, ``contact/shape`` (m, 3) m/√kg, ``contact/position`` (3,) m, ``mass`` kg,
    ``shapes`` (float32; (m, N, 3) at the hex20 nodes or (m, Ns, 3) section amplitudes),
    attribute ``solver``.
``wheel_greens.h5`` (schema ``wheel_greens``)
    ``time_step`` s, ``frequency`` Hz and, per wheel model (now ``stationary``): ``poles``
    rad/s, ``residues`` m/(N s), ``receptance`` (nf, 3, 3) m/N, ``kernel`` (nt, 3, 3) m/N.
"""

from __future__ import annotations

import logging

import numpy as np

from squealcore.artefacts import add_dataset, atomic_output, open_artefact, read_dataset

logger = logging.getLogger(__name__)


def build_mesh(ctx):
    """``wheel-mesh``: section and 3D meshes of the wheel from ``[wheel]``."""
    from fe.hex20 import element_volumes
    from mesh.wheel_mesh import mesh_wheel, write_vtu
    from mesh.wheel_section import WheelParams

    params = WheelParams.from_mapping(ctx.section("wheel"), "wheel")
    with atomic_output(ctx.out_dir / "wheel.msh") as msh_tmp:
        mesh = mesh_wheel(params, msh_path=str(msh_tmp))
    with atomic_output(ctx.out_dir / "wheel.vtu") as vtu_tmp:
        write_vtu(mesh, str(vtu_tmp))
    mass = float(params.density * element_volumes(mesh.hex_nodes, mesh.hex_cells).sum())
    logger.info("wheel mesh: %d section elements, %d hex20 elements, %d nodes, mass %.2f kg (outline %.2f kg)",
                len(mesh.section_cells), len(mesh.hex_cells), len(mesh.hex_nodes), mass, mesh.mass)
    with ctx.writer() as f:
        add_dataset(f, "hex20/nodes", mesh.hex_nodes, "m")
        add_dataset(f, "hex20/cells", mesh.hex_cells.astype(np.int64), "")
        add_dataset(f, "hex20/clamped_nodes", np.asarray(mesh.hex_clamped_nodes, dtype=np.int64), "")
        add_dataset(f, "hex20/elements_around", int(params.elements_around), "")
        add_dataset(f, "section/nodes", mesh.section_nodes, "m")
        add_dataset(f, "section/cells", mesh.section_cells.astype(np.int64), "")
        add_dataset(f, "section/clamped_nodes", np.asarray(mesh.section_clamped_nodes, dtype=np.int64), "")
        add_dataset(f, "contact/hex_node", int(mesh.contact_hex_node), "")
        add_dataset(f, "contact/section_node", int(mesh.contact_section_node), "")
        add_dataset(f, "contact/position", np.asarray(mesh.contact_position, dtype=float), "m")
        add_dataset(f, "mass", mass, "kg")
        add_dataset(f, "mass_outline", float(mesh.mass), "kg")
        add_dataset(f, "density", float(params.density), "kg/m^3")


def read_mesh(path):
    """Read ``wheel_mesh.h5`` into a dict of arrays (checked units and shapes)."""
    with open_artefact(path, "wheel_mesh", 1) as f:
        out = {
            "hex_nodes": read_dataset(f, "hex20/nodes", "m", (None, 3)),
            "hex_cells": read_dataset(f, "hex20/cells", "", (None, 20)),
            "hex_clamped": read_dataset(f, "hex20/clamped_nodes", "", (None,)),
            "elements_around": int(read_dataset(f, "hex20/elements_around", "")),
            "section_nodes": read_dataset(f, "section/nodes", "m", (None, 2)),
            "section_cells": read_dataset(f, "section/cells", "", (None, 8)),
            "section_clamped": read_dataset(f, "section/clamped_nodes", "", (None,)),
            "contact_hex_node": int(read_dataset(f, "contact/hex_node", "")),
            "contact_section_node": int(read_dataset(f, "contact/section_node", "")),
            "contact_position": read_dataset(f, "contact/position", "m", (3,)),
            "mass": float(read_dataset(f, "mass", "kg")),
            "density": float(read_dataset(f, "density", "kg/m^3")),
        }
    return out


def build_modes(ctx):
    """``wheel-modes``: modes up to ``f_max`` with the solver of ``[wheel.fe]``."""
    from fe.wheel_modes import modal_damping, solve_axisymmetric, solve_hex20

    fe = ctx.section("wheel.fe")
    mesh = read_mesh(ctx.inputs["wheel-mesh"])
    material = (fe["youngs_modulus"], fe["poisson_ratio"], mesh["density"])
    if fe["solver"] == "hex20":
        sectors = mesh["elements_around"] if fe["hex20_method"] == "cyclic" else None
        modes = solve_hex20(mesh["hex_nodes"], mesh["hex_cells"], mesh["hex_clamped"], mesh["contact_hex_node"],
                            *material, fe["f_max"], n_sectors=sectors)
    else:
        modes = solve_axisymmetric(mesh["section_nodes"], mesh["section_cells"], mesh["section_clamped"],
                                   mesh["contact_section_node"], *material, fe["f_max"])
    damping = modal_damping(modes.nodal_diameters, fe["damping_ratio"], fe["damping_ratio_low_order"],
                            fe["low_order_max_n"])
    logger.info("%d modes below %.0f Hz (%s solver)", len(modes.frequency), fe["f_max"], modes.solver)
    with ctx.writer() as f:
        f.attrs["solver"] = modes.solver
        add_dataset(f, "frequency", modes.frequency, "Hz")
        add_dataset(f, "damping_ratio", damping, "1")
        add_dataset(f, "nodal_diameters", modes.nodal_diameters, "")
        add_dataset(f, "nodal_circles", modes.nodal_circles, "")
        add_dataset(f, "family", modes.family, "")
        add_dataset(f, "orientation", modes.orientation, "")
        add_dataset(f, "contact/shape", modes.contact_shape, "m/sqrt(kg)")
        add_dataset(f, "contact/position", mesh["contact_position"], "m")
        add_dataset(f, "mass", mesh["mass"], "kg")
        add_dataset(f, "shapes", modes.shapes.astype(np.float32), "m/sqrt(kg)", compress=True)


def read_modes(path, with_shapes=False):
    """Read ``wheel_modes.h5`` into a dict (checked units and shapes)."""
    with open_artefact(path, "wheel_modes", 1) as f:
        out = {
            "solver": str(f.attrs["solver"]),
            "frequency": read_dataset(f, "frequency", "Hz", (None,)),
            "damping_ratio": read_dataset(f, "damping_ratio", "1", (None,)),
            "nodal_diameters": read_dataset(f, "nodal_diameters", "", (None,)),
            "nodal_circles": read_dataset(f, "nodal_circles", "", (None,)),
            "family": read_dataset(f, "family", "", (None,)),
            "orientation": read_dataset(f, "orientation", "", (None,)),
            "contact_shape": read_dataset(f, "contact/shape", "m/sqrt(kg)", (None, 3)),
            "contact_position": read_dataset(f, "contact/position", "m", (3,)),
            "mass": float(read_dataset(f, "mass", "kg")),
        }
        if with_shapes:
            out["shapes"] = read_dataset(f, "shapes", "m/sqrt(kg)")
    m = out["frequency"].size
    for key in ("damping_ratio", "nodal_diameters", "family", "contact_shape"):
        if out[key].shape[0] != m:
            raise ValueError(f"{path}: {key} has {out[key].shape[0]} entries for {m} modes")
    return out


def build_greens(ctx):
    """``wheel-greens``: receptances, poles/residues and discrete kernels of the wheel models."""
    from fe.greens import frequency_grid, modal_poles_residues, ramp_invariant_kernel, receptance

    modes = read_modes(ctx.inputs["wheel-modes"])
    time = ctx.section("time")
    dt = time["time_step"]
    n_kernel = int(round(time["wheel_kernel_duration"] / dt))
    poles, residues = modal_poles_residues(modes["frequency"], modes["damping_ratio"], modes["contact_shape"])
    frequency = frequency_grid(1.0, 0.5 / dt, poles)
    with ctx.writer() as f:
        add_dataset(f, "time_step", dt, "s")
        add_dataset(f, "frequency", frequency, "Hz")
        group = f.create_group("stationary")
        add_dataset(group, "poles", poles, "rad/s")
        add_dataset(group, "residues", residues, "m/(N*s)")
        add_dataset(group, "receptance", receptance(poles, residues, frequency), "m/N", compress=True)
        add_dataset(group, "kernel", ramp_invariant_kernel(poles, residues, dt, n_kernel), "m/N", compress=True)


def read_greens(path, model="stationary"):
    """Read one wheel model of ``wheel_greens.h5``."""
    with open_artefact(path, "wheel_greens", 1) as f:
        if model not in f:
            raise ValueError(f"{path}: no wheel model {model!r} (has {', '.join(k for k in f if isinstance(f[k], type(f)))})")
        g = f[model]
        frequency = read_dataset(f, "frequency", "Hz", (None,))
        return {
            "time_step": float(read_dataset(f, "time_step", "s")),
            "frequency": frequency,
            "poles": read_dataset(g, "poles", "rad/s", (None,)),
            "residues": read_dataset(g, "residues", "m/(N*s)", (None, 3, 3)),
            "receptance": read_dataset(g, "receptance", "m/N", (frequency.size, 3, 3)),
            "kernel": read_dataset(g, "kernel", "m/N", (None, 3, 3)),
        }
