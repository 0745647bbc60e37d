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
``wheel_greens.h5`` (schema ``wheel_greens``, version 2)
    Attribute ``contact_geometry``: the contact it holds, the study's ``contact.geometry``
    (``"manual"``: the mesh's contact node; ``"profiles"``: the computed contact). ``time_step``
    s, ``speed`` m/s, ``spin`` rad/s, ``frequency`` Hz and, per wheel model (``stationary``,
    ``moving_load``, ``eulerian``): ``poles`` rad/s, ``residues`` m/(N s), ``receptance``
    (nf, 3, 3) m/N, ``kernel`` (nt, 3, 3) m/N at that contact; for the computed contact also
    ``profiles/spin`` rad/s, ``rolling_radius`` m, ``position`` (r, z) m, ``section_nodes``,
    ``weights`` and ``contact_shape`` (m, 3) m/√kg; ``modal/...`` at the mesh's contact node
    (:func:`build_greens`). Upright wheel frame: the case turns them into the contact frame.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from fe import moving_load
from fe.greens import frequency_grid, ramp_invariant_kernel, receptance
from fe.hex20 import element_volumes
from fe.rotation import EulerianModel, RotationMatrices, eulerian_model_axisymmetric, eulerian_model_hex20, spin_rate
from fe.wheel_models import WheelState
from interaction.wheel_models import REFERENCE, wheel_model, wheel_model_names, wheel_models
from fe.wheel_modes import (SurfacePoint, WheelModes, contact_shapes_at, hex_nodes_at, modal_damping,
                            running_surface_point, solve_axisymmetric, solve_hex20)
from mesh.wheel_mesh import mesh_wheel, write_vtu
from mesh.wheel_section import WheelParams
from squealcore.artefacts import add_dataset, atomic_output, open_artefact, read_dataset
from stages.geometry import read_operating_contact
from stages.greens_layout import GEOMETRY_ATTRIBUTE, WHEEL_GREENS_VERSION, held_geometry, study_geometry

logger = logging.getLogger(__name__)


def build_mesh(ctx):
    """``wheel-mesh``: section and 3D meshes of the wheel from ``[wheel]``."""
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
        add_dataset(f, "youngs_modulus", fe["youngs_modulus"], "Pa")
        add_dataset(f, "poisson_ratio", fe["poisson_ratio"], "1")
        add_dataset(f, "density", mesh["density"], "kg/m^3")
        add_dataset(f, "shapes", modes.shapes, "m/sqrt(kg)", compress=True)


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
            "youngs_modulus": float(read_dataset(f, "youngs_modulus", "Pa")),
            "poisson_ratio": float(read_dataset(f, "poisson_ratio", "1")),
            "density": float(read_dataset(f, "density", "kg/m^3")),
        }
        if with_shapes:
            out["shapes"] = read_dataset(f, "shapes", "m/sqrt(kg)")
    m = out["frequency"].size
    for key in ("damping_ratio", "nodal_diameters", "family", "contact_shape"):
        if out[key].shape[0] != m:
            raise ValueError(f"{path}: {key} has {out[key].shape[0]} entries for {m} modes")
    return out


def _wheel_modes(modes):
    """A :class:`fe.wheel_modes.WheelModes` from the dict of :func:`read_modes` (with shapes)."""
    return WheelModes(modes["frequency"], modes["nodal_diameters"], modes["nodal_circles"], modes["family"],
                      modes["orientation"], modes["contact_shape"], np.asarray(modes["shapes"], dtype=float),
                      modes["solver"])


