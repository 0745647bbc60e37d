"""Squeal risk over a curve (issue 35 item 3): the half-space screen of every wheel of a curving bogie.

For every curve radius R, vehicle speed V and friction coefficient μ of a grid, the steady curving
of the study's ``[curve]`` bogie is solved (:func:`curving.solve_bogie` on the study's wheel and
rail profiles, :func:`curving.profile_geometry`; the bogie's wheelbase, axle load, cant,
suspension and flange friction from ``[curve]``, :func:`curving_params`) and each of its four
wheels is screened (:func:`stages.screen.screen_study`) for the three wheel models with its own
operating point (:func:`curving.operating.wheel_operating_points`: creepages ξ, η, φ, normal force
and contact angle of its tread contact), the contact linearised by the half-space model
(``contact.model = "halfspace"`` whatever the study says; :mod:`contact.halfspace.linearise`).

What the per-wheel operating point changes, and what it does not (the limitation of this map):

* changed: the creepages (ξ, η and the curving's spin φ, which includes the curve's yaw rate),
  the tread's normal force (Hertz's patch and the half-space grid follow it), the contact angle
  (the wheel's and the rail's receptances are turned into that contact frame, the rail's by the
  study's inclination offset), the speed and the friction coefficient;
* kept: the structures, i.e. the wheel's modes and Green's functions and the rail's receptance
  are those at the study's contact position (``wheel_greens.h5``, the rail fit), and so are the
  contact's curvatures; the flange contact of a flanging wheel is not in the loop (the screen
  has one contact, the tread's). A wheel whose curving contact lies elsewhere on its profile
  (e.g. the flanging outer wheels, the inner wheels shifted by the wheelset's lateral
  displacement) is screened with the receptances of the study's position.

Configurations whose curving has no equilibrium (:class:`curving.CurvingError`, e.g. a speed far
above the curve's balancing speed) are recorded as not solved (NaN).

``curve_map.h5`` (schema ``curve_map``) in the output folder: ``radius`` (nR,) m, ``speed`` (nV,)
m/s, ``friction`` (nμ,) -, attributes ``wheels`` and ``models`` (JSON lists), ``run_wall_time`` (s);
per configuration and wheel (nR, nV, nμ, 4): ``solved`` (0/1: the curving found an equilibrium),
``screened`` (0/1: the wheel's screen ran; a contact solver that does not converge is logged as a
WARNING and leaves its margins NaN), ``lateral_creepage``,
``longitudinal_creepage`` (-), ``spin`` (1/m), ``normal_force`` (N), ``contact_angle`` (rad),
``flange_contact`` (0/1), ``friction_use`` (-), ``saturation`` (-, of the linearised contact), and
per wheel model a group with ``margin`` (1/s; squeal predicted where > 0), ``frequency`` (Hz) and
``n_growing``; ``seconds`` (nR, nV, nμ) of each configuration's curving and screens, and
``curving_seconds`` of its curving alone. The figure
``figures/curve_map.png`` and the summary ``curve_map.md`` are written beside it
(:mod:`stages.curve_map_report`). Run with :func:`curve_map` or ``python pipeline.py curve-map`` (cli/curve_map.py).
"""

from __future__ import annotations

import dataclasses
import json
import logging
import math
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from curving import CurvingError, CurvingParams, profile_geometry, solve_bogie
from curving.operating import WHEEL_LABELS, wheel_operating_points
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
from squealcore.errors import InputError
from squealcore.study import get_section
from stability.rational import RationalModel
from stages.cases import case_contact, case_study
from stages.curve_params import CurveParams
from stages.maps import run_tasks
from stages.screen import WheelModels, linear_contact, screen_study, structures, wheel_point
from stages.wheel import read_mesh, read_modes

logger = logging.getLogger(__name__)

__all__ = ["CURVE_MAP_SCHEMA", "DEFAULT_RADII", "DEFAULT_SPEEDS", "DEFAULT_FRICTIONS", "curve_map", "read_curve_map",
           "curving_params", "curving_geometry", "wheel_contact_point", "wheel_study", "screen_wheel"]

