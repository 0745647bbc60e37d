"""Input files named by a study: where relative paths point, and their contents in stage hashes.

A parameter declared with ``kind="file"`` (:func:`squealcore.schema.param`) names a file unless it
is ``""`` or one of its built-in names (``wheel.tread_profile = "S1002"``, ``rail.profile =
"BV50"``). Such a path written in a study file is relative to that file's folder
(:func:`resolve_file_paths`, applied by :func:`stages.config.load_study`); one given with
``--set`` is relative to the working folder. The SHA-256 of each named file's *contents* joins the
parameter hash of every stage that reads the file's section (:func:`input_file_hashes`, used by
:mod:`stages.engine`), so editing a profile file makes exactly those stages stale.
"""

from __future__ import annotations

from pathlib import Path

from squealcore.artefacts import file_sha256
from squealcore.errors import InputError
from squealcore.schema import file_params
from squealcore.study import dotted_keys, get_section

__all__ = ["resolve_file_paths", "input_file_hashes"]


def _table(study, dotted):
    """The (possibly absent) table at a dotted path of a raw study, or None."""
    table = study
    for part in dotted.split("."):
        if not isinstance(table, dict) or not isinstance(table.get(part), dict):
            return None
        table = table[part]
    return table


def _resolved(value, folder):
    return str(Path(folder) / value) if not Path(value).is_absolute() else value


def resolve_file_paths(study, folder, classes):
    """Make the relative file paths of a study file absolute, against the file's folder.

    Parameters
    ----------
    study : dict
        Tables read from one study file (modified in place): the section keys and the
        ``[sweep]`` values of file parameters; its ``[sweep]`` is given dotted keys
        (:func:`squealcore.study.dotted_keys`).
    folder : Path
        The study file's folder (absolute).
    classes : sequence of type
        The section classes (``stages.config.STUDY_SECTIONS``).

    Returns
    -------
    dict
        ``study``.
    """
    if isinstance(study.get("sweep"), dict):  # its entries by dotted key (unquoted ones are nested tables to TOML)
        study["sweep"] = dotted_keys(study["sweep"])
    sweep = study.get("sweep") if isinstance(study.get("sweep"), dict) else {}
    for cls in classes:
        table = _table(study, cls.SECTION)
        for name, spec in file_params(cls).items():
            if table is not None and spec.names_file(table.get(name)):
                table[name] = _resolved(table[name], folder)
            values = sweep.get(f"{cls.SECTION}.{name}")
            if isinstance(values, list):
                sweep[f"{cls.SECTION}.{name}"] = [_resolved(v, folder) if spec.names_file(v) else v
                                                  for v in values]
    return study


def input_file_hashes(study, sections, classes):
    """SHA-256 of the contents of every file named in the given sections of a study.

    Parameters
    ----------
    study : dict
        A complete, validated study.
    sections : sequence of str
        Dotted section names a stage reads (``Stage.sections``).
    classes : sequence of type
        The section classes (``stages.config.STUDY_SECTIONS``).

    Returns
    -------
    dict
        ``{"wheel.tread_profile": hex digest, ...}``; empty if no file is named.

    Raises
    ------
    InputError
        If a named file cannot be read (naming the key and the file).
    """
    hashes = {}
    for cls in classes:
        if cls.SECTION not in sections:
            continue
        table = get_section(study, cls.SECTION)
        for name, spec in file_params(cls).items():
            value = table.get(name, spec.default)
            if spec.names_file(value):
                key = f"{cls.SECTION}.{name}"
                try:
                    hashes[key] = file_sha256(value)
                except OSError as exc:
                    raise InputError(key, f"cannot read {value!r}: {exc.strerror}") from None
    return hashes
