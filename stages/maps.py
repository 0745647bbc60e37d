"""Squeal maps: the linear stability screen over a grid of configurations, for every wheel model.

The grid is the study's ``[map.grid]`` (dotted keys -> lists of values; every combination is one
configuration). Configurations with the same wheel share one wheel (``wheel-mesh`` and
``wheel-modes`` built once in ``maps/wheels/<label>``; the rotating models are rebuilt per speed
from its modes, :class:`stages.screen.WheelModels`); those with the same rail and track share one
rail mesh (``maps/rails/<label>``) and, per rail contact position, one rational rail model
(``rail_fit.h5`` for the hand-set contact, ``rail_fit_at_<y>mm.h5`` for the computed one).

The contact of each configuration is the time-domain case's (:func:`stages.cases.case_contact`):
with ``contact.geometry = "profiles"`` it is computed in memory from the profiles at the
configuration's ``operating.lateral_displacement`` (a grid axis like any other), the wheel's
models are made at that point (mode shapes interpolated there, spin over its rolling radius)
and everything is turned into the contact frame (:func:`stages.screen.screen_study`); with
``"manual"`` the hand-set contact (``track.contact_lateral_position``, ``wheel.contact_offset``).

The screen runs in chunks, one per (wheel, rail) pair, each written as its own artefact
``maps/chunks/<wheel>--<rail>.h5``: a rerun computes only the chunks that are missing or stale. Structures and chunks run one by one, on a
local Dask cluster (``jobs > 1``) or on a scheduler (:func:`stages.engine.run_on_dask`).

``maps.h5`` (schema ``maps``) gathers the chunks in grid order: attribute ``keys`` (JSON list of
the grid's dotted keys), ``configuration`` (N, n_keys) the values, ``seconds`` (N,) s of
screening per configuration, ``spin`` (N,) rad/s (the speed over the contact's rolling radius),
``saturation`` (N,) -, and per wheel model a
group with ``margin`` (N,) 1/s (the largest growth rate of the in-band oscillating poles:
squeal is predicted where it is > 0), ``frequency`` (N,) Hz of that pole, ``n_growing`` (N,),
``growth_rate`` and ``pole_frequency`` (N, K) of the K fastest growing poles (NaN padded),
``mode_frequency`` (N, 2) Hz, ``mode_share`` (N, 2) - and ``mode_n`` (N, 2) (nodal diameters of
the stationary wheel's mode nearest in frequency) of the two wheel poles contributing most to the
margin pole; attributes ``run_wall_time`` (s) and ``run_chunks_computed`` of the run that computed
its chunks (a rerun that computes none keeps them). ``maps.md`` (the map study's report) and ``figures/maps.png`` are written next to it (:mod:`stages.maps_report`).
"""

from __future__ import annotations

import json
import logging
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from interaction.wheel_models import wheel_model_names
from squealcore.artefacts import (
    ArtefactError,
    add_dataset,
    canonical_json,
    file_sha256,
    freshness,
    open_artefact,
    params_hash,
    read_dataset,
    write_artefact,
)
from squealcore.errors import InputError
from squealcore.study import get_section
from stages import engine
from stages.cases import case_contact, case_study, expand_sweep, table_size
from stages.screen import (
    WheelModels,
    linear_contact,
    rail_fit_check,
    rail_lateral,
    rail_model,
    read_rail_fit,
    screen_study,
    wheel_point,
)
from stages.wheel import read_mesh, read_modes

logger = logging.getLogger(__name__)

MAPS_SCHEMA, MAPS_VERSION = "maps", 1
CHUNK_SCHEMA, CHUNK_VERSION = "map_chunk", 2  # 2: the contact of the cases (computed from the profiles)
#: Growing poles kept per configuration and wheel model.
N_POLES = 4
#: Wheel stages a map's wheel needs (the rotating models are made per speed from the modes).
WHEEL_STAGES = ("wheel-mesh", "wheel-modes")


#: Most configurations one map may have: planning validates each (about 1 ms) and the screen
#: takes a fraction of a second to seconds per configuration (docs/benchmarks.md); a larger grid
#: is refused with its count (split it, or coarsen an axis).
MAX_CONFIGURATIONS = 20000