CURVE_MAP_SCHEMA, CURVE_MAP_VERSION = "curve_map", 2  # 2: screened (a wheel screen that failed)
#: Curve radii of the default map, m: 16 from 50 to 1000 m, evenly spaced in log R.
DEFAULT_RADII = tuple(float(r) for r in np.round(np.geomspace(50.0, 1000.0, 16), 1))
#: Vehicle speeds of the default map, m/s (18, 36 and 54 km/h).
DEFAULT_SPEEDS = (5.0, 10.0, 15.0)
#: Friction coefficients of the default map: a dry and a wet or lubricated rail.
DEFAULT_FRICTIONS = (0.3, 0.5)
#: Most configurations (radius x speed x friction) one map may have.
MAX_CONFIGURATIONS = 5000
#: The wheel-model keys of the result (the registry's names, in its order).
MODELS = tuple(wheel_model_names())


# --------------------------------------------------------------------------- one wheel


def curving_params(study, radius, speed, friction, geometry):
    """The :class:`curving.CurvingParams` of the study's ``[curve]`` bogie (wheelbase, axle load,
    centre of gravity, cant, rigid or on its primary suspension, flange friction:
    :class:`stages.curve_params.CurveParams`, a metro bogie by default) at the map's radius (m),
    speed (m/s) and friction coefficient (-, of the tread contacts; the flange's too unless
    ``curve.flange_friction`` sets it)."""
    curve = CurveParams.from_mapping(get_section(study, "curve"), "curve")
    rigid = curve.rigid_bogie
    return CurvingParams(radius=float(radius), speed=float(speed), cant=curve.cant, wheelbase=curve.wheelbase,
                         axle_load=curve.axle_load, centre_of_gravity_height=curve.centre_of_gravity_height,
                         longitudinal_stiffness=math.inf if rigid else curve.longitudinal_stiffness,
                         lateral_stiffness=math.inf if rigid else curve.lateral_stiffness,
                         axlebox_half_spacing=curve.axlebox_half_spacing, friction=float(friction),
                         flange_friction=None if curve.flange_friction < 0.0 else curve.flange_friction,
                         geometry=geometry)


def curving_geometry(study):
    """The contact geometry of the study's wheel and rail profiles at ``curve.track_gauge``
    (:func:`curving.profile_geometry`)."""
    curve = CurveParams.from_mapping(get_section(study, "curve"), "curve")
    return profile_geometry(study, track_gauge=curve.track_gauge)


def wheel_study(study, operating, friction):
    """The study of one wheel's screen: the curve's speed, friction and the wheel's creepages
    (``contact.spin`` too, read for a hand-set contact), the half-space contact model, no
    ``[curve]`` feeding (the map sets the wheel's values itself); validated
    (:func:`stages.cases.case_study`)."""
    return case_study(study, {"curve.enabled": False, "operating.speed": float(operating.speed),
                              "contact.friction": float(friction), "contact.model": "halfspace",
                              "contact.longitudinal_creepage": float(operating.longitudinal_creepage),
                              "contact.lateral_creepage": float(operating.lateral_creepage),
                              "contact.spin": float(operating.spin)})


def wheel_contact_point(point, operating):
    """The study's contact ``point`` (a ``ContactPoint``) with the wheel's normal force, contact
    angle (the rail's section angle moved by the same amount) and spin (``point.spin = -φ``, as
    :func:`stages.cases.imposed_creepage` reads a computed contact's); its position, rolling
    radius and curvatures are the study's (module docstring)."""
    turn = float(operating.contact_angle) - point.contact_angle
    return dataclasses.replace(point, normal_force=float(operating.normal_force),
                               contact_angle=float(operating.contact_angle),
                               rail_section_angle=point.rail_section_angle + turn, spin=-float(operating.spin))


def screen_wheel(study, point, operating, friction, models, rail):
    """The half-space screen of one wheel of a curving bogie.

    Parameters
    ----------
    study : dict
        The map's study.
    point : contact_geometry.ContactPoint
        The study's contact (the structures').
    operating : curving.operating.WheelOperatingPoint
    friction : float
        μ (-).
    models : dict
        ``{model: (poles, residues)}`` of the wheel at ``operating.speed`` and ``point``, upright.
    rail : RationalModel
        The rail at the study's contact, upright.

    Returns
    -------
    (dict, LinearisedContact)
        ``{model: result of stability.screen.screen}`` and the linearised contact.
    """
    config = wheel_study(study, operating, friction)
    at = wheel_contact_point(point, operating)
    contact = linear_contact(config, at)
    return screen_study(config, models, rail, point=at, contact=contact, pole_modes=False), contact


