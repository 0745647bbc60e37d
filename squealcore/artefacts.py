"""HDF5 artefacts: atomic writing, provenance, checksums, freshness checks and checked reading.

Every stage of the pipeline writes one HDF5 file. Its root attributes record

``schema``
    the artefact kind, e.g. ``"wheel_modes"``;
``schema_version``
    an integer bumped whenever the layout changes;
``params_sha256``
    SHA-256 of the canonical JSON of the configuration sections the stage reads;
``config``
    those sections themselves, as indented JSON text (when the writer passes them);
``inputs``
    JSON object mapping each upstream artefact's file name to the SHA-256 of its bytes;
``code_version``, ``code_commit``, ``created``
    package version, git commit of the source tree (only when the package runs from a git
    checkout) and UTC time of writing;
``checksums``
    JSON object mapping every dataset's path (e.g. ``"moving/kernel"``) to the SHA-256 of its
    dtype, shape and data (:func:`dataset_sha256`), and every other root attribute, as
    ``"@name"`` (e.g. ``"@L_F2"``, ``"@params_sha256"``), to the SHA-256 of its value
    (:func:`attribute_sha256`), so that an edited metric or provenance is found like an edited
    dataset; written after the data;
``complete``
    ``True``, written last.

A file is written to a temporary name in the destination folder and moved into place with
:func:`os.replace` only after it has been closed successfully, so an interrupted run never leaves
a half-written file under the final name. An HDF5 artefact is built in memory (HDF5's ``core``
driver) and its image written to the temporary file by Python, so that a full disk, a lost
permission or a vanished file system is one :class:`OSError` naming the artefact (never an HDF5
error stack or a crash of the library's cache); a file written by another library (gmsh, meshio,
matplotlib) is not published if the disk is full once it is written (it may be truncated:
:func:`atomic_output`). Temporary names carry the writer's process id and host
(``.{name}.{pid}-{host}.{random}.tmp[suffix]``), so that :func:`remove_stale_temporaries` can tell
the leftovers of killed runs from files still being written. Every dataset carries a ``units``
attribute.

:func:`freshness` verifies the checksums (one pass over the data), and :func:`read_dataset`
verifies the checksum of every dataset it reads, so damaged bytes are reported with the file and
dataset they are in instead of surfacing as wrong results.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import errno
import functools
import hashlib
import importlib.metadata
import json
import logging
import os
import re
import socket
import stat
import subprocess
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

logger = logging.getLogger(__name__)

__version__ = "0.1.0"
"""Version of this source tree, recorded when the distribution's metadata cannot be found (keep
equal to ``pyproject.toml``; a test checks it)."""

DISTRIBUTION = "curve-squeal"

_SOURCE_ROOT = Path(__file__).resolve().parent.parent
"""The folder holding the project's top-level packages (the git checkout, when there is one)."""

_BLOCK_BYTES = 1 << 24
"""Checksums read datasets in blocks of about this many bytes (memory bound for large arrays)."""

_HOST = re.sub(r"[^A-Za-z0-9]+", "-", socket.gethostname())[:32].strip("-") or "host"
"""This machine's name as it appears in temporary file names."""

_TEMPORARY = re.compile(r"^\.(?P<name>.+)\.(?P<pid>\d+)-(?P<host>[A-Za-z0-9-]*)\.(?P<token>[a-z0-9_]+)"
                        r"\.tmp(?:\.[A-Za-z0-9]+)*$")
"""Names of the temporary files made by :func:`write_artefact` and :func:`atomic_output`."""

_LEGACY_TEMPORARY = re.compile(r"^\..+\.[a-z0-9_]{8}\.tmp$")
"""Temporary artefacts written before names carried the process id (removed by age only)."""

STALE_TEMPORARY_AGE = 86400.0
"""Age (s) after which any temporary file is considered abandoned, whatever its process id."""


class ArtefactError(RuntimeError):
    """An artefact is missing, unreadable, damaged, of the wrong kind or of an unexpected layout."""


# --------------------------------------------------------------------------------------------
# Provenance