def rotating_base(modes, mesh, rotation):
    """The part of the rotating models' inputs that depends neither on the contact point nor on the speed.

    Returns
    -------
    dict
        ``modes`` (WheelModes), ``zeta``, ``model`` (EulerianModel at the mesh contact node),
        ``switches``, ``axi`` (axisymmetric modes of the moving-load path), ``axi_zeta``,
        ``mesh``, ``rotation``.
    """
    wheel_modes = _wheel_modes(modes)
    zeta = modes["damping_ratio"]
    material = (modes["youngs_modulus"], modes["poisson_ratio"], modes["density"])
    stiffening = rotation["centrifugal_stiffening"]
    if wheel_modes.solver == "axisymmetric":
        model = eulerian_model_axisymmetric(wheel_modes, mesh["section_nodes"], mesh["section_cells"],
                                            mesh["section_clamped"], *material, zeta,
                                            centrifugal_stiffening=stiffening)
    else:
        model = eulerian_model_hex20(wheel_modes, mesh["hex_nodes"], mesh["hex_cells"], mesh["hex_clamped"], *material,
                                     zeta, centrifugal_stiffening=stiffening, n_sectors=mesh["elements_around"])
    switches = dict(gyroscopic=rotation["gyroscopic"], convective=rotation["spin_softening"], centrifugal=stiffening)
    # exact moving-load path: axisymmetric harmonics (solved here on the same section if needed)
    axi = wheel_modes
    if wheel_modes.solver != "axisymmetric":
        axi = solve_axisymmetric(mesh["section_nodes"], mesh["section_cells"], mesh["section_clamped"],
                                 mesh["contact_section_node"], *material, float(modes["frequency"].max()) * 1.001)
        # modal damping is a function of n (docs/design.md §5): take it from the 3D modes of the same n
        by_n = dict(zip(modes["nodal_diameters"].tolist(), zeta.tolist()))
        axi_zeta = np.array([by_n.get(int(n), zeta.min()) for n in axi.nodal_diameters])
    else:
        axi_zeta = zeta
    return {"modes": wheel_modes, "zeta": zeta, "model": model, "switches": switches, "axi": axi,
            "axi_zeta": axi_zeta, "mesh": mesh, "rotation": rotation}


def rotating_at(base, speed, contact=None):
    """The rotating models' inputs at a speed (m/s) and a contact (None: the mesh node), from :func:`rotating_base`.

    Parameters
    ----------
    base : dict
        :func:`rotating_base`.
    speed : float
        m/s; the spin is ``Ω = speed / r0``.
    contact : WheelContact, optional
        The computed contact (:func:`wheel_contact`): its interpolated shapes and its rolling
        radius r0. Default: the mesh's contact node and its radius (the hand-set contact).

    Returns
    -------
    dict
        ``spin`` (rad/s), ``r0`` (m), ``model`` (the EulerianModel at the contact),
        ``switches``, ``axisymmetric`` (the modal data of the exact moving-load path) and
        ``ring`` (the interpolated moving-load path's ring, or None); with the modes at the
        contact they make the :class:`fe.wheel_models.WheelState` (:func:`wheel_state`).
    """
    mesh, rotation, axi = base["mesh"], base["rotation"], base["axi"]
    model = base["model"]
    if contact is None:
        r0 = float(np.hypot(mesh["contact_position"][0], mesh["contact_position"][2]))
        contact_amplitude = axi.shapes[:, mesh["contact_section_node"], :]
        ring_node = mesh["contact_hex_node"]
    else:
        r0 = contact.rolling_radius
        model = replace(model, contact_shape=contact.shapes)
        point = contact.point
        contact_amplitude = np.einsum("k,mkc->mc", point.weights, np.asarray(axi.shapes)[:, point.nodes, :])
        ring_node = contact.ring_node
    spin = spin_rate(speed, r0)
    out = {"spin": spin, "r0": r0, "model": model, "switches": base["switches"]}
    out["axisymmetric"] = {"frequency": axi.frequency, "damping_ratio": base["axi_zeta"],
                           "harmonic": axi.nodal_diameters, "family": axi.orientation,
                           "contact_amplitude": contact_amplitude}
    out["ring"] = None  # the moving-load path's ring: only for the interpolated path
    if rotation["moving_load_path"] != "harmonic":
        if base["modes"].solver != "hex20":
            raise ValueError("wheel.rotation.moving_load_path = 'interpolated' needs wheel.fe.solver = 'hex20'")
        if contact is not None:
            logger.warning("wheel.rotation.moving_load_path = 'interpolated' takes the ring through the mesh node "
                           "nearest to the computed contact (%.4f m from the flange back)", contact.point.position[1])
        out["ring"] = moving_load.RingInterpolant(mesh["hex_nodes"], mesh["hex_cells"], base["modes"].shapes, ring_node)
    return out


