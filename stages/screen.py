"""The linear stability screen of a study's configuration: structures, contact and the closed loop.

Shared by ``pipeline.py stability`` (one configuration, the study's own artefacts) and the
squeal maps (:mod:`stages.maps`, many configurations). The wheel enters as the pole-residue
models of its three wheel models, the rail as the rational model of its receptance at the
contact (:func:`rail_model`, fitted once per rail variant and kept as an artefact), the contact
linearised about steady rolling: the point-contact law
(:func:`contact.point.model.linearise_point_contact`) for ``contact.model = "point"``, the
steady half-space's slopes with the point model's relaxation
(:func:`contact.halfspace.linearise.linearise_halfspace_contact`) for ``"halfspace"``.

``rail_fit.h5`` (schema ``rail_fit``)
    ``poles`` rad/s, ``residues`` m/(N s), ``direct`` m/N, ``band`` Hz, ``frequency`` Hz and
    ``receptance`` (nf, 3, 3) m/N (the fitted samples: the rail's point receptance at the
    contact, speed -> 0), ``max_error`` (-, largest relative magnitude error on the samples).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from fe.rotation import spin_rate
from contact.registry import contact_spec
from interaction.frame import to_contact_frame
from interaction.wheel_models import wheel_model_names
from squealcore.artefacts import (
    add_dataset,
    file_sha256,
    freshness,
    open_artefact,
    params_hash,
    read_dataset,
    write_artefact,
)
from squealcore.study import get_section, set_path
from stability.rational import RationalModel, evaluate, rail_moving_receptance, vector_fit
from stability.screen import screen
from stages import engine
from stages.cases import case_contact, contact_hertz, contact_setup, imposed_creepage
from stages.greens_layout import RAIL_FIT_SCHEMA, RAIL_FIT_VERSION
from stages.rail import read_mesh as read_rail_mesh
from stages.wheel import read_greens, rotating_base, wheel_contact, wheel_models_at
from waveguide.api import build_waveguide
from waveguide.params import TrackParams

logger = logging.getLogger(__name__)

#: Configuration sections the rail fit reads.
RAIL_FIT_SECTIONS = ("rail", "track", "map")


def _rail_fit_params(study):
    params = {s: get_section(study, s) for s in ("rail", "track")}
    params["map"] = {k: v for k, v in get_section(study, "map").items() if k.startswith("rail_")}
    return params


#: The rail's contact position of the computed contact is rounded to this (m) before the rail is
#: fitted there, so that positions equal but for round-off share one fit.
RAIL_POSITION_RESOLUTION = 1e-6


def rail_study(study, lateral=None):
    """The study whose rail receptance is that at ``lateral`` (m) on the rail head.

    ``lateral``: the contact's position (:func:`rail_lateral`) set as ``track.contact_lateral_position`` (where the
    waveguide's load patch lies); None: the study as it is (the hand-set position).
    """
    if lateral is None:
        return study
    return set_path(study, ["track", "contact_lateral_position"], lateral)


def computed_contact(study):
    """True when the study's contact is computed from the profiles (``contact.geometry``)."""
    return study["contact"].get("geometry", "profiles") != "manual"


def rail_lateral(study, point):
    """The rail contact position (m) the screen fits the rail at: None (the study's own
    ``track.contact_lateral_position``) for the hand-set contact, else ``point.rail_section_lateral``
    rounded to :data:`RAIL_POSITION_RESOLUTION`."""
    if not computed_contact(study):
        return None
    return round(float(point.rail_section_lateral) / RAIL_POSITION_RESOLUTION) * RAIL_POSITION_RESOLUTION


def rail_model(study, rail_mesh_path, output, lateral=None):
    """The rational model of the rail's receptance at the contact, from ``output`` if fresh.

    The receptance is the point receptance of the wave sum (the moving receptance's limit
    v -> 0; at 80 km/h the load moves at under 3 % of the slowest wave speed that matters in
    the band, and the fitted model neglects that), sampled at ``map.rail_frequencies``
    log-spaced frequencies in ``[map.rail_f_min, map.rail_f_max]`` and vector-fitted
    (:func:`stability.rational.vector_fit`, symmetric).

    Parameters
    ----------
    study : dict
    rail_mesh_path : Path
        ``rail_mesh.h5`` of the study.
    output : Path
        The ``rail_fit.h5`` artefact (rebuilt when stale).
    lateral : float, optional
        Contact position on the rail head, m (:func:`rail_study`); default the study's
        ``track.contact_lateral_position``.

    Returns
    -------
    RationalModel
        In the rail section's upright frame.
    """
    output = Path(output)
    study = rail_study(study, lateral)
    params_sha, inputs = _rail_fit_provenance(study, rail_mesh_path)
    fresh, reason = freshness(output, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION, params_sha, inputs)
    if not fresh:
        logger.info("rail fit %s: building (%s)", output.name, reason)
        with write_artefact(output, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION, params_sha, inputs,
                            config=_rail_fit_params(study)) as f5:
            _write_rail_fit(f5, study, rail_mesh_path)
    return read_rail_fit(output)