def check_grid_size(grid, limit=MAX_CONFIGURATIONS):
    """Refuse a ``[map.grid]`` of more than ``limit`` configurations before any is planned
    (:class:`InputError` naming the count, each key's number of values and the limit)."""
    total, sizes = table_size(grid)
    if total > limit:
        raise InputError("map.grid", f"{total} configurations ({sizes}), more than the {limit} one map takes "
                                     f"(planning alone would take about {total * 0.001:.0f} s, the screen hours): "
                                     "coarsen an axis or split the map into several, each with its own --out")


def grid_configurations(study):
    """The configurations of a study's ``[map.grid]``, in grid order.

    Returns
    -------
    keys : list of str
        The grid's dotted keys (sorted).
    configurations : list of (dict, dict)
        ``(overrides, study)`` per configuration (``itertools.product`` order over ``keys``).

    Raises
    ------
    InputError
        If the grid is empty, lists ``simulation.wheel_model`` (every model is screened),
        non-numeric values or a value the schema refuses, or has more than
        :data:`MAX_CONFIGURATIONS` configurations.
    """
    grid = study["map"]["grid"]
    if not grid:
        raise InputError("map.grid", "is empty: list at least one dotted key with its values, e.g. "
                                     "\"operating.speed\" = [5.0, 10.0]")
    if "simulation.wheel_model" in grid:
        raise InputError("map.grid", "simulation.wheel_model: every wheel model is screened; leave it out")
    for key, values in grid.items():
        if isinstance(values, list) and any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in values):
            raise InputError(f"map.grid.{key}", f"must be a list of numbers, got {values!r}")
    check_grid_size(grid)
    base = {k: v for k, v in study.items() if k != "sweep"}
    out = []
    try:
        expanded = expand_sweep({"sweep": grid})
    except InputError as exc:
        raise InputError(exc.field.replace("sweep.", "map.grid.", 1), exc.message) from None
    for _, overrides in expanded:
        try:
            config = case_study(base, overrides)
        except InputError as exc:
            field = exc.field.replace("sweep.", "map.grid.", 1)
            raise InputError(f"map.grid.{field}" if field in overrides else field, exc.message) from None
        out.append((overrides, config))
    return sorted(grid), out


def _wheel_key(config):
    return canonical_json(config["wheel"])


def _rail_key(config):
    rail_opts = {k: v for k, v in get_section(config, "map").items() if k.startswith("rail_")}
    return canonical_json({"rail": config["rail"], "track": config["track"], "fit": rail_opts})


def _label(overrides, prefixes):
    picked = {k: v for k, v in overrides.items() if k.split(".")[0] in prefixes}
    return engine.variant_label(picked) if picked else "base"


def plan(study, out_dir):
    """The map's structures and chunks.

    Returns
    -------
    dict
        ``keys``, ``configurations`` (list of (overrides, study)), ``wheels`` and ``rails``
        (label -> (folder, study)), ``chunks`` (list of dicts ``label``, ``wheel``, ``rail``,
        ``indices``).
    """
    out_dir = Path(out_dir)
    keys, configurations = grid_configurations(study)
    wheels, rails, chunks = {}, {}, {}
    wheel_labels, rail_labels = {}, {}
    contacts = ContactCache()
    fits = []
    for index, (overrides, config) in enumerate(configurations):
        w = wheel_labels.setdefault(_wheel_key(config), _label(overrides, ("wheel",)))
        r = rail_labels.setdefault(_rail_key(config), _label(overrides, ("rail", "track")))
        wheels.setdefault(w, (out_dir / "maps" / "wheels" / w, config))
        folder = out_dir / "maps" / "rails" / r
        rail = rails.setdefault(r, (folder, config, {}))
        lateral = rail_lateral(config, contacts(config))
        fit = rail[2].setdefault(lateral, str(folder / rail_fit_name(lateral)))
        fits.append(fit)
        chunk = chunks.setdefault((w, r), {"label": f"{w}--{r}", "wheel": w, "rail": r, "indices": []})
        chunk["indices"].append(index)
    return {"keys": keys, "configurations": configurations, "wheels": wheels, "rails": rails,
            "chunks": list(chunks.values()), "rail_fits": fits}