@dataclass(frozen=True)
class WheelContact:
    """The wheel at a computed contact point.

    Attributes
    ----------
    point : fe.wheel_modes.SurfacePoint
        The running-surface edge and its shape-function weights.
    shapes : (m, 3) ndarray
        Mode shapes interpolated there (contact frame at θ = 0, upright), m/√kg.
    rolling_radius : float
        Of the contact geometry, m (the spin of the rotating models is speed / rolling_radius).
    ring_node : int
        The hex20 node of the edge with the largest weight (the interpolated moving-load path).
    """

    point: SurfacePoint
    shapes: np.ndarray
    rolling_radius: float
    ring_node: int


def wheel_contact(modes, mesh, contact_point):
    """The wheel's :class:`WheelContact` at a ``contact_geometry.ContactPoint``.

    The point on the running surface at ``contact_point.wheel_lateral`` from the flange back
    (:func:`fe.wheel_modes.running_surface_point`), with the modes interpolated there by the
    edge's shape functions (:func:`fe.wheel_modes.contact_shapes_at`).
    """
    wheel_modes = _wheel_modes(modes)
    point = running_surface_point(mesh["section_nodes"], mesh["section_cells"], contact_point.wheel_lateral,
                                  contact_point.rolling_radius)
    shapes = contact_shapes_at(point, wheel_modes, mesh["section_nodes"], mesh["hex_nodes"])
    ring_node = -1
    if wheel_modes.solver == "hex20":
        ring_node = int(hex_nodes_at(point, mesh["section_nodes"], mesh["hex_nodes"])[int(np.argmax(point.weights))])
    return WheelContact(point, shapes, float(contact_point.rolling_radius), ring_node)


def wheel_models_at(modes, base, speed, contact=None):
    """``{model: (poles rad/s, residues m/(N s))}`` of the registered wheel models at a speed and contact.

    The models :func:`build_greens` writes (upright frame), for any speed: ``base`` of
    :func:`rotating_base`, ``contact`` a :class:`WheelContact` (:func:`wheel_contact`) or None
    for the hand-set contact (the mesh's contact node).
    """
    shape = modes["contact_shape"] if contact is None else contact.shapes
    return _wheel_models(wheel_state(modes, rotating_at(base, speed, contact), shape))


def wheel_state(modes, rotating, contact_shape):
    """The :class:`fe.wheel_models.WheelState` of the models at one contact point.

    ``modes`` of :func:`read_modes`, ``rotating`` of :func:`rotating_at`, ``contact_shape`` (m, 3)
    the modes at the contact point (m/√kg).
    """
    return WheelState(modes["frequency"], modes["damping_ratio"], contact_shape, rotating["spin"],
                      rotating["model"], rotating["switches"], rotating["axisymmetric"], rotating["ring"])


def _wheel_models(state):
    """``{name: (poles, residues)}`` of every registered wheel model for a :class:`WheelState`."""
    return {model.name: model.poles_residues(state) for model in wheel_models()}


def _write_models(f, models, state, frequency, dt, n_kernel):
    """The groups ``<model>/{poles, residues, receptance, kernel}`` of ``wheel_greens.h5`` in ``f``."""
    for name, (poles, residues) in models.items():
        group = f.create_group(name)
        add_dataset(group, "poles", poles, "rad/s")
        add_dataset(group, "residues", residues, "m/(N*s)")
        add_dataset(group, "receptance", receptance(poles, residues, frequency), "m/N", compress=True)
        hook = wheel_model(name).kernel
        kernel = hook(state, dt, n_kernel) if hook is not None else None
        if kernel is not None:  # no exact recursion: the interaction convolves with this kernel
            group.attrs["time_stepping"] = "convolution"
        else:
            kernel = ramp_invariant_kernel(poles, residues, dt, n_kernel)
            group.attrs["time_stepping"] = "recursion"
        add_dataset(group, "kernel", kernel, "m/N", compress=True)


