"""HDF5 artefacts: atomic writing, provenance attributes, freshness checks and checked reading.

Every stage of the pipeline writes one HDF5 file. Its root attributes record

``schema``
    the artefact kind, e.g. ``"wheel_modes"``;
``schema_version``
    an integer bumped whenever the layout changes;
``params_sha256``
    SHA-256 of the canonical JSON of the configuration sections the stage reads;
``inputs``
    JSON object mapping each upstream artefact's file name to the SHA-256 of its bytes;
``code_version``, ``created``
    package version and UTC time of writing.

A file is written to a temporary name in the destination folder and moved into place with
:func:`os.replace` only after it has been closed successfully, so an interrupted run never leaves
a half-written file under the final name. Every dataset carries a ``units`` attribute.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import hashlib
import json
import logging
import os
import tempfile
from pathlib import Path

import h5py
import numpy as np

logger = logging.getLogger(__name__)

CODE_VERSION = "0.1.0"


class ArtefactError(RuntimeError):
    """An artefact is missing, unreadable, of the wrong kind or of an unexpected layout."""


def _publish(tmp_name, path):
    """Give a finished temporary file the permissions of a normally created one and move it into place."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp_name, 0o666 & ~mask)
    os.replace(tmp_name, path)


def canonical_json(obj) -> str:
    """Canonical JSON text of ``obj`` (sorted keys, no whitespace, floats via ``repr``).

    Parameters
    ----------
    obj : object
        JSON-serialisable mapping/sequence/scalar (numpy scalars are converted).

    Returns
    -------
    str
    """

    def convert(value):
        if isinstance(value, dict):
            return {str(k): convert(v) for k, v in value.items()}
        if isinstance(value, (list, tuple)):
            return [convert(v) for v in value]
        if isinstance(value, np.generic):
            return value.item()
        if isinstance(value, Path):
            return str(value)
        return value

    return json.dumps(convert(obj), sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def params_hash(obj) -> str:
    """SHA-256 (hex) of the canonical JSON of ``obj``."""
    return hashlib.sha256(canonical_json(obj).encode("ascii")).hexdigest()


def file_sha256(path) -> str:
    """SHA-256 (hex) of a file's bytes."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def add_dataset(group, name, data, units, *, compress=False):
    """Create a dataset with a mandatory ``units`` attribute.

    Parameters
    ----------
    group : h5py.Group
        Where to create it.
    name : str
        Dataset path relative to ``group``.
    data : array_like
        The values (strings are stored as UTF-8 variable-length strings).
    units : str
        Physical unit, ``"1"`` for dimensionless numbers, ``""`` for labels and indices.
    compress : bool
        Use gzip compression (for large arrays).

    Returns
    -------
    h5py.Dataset
    """
    array = np.asarray(data)
    if array.dtype.kind in "UO":
        array = np.asarray(array, dtype=object)
        dset = group.create_dataset(name, data=array, dtype=h5py.string_dtype())
    elif compress and array.size > 1024:
        dset = group.create_dataset(name, data=array, compression="gzip", compression_opts=4, shuffle=True)
    else:
        dset = group.create_dataset(name, data=array)
    dset.attrs["units"] = units
    return dset


@contextlib.contextmanager
def write_artefact(path, schema, schema_version, params_sha256, inputs=None):
    """Write an HDF5 artefact atomically.

    Use as ``with write_artefact(path, "wheel_modes", 1, sha, inputs) as f: ...``. The file is
    created under a temporary name in the same folder, given its provenance attributes, closed and
    then moved to ``path``. If the body raises, the temporary file is removed and ``path`` is left
    as it was.

    Parameters
    ----------
    path : str or Path
        Final file name.
    schema : str
        Artefact kind.
    schema_version : int
        Layout version of that kind.
    params_sha256 : str
        Hash of the configuration sections read by the stage (:func:`params_hash`).
    inputs : dict, optional
        Upstream artefact name -> SHA-256 of its bytes.

    Yields
    ------
    h5py.File
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=path.parent)
    os.close(fd)
    try:
        with h5py.File(tmp_name, "w") as handle:
            handle.attrs["schema"] = schema
            handle.attrs["schema_version"] = int(schema_version)
            handle.attrs["params_sha256"] = params_sha256
            handle.attrs["inputs"] = canonical_json(inputs or {})
            handle.attrs["code_version"] = CODE_VERSION
            handle.attrs["created"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
            yield handle
            handle.attrs["complete"] = True
        _publish(tmp_name, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp_name)
        raise


@contextlib.contextmanager
def atomic_output(path, suffix=None):
    """Yield a temporary path next to ``path``; move it into place on success.

    For files written by third-party writers (gmsh, meshio, matplotlib, wave files).

    Parameters
    ----------
    path : str or Path
        Final file name.
    suffix : str, optional
        Suffix of the temporary file (writers that infer the format from it need the real one);
        defaults to the suffix of ``path``.
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, tmp_name = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=suffix or path.suffix, dir=path.parent)
    os.close(fd)
    try:
        yield Path(tmp_name)
        _publish(tmp_name, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.remove(tmp_name)
        raise


def freshness(path, schema, schema_version, params_sha256, inputs):
    """Tell whether an artefact is up to date.

    Parameters
    ----------
    path : str or Path
        Artefact file.
    schema : str
        Expected kind.
    schema_version : int
        Expected layout version.
    params_sha256 : str
        Expected configuration hash.
    inputs : dict
        Expected upstream hashes.

    Returns
    -------
    (bool, str)
        Whether it is fresh, and why not (empty when fresh).
    """
    path = Path(path)
    if not path.exists():
        return False, "missing"
    try:
        with h5py.File(path, "r") as handle:
            attrs = dict(handle.attrs)
    except (OSError, ValueError) as exc:
        return False, f"unreadable ({exc.__class__.__name__})"
    if not attrs.get("complete", False):
        return False, "incomplete file"
    if attrs.get("schema") != schema:
        return False, f"foreign artefact (schema {attrs.get('schema')!r}, expected {schema!r})"
    if int(attrs.get("schema_version", -1)) != int(schema_version):
        return False, f"schema version {attrs.get('schema_version')} != {schema_version}"
    if attrs.get("params_sha256") != params_sha256:
        return False, "parameters changed"
    if attrs.get("inputs") != canonical_json(inputs or {}):
        return False, "inputs changed"
    return True, ""


def open_artefact(path, schema, schema_version=None):
    """Open an artefact for reading after checking its kind.

    Parameters
    ----------
    path : str or Path
        Artefact file.
    schema : str
        Expected kind.
    schema_version : int, optional
        Expected layout version.

    Returns
    -------
    h5py.File
        Open read-only; the caller closes it (use it as a context manager).

    Raises
    ------
    ArtefactError
        If the file is missing, unreadable, incomplete or of another kind/version.
    """
    path = Path(path)
    if not path.exists():
        raise ArtefactError(f"{path}: artefact missing (run the stage that writes it)")
    try:
        handle = h5py.File(path, "r")
    except (OSError, ValueError) as exc:
        raise ArtefactError(f"{path}: not a readable HDF5 file ({exc})") from exc
    attrs = handle.attrs
    problem = None
    if not attrs.get("complete", False):
        problem = "incomplete"
    elif attrs.get("schema") != schema:
        problem = f"schema {attrs.get('schema')!r}, expected {schema!r}"
    elif schema_version is not None and int(attrs.get("schema_version", -1)) != int(schema_version):
        problem = f"schema version {attrs.get('schema_version')}, expected {schema_version}"
    if problem:
        handle.close()
        raise ArtefactError(f"{path}: {problem}")
    return handle


def read_dataset(group, name, units=None, shape=None, dtype_kind=None):
    """Read a dataset and check its unit and shape.

    Parameters
    ----------
    group : h5py.Group
        Where to read.
    name : str
        Dataset path.
    units : str, optional
        Required value of the ``units`` attribute.
    shape : tuple, optional
        Required shape; ``None`` entries match any length.
    dtype_kind : str, optional
        Allowed numpy dtype kinds, e.g. ``"fc"``.

    Returns
    -------
    numpy.ndarray

    Raises
    ------
    ArtefactError
        If the dataset is missing or its unit, shape or type differ.
    """
    where = f"{group.file.filename}:{group.name.rstrip('/')}/{name}"
    if name not in group:
        raise ArtefactError(f"{where}: dataset missing")
    dset = group[name]
    if units is not None and dset.attrs.get("units") != units:
        raise ArtefactError(f"{where}: units {dset.attrs.get('units')!r}, expected {units!r}")
    if shape is not None:
        if len(dset.shape) != len(shape) or any(s is not None and s != d for s, d in zip(shape, dset.shape)):
            raise ArtefactError(f"{where}: shape {dset.shape}, expected {shape}")
    data = dset[()]
    if dtype_kind is not None and np.asarray(data).dtype.kind not in dtype_kind:
        raise ArtefactError(f"{where}: dtype {np.asarray(data).dtype}, expected kind in {dtype_kind!r}")
    if isinstance(data, np.ndarray) and data.dtype == object:
        data = np.array([v.decode() if isinstance(v, bytes) else v for v in data.ravel()]).reshape(data.shape)
    return data
