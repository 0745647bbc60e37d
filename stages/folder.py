"""A study folder's own records: the study it belongs to (``study.json``) and the lock of a run (``.lock``).

**The study record.** The first command that builds artefacts in a folder (``run``, ``map``,
``stability``, ``geometry --out``) records there the resolved study (every section after the
defaults, the presets, the study file and ``--set``) and how it was given (``study.json``,
indented JSON). Later commands on that folder use it when they are given no configuration
(neither ``--config``, ``--quick`` nor ``--set``); a command given a configuration that resolves
to another study is refused (:class:`squealcore.errors.InputError`, exit status 2) with the
first differences named, unless it is ``run --change-study``, which records the new study and
rebuilds what it makes stale. A folder without a record (made before records existed, or by the
library) takes the study of the command line, as before.

**The lock.** A command that builds artefacts holds ``.lock`` in the folder while it runs: a JSON
object with the process id, host, start time and command. The file is created atomically (written
under a temporary name, then hard-linked into place, which fails if a lock exists), removed on every
exit path, and a lock whose process no longer runs on this host (or whose process id now belongs to
a process started after the lock) is stale and taken over. Commands that only read (``status``,
``export``) take no lock: they read complete artefacts only, which the atomic writes guarantee.
"""

from __future__ import annotations

import contextlib
import datetime as _dt
import json
import logging
import os
import socket
import stat
from pathlib import Path

from squealcore.artefacts import atomic_output, canonical_json, package_version, readable_json
from squealcore.errors import InputError

logger = logging.getLogger(__name__)

#: The study record's file name, in the study folder.
RECORD = "study.json"
#: Layout version of the study record.
RECORD_VERSION = 1
#: Largest study record read (bytes): a record is a few kB.
RECORD_MAX_BYTES = 16 << 20
#: The lock's file name, in the study folder.
LOCK = ".lock"
#: Differences named in a refusal.
SHOWN_DIFFERENCES = 2


class FolderError(RuntimeError):
    """A fault of the study folder (exit status 1)."""


class FolderBusy(FolderError):
    """Another process holds the folder's lock (exit status 1)."""


class RecordError(FolderError):
    """The folder's study record cannot be read (exit status 1)."""


#: Sub-folders the commands write into (``variants/<label>`` too).
SUBFOLDERS = ("cases", "radiation", "sounds", "figures", "exports", "variants", "maps", "confirm")


def check_no_links(out):
    """Refuse symbolic links where the commands write inside the folder ``out`` (its sub-folders and
    the variant folders): files would land outside ``--out``.

    Raises
    ------
    FolderError
        Naming the link and where it points.
    """
    out = Path(out)
    candidates = [out / name for name in SUBFOLDERS]
    variants = out / "variants"
    if variants.is_dir() and not variants.is_symlink():
        try:
            candidates += sorted(variants.iterdir())
        except OSError:
            pass
    for path in candidates:
        if path.is_symlink():
            try:
                target = os.readlink(path)
            except OSError:
                target = "?"
            raise FolderError(f"{path}: is a symbolic link (to {target}); the commands write only inside --out: "
                              "replace the link by a folder")


# --------------------------------------------------------------------------- the study record


def record_path(out):
    """Path of the study record of the folder ``out``."""
    return Path(out) / RECORD


def _normal(study):
    """``study`` as the record holds it (JSON types: lists, floats, strings)."""
    return json.loads(canonical_json(study))


def read_record(out):
    """The study record of ``out`` (``{"study": ..., "given": ...}``), or None if it has none.

    Raises
    ------
    RecordError
        If the record is not a regular file, too large, not JSON or not a record.
    """
    path = record_path(out)
    try:
        info = path.lstat()
    except (FileNotFoundError, NotADirectoryError):
        return None
    if not stat.S_ISREG(info.st_mode):
        raise RecordError(f"{path}: the folder's study record is not a regular file")
    if info.st_size > RECORD_MAX_BYTES:
        raise RecordError(f"{path}: the folder's study record is larger than {RECORD_MAX_BYTES >> 20} MB")
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError) as exc:
        raise RecordError(f"{path}: the folder's study record is unreadable ({exc.__class__.__name__}); remove it "
                          "to give the folder the study of the next run") from None
    if not isinstance(record, dict) or not isinstance(record.get("study"), dict):
        raise RecordError(f"{path}: not a study record (no 'study' table); remove it to give the folder the study "
                          "of the next run")
    return record


def write_record(out, study, given):
    """Record ``study`` as the folder's study (atomically; nothing is written if it is already recorded).

    Parameters
    ----------
    out : Path
        The study folder (created if missing).
    study : dict
        The resolved, validated study.
    given : dict
        How it was given: ``config`` (path or None), ``quick`` (bool), ``set`` (list of str).

    Returns
    -------
    bool
        Whether the record was written.
    """
    try:
        current = read_record(out)
    except RecordError:
        current = None
    if current is not None and current["study"] == _normal(study):
        return False
    text = readable_json({"record_version": RECORD_VERSION, "code_version": package_version(),
                          "created": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
                          "given": given, "study": study}) + "\n"
    with atomic_output(record_path(out)) as partial:
        partial.write_text(text, encoding="utf-8")
    return True


