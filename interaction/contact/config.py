"""Contact case files (TOML): parse, check and build the model and its inputs.

Format (SI units; every key but the geometry and the load has a default)::

    model = "halfspace"            # or "point"
    kind = "steady"                # steady | transient | shift
    [geometry]
    semi_axes = [a, b]             # Hertz semi-axes (m) at the given load, or
    curvatures = [A, B]            # gap h = A x^2 + B y^2 (1/m), or
    gap_file = "gap.csv"           # gap (m) on the grid, nx rows x ny columns (needs grid.dx, dy)
    [material]
    shear_modulus = 82e9           # Pa (or young_modulus = ...)
    poisson_ratio = 0.28
    [grid]
    nx = 40                        # elements covering the Hertz patch + 10 % (or dx = ... m)
    ny = 40
    [load]
    normal_force = 82e3            # N, or approach = ... (m)
    [friction]
    coefficient = 0.3              # static (and kinetic unless given)
    kinetic = 0.3
    [rolling]
    creepage = [xi, eta, phi]      # -, -, 1/m
    speed = 30.0                   # m/s
    steps = 1
    time_step = ...                # s, point model only (default dx / speed)
    [shift]
    displacement = [sx, sy, rot]   # rigid shift per step (m, m, rad), kind = "shift"
"""

from __future__ import annotations

import os
import tomllib
from dataclasses import dataclass

import numpy as np

from squealcore.errors import InputError, require_range

from .halfspace import Grid, HalfspaceContact
from .hertz import HertzSolution, hertz_from_curvatures, hertz_from_semi_axes
from .params import Friction, Material, check_creepage
from .point import PointContact

__all__ = ["Case", "load_case", "parse_case"]

_ALLOWED = {
    "": {"model", "kind", "geometry", "material", "grid", "load", "friction", "rolling", "shift"},
    "geometry": {"semi_axes", "curvatures", "gap_file"},
    "material": {"shear_modulus", "poisson_ratio", "young_modulus"},
    "grid": {"nx", "ny", "dx", "dy"},
    "load": {"normal_force", "approach"},
    "friction": {"coefficient", "kinetic"},
    "rolling": {"creepage", "speed", "steps", "time_step"},
    "shift": {"displacement"},
}


@dataclass(frozen=True)
class Case:
    """A parsed contact case.

    Attributes
    ----------
    model : HalfspaceContact or PointContact
    load : dict
        ``{"normal_force": F}`` or ``{"approach": d}`` for :meth:`solve`.
    creepage : tuple
        (xi, eta, phi).
    shift : tuple or None
        Rigid shift per step (m, m, rad).
    steps : int
    hertz : HertzSolution or None
        Hertz solution of the geometry (None for a gap file).
    config : dict
        The TOML content.
    """

    model: object
    load: dict
    creepage: tuple
    shift: tuple | None
    steps: int
    hertz: HertzSolution | None
    config: dict


def _pair(section, key, value, unit):
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise InputError(f"{section}.{key}", f"must be a list of 2 numbers ({unit}), got {value!r}")
    return [require_range(f"{section}.{key}", v, 0.0, None, low_open=True, unit=unit) for v in value]


def _check_keys(cfg):
    for key in cfg:
        if key not in _ALLOWED[""]:
            raise InputError(key, f"unknown key; allowed: {sorted(_ALLOWED[''])}")
    for sec, allowed in _ALLOWED.items():
        if not sec or sec not in cfg:
            continue
        if not isinstance(cfg[sec], dict):
            raise InputError(sec, "must be a table")
        for key in cfg[sec]:
            if key not in allowed:
                raise InputError(f"{sec}.{key}", f"unknown key; allowed: {sorted(allowed)}")


def _material(cfg):
    m = cfg.get("material", {})
    nu = m.get("poisson_ratio", 0.28)
    if "shear_modulus" in m and "young_modulus" in m:
        raise InputError("material", "give shear_modulus or young_modulus, not both")
    if "young_modulus" in m:
        require_range("material.poisson_ratio", nu, 0.0, 0.5, high_open=True)
        return Material.from_young(m["young_modulus"], nu)
    return Material(m.get("shear_modulus", 82e9), nu)