@functools.lru_cache(maxsize=None)
def package_version() -> str:
    """Installed version of the ``curve-squeal`` distribution (``__version__`` if not installed).

    Returns
    -------
    str
    """
    try:
        return importlib.metadata.version(DISTRIBUTION)
    except importlib.metadata.PackageNotFoundError:
        return __version__


@functools.lru_cache(maxsize=None)
def source_commit():
    """Git commit of the source tree the package runs from, or ``None`` outside a git checkout.

    Asks ``git rev-parse`` (local, no network) once per process. The commit is only reported
    when the checkout's top folder is the folder holding the package, so that a package
    installed inside some other repository is not credited with that repository's commit.

    Returns
    -------
    str or None
        The full hexadecimal commit hash.
    """
    try:
        completed = subprocess.run(["git", "rev-parse", "--show-toplevel", "HEAD"], cwd=_SOURCE_ROOT,
                                   capture_output=True, text=True, timeout=10, check=True,
                                   env={**os.environ, "GIT_OPTIONAL_LOCKS": "0"})
    except (OSError, subprocess.SubprocessError) as exc:
        logger.debug("no git commit for %s: %s", _SOURCE_ROOT, exc)
        return None
    lines = completed.stdout.split()
    if len(lines) != 2 or Path(lines[0]).resolve() != _SOURCE_ROOT:
        return None
    commit = lines[1].lower()
    return commit if re.fullmatch(r"[0-9a-f]{40}|[0-9a-f]{64}", commit) else None


# --------------------------------------------------------------------------------------------
# Canonical JSON and hashes