def restore_record(out, text):
    """Put back the record ``text`` (bytes) of the folder ``out`` (None: remove the record)."""
    path = record_path(out)
    if text is None:
        with contextlib.suppress(FileNotFoundError):
            path.unlink()
        return
    with atomic_output(path) as partial:
        partial.write_bytes(text)


_ABSENT = object()


def differences(recorded, given, prefix=""):
    """``[(dotted key, recorded value, given value)]`` where two studies differ (absent: ``_ABSENT``)."""
    found = []
    for key in sorted(set(recorded) | set(given)):
        a, b = recorded.get(key, _ABSENT), given.get(key, _ABSENT)
        name = f"{prefix}{key}"
        if isinstance(a, dict) and isinstance(b, dict):
            found += differences(a, b, name + ".")
        elif a != b:
            found.append((name, a, b))
    return found


def _show(value, limit=60):
    if value is _ABSENT:
        return "unset"
    text = json.dumps(value, ensure_ascii=True)
    return text if len(text) <= limit else text[:limit - 3] + "..."


def describe_differences(found):
    """``time.duration is 0.05 there, 2.0 here (and 3 more)``."""
    shown = "; ".join(f"{key} is {_show(a)} there, {_show(b)} here" for key, a, b in found[:SHOWN_DIFFERENCES])
    more = len(found) - SHOWN_DIFFERENCES
    return shown + (f" (and {more} more difference(s))" if more > 0 else "")


def describe_given(given):
    """``given with --quick --set time.duration=2.0`` from a record's ``given``."""
    if not isinstance(given, dict):
        return "given elsewhere"
    words = (["--config", str(given["config"])] if given.get("config") else []) + (["--quick"] if given.get("quick")
                                                                                    else [])
    for assignment in given.get("set") or []:
        words += ["--set", str(assignment)]
    return "given with " + " ".join(words) if words else "the default study"


def given_configuration(config, quick, assignments):
    """How a command line gave its study (recorded with it)."""
    return {"config": None if config is None else str(Path(config).resolve()), "quick": bool(quick),
            "set": list(assignments)}


def folder_study(out, config=None, quick=False, assignments=(), *, change=False, ignore=(), keep=(), command="run"):
    """The study a command works on in the folder ``out``: the recorded one, or the command line's.

    Parameters
    ----------
    out : str or Path or None
        The study folder (None: no folder, the command line's study).
    config, quick, assignments
        The command line's ``--config``, ``--quick`` and ``--set``.
    change : bool
        ``run --change-study``: take the command line's study even if the folder records another.
    ignore : tuple of str
        Prefixes of dotted keys whose differences are allowed (``stability`` screens any friction
        and creepage on the folder's structures: ``contact.``, ``simulation.``, ...); the command
        line's study is used.
    keep : tuple of str
        Dotted keys compared even though a prefix of ``ignore`` covers them (``contact.geometry``).
    command : str
        The command's name, for the message.

    Returns
    -------
    (dict, dict or None)
        The validated study, and the folder's record (None if it has none).

    Raises
    ------
    InputError
        If the command line gives a study other than the recorded one (field ``--out``).
    RecordError
        If the record is unreadable.
    """
    from stages.config import load_study, validate  # lazy: every package's parameters (pipeline.py's start-up)

    record = None if out is None else read_record(out)
    given = bool(config or quick or assignments)
    if record is None or (given and change):
        return load_study(config, quick, assignments), record
    if not given:
        study = record["study"]
        try:
            validate(study)
        except InputError as exc:
            raise InputError("--out", f"{record_path(out)}: the recorded study is not valid for this version "
                                      f"({exc.field}: {exc.message}); give the study with --config/--quick/--set "
                                      "and run --change-study") from None
        logger.info("study of %s: recorded in %s", out, record_path(out))
        return study, record
    study = load_study(config, quick, assignments)
    found = [d for d in differences(record["study"], _normal(study))
             if d[0] in keep or not d[0].startswith(tuple(ignore))]
    if found:
        remedy = ("leave out --config, --quick and --set to use the folder's study, choose another --out"
                  + (", or pass --change-study to rebuild the folder for this study" if command == "run" else ""))
        raise InputError("--out", f"{out} holds another study ({RECORD}, {describe_given(record.get('given'))}): "
                                  f"{describe_differences(found)}; {remedy}")
    return study, record


# --------------------------------------------------------------------------- the lock


def lock_path(out):
    """Path of the lock of the folder ``out``."""
    return Path(out) / LOCK


def _host():
    return socket.gethostname()