def build_greens(ctx):
    """``wheel-greens``: receptances, poles/residues and discrete kernels of the three wheel models.

    At the contact ``contact.geometry`` selects, and only there: ``"manual"``, the hand-set
    contact (the mesh's contact node, spin from its radius); ``"profiles"``, the computed contact
    of ``contact_geometry.h5`` (modes interpolated on the running surface, spin from the
    geometry's rolling radius; its position and shapes also under ``profiles/``). The root
    attribute ``contact_geometry`` names it (:func:`stages.greens_layout.held_geometry`).
    ``modal/`` keeps the modal data at the mesh's contact node.
    """
    modes = read_modes(ctx.inputs["wheel-modes"], with_shapes=True)
    mesh = read_mesh(ctx.inputs["wheel-modes"].parent / "wheel_mesh.h5")
    time = ctx.section("time")
    rotation = ctx.section("wheel.rotation")
    speed = ctx.section("operating")["speed"]
    geometry = study_geometry(ctx.study)
    dt = time["time_step"]
    n_kernel = int(round(time["wheel_kernel_duration"] / dt))
    base = rotating_base(modes, mesh, rotation)
    computed = None
    if geometry == "profiles":
        computed = wheel_contact(modes, mesh, read_operating_contact(ctx.inputs["contact-geometry"]))
        logger.info("wheel at the computed contact: %.4f m from the flange back, radius %.4f m",
                    computed.point.position[1], computed.rolling_radius)
    rotating = rotating_at(base, speed, computed)
    state = wheel_state(modes, rotating, modes["contact_shape"] if computed is None else computed.shapes)
    models = _wheel_models(state)
    frequency = frequency_grid(1.0, 0.5 / dt, np.concatenate([p for p, _ in models.values()]))
    logger.info("wheel models at the %s contact, %.2f m/s (spin %.2f rad/s): %s", geometry, speed, rotating["spin"],
                ", ".join(f"{k} {len(p)} poles" for k, (p, _) in models.items()))
    with ctx.writer() as f:
        f.attrs["spin"] = rotating["spin"]
        f.attrs[GEOMETRY_ATTRIBUTE] = geometry
        add_dataset(f, "time_step", dt, "s")
        add_dataset(f, "speed", speed, "m/s")
        add_dataset(f, "spin", rotating["spin"], "rad/s")
        add_dataset(f, "frequency", frequency, "Hz")
        _write_models(f, models, state, frequency, dt, n_kernel)
        if computed is not None:
            profiles = f.create_group("profiles")
            add_dataset(profiles, "spin", rotating["spin"], "rad/s")
            add_dataset(profiles, "rolling_radius", computed.rolling_radius, "m")
            add_dataset(profiles, "position", computed.point.position, "m")
            add_dataset(profiles, "section_nodes", computed.point.nodes.astype(np.int64), "")
            add_dataset(profiles, "weights", computed.point.weights, "1")
            add_dataset(profiles, "contact_shape", computed.shapes, "m/sqrt(kg)")
        _write_wheel_state(f, state, modes)


def _write_wheel_state(f, state, modes):
    """Store what :func:`read_wheel_state` needs to rebuild the models at any speed (Campbell
    diagram, report): the modal data at the mesh's contact node (``modal/``), the Eulerian model's
    matrices and switches (``eulerian/``) and the harmonics of the exact moving-load path
    (``axisymmetric/``)."""
    mats = state.eulerian.matrices
    add_dataset(f, "eulerian/gyroscopic", mats.gyroscopic, "1")
    add_dataset(f, "eulerian/convective", mats.convective, "1")
    if mats.geometric is not None:
        add_dataset(f, "eulerian/geometric", mats.geometric, "1")
    f["eulerian"].attrs.update({k: bool(v) for k, v in state.switches.items()})
    add_dataset(f, "modal/frequency", modes["frequency"], "Hz")
    add_dataset(f, "modal/damping_ratio", modes["damping_ratio"], "1")
    add_dataset(f, "modal/contact_shape", modes["contact_shape"], "m/sqrt(kg)")
    add_dataset(f, "modal/nodal_diameters", modes["nodal_diameters"], "")
    add_dataset(f, "modal/family", modes["family"], "")
    add_dataset(f, "modal/nodal_circles", modes["nodal_circles"], "")
    axi = state.axisymmetric
    add_dataset(f, "axisymmetric/frequency", axi["frequency"], "Hz")
    add_dataset(f, "axisymmetric/damping_ratio", axi["damping_ratio"], "1")
    add_dataset(f, "axisymmetric/harmonic", axi["harmonic"], "")
    add_dataset(f, "axisymmetric/family", axi["family"], "")
    add_dataset(f, "axisymmetric/contact_amplitude", axi["contact_amplitude"], "m/sqrt(kg)")


