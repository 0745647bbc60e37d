"""Study files: TOML loading, merging over the defaults, ``--set`` overrides and field checks.

A study is a nested mapping of TOML tables (``[wheel]``, ``[wheel.fe]``, ``[track]``, ...). The
defaults are a complete study file; a user's file and ``--set section.key=value`` overrides are
merged over it. Merging refuses keys that the defaults do not have (typos), so every later check
can assume a complete, known set of keys. Range checks are made per section by the section
classes of :mod:`squealcore.schema`, declared in the packages that use them.
"""

from __future__ import annotations

import copy

try:  # Python >= 3.11
    import tomllib
except ModuleNotFoundError:  # pragma: no cover - Python 3.10
    import tomli as tomllib

from pathlib import Path

from .errors import InputError, check_input_file

# Tables whose keys are free (they name other keys): a user's table replaces the default one.
FREE_TABLES = ("sweep", "map.grid")


def dotted_keys(table, prefix=""):
    """A free table with dotted keys: ``{"contact": {"friction": [...]}}`` becomes ``{"contact.friction": [...]}``.

    The entries of a free table (:data:`FREE_TABLES`) are lists, never tables, so a table inside
    one can only be the parts of dotted keys, as TOML reads ``contact.friction = [0.3, 0.6]``
    written without quotes.
    """
    flat = {}
    for key, value in table.items():
        if isinstance(value, dict):
            flat.update(dotted_keys(value, f"{prefix}{key}."))
        else:
            flat[f"{prefix}{key}"] = value
    return flat


def free_table_entry(path):
    """``(table, key)`` if the key path names an entry of a free table, e.g. ``("sweep", "contact.friction")``; else None."""
    for table in FREE_TABLES:
        head = table.split(".")
        if path[:len(head)] == head and len(path) > len(head):
            return table, ".".join(path[len(head):])
    return None


def set_free_entry(mapping, table, key, value):
    """Return a copy of ``mapping`` with ``value`` at ``key`` of the free table ``table``, its other entries kept."""
    result = copy.deepcopy(mapping)
    node = result
    for part in table.split("."):
        node = node[part]
    node[key] = copy.deepcopy(value)
    return result


def load_toml(path):
    """Read a TOML file.

    Parameters
    ----------
    path : str or Path
        The file.

    Returns
    -------
    dict

    Raises
    ------
    InputError
        If the file is missing, a directory, unreadable, not UTF-8 text (e.g. binary) or not
        valid TOML (the field is the file name).
    """
    if not Path(path).is_dir():  # a FIFO would block, /dev/zero never end (a folder: the message below)
        check_input_file(str(path), path, what="TOML file", show_path=False)
    try:
        with open(path, "rb") as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        raise InputError(str(path), "file not found") from None
    except IsADirectoryError:
        raise InputError(str(path), "is a directory, expected a TOML file") from None
    except PermissionError:
        raise InputError(str(path), "permission denied: the file cannot be read") from None
    except OSError as exc:
        raise InputError(str(path), f"cannot be read ({exc.strerror or exc})") from None
    except UnicodeDecodeError:
        raise InputError(str(path), "not a text file (TOML must be UTF-8 text)") from None
    except tomllib.TOMLDecodeError as exc:
        raise InputError(str(path), f"not valid TOML: {exc}") from None


def parse_value(text):
    """Read a ``--set`` value as a TOML value; a bare word is a string.

    Parameters
    ----------
    text : str
        e.g. ``"0.4"``, ``"[0.3, 0.6]"``, ``"true"``, ``"axisymmetric"``.

    Returns
    -------
    object
    """
    try:
        return tomllib.loads(f"value = {text}")["value"]
    except tomllib.TOMLDecodeError:
        return text


def _key_path(key):
    """The parts of a dotted key read as TOML reads one (a quoted part may hold dots), or None."""
    try:
        table = tomllib.loads(f"{key} = 0")
    except tomllib.TOMLDecodeError:
        return None
    path = []
    while isinstance(table, dict):
        (part, table), = table.items()
        path.append(part)
    return path


def parse_assignment(assignment):
    """Split ``section.key=value`` into a key path and a value.

    The key is a TOML dotted key: ``sweep."contact.friction"`` is the path
    ``["sweep", "contact.friction"]``.

    Parameters
    ----------
    assignment : str

    Returns
    -------
    (list of str, object)

    Raises
    ------
    InputError
        If there is no ``=`` or no dotted key.
    """
    if "=" not in assignment:
        raise InputError("--set", f"expected section.key=value, got {assignment!r}")
    key, text = assignment.split("=", 1)
    path = _key_path(key.strip())
    if path is None or len(path) < 2 or not all(path):
        raise InputError("--set", f"expected a dotted key such as wheel.rolling_radius, got {key!r}")
    return path, parse_value(text.strip())


def _kind(value):
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, (int, float)):
        return "number"
    if isinstance(value, str):
        return "string"
    if isinstance(value, list):
        return "list"
    if isinstance(value, dict):
        return "table"
    return type(value).__name__


def merge(base, override, prefix=""):
    """Merge ``override`` over a copy of ``base``, refusing unknown keys and wrong kinds.

    Parameters
    ----------
    base : dict
        Complete defaults.
    override : dict
        User values.
    prefix : str
        Dotted path of ``base`` (for messages).

    Returns
    -------
    dict
        A new mapping.

    Raises
    ------
    InputError
        For a key that ``base`` does not have, or a value of another kind (number, string,
        boolean, list, table) than the default's.
    """
    result = copy.deepcopy(base)
    for key, value in override.items():
        field = f"{prefix}{key}"
        if field in FREE_TABLES:
            # A free table (e.g. [sweep]) is replaced as a whole, not merged key by key.
            if not isinstance(value, dict):
                raise InputError(field, f"must be a table, got {value!r}")
            result[key] = dotted_keys(copy.deepcopy(value))
            continue
        if key not in result:
            raise InputError(field, f"unknown key ({_known_here(result)})")
        default = result[key]
        if isinstance(default, dict):
            if not isinstance(value, dict):
                raise InputError(field, f"must be a table, got {value!r}")
            result[key] = merge(default, value, f"{field}.")
            continue
        if _kind(value) != _kind(default):
            raise InputError(field, f"must be a {_kind(default)}, got {value!r}")
        result[key] = copy.deepcopy(value)
    return result


def _known_here(table):
    """The keys and sub-tables of ``table``, for a message about a key it does not have."""
    keys = ", ".join(sorted(k for k in table if not isinstance(table[k], dict)))
    tables = ", ".join(sorted(k for k in table if isinstance(table[k], dict)))
    if keys and tables:
        return f"known keys here: {keys}; tables: {tables}"
    return f"known keys here: {keys}" if keys else f"known tables here: {tables}"


def set_path(mapping, path, value):
    """Return a copy of ``mapping`` with ``value`` at the key path, checked like :func:`merge`."""
    override = value
    for part in reversed(path):
        override = {part: override}
    return merge(mapping, override)


def get_section(study, dotted):
    """The table at a dotted path, without its sub-tables.

    Parameters
    ----------
    study : dict
    dotted : str
        e.g. ``"wheel"`` or ``"wheel.fe"``.

    Returns
    -------
    dict
    """
    table = study
    for part in dotted.split("."):
        table = table[part]
    return {k: v for k, v in table.items() if not isinstance(v, dict)}