def rail_fit_name(lateral):
    """File name of a map rail's fit at a rail contact position (m; None: the hand-set one)."""
    return "rail_fit.h5" if lateral is None else f"rail_fit_at_{lateral * 1e3:+.3f}mm.h5"


class ContactCache:
    """The contact of each configuration (:func:`stages.cases.case_contact`, computed in memory
    from the profiles; its cost: docs/benchmarks.md), computed once per distinct geometry (the study's sections
    but ``[contact]`` other than its geometry keys and the speed, which the contact geometry
    does not read)."""

    def __init__(self):
        self._points = {}

    def __call__(self, config):
        contact = config["contact"]
        key = canonical_json({**{s: config.get(s) for s in ("wheel", "rail", "track", "geometry")},
                              "operating": {k: v for k, v in config["operating"].items() if k != "speed"},
                              "contact": {k: v for k, v in contact.items()
                                          if k not in ("friction", "lateral_creepage", "longitudinal_creepage",
                                                       "model")}})
        if key not in self._points:
            self._points[key] = case_contact(config)
        return self._points[key]


# --------------------------------------------------------------------------- tasks (run in workers)


def prepare_wheel(payload):
    """Task: bring a map wheel's mesh and modes up to date; returns ``{"label", "seconds"}``."""
    start = time.perf_counter()
    stages = [engine.STAGE_BY_NAME[name] for name in WHEEL_STAGES]
    engine.run_structural(payload["study"], Path(payload["folder"]), stages, progress=False)
    return {"label": payload["label"], "seconds": time.perf_counter() - start}


def prepare_rail(payload):
    """Task: bring a map rail's mesh and its rational models (one per rail contact position,
    ``payload["laterals"]``, m or None) up to date; returns ``{"label", "seconds"}``."""
    start = time.perf_counter()
    folder = Path(payload["folder"])
    engine.run_structural(payload["study"], folder, [engine.STAGE_BY_NAME["rail-mesh"]], progress=False)
    for lateral in payload["laterals"]:
        rail_model(payload["study"], folder / "rail_mesh.h5", folder / rail_fit_name(lateral), lateral)
    return {"label": payload["label"], "seconds": time.perf_counter() - start}


def _pad(values, size):
    out = np.full(size, np.nan)
    out[:min(size, len(values))] = values[:size]
    return out


def compute_chunk(payload):
    """Task: screen the configurations of one chunk and write its artefact.

    Returns
    -------
    dict
        ``label``, ``count`` (configurations), ``seconds`` (wall time of the chunk, s).
    """
    start = time.perf_counter()
    wheel_dir = Path(payload["wheel_dir"])
    modes = read_modes(wheel_dir / "wheel_modes.h5", with_shapes=True)
    mesh = read_mesh(wheel_dir / "wheel_mesh.h5")
    configs = payload["configurations"]
    rails = {path: read_rail_fit(path) for path in sorted(set(payload["rail_fits"]))}
    wheel = WheelModels(modes, mesh, get_section(configs[0][1], "wheel.rotation"))
    contacts = ContactCache()
    stationary_hz = modes["frequency"]
    n = len(configs)
    arrays = {name: {"margin": np.full(n, -np.inf), "frequency": np.full(n, np.nan), "n_growing": np.zeros(n, int),
                     "out_of_band": np.zeros(n, int), "growth_rate": np.full((n, N_POLES), np.nan),
                     "pole_frequency": np.full((n, N_POLES), np.nan), "mode_frequency": np.full((n, 2), np.nan),
                     "mode_share": np.full((n, 2), np.nan), "mode_n": np.full((n, 2), -1, int)}
              for name in wheel_model_names()}
    seconds, spin, saturation = np.zeros(n), np.zeros(n), np.zeros(n)
    by_state = {}
    for row, (_, config) in enumerate(configs):
        t0 = time.perf_counter()
        speed = config["operating"]["speed"]
        point = contacts(config)
        at = wheel_point(config, point)
        state = (speed, None if at is None else (at.wheel_lateral, at.rolling_radius))
        if state not in by_state:
            by_state[state] = wheel.at(speed, at)
        models = by_state[state]
        contact = linear_contact(config, point)
        results = screen_study(config, models, rails[payload["rail_fits"][row]], point=point, contact=contact,
                               pole_modes=False)
        spin[row] = wheel.spin(speed, at)
        for name, result in results.items():
            a = arrays[name]
            a["margin"][row] = result["margin"]
            a["frequency"][row] = result["margin_frequency"]
            a["n_growing"][row] = len(result["poles"])
            a["out_of_band"][row] = result["out_of_band"]
            a["growth_rate"][row] = _pad([p["growth_rate"] for p in result["poles"]], N_POLES)
            a["pole_frequency"][row] = _pad([p["frequency"] for p in result["poles"]], N_POLES)
            poles = np.asarray(models[name][0])
            top = result["margin_modes"][:2]
            hz = [float(poles[k].imag / (2 * np.pi)) for k in top]
            a["mode_frequency"][row] = _pad(hz, 2)
            a["mode_share"][row] = _pad(result["margin_shares"][:2], 2)
            for j, f in enumerate(hz):
                a["mode_n"][row, j] = int(modes["nodal_diameters"][np.argmin(np.abs(stationary_hz - f))])
        saturation[row] = contact.saturation
        seconds[row] = time.perf_counter() - t0
    with write_artefact(payload["output"], CHUNK_SCHEMA, CHUNK_VERSION, payload["params_sha256"],
                        payload["inputs"]) as f:
        add_dataset(f, "index", np.array([i for i, _ in configs], dtype=np.int64), "")
        add_dataset(f, "seconds", seconds, "s")
        add_dataset(f, "spin", spin, "rad/s")
        add_dataset(f, "saturation", saturation, "1")
        for name, a in arrays.items():
            g = f.create_group(name)
            for key, value in a.items():
                unit = {"margin": "1/s", "growth_rate": "1/s", "frequency": "Hz", "pole_frequency": "Hz",
                        "mode_frequency": "Hz"}.get(key, "")
                add_dataset(g, key, value, unit)
    return {"label": payload["label"], "count": n, "seconds": time.perf_counter() - start}