def _plain(value):
    """``value`` with numpy scalars, tuples and paths turned into JSON types."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Path):
        return str(value)
    return value


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
    return json.dumps(_plain(obj), sort_keys=True, separators=(",", ":"), ensure_ascii=True)


def readable_json(obj) -> str:
    """Indented JSON text of ``obj`` with sorted keys (for attributes people read).

    Parameters
    ----------
    obj : object
        JSON-serialisable mapping/sequence/scalar (numpy scalars are converted).

    Returns
    -------
    str
    """
    return json.dumps(_plain(obj), sort_keys=True, indent=2, ensure_ascii=False)


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


def _item_bytes(item) -> bytes:
    """Bytes of one element of an object array (variable-length strings or arrays)."""
    if isinstance(item, bytes):
        return item
    if isinstance(item, str):
        return item.encode("utf-8")
    array = np.asarray(item)
    return f"{array.dtype.str}{array.shape}".encode("ascii") + array.tobytes()


def _update_digest(digest, block):
    """Feed the values of ``block`` (as read by h5py) into ``digest``."""
    if isinstance(block, h5py.Empty):
        return
    array = np.asarray(block)
    if array.dtype.kind == "O":
        for item in array.ravel():
            data = _item_bytes(item)
            digest.update(len(data).to_bytes(8, "little"))
            digest.update(data)
    else:
        digest.update(np.ascontiguousarray(array).tobytes())


def _new_digest(dset):
    digest = hashlib.sha256()
    digest.update(f"{dset.dtype.str}|{dset.shape}|".encode("ascii"))
    return digest


def dataset_sha256(dset) -> str:
    """SHA-256 (hex) of a dataset's dtype, shape and values, read in blocks.

    The hash covers the text ``"{dtype.str}|{shape}|"`` followed by the values in C order: the
    raw bytes of numeric data, or for variable-length data each element's length (8 bytes,
    little-endian) and UTF-8 bytes. It is the hash of the data as h5py returns it, so it does not
    depend on the storage layout, chunking or compression.

    Parameters
    ----------
    dset : h5py.Dataset

    Returns
    -------
    str
    """
    digest = _new_digest(dset)
    if dset.shape is None or dset.ndim == 0 or dset.shape[0] == 0:
        _update_digest(digest, dset[()])
        return digest.hexdigest()
    row_bytes = max(1, dset.dtype.itemsize * int(np.prod(dset.shape[1:], dtype=np.int64)))
    rows = max(1, _BLOCK_BYTES // row_bytes)
    for start in range(0, dset.shape[0], rows):
        _update_digest(digest, dset[start:start + rows])
    return digest.hexdigest()


def _values_sha256(dset, values) -> str:
    """SHA-256 as :func:`dataset_sha256`, of values already read from ``dset`` with ``dset[()]``."""
    digest = _new_digest(dset)
    _update_digest(digest, values)
    return digest.hexdigest()


def _dataset_names(handle):
    """Paths (without the leading ``/``) of every dataset in an open file."""
    names = []
    handle.visititems(lambda name, obj: names.append(name) if isinstance(obj, h5py.Dataset) else None)
    return names


#: Root attributes the checksums do not cover (written after them).
UNCHECKED_ATTRIBUTES = ("checksums", "complete")


def attribute_sha256(value) -> str:
    """SHA-256 (hex) of an attribute's value as h5py reads it: its dtype, shape and bytes (strings:
    UTF-8)."""
    digest = hashlib.sha256()
    if isinstance(value, bytes):
        value = value.decode("utf-8", "surrogateescape")
    if isinstance(value, str):
        digest.update(b"str|" + value.encode("utf-8", "surrogateescape"))
        return digest.hexdigest()
    array = np.asarray(value)
    digest.update(f"{array.dtype.str}|{array.shape}|".encode("ascii"))
    _update_digest(digest, array)
    return digest.hexdigest()


def attribute_checksums(handle):
    """``{"@name": SHA-256}`` of the root attributes of an open file the checksums cover."""
    return {f"@{name}": attribute_sha256(handle.attrs[name]) for name in handle.attrs
            if name not in UNCHECKED_ATTRIBUTES}


def attribute_problems(handle, recorded):
    """Root attributes that differ from the ``"@name"`` checksums in ``recorded`` (none recorded:
    an artefact of the older layout, nothing to compare)."""
    expected = {k: v for k, v in recorded.items() if k.startswith("@")}
    if not expected:
        return []
    try:
        actual = attribute_checksums(handle)
    except Exception as exc:  # damaged attribute storage
        return [f"attributes unreadable ({exc.__class__.__name__})"]
    problems = [f"attribute {k[1:]} missing" for k in sorted(set(expected) - set(actual))]
    problems += [f"unexpected attribute {k[1:]}" for k in sorted(set(actual) - set(expected))]
    problems += [f"attribute {k[1:]} changed (checksum mismatch)" for k in sorted(set(expected) & set(actual))
                 if expected[k] != actual[k]]
    return problems


def _recorded_checksums(handle):
    """The ``checksums`` attribute of an open file as a dict, ``None`` if it has none.

    Raises
    ------
    ArtefactError
        If the attribute is not a JSON object of strings.
    """
    text = handle.attrs.get("checksums")
    if text is None:
        return None
    try:
        recorded = json.loads(text)
    except (TypeError, ValueError):
        recorded = None
    if not isinstance(recorded, dict) or not all(isinstance(v, str) for v in recorded.values()):
        raise ArtefactError(f"{handle.filename}: checksums attribute unreadable")
    return recorded


def integrity_problems(handle, limit=4):
    """Compare an open artefact's datasets with its recorded checksums.

    Parameters
    ----------
    handle : h5py.File
        Open artefact.
    limit : int
        Report at most this many problems (and how many more there are).

    Returns
    -------
    list of str
        Empty when every recorded dataset is present and intact and no other dataset exists;
        otherwise e.g. ``"no checksums (older layout)"``, ``"dataset rail/x missing"``,
        ``"unexpected dataset extra"``, ``"checksum mismatch in moving/kernel"``,
        ``"dataset receptance unreadable (OSError)"``.
    """
    try:
        recorded = _recorded_checksums(handle)
    except ArtefactError:
        return ["checksums attribute unreadable"]
    if recorded is None:
        return ["no checksums (older layout)"]
    try:
        present = _dataset_names(handle)
    except Exception as exc:  # damaged group structure: h5py raises various types
        return [f"unreadable structure ({exc.__class__.__name__})"]
    problems = attribute_problems(handle, recorded)
    recorded = {k: v for k, v in recorded.items() if not k.startswith("@")}
    problems += [f"dataset {name} missing" for name in sorted(set(recorded) - set(present))]
    problems += [f"unexpected dataset {name}" for name in sorted(set(present) - set(recorded))]
    for name in sorted(set(recorded) & set(present)):
        try:
            actual = dataset_sha256(handle[name])
        except Exception as exc:  # damaged chunks: decompression and read errors of any type
            problems.append(f"dataset {name} unreadable ({exc.__class__.__name__})")
            continue
        if actual != recorded[name]:
            problems.append(f"checksum mismatch in {name}")
    if len(problems) > limit:
        problems = problems[:limit] + [f"{len(problems) - limit} more problem(s)"]
    return problems


# --------------------------------------------------------------------------------------------
# Writing


def _temporary_file(path, suffix=""):
    """Create an empty temporary file next to ``path`` named after it, this process and host.

    An OSError names ``path``, the file asked for, not the temporary one.
    """
    try:
        fd, name = tempfile.mkstemp(prefix=f".{path.name}.{os.getpid()}-{_HOST}.", suffix=f".tmp{suffix}",
                                    dir=path.parent)
    except OSError as exc:
        raise OSError(exc.errno, f"cannot write here ({exc.strerror})", str(path)) from None
    os.close(fd)
    return name


#: ``errno`` values of faults of the environment's resources (a full disk, a quota, a permission or
#: file system lost): raised as :class:`OSError` naming the file, they stop a run (a case that meets
#: one is not "failed": the rerun after the fault is repaired resumes).
RESOURCE_ERRNOS = frozenset(getattr(errno, name) for name in ("ENOSPC", "EDQUOT", "EROFS", "EACCES", "EPERM", "EIO",
                                                                "ESTALE", "EFBIG", "ENOTCONN", "ENODEV")
                            if hasattr(errno, name))

#: Free bytes below which a file written by another library is taken as possibly truncated.
MIN_FREE_BYTES = 4096


def resource_fault(exc, path):
    """``exc`` as an :class:`OSError` naming ``path`` if it is a fault of the environment's resources,
    else None (HDF5 reports them as ``RuntimeError``/``OSError`` texts with ``errno = 28``)."""
    number = exc.errno if isinstance(exc, OSError) else None
    if number is None:
        match = re.search(r"errno = (\d+)|\[Errno (\d+)\]", str(exc))
        if match:
            number = int(match.group(1) or match.group(2))
        elif "No space left on device" in str(exc):
            number = errno.ENOSPC
    if number not in RESOURCE_ERRNOS:
        return None
    return OSError(number, os.strerror(number), str(path))


def free_bytes(folder):
    """Bytes available to this user on the file system of ``folder`` (None if it cannot be told)."""
    try:
        info = os.statvfs(folder)
    except (OSError, AttributeError):
        return None
    root = hasattr(os, "geteuid") and os.geteuid() == 0  # root may write into the blocks reserved for it
    return (info.f_bfree if root else info.f_bavail) * info.f_frsize


def write_image(tmp_name, image):
    """Write the bytes ``image`` to the (created) temporary file ``tmp_name``."""
    with open(tmp_name, "wb") as handle:
        handle.write(image)


def _publish(tmp_name, path):
    """Give a finished temporary file the permissions of a normally created one and move it into place."""
    mask = os.umask(0)
    os.umask(mask)
    os.chmod(tmp_name, 0o666 & ~mask)
    os.replace(tmp_name, path)


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
def write_artefact(path, schema, schema_version, params_sha256, inputs=None, *, config=None):
    """Write an HDF5 artefact atomically, with its provenance and checksums.

    Use as ``with write_artefact(path, "wheel_modes", 1, sha, inputs, config=sections) as f: ...``.
    The file is created under a temporary name in the same folder and given its provenance
    attributes; after the body, the checksum of every dataset is recorded, then ``complete``,
    and the closed file is moved to ``path``. If the body raises, the temporary file is removed
    and ``path`` is left as it was.

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
    config : dict, optional
        The resolved configuration sections the stage read (``{section: table}``), stored as
        indented JSON text in the attribute ``config``.

    Yields
    ------
    h5py.File
    """
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    tmp_name = _temporary_file(path)
    try:
        # in memory (nothing written by HDF5 itself), the image written below by Python
        with h5py.File(tmp_name, "w", driver="core", backing_store=False) as handle:
            handle.attrs["schema"] = schema
            handle.attrs["schema_version"] = int(schema_version)
            handle.attrs["params_sha256"] = params_sha256
            handle.attrs["inputs"] = canonical_json(inputs or {})
            if config is not None:
                handle.attrs["config"] = readable_json(config)
            handle.attrs["code_version"] = package_version()
            commit = source_commit()
            if commit is not None:
                handle.attrs["code_commit"] = commit
            handle.attrs["created"] = _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds")
            yield handle
            handle.flush()
            handle.attrs["checksums"] = canonical_json({**{name: dataset_sha256(handle[name])
                                                           for name in _dataset_names(handle)},
                                                        **attribute_checksums(handle)})
            handle.attrs["complete"] = True
            handle.flush()
            image = handle.id.get_file_image()
        write_image(tmp_name, image)
        del image
        _publish(tmp_name, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.remove(tmp_name)
        fault = resource_fault(exc, path) if isinstance(exc, Exception) else None
        if fault is not None:
            raise fault from None
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
    tmp_name = _temporary_file(path, path.suffix if suffix is None else suffix)
    try:
        yield Path(tmp_name)
        # writers such as gmsh do not report a full disk: a file written onto one may be truncated
        free = free_bytes(path.parent)
        if free is not None and free < MIN_FREE_BYTES:
            raise OSError(errno.ENOSPC, f"{os.strerror(errno.ENOSPC)} (the file written may be incomplete; "
                                        "not published)", str(path))
        _publish(tmp_name, path)
    except BaseException as exc:
        with contextlib.suppress(OSError):
            os.remove(tmp_name)
        fault = resource_fault(exc, path) if isinstance(exc, Exception) and not (
            isinstance(exc, OSError) and exc.filename == str(path)) else None
        if fault is not None:
            raise fault from None
        raise


def _pid_alive(pid) -> bool:
    """Whether a process with this id runs on this machine (``True`` when it cannot be told)."""
    if os.name == "nt":  # os.kill would terminate the process there
        return True
    if pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # exists, owned by another user
        return True
    except (OSError, OverflowError):
        return False
    return True


def _abandoned(name, mtime, now, max_age):
    """Whether a file called ``name`` (modified at ``mtime``) is a temporary file nobody writes."""
    match = _TEMPORARY.match(name)
    if match is None:
        return _LEGACY_TEMPORARY.match(name) is not None and now - mtime > max_age
    if now - mtime > max_age:
        return True
    return match["host"] == _HOST and not _pid_alive(int(match["pid"]))


def remove_stale_temporaries(folder, max_age=STALE_TEMPORARY_AGE):
    """Remove the temporary files of killed runs below ``folder``.

    A temporary file (named by :func:`write_artefact` or :func:`atomic_output`) is removed when
    the process that made it, on this machine, no longer runs, or when it is older than
    ``max_age`` (process ids are reused; files made on other machines are only removed by age).
    Temporary artefacts of the older naming (without process id) are removed by age only.

    Parameters
    ----------
    folder : str or Path
        The study folder (searched recursively; symbolic links are not followed).
    max_age : float
        Age (s, from the modification time) after which any temporary file is removed.

    Returns
    -------
    list of Path
        The files removed. Files that vanish or cannot be removed are skipped with a warning;
        this function does not raise for a single file.
    """
    removed = []
    now = time.time()
    for root, _, files in os.walk(folder):
        for name in files:
            candidate = Path(root) / name
            try:
                info = candidate.lstat()
                if not stat.S_ISREG(info.st_mode) or not _abandoned(name, info.st_mtime, now, max_age):
                    continue
                candidate.unlink()
            except FileNotFoundError:
                continue
            except OSError as exc:
                logger.warning("could not remove stale temporary file %s: %s", candidate, exc)
                continue
            logger.info("removed stale temporary file %s", candidate)
            removed.append(candidate)
    return removed


# --------------------------------------------------------------------------------------------
# Checking and reading


def freshness(path, schema, schema_version, params_sha256, inputs):
    """Tell whether an artefact is up to date and intact.

    Never raises: every problem is a reason. Checks, in order: the path is a readable HDF5 file,
    of the expected kind and version, complete, written from the same configuration and upstream
    artefacts, and every dataset matches its recorded checksum (one pass over the data).

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
        Whether it is fresh, and why not (empty when fresh), e.g. ``"missing"``, ``"is a
        directory"``, ``"not a file"``, ``"unreadable (OSError)"``, ``"foreign artefact ..."``,
        ``"incomplete file"``, ``"parameters changed"``, ``"inputs changed"``, ``"no checksums
        (older layout)"``, ``"dataset rail/x missing"``, ``"checksum mismatch in moving/kernel"``.
    """
    path = Path(path)
    try:
        info = path.stat()
    except FileNotFoundError:
        return False, "missing"
    except OSError as exc:
        return False, f"unreadable ({exc.__class__.__name__})"
    if stat.S_ISDIR(info.st_mode):
        return False, "is a directory"
    if not stat.S_ISREG(info.st_mode):
        return False, "not a file"
    try:
        with h5py.File(path, "r") as handle:
            attrs = dict(handle.attrs)
            reason = _attribute_problem(attrs, schema, schema_version, params_sha256, inputs)
            if reason:
                return False, reason
            problems = integrity_problems(handle)
    except Exception as exc:  # h5py reports damaged files with several exception types
        return False, f"unreadable ({exc.__class__.__name__})"
    if problems:
        return False, "; ".join(problems)
    return True, ""


def _attribute_problem(attrs, schema, schema_version, params_sha256, inputs):
    """Why the root attributes of an artefact do not match what is expected ("" if they do)."""
    if "schema" not in attrs:
        return "foreign HDF5 file (no schema attribute)"
    if attrs.get("schema") != schema:
        return f"foreign artefact (schema {attrs.get('schema')!r}, expected {schema!r})"
    if not attrs.get("complete", False):
        return "incomplete file"
    if int(attrs.get("schema_version", -1)) != int(schema_version):
        return f"schema version {attrs.get('schema_version')} != {schema_version}"
    if attrs.get("params_sha256") != params_sha256:
        return "parameters changed"
    if attrs.get("inputs") != canonical_json(inputs or {}):
        return "inputs changed"
    return ""


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
    """Read a dataset and check its unit, shape and (if the file has checksums) its checksum.

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
        Naming the file and the dataset, if the dataset is missing, unreadable, damaged (its
        checksum differs from the one recorded in the file, or the file records none for it),
        or its unit, shape or type differ.
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
    try:
        data = dset[()]
    except Exception as exc:  # damaged chunks: decompression and read errors of any type
        raise ArtefactError(f"{where}: unreadable ({exc.__class__.__name__}: {exc}); the file is damaged, "
                            "rerun the stage that writes it") from exc
    recorded = _recorded_checksums(group.file)
    if recorded is not None:
        key = dset.name.lstrip("/")
        if key not in recorded:
            raise ArtefactError(f"{where}: unexpected dataset (not in the file's checksums)")
        if _values_sha256(dset, data) != recorded[key]:
            raise ArtefactError(f"{where}: checksum mismatch (the file is damaged; rerun the stage that writes it)")
    if dtype_kind is not None and np.asarray(data).dtype.kind not in dtype_kind:
        raise ArtefactError(f"{where}: dtype {np.asarray(data).dtype}, expected kind in {dtype_kind!r}")
    if isinstance(data, np.ndarray) and data.dtype == object:
        data = np.array([v.decode() if isinstance(v, bytes) else v for v in data.ravel()]).reshape(data.shape)
    return data