# --------------------------------------------------------------------------- tasks (run in workers)

#: Per-wheel quantities of the result and their units.
WHEEL_FIELDS = {"solved": "", "screened": "", "lateral_creepage": "1", "longitudinal_creepage": "1", "spin": "1/m",
                "normal_force": "N", "contact_angle": "rad", "flange_contact": "", "friction_use": "1",
                "saturation": "1"}
MODEL_FIELDS = {"margin": "1/s", "frequency": "Hz", "n_growing": ""}


def _rail_payload(rail):
    return {"poles": rail.poles, "residues": rail.residues, "direct": rail.direct, "proportional": rail.proportional,
            "band": list(rail.band)}


def compute_chunk(payload):
    """Task: the curving and the four wheels' screens of the configurations of one speed.

    Returns
    -------
    dict
        ``rows``: per configuration ``(index, seconds, curving seconds, wheels)``, ``wheels`` a list of four dicts
        (``WHEEL_FIELDS`` and per model ``MODEL_FIELDS``) or None when the curving failed;
        ``label``, ``count``, ``seconds``.
    """
    start = time.perf_counter()
    study = payload["study"]
    out = Path(payload["out"])
    point = case_contact(study, out / "contact_geometry.h5")
    r = payload["rail"]
    rail = RationalModel(np.asarray(r["poles"]), np.asarray(r["residues"]), np.asarray(r["direct"]),
                         np.asarray(r["proportional"]), tuple(r["band"]))
    wheel = WheelModels(read_modes(out / "wheel_modes.h5", with_shapes=True), read_mesh(out / "wheel_mesh.h5"),
                        get_section(study, "wheel.rotation"))
    geometry = curving_geometry(study)
    speed = payload["speed"]
    models = wheel.at(speed, wheel_point(study, point))
    rows = []
    for index, radius, friction in payload["configurations"]:
        t0 = time.perf_counter()
        try:
            result = solve_bogie(curving_params(study, radius, speed, friction, geometry))
        except CurvingError as exc:
            logger.info("curve map: R = %g m, V = %g m/s, mu = %g: %s", radius, speed, friction, exc)
            rows.append((index, time.perf_counter() - t0, time.perf_counter() - t0, None))
            continue
        curving_seconds = time.perf_counter() - t0
        operating = wheel_operating_points(result)
        wheels = []
        for label in WHEEL_LABELS:
            op = operating[label]
            record = {"solved": 1, "screened": 1, "lateral_creepage": op.lateral_creepage,
                      "longitudinal_creepage": op.longitudinal_creepage, "spin": op.spin,
                      "normal_force": op.normal_force, "contact_angle": op.contact_angle,
                      "flange_contact": int(op.flange_contact), "friction_use": op.friction_use}
            try:
                results, contact = screen_wheel(study, point, op, friction, models, rail)
            except (InputError, RuntimeError) as exc:  # e.g. a contact solver's NotConvergedError
                logger.warning("curve map: R = %g m, V = %g m/s, mu = %g, %s not screened: %s", radius, speed,
                               friction, label, exc)
                record["screened"] = 0
                wheels.append(record)
                continue
            record["saturation"] = contact.saturation
            for name in MODELS:
                record[f"{name}/margin"] = results[name]["margin"]
                record[f"{name}/frequency"] = results[name]["margin_frequency"]
                record[f"{name}/n_growing"] = len(results[name]["poles"])
            wheels.append(record)
        rows.append((index, time.perf_counter() - t0, curving_seconds, wheels))
    return {"label": payload["label"], "rows": rows, "count": len(rows), "seconds": time.perf_counter() - start}


# --------------------------------------------------------------------------- the map