# --------------------------------------------------------------------------- running


def run_tasks(function, payloads, keys, collect, jobs=1, scheduler=None):
    """Run ``function`` on every payload here (``jobs == 1``) or on Dask; ``collect`` each result."""
    if scheduler is None and jobs <= 1:
        for payload in payloads:
            collect(function(payload))
    elif payloads:
        engine.run_on_dask(function, payloads, keys, collect, jobs, scheduler)


#: Study sections the screen of a configuration reads (with the scalar options of ``[map]``).
SCREEN_SECTIONS = ("wheel", "rail", "track", "operating", "contact", "geometry")


def screen_params(config):
    """What a configuration's screen depends on, hashed into its chunk: the sections of
    :data:`SCREEN_SECTIONS` and ``[map]`` without the grid (so that another report option, or
    another value elsewhere in the grid, leaves the chunk fresh)."""
    return {**{s: config[s] for s in SCREEN_SECTIONS}, "map": get_section(config, "map")}


def _chunk_payload(study, out_dir, chunk, layout):
    wheel_dir = layout["wheels"][chunk["wheel"]][0]
    configs = [(i, layout["configurations"][i][1]) for i in chunk["indices"]]
    fits = [layout["rail_fits"][i] for i in chunk["indices"]]
    params_sha = params_hash({"configurations": [[i, screen_params(c)] for i, c in configs],
                              "version": CHUNK_VERSION})
    inputs = {"wheel_modes.h5": file_sha256(wheel_dir / "wheel_modes.h5")}
    inputs.update({Path(fit).name: file_sha256(fit) for fit in sorted(set(fits))})
    return {"label": chunk["label"], "output": str(Path(out_dir) / "maps" / "chunks" / f"{chunk['label']}.h5"),
            "wheel_dir": str(wheel_dir), "rail_fits": fits, "configurations": configs,
            "params_sha256": params_sha, "inputs": inputs}


