"""Contact case files (TOML): the schema of their tables, checks, and the model they describe.

Format (SI units; every key but ``model`` has a default, see ``docs/parameters.md``)::

    model = "halfspace"            # or "point" (required)
    kind = "steady"                # steady | transient | shift
    [geometry]                     # at most one key; default: the default study's contact
    semi_axes = [a, b]             # Hertz semi-axes (m) at the given load, or
    curvatures = [A, B]            # gap h = A x^2 + B y^2 (1/m), or
    gap_file = "gap.csv"           # gap (m) on the grid, nx rows x ny columns (needs grid.dx, dy)
    [material]
    shear_modulus = 82e9           # Pa (or young_modulus = ...)
    poisson_ratio = 0.28
    [grid]
    nx = 40                        # elements covering the Hertz patch + 10 % (or dx = ... m)
    ny = 40
    extent = [Lx, Ly]              # optional (m): explicit grid of nx x ny (or dx x dy) elements
    [load]
    normal_force = 50e3            # N, or approach = ... (m)
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

Each table is a section class of :mod:`squealcore.schema`, declared in
:mod:`contact.params` (:data:`~contact.params.CASE_SECTIONS`); the friction
coefficient, Poisson's ratio, Young's modulus and creepages share their declarations with the
study's ``[contact]`` section. The default geometry and load are those of the default study:
curvatures from the wheel's rolling radius and the rail head radius, and the wheel load.
"""

from __future__ import annotations

import logging
import os
from dataclasses import asdict, dataclass

import numpy as np

from squealcore.errors import InputError, check_input_file
from squealcore.schema import build
from squealcore.study import load_toml

from contact.halfspace.model import Grid
from contact.hertz import HertzSolution, hertz_from_curvatures, hertz_from_semi_axes
from contact.params import CASE_SECTIONS, DEFAULT_CURVATURES, MIN_ELEMENTS_PER_SEMI_AXIS, CaseTop
from contact.registry import ContactSetup, contact_spec

__all__ = ["Case", "load_case", "parse_case"]

log = logging.getLogger(__name__)

