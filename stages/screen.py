"""The linear stability screen of a study's configuration: structures, contact and the closed loop.

Shared by ``pipeline.py stability`` (one configuration, the study's own artefacts) and the
squeal maps (:mod:`stages.maps`, many configurations). The wheel enters as the pole-residue
models of its three wheel models, the rail as the rational model of its receptance at the
contact (:func:`rail_model`, fitted once per rail variant and kept as an artefact), the contact
as the point-contact law linearised about steady rolling
(:func:`interaction.stability.linearise_point_contact`, whatever ``contact.model`` the study's
time-domain cases use: the screen is the point model's linearisation).

``rail_fit.h5`` (schema ``rail_fit``)
    ``poles`` rad/s, ``residues`` m/(N s), ``direct`` m/N, ``band`` Hz, ``frequency`` Hz and
    ``receptance`` (nf, 3, 3) m/N (the fitted samples: the rail's point receptance at the
    contact, speed -> 0), ``max_error`` (-, largest relative magnitude error on the samples).
"""

from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from fe import moving_load
from fe.greens import modal_poles_residues
from fe.rotation import spin_rate
from interaction.contact.params import ContactParams
from interaction.contact.point import PointContact
from interaction.params import WHEEL_MODELS
from interaction.rational import RationalModel, evaluate, rail_moving_receptance, vector_fit
from interaction.stability import linearise_point_contact, screen
from squealcore.artefacts import (
    add_dataset,
    file_sha256,
    freshness,
    open_artefact,
    params_hash,
    read_dataset,
    write_artefact,
)
from squealcore.study import get_section
from stages.cases import contact_hertz
from stages.rail import read_mesh as read_rail_mesh
from stages.wheel import rotating_models
from waveguide.api import build_waveguide
from waveguide.params import TrackParams

logger = logging.getLogger(__name__)

RAIL_FIT_SCHEMA, RAIL_FIT_VERSION = "rail_fit", 1
#: Configuration sections the rail fit reads.
RAIL_FIT_SECTIONS = ("rail", "track", "map")


def _rail_fit_params(study):
    params = {s: get_section(study, s) for s in ("rail", "track")}
    params["map"] = {k: v for k, v in get_section(study, "map").items() if k.startswith("rail_")}
    return params


def rail_model(study, rail_mesh_path, output):
    """The rational model of the rail's receptance at the contact, from ``output`` if fresh.

    The receptance is the point receptance of the wave sum (the moving receptance's limit
    v -> 0; at 80 km/h the load moves at under 3 % of the slowest wave speed that matters in
    the band, and the fitted model neglects that), sampled at ``map.rail_frequencies``
    log-spaced frequencies in ``[map.rail_f_min, map.rail_f_max]`` and vector-fitted
    (:func:`interaction.rational.vector_fit`, symmetric).

    Parameters
    ----------
    study : dict
    rail_mesh_path : Path
        ``rail_mesh.h5`` of the study.
    output : Path
        The ``rail_fit.h5`` artefact (rebuilt when stale).

    Returns
    -------
    RationalModel
    """
    output = Path(output)
    params_sha = params_hash(_rail_fit_params(study))
    inputs = {"rail_mesh.h5": file_sha256(rail_mesh_path)}
    fresh, reason = freshness(output, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION, params_sha, inputs)
    if not fresh:
        logger.info("rail fit %s: building (%s)", output.name, reason)
        opts = get_section(study, "map")
        track = TrackParams.from_mapping(get_section(study, "track"), "track")
        waveguide = build_waveguide(read_rail_mesh(rail_mesh_path), track)
        f = np.geomspace(opts["rail_f_min"], opts["rail_f_max"], opts["rail_frequencies"])
        h = rail_moving_receptance(waveguide, 0.0, f)
        model = vector_fit(f, h, n_pairs=opts["rail_pole_pairs"], n_iterations=opts["rail_iterations"],
                           symmetric=True)
        fit = evaluate(model, f)
        big = np.abs(h) > 1e-3 * np.abs(h).max()
        error = float((np.abs(np.abs(fit) - np.abs(h))[big] / np.abs(h)[big]).max())
        logger.info("rail fit: %d poles, largest magnitude error %.2g on the samples", model.poles.size, error)
        with write_artefact(output, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION, params_sha, inputs,
                            config=_rail_fit_params(study)) as f5:
            add_dataset(f5, "poles", model.poles, "rad/s")
            add_dataset(f5, "residues", model.residues, "m/(N*s)")
            add_dataset(f5, "direct", model.direct, "m/N")
            add_dataset(f5, "band", np.asarray(model.band, float), "Hz")
            add_dataset(f5, "frequency", f, "Hz")
            add_dataset(f5, "receptance", h, "m/N")
            add_dataset(f5, "max_error", error, "1")
    return read_rail_fit(output)


