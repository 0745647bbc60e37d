"""The ``curve`` command: ``python pipeline.py curve --radius R --speed V [--cant H] [--config F] [--set k=v] [--json]``.

Solves the quasi-static steady curving of the study's ``[curve]`` bogie on its wheel and rail
profiles (:func:`stages.curve.study_curve`) and prints every wheel's operating point in the squeal
study's conventions (:mod:`curving.operating`): creepages, normal force, contact positions and
angle, flange contact. ``--radius``, ``--speed`` and ``--cant`` set ``curve.radius``,
``curve.speed`` and ``curve.cant`` (without ``--speed``: ``curve.speed``, or the study's
``operating.speed``). Nothing is written. ``--json`` prints one JSON object (SI units):
``{"radius", "speed", "cant", "feeds": the wheel curve.wheel names, "loads", "wheelsets",
"residuals", "wheels": {label: WheelOperatingPoint as a dict}}``.
"""

from __future__ import annotations

import json
import sys

from stages.config import load_study
from stages.curve import study_curve

__all__ = ["add_args", "command", "format_points"]

#: Rows of the table: (label, WheelOperatingPoint attribute, scale, format).
ROWS = (("longitudinal creepage xi (%)", "longitudinal_creepage", 100.0, ".3f"),
        ("lateral creepage eta (%)", "lateral_creepage", 100.0, ".3f"),
        ("spin phi (1/m)", "spin", 1.0, ".4f"),
        ("normal force of the tread (kN)", "normal_force", 1e-3, ".2f"),
        ("wheel load (kN)", "wheel_load", 1e-3, ".2f"),
        ("wheel displacement on the rail (mm)", "wheel_displacement", 1e3, ".3f"),
        ("contact on the wheel from the flange back (mm)", "wheel_lateral", 1e3, ".2f"),
        ("contact on the rail from its centre line (mm)", "rail_lateral", 1e3, ".2f"),
        ("contact angle (rad)", "contact_angle", 1.0, ".4f"),
        ("rolling radius (mm)", "rolling_radius", 1e3, ".2f"),
        ("angle of attack (mrad)", "angle_of_attack", 1e3, ".3f"),
        ("flange contact", "flange_contact", None, ""),
        ("flange force (kN)", "flange_force", 1e-3, ".2f"),
        ("friction use |F|/(mu N)", "friction_use", 1.0, ".3f"))


def add_args(parser):
    """Arguments of ``curve``."""
    parser.add_argument("--radius", type=float, help="curve radius (m): curve.radius")
    parser.add_argument("--speed", type=float, help="vehicle speed (m/s): curve.speed (default: the study's "
                                                    "operating.speed)")
    parser.add_argument("--cant", type=float, help="cant, the outer rail above the inner one (m): curve.cant")
    parser.add_argument("--config", help="study TOML file merged over the defaults (studies/paper.toml)")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML; a bare word is a string), e.g. "
                             "curve.wheelbase=2.1; repeatable")
    parser.add_argument("--json", action="store_true", help="print one JSON object (SI units)")
    return parser


def _cell(point, attr, scale, fmt):
    value = getattr(point, attr)
    if scale is None:
        return "yes" if value else "no"
    value = value * scale
    return "-" if value != value else format(value, fmt)


def format_points(result, points, feeds) -> str:
    """The curve, the wheelsets' positions and a table of every wheel's operating point."""
    inputs, loads = result["inputs"], result["loads"]
    bogie = "rigid bogie" if inputs["longitudinal_stiffness"] is None else (
        f"primary suspension k_x = {inputs['longitudinal_stiffness']:.3g} N/m, "
        f"k_y = {inputs['lateral_stiffness']:.3g} N/m")
    lines = [f"steady curving: R = {inputs['radius']:g} m, V = {inputs['speed']:.3f} m/s, cant {inputs['cant'] * 1e3:g} mm "
             f"(cant deficiency {loads['cant_deficiency'] * 1e3:.1f} mm, lateral acceleration "
             f"{loads['lateral_acceleration']:.3f} m/s^2)",
             f"{bogie}, wheelbase {inputs['wheelbase']:g} m, axle load {inputs['axle_load'] * 1e-3:g} kN, "
             f"friction {inputs['friction']:g} (flange {inputs['flange_friction']:g}); {inputs['geometry'].get('profiles', 'conical')}"]
    for ws in result["wheelsets"]:
        flange = ", ".join(ws["flange_contact"]) or "none"
        lines.append(f"  {ws['position']:<9} wheelset: lateral displacement {ws['lateral_displacement'] * 1e3:7.3f} mm, "
                     f"angle of attack {ws['angle_of_attack'] * 1e3:7.3f} mrad, flange contact: {flange}")
    labels = list(points)
    width = max(len(label) for label, *_ in ROWS)
    column = max(15, max(len(label) for label in labels) + 1)
    lines.append("")
    lines.append(" " * width + "".join(f"{label:>{column}}" for label in labels))
    for label, attr, scale, fmt in ROWS:
        lines.append(f"{label:<{width}}" + "".join(f"{_cell(points[w], attr, scale, fmt):>{column}}" for w in labels))
    lines.append("")
    lines.append("each wheel in its own contact frame (x rolling, y towards its field side), creepages of the wheel "
                 "relative to the rail, as contact.* of a study (docs/user-guide.md, From a curve)")
    lines.append(f"a study with curve.enabled = true feeds the cases from curve.wheel = {feeds}")
    return "\n".join(lines)


def command(args):
    """``curve``: print every wheel's operating point in the curve; returns the exit status."""
    assignments = list(args.assignments)
    for option, key in (("radius", "curve.radius"), ("speed", "curve.speed"), ("cant", "curve.cant")):
        value = getattr(args, option)
        if value is not None:
            assignments.append(f"{key}={value!r}")
    study = load_study(args.config, args.quick, assignments)
    result, points = study_curve(study)
    feeds = study["curve"]["wheel"]
    if args.json:
        inputs = result["inputs"]
        out = {"radius": inputs["radius"], "speed": inputs["speed"], "cant": inputs["cant"], "feeds": feeds,
               "inputs": inputs, "loads": result["loads"], "wheelsets": result["wheelsets"],
               "residuals": result["residuals"], "wheels": {label: p.to_dict() for label, p in points.items()}}
        print(json.dumps(out, indent=1, allow_nan=False))
    else:
        print(format_points(result, points, feeds))
    sys.stdout.flush()
    return 0