_TABLES = {cls.SECTION: cls for cls in CASE_SECTIONS if cls.SECTION}


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
        The resolved case: every key with its value (defaults filled in; keys "not given" left out).
    """

    model: object
    load: dict
    creepage: tuple
    shift: tuple | None
    steps: int
    hertz: HertzSolution | None
    config: dict


def _read_tables(cfg):
    """Validate every table of a case dictionary; returns section name -> instance."""
    top = {k: v for k, v in cfg.items() if k not in _TABLES}
    for key in top:
        if isinstance(top[key], dict) or key not in ("model", "kind"):
            raise InputError(key, f"unknown key; must be one of: model, kind, {', '.join(_TABLES)}")
    tables = {"": build(CaseTop, top, "")}
    for name, cls in _TABLES.items():
        value = cfg.get(name, {})
        if not isinstance(value, dict):
            raise InputError(name, f"must be a table ([{name}]), got {value!r}")
        tables[name] = build(cls, value, name)
    return tables


def _resolved(tables):
    """The resolved configuration (JSON-ready): top-level keys and one dict per table, None left out."""
    out = {k: v for k, v in asdict(tables[""]).items()}
    for name in _TABLES:
        out[name] = {k: v for k, v in asdict(tables[name]).items() if v is not None}
    return out


def _hertz(geometry, load, contact_modulus):
    """Hertz solution of a semi-axes or curvatures geometry at the given load."""
    if geometry.semi_axes is not None:
        a, b = geometry.semi_axes
        if "normal_force" in load:
            force = load["normal_force"]
        else:  # the semi-axes belong to the given approach: delta = p0 b_min K(e) / E*
            # at fixed semi-axes p0 and the approach are proportional to the force
            force = load["approach"] / hertz_from_semi_axes(a, b, 1.0, contact_modulus).approach
        return hertz_from_semi_axes(a, b, force, contact_modulus)
    A, B = geometry.curvatures if geometry.curvatures is not None else DEFAULT_CURVATURES
    if "normal_force" in load:
        return hertz_from_curvatures(A, B, load["normal_force"], contact_modulus)
    h1 = hertz_from_curvatures(A, B, 1.0, contact_modulus)
    return h1.scaled((load["approach"] / h1.approach) ** 1.5)


def _explicit_grid(grid_cfg) -> Grid:
    """The grid of ``grid.extent`` [Lx, Ly] (m) with nx x ny elements or elements of dx x dy, as given."""
    sizes = []
    for axis, length in zip("xy", grid_cfg.extent):
        n, d = getattr(grid_cfg, "n" + axis), getattr(grid_cfg, "d" + axis)
        if n is not None:
            if d is not None and abs(n * d - length) > 1e-9 * length:
                raise InputError(f"grid.d{axis}", f"n{axis} d{axis} = {n * d:g} m must equal the extent {length:g} m")
            sizes.append((n, length / n))
        elif d is not None:
            count = round(length / d)
            if count < 3 or abs(count * d - length) > 1e-9 * length:
                raise InputError(f"grid.d{axis}", f"must divide the extent {length:g} m into an integer number "
                                 f">= 3 of elements, got {d:g} m")
            sizes.append((int(count), float(d)))
        else:
            raise InputError(f"grid.n{axis}", f"give n{axis} or d{axis} with grid.extent")
    (nx, dx), (ny, dy) = sizes
    return Grid(int(nx), int(ny), float(dx), float(dy))


def _warn_if_coarse(grid: Grid, hertz: HertzSolution):
    """Log a WARNING with the numbers if the grid resolves a Hertz semi-axis by too few elements."""
    for axis, d, half in (("x", grid.dx, hertz.a), ("y", grid.dy, hertz.b)):
        if half / d < MIN_ELEMENTS_PER_SEMI_AXIS:
            log.warning("grid.d%s = %g m resolves the contact's semi-axis %s = %g m by %.3g elements (fewer than "
                        "%d): the half-space solution is that of a few elements; refine the grid",
                        axis, d, "a" if axis == "x" else "b", half, half / d, MIN_ELEMENTS_PER_SEMI_AXIS)


#: Largest contact grid of the contact command, in elements (500 x 500): the half-space solver's
#: influence products hold about :data:`BYTES_PER_ELEMENT` per element, and a larger grid runs for
#: minutes per step (CONTACT's own benchmark grids are below 200 x 200).
MAX_GRID_ELEMENTS = 250_000
#: Memory of the half-space solver per grid element (B), for the estimate in the refusal: 1.6 GB
#: was measured on a 2000 x 2000 grid.
BYTES_PER_ELEMENT = 400


def _check_grid_size(grid: Grid):
    """Refuse a grid over :data:`MAX_GRID_ELEMENTS` elements, with its count and a memory estimate."""
    count = grid.nx * grid.ny
    if count > MAX_GRID_ELEMENTS:
        raise InputError("grid", f"{grid.nx} x {grid.ny} = {count:,} elements is more than the {MAX_GRID_ELEMENTS:,} "
                                 f"allowed (it would need about {count * BYTES_PER_ELEMENT / 1e9:.1f} GB and minutes "
                                 "per step); use fewer or larger elements (grid.nx, ny or dx, dy)")


def parse_case(cfg: dict, base_dir: str = ".") -> Case:
    """Check a case dictionary and build the model.

    Parameters
    ----------
    cfg : dict
        The parsed TOML case.
    base_dir : str
        Folder that a relative ``geometry.gap_file`` is relative to.

    Returns
    -------
    Case

    Raises
    ------
    InputError
        Naming the offending field.
    """
    tables = _read_tables(cfg)
    name, kind = tables[""].model, tables[""].kind
    geometry, grid_cfg, rolling = tables["geometry"], tables["grid"], tables["rolling"]
    material = tables["material"].to_material()
    friction = tables["friction"].to_friction()
    load = tables["load"].solve_arguments()
    creepage = tuple(rolling.creepage)
    shift = None
    if "shift" in cfg:
        if kind != "shift":
            raise InputError("shift", "only with kind = 'shift'")
        shift = tuple(tables["shift"].displacement)
    elif kind == "shift":
        shift = (0.0, 0.0, 0.0)
    spec = contact_spec(name)
    if kind not in spec.kinds:
        raise InputError("kind", f"the {name} model supports {' and '.join(repr(k) for k in spec.kinds)}")

    hertz = None
    if geometry.gap_file is not None:
        if not spec.solves_on_grid:
            raise InputError("geometry.gap_file", f"the {name} model needs semi_axes or curvatures")
        path = os.path.join(base_dir, geometry.gap_file)
        check_input_file("geometry.gap_file", path, what="CSV gap file")  # no FIFO, device or huge file
        try:
            gap = np.atleast_2d(np.loadtxt(path, delimiter=","))
        except (OSError, ValueError) as exc:
            raise InputError("geometry.gap_file", f"cannot read a CSV gap (m) from {path}: {exc}") from None
        if not np.all(np.isfinite(gap)):
            raise InputError("geometry.gap_file", f"must hold finite numbers (m), {path} does not")
        if grid_cfg.extent is not None:
            raise InputError("grid.extent", "not with a gap file (its size and grid.dx, dy set the grid)")
        if grid_cfg.dx is None or grid_cfg.dy is None:
            raise InputError("grid.dx", "grid.dx and grid.dy (m) are required with a gap file")
        grid = Grid(gap.shape[0], gap.shape[1], grid_cfg.dx, grid_cfg.dy)
        _check_grid_size(grid)
        for k in ("nx", "ny"):
            if getattr(grid_cfg, k) is not None and getattr(grid_cfg, k) != getattr(grid, k):
                raise InputError(f"grid.{k}", f"must equal the gap file's size {getattr(grid, k)}")
    else:
        hertz = _hertz(geometry, load, material.contact_modulus)
        if grid_cfg.extent is not None:
            grid = _explicit_grid(grid_cfg)
        else:
            grid = Grid.covering(hertz.a, hertz.b, grid_cfg.nx, grid_cfg.ny, grid_cfg.dx, grid_cfg.dy)
            # a grid derived from the Hertz patch must keep the patch off its border elements: their
            # centres at least 2 % of the semi-axis outside it (the discrete contact can reach a
            # little past the Hertz ellipse; 22 x 18 over the patch + 10 % passes, 12 elements do
            # not); an explicit grid (grid.extent) is taken as given, as in CONTACT
            for axis, n, d, half in (("x", grid.nx, grid.dx, hertz.a), ("y", grid.ny, grid.dy, hertz.b)):
                if 0.5 * (n - 1) * d < 1.02 * half:
                    raise InputError(f"grid.n{axis}", f"the grid ({n} x {d:g} m) puts its border elements on the "
                                     f"contact (semi-axis {half:g} m); enlarge n{axis} or d{axis}, or give "
                                     "grid.extent to use the grid as given")
        _check_grid_size(grid)
        X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
        gap = hertz.A * X ** 2 + hertz.B * Y ** 2
        if spec.solves_on_grid:
            _warn_if_coarse(grid, hertz)
    setup = ContactSetup(material, friction, hertz, rolling.speed, rolling.time_step)
    model = spec.hook("command")(setup, grid, gap, kind)
    return Case(model, load, creepage, shift, rolling.steps, hertz, _resolved(tables))


def load_case(path) -> Case:
    """Read and parse a TOML case file.

    Raises
    ------
    InputError
        Naming the field; a missing, unreadable or invalid file is named by its path.
    """
    return parse_case(load_toml(path), os.path.dirname(os.path.abspath(path)))