def map_status(study, out_dir):
    """Freshness of a map's cached artefacts in ``out_dir``, as ``status`` reports them (nothing is built).

    Returns
    -------
    list of (str, bool, str)
        ``(name, fresh, reason)`` rows: per map wheel its structural stages (``map-wheel:<label>:<stage>``),
        per map rail its mesh and each rail fit (``map-rail:<label>:<file>``), per chunk
        (``map-chunk:<label>``) and ``maps.h5`` (stale when a chunk is). Empty when the study has no
        ``[map.grid]`` or the folder holds no map (no ``maps/``).
    """
    out_dir = Path(out_dir)
    if not (out_dir / "maps").is_dir() or not study.get("map", {}).get("grid"):
        return []
    layout = plan(study, out_dir)
    rows = []
    for label, (folder, config) in layout["wheels"].items():
        for name in WHEEL_STAGES:
            fresh, reason, _, _ = engine.inspect(engine.STAGE_BY_NAME[name], config, folder)
            rows.append((f"map-wheel:{label}:{name}", fresh, reason))
    for label, (folder, config, fits) in layout["rails"].items():
        fresh, reason, _, _ = engine.inspect(engine.STAGE_BY_NAME["rail-mesh"], config, folder)
        rows.append((f"map-rail:{label}:rail-mesh", fresh, reason))
        for lateral, path in fits.items():
            fresh, reason = rail_fit_check(config, folder / "rail_mesh.h5", path, lateral)
            rows.append((f"map-rail:{label}:{Path(path).name}", fresh, reason))
    structures_fresh = all(fresh for _, fresh, _ in rows)
    for chunk in layout["chunks"]:
        payload = _chunk_payload(study, out_dir, chunk, layout) if structures_fresh else None
        if payload is None:
            fresh, reason = False, "upstream stale"
        else:
            fresh, reason = freshness(payload["output"], CHUNK_SCHEMA, CHUNK_VERSION, payload["params_sha256"],
                                      payload["inputs"])
        rows.append((f"map-chunk:{chunk['label']}", fresh, reason))
    all_fresh = all(fresh for _, fresh, _ in rows)
    maps_file = out_dir / "maps.h5"
    rows.append(("maps.h5", all_fresh and maps_file.exists(),
                 "" if all_fresh and maps_file.exists() else ("missing" if all_fresh else "upstream stale")))
    return rows


def run_map(study, out_dir, jobs=1, scheduler=None, progress=True, record=None):
    """Build the stale structures and chunks of a map, then ``maps.h5``, its figures and ``maps.md``.

    Parameters
    ----------
    study : dict
        The validated study with its ``[map.grid]``.
    out_dir : Path
        Output folder.
    jobs : int
        Local worker processes (1: in this process).
    scheduler : str, optional
        Address of a Dask scheduler.
    progress : bool
        Show progress bars (structures; configurations done / total with the time left).
    record : list, optional
        Receives the label of every chunk as soon as it is written.

    Returns
    -------
    dict
        ``chunks_computed`` (int), ``configurations`` (int), ``seconds`` (wall time, s),
        ``path`` (Path of maps.h5).
    """
    from stages.maps_report import write_report  # lazy: matplotlib (~0.5 s) only when a map is written

    start = time.perf_counter()
    out_dir = Path(out_dir)
    engine.remove_stale_temporaries(out_dir)
    layout = plan(study, out_dir)
    structure_tasks = []
    for label, (folder, config) in layout["wheels"].items():
        structure_tasks.append((prepare_wheel, {"label": label, "folder": str(folder), "study": config},
                                f"map-wheel-{label}"))
    for label, (folder, config, fits) in layout["rails"].items():
        structure_tasks.append((prepare_rail, {"label": label, "folder": str(folder), "study": config,
                                               "laterals": list(fits)}, f"map-rail-{label}"))
    with tqdm(total=len(structure_tasks), desc="map structures", unit="structure", disable=not progress,
              leave=False, dynamic_ncols=True) as bar:
        for function in (prepare_wheel, prepare_rail):
            tasks = [(p, k) for f, p, k in structure_tasks if f is function]
            run_tasks(function, [p for p, _ in tasks], [k for _, k in tasks], lambda r: bar.update(), jobs, scheduler)
    pending = []
    for chunk in layout["chunks"]:
        payload = _chunk_payload(study, out_dir, chunk, layout)
        fresh, reason = freshness(payload["output"], CHUNK_SCHEMA, CHUNK_VERSION, payload["params_sha256"],
                                  payload["inputs"])
        if fresh:
            logger.info("chunk %s fresh", chunk["label"])
        else:
            logger.info("chunk %s: %s", chunk["label"], reason)
            pending.append(payload)
    total = len(layout["configurations"])
    done = total - sum(len(p["configurations"]) for p in pending)
    with tqdm(total=total, initial=done, desc="map", unit="config", disable=not progress, leave=False,
              dynamic_ncols=True, smoothing=0.1) as bar:
        def collect(result):
            bar.update(result["count"])
            logger.info("chunk %s: %d configurations in %.1f s", result["label"], result["count"], result["seconds"])
            if record is not None:
                record.append(result["label"])

        run_tasks(compute_chunk, pending, [f"map-chunk-{p['label']}-{p['params_sha256'][:8]}" for p in pending],
                  collect, jobs, scheduler)
    seconds = time.perf_counter() - start
    run = {"wall_time": seconds, "chunks_computed": len(pending)}
    if not pending:  # nothing computed: maps.h5 keeps the cost of the run that computed its chunks
        try:
            previous = read_maps(out_dir / "maps.h5")
            run = {"wall_time": previous["run_wall_time"], "chunks_computed": previous["run_chunks_computed"]}
        except ArtefactError:
            pass
    path = gather(study, out_dir, layout, run)
    write_report(study, out_dir, read_maps(path))
    return {"chunks_computed": len(pending), "configurations": total, "seconds": seconds, "path": path}


