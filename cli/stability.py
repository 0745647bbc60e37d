"""``pipeline.py stability``: the linear stability screen of a study's configuration.

Builds what is stale of the structures the screen needs in ``--out`` (the wheel's Green's
artefact with its three wheel models at the study's speed, the rail's mesh and the rational fit
of its receptance, ``rail_fit.h5``), linearises the contact at the study's wheel load, friction
and creepages, and prints the growing poles of the wheel-contact-rail loop of every wheel model
(or of the one ``--set simulation.wheel_model=...`` names). The study's ``[sweep]`` is not
expanded: the screen is of the configuration the study file and ``--set`` give.
"""

from __future__ import annotations

import json
import logging

import numpy as np

from interaction.wheel_models import wheel_model_names
from stages.folder import FolderLock, folder_study
from stages.screen import screen_study, structures

logger = logging.getLogger(__name__)

MODEL_KEY = "simulation.wheel_model"
#: Prefixes of the keys the screen reads that no structure it reads depends on: a folder's study
#: may differ there (``contact.geometry`` excepted, see :func:`command`).
SCREEN_KEYS = ("contact.", "simulation.", "sweep.", "report.", "time.duration")


def add_args(parser):
    """Arguments of ``stability``."""
    parser.add_argument("--config", help="study TOML file merged over the defaults (studies/paper.toml)")
    parser.add_argument("--out", default="out", help="folder of the study's artefacts (default: out)")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML); --set simulation.wheel_model=NAME screens that "
                             "wheel model only")
    parser.add_argument("--json", action="store_true", help="print the growing poles as JSON")
    return parser


def _chosen_models(assignments, study):
    named = any(a.split("=", 1)[0].strip() == MODEL_KEY for a in assignments)
    return (study["simulation"]["wheel_model"],) if named else wheel_model_names()


def pole_records(results, models):
    """The growing poles of :func:`stages.screen.screen_study`'s results as plain data, fastest first.

    Returns
    -------
    list of dict
        ``wheel_model``, ``frequency`` (Hz), ``growth_rate`` (1/s) and ``modes``: per
        contributing wheel pole its ``index`` (into the model's poles), open-loop ``frequency``
        (Hz) and ``share`` (-).
    """
    out = []
    for name, result in results.items():
        poles = np.asarray(models[name][0])
        for pole in result["poles"]:
            out.append({"wheel_model": name, "frequency": pole["frequency"], "growth_rate": pole["growth_rate"],
                        "modes": [{"index": k, "frequency": float(poles[k].imag / (2 * np.pi)), "share": share}
                                  for k, share in zip(pole["wheel_modes"], pole["participation"])]})
    out.sort(key=lambda p: -p["growth_rate"])
    return out


def command(args):
    """Run ``stability``; returns the exit status (0)."""
    # the screen's own keys (friction, creepages, wheel model, ...) may differ from the folder's study;
    # what its structures are built from may not
    study, _ = folder_study(args.out, args.config, args.quick, args.assignments, ignore=SCREEN_KEYS,
                            keep=("contact.geometry",), command="stability")
    names = _chosen_models(args.assignments, study)
    # it builds what is stale of the structures, so it holds the folder's lock (stages/folder.py)
    with FolderLock(args.out, "pipeline.py stability"):
        models, rail, point = structures(study, args.out, progress=not getattr(args, "quiet", False))
    results = screen_study(study, models, rail, names, point=point)
    poles = pole_records(results, models)
    if args.json:
        print(json.dumps({"poles": poles}))
        return 0
    print(f"linear stability, wheel on the flexible rail (rail model {rail.band[0]:g}-{rail.band[1]:g} Hz): "
          f"mu = {study['contact']['friction']:g}, eta = {study['contact']['lateral_creepage']:g}, "
          f"v = {study['operating']['speed']:.3g} m/s")
    for name in names:
        growing = [p for p in poles if p["wheel_model"] == name]
        if not growing:
            print(f"  {name}: stable (least damped pole {results[name]['margin']:.1f} 1/s at "
                  f"{results[name]['margin_frequency']:.0f} Hz)")
        for p in growing:
            modes = ", ".join(f"{m['frequency']:.0f} Hz ({m['share']:.2f})" for m in p["modes"])
            print(f"  {name}: {p['frequency']:.0f} Hz grows at {p['growth_rate']:.1f} 1/s; wheel modes {modes}")
    return 0
