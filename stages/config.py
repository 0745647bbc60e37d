"""The study configuration: the study schema, defaults, presets, user files, ``--set`` and validation.

The study schema is the list of section classes :data:`STUDY_SECTIONS`, each declared (with
:mod:`squealcore.schema`) in the package that uses it. The complete default study is built from
their defaults; ``studies/paper.toml`` (the paper's values and the assumptions, each with its
reason) is merged over it, then ``studies/quick.toml`` with ``--quick``, a user's study file and
the ``--set`` overrides. Every section is then checked by its class, so a bad value is reported
before anything is computed or written. The sweep (``[sweep]``) is expanded by the caller
(:mod:`stages.cases`), which validates every case when it plans them.

``python -m stages.config`` rewrites ``docs/parameters.md`` from the schema
(``--check``: exit 1 if the file is out of date).
"""

from __future__ import annotations

import argparse
import logging
import sys
from dataclasses import dataclass
from pathlib import Path

from contact_geometry.params import GeometryParams
from fe.params import RotationParams, WheelFEParams
from contact.params import CASE_SECTIONS, ContactParams
from interaction.params import OperatingParams, SimulationParams, TimeParams
from mesh.wheel_section import WheelParams
from profiles.rail_section import RailParams
from squealcore.errors import InputError, check_input_file
from squealcore.schema import defaults, file_params, markdown_table, param, section
from squealcore.study import (FREE_TABLES, free_table_entry, get_section, load_toml, merge, parse_assignment,
                              set_free_entry, set_path)
from stages.curve import apply_curve, check_hand_set
from stages.curve_params import CurveParams
from stages.input_files import resolve_file_paths
from stages.maps_params import MapParams
from studies import study_path
from waveguide.params import TrackParams

__all__ = ["STUDY_SECTIONS", "ReportParams", "schema_defaults", "default_study", "load_study",
           "validate", "parameters_markdown", "PARAMETERS_DOC"]

logger = logging.getLogger(__name__)


@section("report")
@dataclass(frozen=True)
class ReportParams:
    """Figures and tables of the report stage."""

    dpi: int = param(120, low=30, high=600, doc="Resolution of the figures (dots per inch).")
    receptance_f_min: float = param(50.0, unit="Hz", low=0.0, high=1e5, low_open=True,
                                    doc="Lower end of the receptance figures.")
    receptance_f_max: float = param(10000.0, unit="Hz", low=0.0, high=1e5, low_open=True,
                                    doc="Upper end of the receptance figures (> receptance_f_min).")

    def cross_check(self, prefix: str = "report") -> None:
        """The receptance band must be ordered (raises :class:`InputError`)."""
        if self.receptance_f_max <= self.receptance_f_min:
            raise InputError(f"{prefix}.receptance_f_max",
                             f"must be larger than receptance_f_min = {self.receptance_f_min:g} Hz, "
                             f"got {self.receptance_f_max:g} Hz")


#: The study schema: one section class per table, in the order of the study file.
STUDY_SECTIONS = (WheelParams, WheelFEParams, RotationParams, RailParams, TrackParams, OperatingParams, GeometryParams,
                  TimeParams, ReportParams, ContactParams, SimulationParams, MapParams, CurveParams)

#: Where ``python -m stages.config`` writes the parameter tables.
PARAMETERS_DOC = Path(__file__).resolve().parents[1] / "docs" / "parameters.md"


def schema_defaults():
    """The complete default study from the schema alone (every section's defaults, empty sweep).

    Returns
    -------
    dict
        Nested tables, e.g. ``{"wheel": {..., "fe": {...}, "rotation": {...}}, ..., "sweep": {}}``.
    """
    study = {}
    for cls in STUDY_SECTIONS:
        *parents, name = cls.SECTION.split(".")
        table = study
        for part in parents:
            table = table[part]
        table[name] = defaults(cls)
    for name in FREE_TABLES:
        *parents, last = name.split(".")
        table = study
        for part in parents:
            table = table[part]
        table[last] = {}
    return study