def gather(study, out_dir, layout, run):
    """Write ``maps.h5`` from the chunk artefacts (atomically); returns its path. ``run``
    (``wall_time`` s, ``chunks_computed``) describes the run that computed the chunks (attributes
    ``run_wall_time``, ``run_chunks_computed``: the cost of the run, not part of the results; a
    rerun that computes nothing keeps them)."""
    out_dir = Path(out_dir)
    keys = layout["keys"]
    total = len(layout["configurations"])
    chunk_paths = [out_dir / "maps" / "chunks" / f"{c['label']}.h5" for c in layout["chunks"]]
    data = None
    for path in chunk_paths:
        with open_artefact(path, CHUNK_SCHEMA, CHUNK_VERSION) as f:
            index = read_dataset(f, "index", "", (None,))
            if data is None:
                data = {"seconds": np.zeros(total), "spin": np.zeros(total), "saturation": np.zeros(total)}
                for name in wheel_model_names():
                    for key, dset in f[name].items():
                        data[f"{name}/{key}"] = np.zeros((total,) + dset.shape[1:], dset.dtype)
            for key in data:
                data[key][index] = f[key][()]
    configuration = np.array([[float(overrides[k]) for k in keys] for overrides, _ in layout["configurations"]])
    inputs = {f"chunks/{p.name}": file_sha256(p) for p in chunk_paths}
    path = out_dir / "maps.h5"
    units = {"seconds": "s", "spin": "rad/s", "margin": "1/s", "growth_rate": "1/s", "frequency": "Hz",
             "pole_frequency": "Hz", "mode_frequency": "Hz"}
    with write_artefact(path, MAPS_SCHEMA, MAPS_VERSION, params_hash({"keys": keys, "grid": study["map"]["grid"]}),
                        inputs) as f:
        f.attrs["keys"] = json.dumps(keys)
        f.attrs["models"] = json.dumps(list(wheel_model_names()))
        f.attrs["run_wall_time"] = float(run["wall_time"])
        f.attrs["run_chunks_computed"] = int(run["chunks_computed"])
        add_dataset(f, "configuration", configuration, "")
        for key, value in data.items():
            add_dataset(f, key, value, units.get(key.split("/")[-1], "1" if key == "saturation" else ""))
    return path


def read_maps(path):
    """``maps.h5`` as a dict: ``keys``, ``configuration`` (N, n_keys) and every dataset by name."""
    with open_artefact(path, MAPS_SCHEMA, MAPS_VERSION) as f:
        out = {"keys": json.loads(f.attrs["keys"]), "models": json.loads(f.attrs["models"]),
               "run_wall_time": float(f.attrs["run_wall_time"]),
               "run_chunks_computed": int(f.attrs["run_chunks_computed"])}
        out["configuration"] = read_dataset(f, "configuration", "")
        for name in ("seconds", "spin", "saturation"):
            out[name] = read_dataset(f, name)
        for model in out["models"]:
            for key in f[model]:
                out[f"{model}/{key}"] = read_dataset(f[model], key)
    return out