def _rail_fit_provenance(study, rail_mesh_path):
    """Parameter hash and input hashes of the rail fit of ``study`` (at its rail position)."""
    return params_hash(_rail_fit_params(study)), {"rail_mesh.h5": file_sha256(rail_mesh_path)}


def rail_fit_check(study, rail_mesh_path, output, lateral=None):
    """Freshness of a rail fit :func:`rail_model` keeps (``(fresh, reason)``; nothing is built)."""
    rail_mesh_path = Path(rail_mesh_path)
    if not rail_mesh_path.exists():
        return False, f"{rail_mesh_path.name} missing"
    return freshness(Path(output), RAIL_FIT_SCHEMA, RAIL_FIT_VERSION,
                     *_rail_fit_provenance(rail_study(study, lateral), rail_mesh_path))


def _write_rail_fit(f5, study, rail_mesh_path):
    """Fit the rail's receptance of ``study`` (its ``track.contact_lateral_position``) and write
    the fit into the open artefact ``f5`` (:func:`rail_model` describes the fit)."""
    opts = get_section(study, "map")
    track = TrackParams.from_mapping(get_section(study, "track"), "track")
    waveguide = build_waveguide(read_rail_mesh(rail_mesh_path), track)
    f = np.geomspace(opts["rail_f_min"], opts["rail_f_max"], opts["rail_frequencies"])
    h = rail_moving_receptance(waveguide, 0.0, f)
    model = vector_fit(f, h, n_pairs=opts["rail_pole_pairs"], n_iterations=opts["rail_iterations"], symmetric=True)
    fit = evaluate(model, f)
    big = np.abs(h) > 1e-3 * np.abs(h).max()
    error = float((np.abs(np.abs(fit) - np.abs(h))[big] / np.abs(h)[big]).max())
    logger.info("rail fit: %d poles, largest magnitude error %.2g on the samples", model.poles.size, error)
    add_dataset(f5, "poles", model.poles, "rad/s")
    add_dataset(f5, "residues", model.residues, "m/(N*s)")
    add_dataset(f5, "direct", model.direct, "m/N")
    add_dataset(f5, "band", np.asarray(model.band, float), "Hz")
    add_dataset(f5, "frequency", f, "Hz")
    add_dataset(f5, "receptance", h, "m/N")
    add_dataset(f5, "max_error", error, "1")


def build_rail_fit(ctx):
    """Stage ``rail-fit``: the rational model of the rail's receptance at the study's contact
    (``rail_fit.h5``; the screen of the report and of ``pipeline.py stability`` reads it).

    The rail position is the hand-set ``track.contact_lateral_position``, or, for the computed
    contact, the contact's position on the rail head read from ``contact_geometry.h5``
    (:func:`rail_lateral`)."""
    point = case_contact(ctx.study, ctx.inputs.get("contact-geometry"))
    study = rail_study(ctx.study, rail_lateral(ctx.study, point))
    with ctx.writer() as f5:
        _write_rail_fit(f5, study, ctx.inputs["rail-mesh"])


def read_rail_fit(path):
    """The :class:`RationalModel` of ``rail_fit.h5``."""
    with open_artefact(path, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION) as f:
        poles = read_dataset(f, "poles", "rad/s", (None,))
        residues = read_dataset(f, "residues", "m/(N*s)", (poles.size, 3, 3))
        direct = read_dataset(f, "direct", "m/N", (3, 3))
        band = tuple(float(b) for b in read_dataset(f, "band", "Hz", (2,)))
    return RationalModel(poles, residues, direct, np.zeros((3, 3)), band)