def _process_start(pid):
    """Start time (Unix s) of process ``pid`` on this machine, or None if it cannot be told (not Linux)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        ticks = int(fields[19])
        boot = next(float(line.split()[1]) for line in Path("/proc/stat").read_text().splitlines()
                    if line.startswith("btime "))
        return boot + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration):
        return None


def _alive(pid):
    """Whether process ``pid`` runs on this machine."""
    if not isinstance(pid, int) or pid <= 0:
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        return True
    except (OSError, OverflowError):
        return False
    return True


def read_holder(out):
    """The lock's record (dict) of the folder ``out``; None if there is no lock, ``{}`` if unreadable."""
    path = lock_path(out)
    try:
        with open(path, "rb") as handle:
            data = handle.read(1 << 16)
    except FileNotFoundError:
        return None
    except OSError:
        return {}
    try:
        holder = json.loads(data.decode("utf-8"))
    except ValueError:
        return {}
    return holder if isinstance(holder, dict) else {}


def holder_stale(holder):
    """Whether a lock's record names a process that no longer holds it (this host only; other hosts: never)."""
    if not holder or holder.get("host") != _host():
        return False
    pid = holder.get("pid")
    if not _alive(pid):
        return True
    started = holder.get("started_unix")
    begun = _process_start(pid)
    # the process id now belongs to a process started after the lock was taken
    return isinstance(started, (int, float)) and begun is not None and begun > started + 2.0


def describe_holder(holder):
    """``process 1234 on host node7 since 2026-12-03T17:00:00+00:00 (run --quick)``."""
    if not holder:
        return "an unreadable lock"
    from squealcore.errors import printable  # lazy: tiny
    command = f" ({printable(holder['command'])})" if holder.get("command") else ""
    return (f"process {printable(holder.get('pid'))} on host {printable(holder.get('host'))} since "
            f"{printable(holder.get('started'))}{command}")


class FolderLock:
    """The lock of a study folder, held by one process that builds artefacts in it.

    Use :meth:`acquire` and :meth:`release` (or ``with FolderLock(out, "run"):``). Releasing a lock
    that is not held does nothing, so it may be called on every exit path.
    """

    def __init__(self, out, command=""):
        self.out = Path(out)
        self.path = lock_path(out)
        self.command = command
        self.held = False
        self.record = None

    def __enter__(self):
        self.acquire()
        return self

    def __exit__(self, *exc):
        self.release()
        return False

    def acquire(self):
        """Take the lock (the folder is created if missing).

        Raises
        ------
        FolderBusy
            Naming the holder, if another live process holds it.
        """
        if self.held:
            return
        check_no_links(self.out)
        self.out.mkdir(parents=True, exist_ok=True)
        now = _dt.datetime.now(_dt.timezone.utc)
        self.record = {"pid": os.getpid(), "host": _host(), "started": now.isoformat(timespec="seconds"),
                       "started_unix": now.timestamp(), "command": self.command}
        for _ in range(5):
            if self._create():
                self.held = True
                return
            holder = read_holder(self.out)
            if holder is None:  # released meanwhile
                continue
            if not holder:  # unreadable: stale once it is old (a lock is complete when it appears)
                try:
                    age = _dt.datetime.now().timestamp() - self.path.stat().st_mtime
                except OSError:
                    continue
                if age < 10.0:
                    raise FolderBusy(f"{self.path}: the folder is locked (unreadable lock file); if no run is going, "
                                     "remove it")
            elif not holder_stale(holder):
                raise FolderBusy(f"{self.out}: another run holds this folder: {describe_holder(holder)}; wait for it "
                                 f"to finish (read commands such as status may run meanwhile), or, if it no longer "
                                 f"runs, remove {self.path}")
            else:
                logger.warning("taking over the stale lock of %s (no longer running)", describe_holder(holder))
            self._take_over(holder)
        raise FolderBusy(f"{self.path}: could not take the folder's lock (other processes keep taking it)")

    def _create(self):
        """Create the lock with this process's record; False if a lock exists."""
        temporary = self.path.with_name(f".lock.{os.getpid()}.new")
        try:
            temporary.write_text(json.dumps(self.record) + "\n", encoding="utf-8")
            try:
                os.link(temporary, self.path)
            except FileExistsError:
                return False
            except OSError:  # a file system without hard links: exclusive creation instead
                try:
                    fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o644)
                except FileExistsError:
                    return False
                with os.fdopen(fd, "w", encoding="utf-8") as handle:
                    handle.write(json.dumps(self.record) + "\n")
            return True
        finally:
            with contextlib.suppress(OSError):
                temporary.unlink()

    def _take_over(self, holder):
        """Remove a stale lock, unless another process replaced it meanwhile."""
        aside = self.path.with_name(f".lock.{os.getpid()}.stale")
        try:
            os.rename(self.path, aside)
        except FileNotFoundError:
            return
        try:
            moved = json.loads(aside.read_text(encoding="utf-8"))
        except (OSError, ValueError):
            moved = {}
        if moved != holder:  # a live process's lock was moved aside: put it back
            with contextlib.suppress(OSError):
                os.link(aside, self.path)
        with contextlib.suppress(OSError):
            aside.unlink()

    def release(self):
        """Remove the lock if this process holds it (never raises)."""
        if not self.held:
            return
        self.held = False
        try:
            holder = read_holder(self.out)
            if holder and holder.get("pid") == os.getpid() and holder.get("host") == _host():
                self.path.unlink()
        except OSError as exc:
            logger.warning("could not remove the lock %s: %s", self.path, exc)