def _axis(name, values, low, high, low_open, unit):
    try:
        values = [float(v) for v in values]
    except (TypeError, ValueError):
        raise InputError(f"curve_map.{name}", f"must be a list of numbers, got {values!r}") from None
    if not values:
        raise InputError(f"curve_map.{name}", "is empty: give at least one value")
    for v in values:
        if not math.isfinite(v) or v < low or v > high or (low_open and v == low):
            interval = f"{'(' if low_open else '['}{low:g}, {high:g}]"
            raise InputError(f"curve_map.{name}", f"{v!r} {unit} is outside {interval}")
    if len(set(values)) != len(values):
        raise InputError(f"curve_map.{name}", f"lists a value twice: {values}")
    return tuple(sorted(values))


def check_grid(radii, speeds, frictions):
    """The grid's three axes, validated and sorted (:class:`InputError` naming ``curve_map.<axis>``):
    radii in [20, 1e5] m, speeds in (0, 100] m/s, frictions in (0, 1], at most
    :data:`MAX_CONFIGURATIONS` configurations."""
    radii = _axis("radii", radii, 20.0, 1e5, False, "m")
    speeds = _axis("speeds", speeds, 0.0, 100.0, True, "m/s")
    frictions = _axis("frictions", frictions, 0.0, 1.0, True, "-")
    total = len(radii) * len(speeds) * len(frictions)
    if total > MAX_CONFIGURATIONS:
        raise InputError("curve_map.radii", f"{total} configurations ({len(radii)} radii x {len(speeds)} speeds x "
                                            f"{len(frictions)} frictions), more than the {MAX_CONFIGURATIONS} one map "
                                            "takes: coarsen an axis")
    return radii, speeds, frictions


def _chunks(radii, speeds, frictions, jobs):
    """Payload skeletons: per speed (the wheel models are made once per chunk), split so that every
    worker gets a few chunks."""
    per_speed = [(i, k) for i in range(len(radii)) for k in range(len(frictions))]
    pieces = max(1, math.ceil(3 * max(jobs, 1) / len(speeds))) if jobs > 1 else 1
    size = max(1, math.ceil(len(per_speed) / pieces))
    out = []
    for j, speed in enumerate(speeds):
        for c in range(0, len(per_speed), size):
            configs = [((i, j, k), radii[i], frictions[k]) for i, k in per_speed[c:c + size]]
            out.append({"label": f"v{speed:g}-{c // size}", "speed": speed, "configurations": configs})
    return out


def _params(study, radii, speeds, frictions):
    sections = {s: get_section(study, s) for s in ("wheel", "rail", "track", "operating", "contact", "geometry",
                                                   "time", "simulation", "curve")}
    return {"sections": sections, "map": get_section(study, "map"), "radii": list(radii), "speeds": list(speeds),
            "frictions": list(frictions), "version": CURVE_MAP_VERSION}