class WheelModels:
    """The three wheel models of one wheel at any speed and contact, from its modes (``wheel_modes.h5``).

    The speed- and point-independent part (the Eulerian model's matrices, the axisymmetric modes
    of the moving-load path: :func:`stages.wheel.rotating_base`) is assembled once; the models
    at a speed and contact are those of the wheel's Green's stage
    (:func:`stages.wheel.wheel_models_at`), spinning at ``speed / rolling radius``.

    Parameters
    ----------
    modes : dict
        :func:`stages.wheel.read_modes` with shapes.
    mesh : dict
        :func:`stages.wheel.read_mesh`.
    rotation : dict
        ``[wheel.rotation]``.
    """

    def __init__(self, modes, mesh, rotation):
        self.modes, self.mesh, self.rotation = modes, mesh, rotation
        self.base = rotating_base(modes, mesh, rotation)
        #: rolling radius of the hand-set contact (the mesh's contact node), m
        self.r0 = float(np.hypot(mesh["contact_position"][0], mesh["contact_position"][2]))
        self._contacts = {}

    def contact(self, point=None):
        """The :class:`stages.wheel.WheelContact` at a computed ``ContactPoint`` (cached per
        position and radius); None for the hand-set contact (``point`` None: pass
        :func:`wheel_point`)."""
        if point is None:
            return None
        key = (point.wheel_lateral, point.rolling_radius)
        if key not in self._contacts:
            self._contacts[key] = wheel_contact(self.modes, self.mesh, point)
        return self._contacts[key]

    def spin(self, speed, point=None):
        """The spin (rad/s) at ``speed`` (m/s): over the contact's rolling radius (the mesh node's
        for ``point`` None)."""
        return spin_rate(speed, self.r0 if point is None else point.rolling_radius)

    def at(self, speed, point=None):
        """``{model: (poles rad/s, residues m/(N s))}`` at ``speed`` (m/s) and the computed
        contact ``point`` (None: the hand-set one), in the wheel's upright frame."""
        return wheel_models_at(self.modes, self.base, speed, self.contact(point))

    def at_speed(self, speed):
        """:meth:`at` the hand-set contact."""
        return self.at(speed)


def wheel_point(study, point):
    """The point :class:`WheelModels` takes: ``point`` for a computed contact, None (the mesh's
    contact node, as the cases' hand-set wheel models) otherwise."""
    return point if computed_contact(study) else None


def screen_point(study, point=None):
    """The contact the screen of ``study`` uses: ``point``, or the cases' :func:`stages.cases.case_contact`
    (hand-set, or computed from the profiles in memory) when None."""
    return case_contact(study) if point is None else point


def linear_contact(study, point=None):
    """The contact of a study at its static normal force and imposed creepages, linearised
    (:class:`stability.linearised_contact.LinearisedContact`) by the registered model's own hook
    (:mod:`contact.registry`): the point model's law, the steady half-space on the
    case's grid (computed once per distinct contact).

    The contact of the time-domain cases: Hertz at ``point`` (:func:`stages.cases.contact_hertz`),
    the normal force ``point.normal_force``, the creepages of :func:`stages.cases.imposed_creepage`
    (with the geometric spin of the computed contact). ``point`` default: :func:`stages.cases.case_contact`.
    """
    point = screen_point(study, point)
    linearise = contact_spec(study["contact"]["model"]).hook("linearise")
    return linearise(contact_setup(study, point), point.normal_force, imposed_creepage(study, point))


#: Rails turned into a contact frame, by (id of the upright model, angle); the upright model is
#: kept with its entry so that ids are not reused. The same rotated model then serves every
#: configuration at that contact (and the loop's cached realisation of it).
_ROTATED_RAILS = {}


def rail_in_contact_frame(rail, angle):
    """The rail's :class:`RationalModel` turned into the contact frame by ``angle`` (rad, the
    contact's ``rail_section_angle``; :func:`interaction.frame.to_contact_frame`); the same object
    for the same rail and angle."""
    if angle == 0.0:
        return rail
    entry = _ROTATED_RAILS.get((id(rail), angle))
    if entry is None or entry[0] is not rail:
        if len(_ROTATED_RAILS) >= 16:
            _ROTATED_RAILS.pop(next(iter(_ROTATED_RAILS)))
        rotated = RationalModel(rail.poles, to_contact_frame(rail.residues, angle),
                                to_contact_frame(rail.direct, angle), to_contact_frame(rail.proportional, angle),
                                rail.band)
        entry = _ROTATED_RAILS[(id(rail), angle)] = (rail, rotated)
    return entry[1]