def parse_case(cfg: dict, base_dir: str = ".") -> Case:
    """Check a case dictionary and build the model.

    Raises
    ------
    InputError
        Naming the offending field.
    """
    _check_keys(cfg)
    name = cfg.get("model", "halfspace")
    if name not in ("halfspace", "point"):
        raise InputError("model", f"must be 'halfspace' or 'point', got {name!r}")
    kind = cfg.get("kind", "steady")
    if kind not in ("steady", "transient", "shift"):
        raise InputError("kind", f"must be 'steady', 'transient' or 'shift', got {kind!r}")
    material = _material(cfg)
    fr = cfg.get("friction", {})
    friction = Friction(fr.get("coefficient", 0.3), fr.get("kinetic"))

    load_cfg = cfg.get("load", {})
    if ("normal_force" in load_cfg) == ("approach" in load_cfg):
        raise InputError("load", "give exactly one of load.normal_force (N) and load.approach (m)")
    if "normal_force" in load_cfg:
        load = {"normal_force": require_range("load.normal_force", load_cfg["normal_force"], 0.0, None,
                                              low_open=True, unit="N")}
    else:
        load = {"approach": require_range("load.approach", load_cfg["approach"], 0.0, None,
                                          low_open=True, unit="m")}

    ro = cfg.get("rolling", {})
    creepage = check_creepage(ro.get("creepage", [0.0, 0.0, 0.0]))
    speed = require_range("rolling.speed", ro.get("speed", 30.0), 0.0, None, low_open=True, unit="m/s")
    steps = ro.get("steps", 1)
    if isinstance(steps, bool) or not isinstance(steps, int) or not 1 <= steps <= 100000:
        raise InputError("rolling.steps", f"must be an integer in [1, 100000], got {steps!r}")
    shift = None
    if "shift" in cfg:
        if kind != "shift":
            raise InputError("shift", "only with kind = 'shift'")
        d = cfg["shift"].get("displacement", [0.0, 0.0, 0.0])
        if not isinstance(d, list) or len(d) != 3:
            raise InputError("shift.displacement", f"must be [sx, sy, rot] (m, m, rad), got {d!r}")
        shift = tuple(require_range("shift.displacement", v, -1.0, 1.0) for v in d)
    elif kind == "shift":
        shift = (0.0, 0.0, 0.0)

    geo = cfg.get("geometry", {})
    given = [k for k in ("semi_axes", "curvatures", "gap_file") if k in geo]
    if len(given) != 1:
        raise InputError("geometry", "give exactly one of semi_axes, curvatures, gap_file")
    Es = material.contact_modulus
    gr = cfg.get("grid", {})
    hertz = None
    gap = None
    if given[0] == "gap_file":
        if name == "point":
            raise InputError("geometry.gap_file", "the point model needs semi_axes or curvatures")
        path = os.path.join(base_dir, str(geo["gap_file"]))
        try:
            gap = np.atleast_2d(np.loadtxt(path, delimiter=","))
        except (OSError, ValueError) as exc:
            raise InputError("geometry.gap_file", f"cannot read a CSV gap (m) from {path}: {exc}") from None
        if "dx" not in gr or "dy" not in gr:
            raise InputError("grid.dx", "grid.dx and grid.dy (m) are required with a gap file")
        grid = Grid(gap.shape[0], gap.shape[1], gr["dx"], gr["dy"])
        for k in ("nx", "ny"):
            if k in gr and gr[k] != getattr(grid, k):
                raise InputError(f"grid.{k}", f"must equal the gap file's size {getattr(grid, k)}")
    else:
        if given[0] == "semi_axes":
            a, b = _pair("geometry", "semi_axes", geo["semi_axes"], "m")
            if "normal_force" in load:
                force = load["normal_force"]
            else:  # the semi-axes belong to the given approach: delta = p0 b_min K(e) / E*
                # at fixed semi-axes p0 and the approach are proportional to the force
                force = load["approach"] / hertz_from_semi_axes(a, b, 1.0, Es).approach
            hertz = hertz_from_semi_axes(a, b, force, Es)
        else:
            A, B = _pair("geometry", "curvatures", geo["curvatures"], "1/m")
            if "normal_force" in load:
                hertz = hertz_from_curvatures(A, B, load["normal_force"], Es)
            else:
                h1 = hertz_from_curvatures(A, B, 1.0, Es)
                hertz = h1.scaled((load["approach"] / h1.approach) ** 1.5)
        grid = Grid.covering(hertz.a, hertz.b, gr.get("nx"), gr.get("ny"), gr.get("dx"), gr.get("dy"))
        X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
        gap = hertz.A * X ** 2 + hertz.B * Y ** 2
        # the Hertz patch must leave at least one exterior element on each side
        if grid.nx * grid.dx < 2.0 * hertz.a + 2.0 * grid.dx:
            raise InputError("grid.nx", f"the grid ({grid.nx} x {grid.dx:g} m) is too small for the "
                             f"contact length 2a = {2 * hertz.a:g} m; enlarge nx or dx")
        if grid.ny * grid.dy < 2.0 * hertz.b + 2.0 * grid.dy:
            raise InputError("grid.ny", f"the grid ({grid.ny} x {grid.dy:g} m) is too small for the "
                             f"contact width 2b = {2 * hertz.b:g} m; enlarge ny or dy")
    if name == "halfspace":
        model = HalfspaceContact(material=material, friction=friction, grid=grid, gap=gap, kind=kind,
                                 speed=speed)
    else:
        if kind == "shift":
            raise InputError("kind", "the point model supports 'steady' and 'transient'")
        dt = ro.get("time_step", grid.dx / speed)
        model = PointContact(material=material, friction=friction, hertz=hertz,
                             kind=kind, speed=speed, time_step=dt)
    return Case(model, load, creepage, shift, steps, hertz, cfg)


def load_case(path: str) -> Case:
    """Read and parse a TOML case file (errors name the field; a missing/bad file is ``case``)."""
    try:
        with open(path, "rb") as fh:
            cfg = tomllib.load(fh)
    except OSError as exc:
        raise InputError("case", f"cannot read {path}: {exc.strerror}") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError("case", f"invalid TOML in {path}: {exc}") from None
    return parse_case(cfg, os.path.dirname(os.path.abspath(path)))