def curve_map(study, out, radii=DEFAULT_RADII, speeds=DEFAULT_SPEEDS, frictions=DEFAULT_FRICTIONS, progress=True,
              jobs=1, scheduler=None):
    """The squeal-risk map of a curve over radius x speed x friction, every wheel of the bogie.

    Parameters
    ----------
    study : dict
        A validated study (its structures are built in ``out`` if missing or stale).
    out : path-like
        Output folder: the structures, ``curve_map.h5``, ``curve_map.md``, ``figures/curve_map.png``.
    radii, speeds, frictions : sequence of float
        Curve radii (m, in [20, 1e5]), vehicle speeds (m/s, in (0, 100]) and friction coefficients
        (-, in (0, 1]).
    progress : bool
        Show progress bars (structures; configurations done / total).
    jobs : int
        Local worker processes (1: in this process).
    scheduler : str, optional
        Address of a Dask scheduler (:func:`stages.engine.run_on_dask`).

    Returns
    -------
    dict
        ``path`` (curve_map.h5), ``configurations`` (radius x speed x friction), ``wheel_screens``
        (configurations x 4), ``seconds`` (wall time, s), ``computed`` (False when curve_map.h5
        was fresh).
    """
    from stages.curve_map_report import write_report  # lazy: matplotlib (~0.5 s) only when a map is written

    start = time.perf_counter()
    radii, speeds, frictions = check_grid(radii, speeds, frictions)
    out = Path(out)
    _, rail, _ = structures(study, out, progress)
    path = out / "curve_map.h5"
    params_sha = params_hash(_params(study, radii, speeds, frictions))
    inputs = {name: file_sha256(out / name) for name in ("wheel_modes.h5", "wheel_mesh.h5", "contact_geometry.h5")}
    fresh, reason = freshness(path, CURVE_MAP_SCHEMA, CURVE_MAP_VERSION, params_sha, inputs)
    shape = (len(radii), len(speeds), len(frictions))
    if fresh:
        logger.info("curve map fresh: %s", path)
        data = read_curve_map(path)
        write_report(study, out, data)
        return {"path": path, "configurations": int(np.prod(shape)), "wheel_screens": 4 * int(np.prod(shape)),
                "seconds": time.perf_counter() - start, "computed": False}
    logger.info("curve map: computing (%s)", reason)
    wheel_arrays = {key: np.full(shape + (4,), np.nan) for key in WHEEL_FIELDS}
    wheel_arrays["solved"][:] = 0
    wheel_arrays["screened"][:] = 0
    for name in MODELS:
        for key in MODEL_FIELDS:
            wheel_arrays[f"{name}/{key}"] = np.full(shape + (4,), np.nan)
    seconds, curving_seconds = np.zeros(shape), np.zeros(shape)
    payloads = []
    for chunk in _chunks(radii, speeds, frictions, jobs if scheduler is None else max(jobs, 2)):
        payloads.append({**chunk, "study": study, "out": str(out), "rail": _rail_payload(rail)})
    total = int(np.prod(shape))
    with tqdm(total=total, desc="curve map", unit="config", disable=not progress, leave=False, dynamic_ncols=True,
              smoothing=0.1) as bar:
        def collect(result):
            for index, dt, dt_curving, wheels in result["rows"]:
                index = tuple(index)
                seconds[index] = dt
                curving_seconds[index] = dt_curving
                for w, record in enumerate(wheels or ()):
                    for key, value in record.items():
                        wheel_arrays[key][index + (w,)] = value
            bar.update(result["count"])
            logger.info("curve map chunk %s: %d configurations in %.1f s", result["label"], result["count"],
                        result["seconds"])

        run_tasks(compute_chunk, payloads, [f"curve-map-{p['label']}-{params_sha[:8]}" for p in payloads], collect,
                  jobs, scheduler)
    wall = time.perf_counter() - start
    with write_artefact(path, CURVE_MAP_SCHEMA, CURVE_MAP_VERSION, params_sha, inputs,
                        config={"radii": list(radii), "speeds": list(speeds), "frictions": list(frictions)}) as f:
        f.attrs["wheels"] = json.dumps(list(WHEEL_LABELS))
        f.attrs["models"] = json.dumps(list(MODELS))
        f.attrs["run_wall_time"] = float(wall)
        add_dataset(f, "radius", np.array(radii), "m")
        add_dataset(f, "speed", np.array(speeds), "m/s")
        add_dataset(f, "friction", np.array(frictions), "1")
        add_dataset(f, "seconds", seconds, "s")
        add_dataset(f, "curving_seconds", curving_seconds, "s")
        for key, unit in WHEEL_FIELDS.items():
            add_dataset(f, key, wheel_arrays[key], unit)
        for name in MODELS:
            g = f.create_group(name)
            for key, unit in MODEL_FIELDS.items():
                add_dataset(g, key, wheel_arrays[f"{name}/{key}"], unit)
    data = read_curve_map(path)
    write_report(study, out, data)
    return {"path": path, "configurations": total, "wheel_screens": 4 * total, "seconds": wall, "computed": True}


def read_curve_map(path):
    """``curve_map.h5`` as a dict: ``radius``, ``speed``, ``friction``, ``wheels``, ``models``,
    ``run_wall_time``, ``seconds`` and every per-wheel dataset (``"<model>/margin"`` etc.)."""
    with open_artefact(path, CURVE_MAP_SCHEMA, CURVE_MAP_VERSION) as f:
        data = {"wheels": json.loads(f.attrs["wheels"]), "models": json.loads(f.attrs["models"]),
                "run_wall_time": float(f.attrs["run_wall_time"])}
        for key in ("radius", "speed", "friction", "seconds", "curving_seconds", *WHEEL_FIELDS):
            data[key] = read_dataset(f, key)
        for name in data["models"]:
            for key in f[name]:
                data[f"{name}/{key}"] = read_dataset(f[name], key)
    return data


# --------------------------------------------------------------------------- command line