def wheel_at_contact(models, point):
    """The wheel models turned into the contact frame (residues rotated by ``point.contact_angle``,
    :func:`interaction.frame.to_contact_frame`), as the time-domain case takes them.

    Parameters
    ----------
    models : dict
        ``{model: (poles rad/s, residues m/(N s))}`` in the wheel's upright frame.
    point : contact_geometry.ContactPoint

    Returns
    -------
    dict
        ``{model: (poles, residues)}`` in the contact frame.
    """
    return {name: (poles, to_contact_frame(residues, point.contact_angle)) for name, (poles, residues) in models.items()}


def hertz_stiffness(study, point):
    """The contact's normal stiffness ``dF/dδ = 3 F_z / (2 δ)`` (N/m) at ``point`` and its normal
    force (Hertz, :func:`stages.cases.contact_hertz`)."""
    _, hertz = contact_hertz(study, point)
    return 1.5 * hertz.normal_force / hertz.approach


def screen_study(study, models, rail, names=None, point=None, contact=None, pole_modes=True, structured=True):
    """The screen of one configuration for the wheel models ``names``.

    Everything enters as the time-domain case of the same configuration takes it
    (:func:`stages.cases.case_structures`): the wheel's residues turned into the contact frame
    by ``point.contact_angle``, the rail's by ``point.rail_section_angle``, the contact
    linearised at the point (:func:`linear_contact`).

    Parameters
    ----------
    study : dict
        The configuration (operating state and contact).
    models : dict
        ``{model: (poles, residues)}`` at the study's speed and contact, upright frame.
    rail : RationalModel
        At the contact's rail position, upright frame.
    names : sequence of str
    point : contact_geometry.ContactPoint, optional
        The contact (default :func:`stages.cases.case_contact` of the study).
    contact : LinearisedContact, optional
        :func:`linear_contact` of ``study`` and ``point`` when already at hand.
    pole_modes : bool
        Give every growing pole its wheel modes (else the margin pole's only; see
        :func:`stability.screen.screen`).
    structured : bool
        The eigenvalues as roots of the contact determinant (default) or from the dense loop
        matrix alone (:func:`stability.screen.screen`; the same to rounding).

    Returns
    -------
    dict
        ``{model: result of stability.screen.screen}``.
    """
    point = screen_point(study, point)
    contact = linear_contact(study, point) if contact is None else contact
    speed = study["operating"]["speed"]
    min_share = study["map"]["min_share"]
    rail = rail_in_contact_frame(rail, point.rail_section_angle)
    names = wheel_model_names() if names is None else names
    wheel = wheel_at_contact({name: models[name] for name in names}, point)
    return {name: screen(*wheel[name], rail, contact, speed, min_share, pole_modes, structured) for name in names}


def structures(study, out, progress=False):
    """Bring the wheel's Green's artefact and the rail fit of ``out`` up to date.

    The contact is the cases' (:func:`stages.cases.case_contact`): the wheel models of
    ``wheel_greens.h5`` at it (``contact.geometry``), the rail fitted at its rail position
    (the ``rail-fit`` stage's ``rail_fit.h5``).

    Returns
    -------
    (dict, RationalModel, ContactPoint)
        ``{model: (poles, residues)}`` (upright frame), the rail model (upright) and the contact.
    """
    out = Path(out)
    engine.run_structural(study, out, engine.required_stages("wheel-greens"), progress)
    engine.run_structural(study, out, engine.required_stages("rail-fit"), progress)
    return read_structures(study, out)


def read_structures(study, out):
    """What :func:`structures` returns, from the artefacts in ``out`` as they are (the report's
    screen, which runs after the structural stages): the wheel models of ``wheel_greens.h5``, the
    rail fit of the ``rail-fit`` stage (``rail_fit.h5``) and the contact."""
    out = Path(out)
    point = case_contact(study, out / "contact_geometry.h5")
    rail = read_rail_fit(out / "rail_fit.h5")
    geometry = "profiles" if computed_contact(study) else "manual"
    models = {}
    for name in wheel_model_names():
        greens = read_greens(out / "wheel_greens.h5", name, geometry)
        models[name] = (greens["poles"], greens["residues"])
    return models, rail, point