def default_study(quick=False):
    """The default study: schema defaults, ``paper.toml`` merged over them, then ``quick.toml`` if asked."""
    study = merge(schema_defaults(), load_toml(study_path("paper.toml")))
    if quick:
        study = merge(study, load_toml(study_path("quick.toml")))
    return study


def load_study(config=None, quick=False, assignments=()):
    """Build and validate a study.

    Parameters
    ----------
    config : str or Path, optional
        User study file merged over the defaults; relative paths of file parameters in it (e.g.
        ``wheel.tread_profile``, also in ``[sweep]``) are taken from the file's folder.
    quick : bool
        Merge the quick preset first.
    assignments : sequence of str
        ``section.key=value`` overrides, applied last (values read as TOML, bare words as strings;
        keys as TOML dotted keys). An override of a swept key replaces the sweep: the key leaves
        ``[sweep]`` and the single value is used (logged at INFO). ``sweep.KEY=[...]`` (or
        ``sweep."KEY"=[...]``) sets the sweep list of the dotted key KEY (checked by
        :func:`stages.cases.expand_sweep` and :func:`stages.cases.case_study`), and
        ``map.grid.KEY=[...]`` an axis of the squeal map's grid, the table's other entries kept.
        With ``curve.enabled = true`` the curve's operating point is written into the study
        (:func:`stages.curve.apply_curve`); a value it sets that is also set by hand (or swept) is
        refused (:func:`stages.curve.check_hand_set`).

    Returns
    -------
    dict
        The complete, validated study (its sweep is expanded and each case validated by the
        caller, see :func:`stages.cases.expand_sweep` and :func:`stages.cases.case_study`).

    Raises
    ------
    InputError
        For unknown keys, values of the wrong kind, non-finite or out of range.
    """
    study = default = default_study(quick)
    if config is not None:
        # file paths in a study file are relative to its folder (--set ones to the working folder)
        study = merge(study, resolve_file_paths(load_toml(config), Path(config).resolve().parent, STUDY_SECTIONS))
    read_as = {}  # dotted key -> (text, value) of the --set values TOML read as something else than text
    try:
        for assignment in assignments:
            path, value = parse_assignment(assignment)
            text = assignment.split("=", 1)[1].strip()
            if not isinstance(value, str) and any(c.isalpha() for c in text) and text not in ("true", "false"):
                read_as[".".join(path)] = (text, value)
            entry = free_table_entry(path)
            if entry is not None:  # sweep.contact.friction or sweep."contact.friction": one entry, the others kept
                study = set_free_entry(study, *entry, value)
                continue
            study = set_path(study, path, value)
            key = ".".join(path)
            if key in study.get("sweep", {}):
                logger.info("--set %s=%r replaces the sweep over %s (%r)", key, value, key, study["sweep"][key])
                del study["sweep"][key]  # set_path returned a new study
        check_input_files(study)
        validate(study)
        # a curve (curve.enabled) sets the cases' creepages, load and contact position: refuse them set
        # by hand too, then write the curve's in (stages/curve.py)
        study = apply_curve(check_hand_set(study, default))
        validate(study)
    except InputError as exc:
        if exc.field in read_as:  # e.g. rail.profile=60E1, read by TOML as the number 600.0
            text, value = read_as[exc.field]
            raise InputError(exc.field, f"{exc.message} (--set read {text!r} as the "
                                        f"{type(value).__name__} {value!r}; quote strings: "
                                        f"--set '{exc.field}=\"{text}\"')") from None
        raise
    return study


def check_input_files(study):
    """Refuse files named by the study (in its sections and its sweep) that are not regular files or
    are too large (:func:`squealcore.errors.check_input_file`), before any of them is read.

    Raises
    ------
    InputError
        Naming the key and the file.
    """
    sweep = study.get("sweep") if isinstance(study.get("sweep"), dict) else {}
    for cls in STUDY_SECTIONS:
        try:
            table = get_section(study, cls.SECTION)
        except (KeyError, TypeError, InputError):
            continue
        for name, spec in file_params(cls).items():
            key = f"{cls.SECTION}.{name}"
            values = [table.get(name)] if isinstance(table, dict) else []
            if isinstance(sweep.get(key), list):
                values += sweep[key]
            for value in values:
                if isinstance(value, str) and spec.names_file(value):
                    check_input_file(key, value, what=f"{name.replace('_', ' ')} file", missing_ok=True)