def read_rail_fit(path):
    """The :class:`RationalModel` of ``rail_fit.h5``."""
    with open_artefact(path, RAIL_FIT_SCHEMA, RAIL_FIT_VERSION) as f:
        poles = read_dataset(f, "poles", "rad/s", (None,))
        residues = read_dataset(f, "residues", "m/(N*s)", (poles.size, 3, 3))
        direct = read_dataset(f, "direct", "m/N", (3, 3))
        band = tuple(float(b) for b in read_dataset(f, "band", "Hz", (2,)))
    return RationalModel(poles, residues, direct, np.zeros((3, 3)), band)


class WheelModels:
    """The three wheel models of one wheel at any speed, from its modes (``wheel_modes.h5``).

    The stationary model does not depend on the speed; the rotating ones are rebuilt per spin
    ``Ω = v / r0`` from the wheel's Eulerian matrices, assembled once (:func:`stages.wheel.rotating_models`).

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
        self.stationary = modal_poles_residues(modes["frequency"], modes["damping_ratio"], modes["contact_shape"])
        self._rotating = rotating_models(modes, mesh, rotation, 0.0)
        self.r0 = self._rotating["r0"]

    def at_speed(self, speed):
        """``{model: (poles rad/s, residues m/(N s))}`` of every wheel model at ``speed`` (m/s)."""
        spin = spin_rate(speed, self.r0)
        rot = self._rotating
        eulerian = rot["model"].poles_residues(spin, **rot["switches"])
        if self.rotation["moving_load_path"] == "harmonic":
            axi = rot["axisymmetric"]
            moving = moving_load.moving_poles_residues_axisymmetric(
                axi["frequency"], axi["damping_ratio"], axi["harmonic"], axi["family"], axi["contact_amplitude"], spin)
        else:
            moving = rotating_models(self.modes, self.mesh, self.rotation, speed)["moving_load"]
        return {"stationary": self.stationary, "moving_load": moving, "eulerian": eulerian}


def linear_contact(study):
    """The point contact of a study at its wheel load and creepages, linearised
    (:class:`interaction.stability.LinearisedContact`)."""
    contact = ContactParams.from_mapping(study["contact"], "contact")
    material, hertz = contact_hertz(study)
    point = PointContact(material=material, friction=contact.to_friction(), hertz=hertz, kind="transient",
                         speed=study["operating"]["speed"], time_step=study["time"]["time_step"])
    creepage = (contact.longitudinal_creepage, contact.lateral_creepage, contact.spin)
    return linearise_point_contact(point, study["operating"]["wheel_load"], creepage)


def screen_study(study, models, rail, names=WHEEL_MODELS):
    """The screen of one configuration for the wheel models ``names``.

    Parameters
    ----------
    study : dict
        The configuration (operating state and contact).
    models : dict
        ``{model: (poles, residues)}`` at the study's speed.
    rail : RationalModel
    names : sequence of str

    Returns
    -------
    dict
        ``{model: result of interaction.stability.screen}``.
    """
    contact = linear_contact(study)
    speed = study["operating"]["speed"]
    min_share = study["map"]["min_share"]
    return {name: screen(*models[name], rail, contact, speed, min_share) for name in names}