def read_wheel_state(f):
    """The :class:`fe.wheel_models.WheelState` an open ``wheel_greens.h5`` holds (:func:`_write_wheel_state`).

    At the artefact's spin and at the mesh's contact node, with the exact moving-load path (no
    ring): enough to rebuild every registered model's poles at any spin
    (``model.poles_residues(dataclasses.replace(state, spin=...))``); the residues are those at the
    mesh node.
    """
    switches = {k: bool(f["eulerian"].attrs[k]) for k in ("gyroscopic", "convective", "centrifugal")}
    geometric = read_dataset(f, "eulerian/geometric", "1") if "geometric" in f["eulerian"] else None
    matrices = RotationMatrices(read_dataset(f, "eulerian/gyroscopic", "1"), read_dataset(f, "eulerian/convective", "1"),
                                geometric)
    modal = {k: read_dataset(f, f"modal/{k}") for k in ("frequency", "damping_ratio", "contact_shape")}
    axi = {k: read_dataset(f, f"axisymmetric/{k}") for k in ("frequency", "damping_ratio", "harmonic", "family",
                                                             "contact_amplitude")}
    eulerian = EulerianModel(modal["frequency"], modal["damping_ratio"], modal["contact_shape"], matrices)
    return WheelState(modal["frequency"], modal["damping_ratio"], modal["contact_shape"],
                      float(read_dataset(f, "spin", "rad/s")), eulerian, switches, axi, None)


def read_greens(path, model=REFERENCE, geometry=None, response=True):
    """Read one wheel model of ``wheel_greens.h5``.

    Parameters
    ----------
    path : path-like
    model : str
        A registered wheel model (:mod:`interaction.wheel_models`).
    geometry : {"manual", "profiles"}, optional
        The contact the caller needs: the hand-set one (the mesh's contact node) or the computed
        one (``contact_geometry.h5``), see :func:`build_greens`. None: the one the artefact holds.
    response : bool
        Also read the receptance and the discrete Green's kernel (the time loop and the report
        need them; the radiation needs only the modal part).

    Returns
    -------
    dict
        ``time_step`` (s), ``time_stepping``, ``poles`` (rad/s), ``residues`` (m/(N s), track
        frame), ``spin`` (rad/s), ``contact_shape`` (m/sqrt(kg), the modes at the contact held),
        and with ``response`` ``frequency`` (Hz), ``receptance`` (m/N), ``kernel`` (m/N).

    Raises
    ------
    ArtefactError
        If the artefact is missing or damaged, or holds the other contact than ``geometry``.
    ValueError
        If ``model`` is not a wheel model of the artefact.
    """
    with open_artefact(path, "wheel_greens", WHEEL_GREENS_VERSION) as f:
        held = held_geometry(f, geometry)
        if model not in wheel_model_names() or model not in f:
            raise ValueError(f"{path}: no wheel model {model!r} at the {held} contact")
        g = f[model]
        shape_path = "modal/contact_shape" if held == "manual" else "profiles/contact_shape"
        out = {
            "time_step": float(read_dataset(f, "time_step", "s")),
            "time_stepping": str(g.attrs.get("time_stepping", "recursion")),
            "poles": read_dataset(g, "poles", "rad/s", (None,)),
            "residues": read_dataset(g, "residues", "m/(N*s)", (None, 3, 3)),
            "spin": float(read_dataset(f, "spin", "rad/s")),
            "contact_shape": read_dataset(f, shape_path, "m/sqrt(kg)", (None, 3)),
        }
        if response:
            frequency = read_dataset(f, "frequency", "Hz", (None,))
            out["frequency"] = frequency
            out["receptance"] = read_dataset(g, "receptance", "m/N", (frequency.size, 3, 3))
            out["kernel"] = read_dataset(g, "kernel", "m/N", (None, 3, 3))
        return out