def validate(study):
    """Check every section of a study against its schema.

    Parameters
    ----------
    study : dict
        A complete study (see :func:`load_study`).

    Returns
    -------
    dict
        Section name -> validated section instance (e.g. ``"wheel"`` -> :class:`WheelParams`).

    Raises
    ------
    InputError
        Naming the first bad field and what is allowed.
    """
    return {cls.SECTION: cls.from_mapping(_table(study, cls.SECTION), cls.SECTION) for cls in STUDY_SECTIONS}


def _table(study, name):
    """A section's table, or ``{}`` (its defaults) when the study has none: a study recorded in a
    folder before the section existed (e.g. ``[curve]``)."""
    try:
        return get_section(study, name)
    except KeyError:
        return {}


PARAMETERS_INTRO = """# Parameters

<!-- Generated by `python -m stages.config` from the schema (squealcore/schema.py and the section
classes listed below); do not edit by hand. tests/test_schema.py fails when this file is out of date. -->

Every parameter of a study file and of a contact case file, with its default, unit and allowed
values (SI units; `[a, b]` closed, `(a, b)` open bounds; numbers must be finite). A study file
only needs the keys it changes: the default study is built from these defaults with
[`studies/paper.toml`](../studies/paper.toml) (the paper's values and the assumptions) merged
over them. `--set section.key=value` on a key that `[sweep]` lists replaces the sweep over that
key by the single value.
"""


def _markdown(text):
    """Docstring text (reStructuredText literals) as Markdown."""
    return text.replace("``", "`")


def parameters_markdown():
    """The text of ``docs/parameters.md``: one table per study section and per case-file table."""
    parts = [PARAMETERS_INTRO, "## Study files\n"]
    for cls in STUDY_SECTIONS:
        parts.append(f"### `[{cls.SECTION}]` ({cls.__module__}.{cls.__name__})\n\n{_markdown(cls.SECTION_DOC)}\n\n"
                     f"{markdown_table(cls)}\n")
    parts.append("### `[sweep]`\n\nEach key is a dotted parameter name (e.g. `\"contact.friction\"`) with a list "
                 "of values; the study runs every combination.\n")
    parts.append("### `[map.grid]`\n\nThe grid of `pipeline.py map`: dotted parameter names with lists of values, "
                 "as `[sweep]`; every combination is screened for every wheel model.\n")
    parts.append("## Contact case files (`pipeline.py contact CASE.toml`)\n")
    for cls in CASE_SECTIONS:
        title = f"`[{cls.SECTION}]`" if cls.SECTION else "top level"
        parts.append(f"### {title} ({cls.__module__}.{cls.__name__})\n\n{_markdown(cls.SECTION_DOC)}\n\n"
                     f"{markdown_table(cls)}\n")
    return "\n".join(parts)


def main(argv=None):
    """Write (or ``--check``) ``docs/parameters.md``; returns the exit status."""
    parser = argparse.ArgumentParser(prog="python -m stages.config", description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=PARAMETERS_DOC, help="file to write")
    parser.add_argument("--check", action="store_true", help="exit 1 if the file differs from the schema")
    args = parser.parse_args(argv)
    text = parameters_markdown()
    if args.check:
        current = args.out.read_text(encoding="utf-8") if args.out.is_file() else ""
        if current != text:
            print(f"{args.out} is out of date: run python -m stages.config", file=sys.stderr)
            return 1
        return 0
    args.out.write_text(text, encoding="utf-8")
    return 0


if __name__ == "__main__":
    # run the imported module, not this __main__ copy, so that the classes carry their real module name
    import stages.config

    sys.exit(stages.config.main())
