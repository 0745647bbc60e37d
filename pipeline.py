"""Command line of the curve-squeal toolkit (``python pipeline.py ...`` or ``curve-squeal ...``).

``run`` builds every stage of the study whose artefact is missing or stale; ``status`` tells which
are fresh and why the others are not; ``export`` writes artefacts in formats other programs read;
``contact`` solves a stand-alone contact problem. The stage graph is in ``stages/engine.py``.

Exit status: 0 success (``status``: everything fresh); 1 a fault of the environment (permission,
disk, unreachable scheduler, damaged artefact, failed case; ``status``: something is stale);
2 bad input (one line ``error: <field>: <what is wrong and what is allowed>``); 130 interrupted
(Ctrl-C; rerunning the same command resumes), 143 terminated (SIGTERM), 129 hung up (SIGHUP), both
handled as Ctrl-C; 141 the output pipe was closed.

A folder belongs to one study (``stages/folder.py``): the first ``run`` records it (``study.json``),
later commands without ``--config``/``--quick``/``--set`` use it, and one given another study is
refused (exit 2; ``run --change-study`` rebuilds). ``run``, ``map``, ``stability`` and
``geometry --out`` hold the folder's lock (``.lock``) while they build; ``status`` and ``export``
only read, never build.
"""

from __future__ import annotations

import os

# The dense linear algebra here is many small problems (waveguide eigenproblems per frequency,
# sector and harmonic eigenproblems): threaded BLAS only adds contention, and sweeps get their
# parallelism from Dask workers. Must be set before numpy loads its BLAS; the user's own
# settings win.
for _variable in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_variable, "1")

import argparse  # noqa: E402 (after the thread settings above)
import contextlib  # noqa: E402
import logging  # noqa: E402
import re  # noqa: E402
import signal  # noqa: E402
import socket  # noqa: E402
import sys  # noqa: E402
import threading  # noqa: E402
import time  # noqa: E402
import traceback  # noqa: E402
from pathlib import Path  # noqa: E402

from squealcore.errors import InputError, printable  # noqa: E402
from squealcore.library_output import LOG_FORMAT, route_library_warnings  # noqa: E402

# Start-up: a command imports only what it uses. The modules behind the commands are imported by
# the functions below when their command is chosen (marked ``# lazy:``). Importing all of them at
# the top made every command, even ``--version``, pay 2-4 s of imports (python -X importtime,
# 2-core machine at load 2-3: this module 2.1-4.1 s before, 0.02-0.06 s now); cumulative import
# times of the command modules, same conditions: cli.maps 3.6 s (scipy.signal, scipy.stats),
# exports 2.2 s, cli.geometry 1.7 s, cli.stability 1.7 s, stages.engine 1.3 s,
# stages.config 1.3 s, contact.cli 1.3 s, squealcore.artefacts 0.44 s (h5py).


def _engine():
    """The stage engine (:mod:`stages.engine`), imported on first use."""
    from stages import engine  # lazy: h5py, dask helpers, every stage module: 1.3 s (see the top)
    return engine


def _loaded(module, name):
    """Class ``name`` of ``module`` if that module has been imported, else a class nothing is an instance of.

    ``except`` clauses use it for the errors of modules a command may never import: an error of a
    module that was not imported cannot have been raised.
    """
    loaded = sys.modules.get(module)
    return getattr(loaded, name) if loaded is not None else _NeverRaised


class _NeverRaised(Exception):
    """Stands for the error class of a module that was not imported (never raised)."""


logger = logging.getLogger("pipeline")

#: Exit statuses (see the module docstring).
EXIT_OK, EXIT_FAULT, EXIT_INPUT, EXIT_INTERRUPTED, EXIT_PIPE = 0, 1, 2, 130, 141
#: Signals handled as Ctrl-C (a batch scheduler's time limit sends SIGTERM, a closed terminal
#: SIGHUP); the exit status is 128 + the signal's number (130, 143, 129).
STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


def interrupted_status(signum):
    """Exit status after a stop signal: 128 + its number (130 for Ctrl-C)."""
    return 128 + int(signum)


class Interrupted(KeyboardInterrupt):
    """Ctrl-C, SIGTERM or SIGHUP: every ``except KeyboardInterrupt`` cleans up as after Ctrl-C.

    Attributes
    ----------
    signum : int
        The signal received.
    """

    def __init__(self, message="", signum=signal.SIGINT):
        super().__init__(message)
        self.signum = signum


def _raise_interrupted(signum, frame):
    """Handler of SIGTERM and SIGHUP in the main thread: raise :class:`Interrupted`."""
    raise Interrupted("", signum)


@contextlib.contextmanager
def stop_signals_as_interrupts():
    """SIGTERM and SIGHUP raise :class:`Interrupted` in the main thread while the block runs
    (elsewhere, and for signals this process ignores, nothing changes)."""
    previous = {}
    if threading.current_thread() is threading.main_thread():
        for signum in STOP_SIGNALS:
            if signum == signal.SIGINT:
                continue
            current = signal.getsignal(signum)
            if current in (signal.SIG_IGN, None):  # nohup: the user asked to ignore it
                continue
            previous[signum] = current
            signal.signal(signum, _raise_interrupted)
    try:
        yield
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)
#: Seconds the main thread has, after Ctrl-C, to start unwinding before the process is stopped
#: from the watch thread (it may be inside compiled code that Python cannot interrupt).
INTERRUPT_GRACE = 0.7


class EnvironmentFault(RuntimeError):
    """A fault of the environment, not of the input (exit status 1)."""


# --------------------------------------------------------------------------- argument parsing


class _Parser(argparse.ArgumentParser):
    """Argument parser whose errors are :class:`InputError` (one line, exit status 2)."""

    def error(self, message):
        match = re.match(r"argument ([^:]+): (.*)", message, re.S)
        if match:
            raise InputError(match.group(1).split("/")[-1], match.group(2))
        raise InputError(self.prog.split()[-1], message)


def _common_arguments():
    common = _Parser(add_help=False)
    chatter = common.add_mutually_exclusive_group()
    chatter.add_argument("-v", "--verbose", action="store_true", help="log what every stage does (INFO)")
    chatter.add_argument("-q", "--quiet", action="store_true", help="print errors only, no progress bar")
    common.add_argument("--debug", action="store_true", help="show the traceback of an error")
    return common


def _study_arguments(parser):
    parser.add_argument("--config", help="study TOML file merged over the defaults (studies/paper.toml)")
    parser.add_argument("--out", default="out", help="output folder (default: out)")
    parser.add_argument("--quick", action="store_true", help="coarse, fast preset (studies/quick.toml)")
    parser.add_argument("--set", dest="assignments", action="append", default=[], metavar="SECTION.KEY=VALUE",
                        help="override one value (read as TOML; a bare word is a string); repeatable")


def add_run_args(parser):
    """Arguments of ``run``."""
    _study_arguments(parser)
    parser.add_argument("--change-study", action="store_true",
                        help="the folder records another study: record this one and rebuild what it makes stale")
    parser.add_argument("--until", help=f"last stage to build ({', '.join(_engine().ALL_STAGE_NAMES)})")
    parser.add_argument("--jobs", type=int, default=1, help="run cases in parallel on a local Dask cluster (>= 1)")
    parser.add_argument("--scheduler", help="address of a Dask scheduler you control, e.g. tcp://host:8786")


def add_status_args(parser):
    """Arguments of ``status``."""
    _study_arguments(parser)


EXPORT_TARGETS = ("receptances", "modes", "rail", "case", "xdmf")


def _export_options(parser):
    _study_arguments(parser)
    parser.add_argument("--dir", help="folder for the exported files (default: OUT/exports, with --variant "
                                      "OUT/exports/LABEL)")
    parser.add_argument("--file", help="modes: output .vtu (default: OUT/wheel_modes.vtu, with --variant "
                                       "OUT/variants/LABEL/wheel_modes.vtu)")
    parser.add_argument("--variant", metavar="LABEL", help="modes, receptances, rail: the structural variant of a "
                                                           "sweep to export (a folder name in OUT/variants, or its "
                                                           "part before the hash)")
    parser.add_argument("--modes", type=int, nargs="*", help="modes: mode numbers (1-based); default all")
    parser.add_argument("--case", help="case: the case id (as in OUT/cases/<id>.h5)")
    parser.add_argument("--steps", type=int, nargs="*", default=[], help="case: time steps whose contact "
                                                                           "tractions are exported")


#: The options each export target reads; one given to another target is refused, not ignored
#: (``--variant`` is checked by ``exports.choose_variant``, which says why a target has none).
EXPORT_OPTIONS = {
    "modes": ("file", "modes"),
    "receptances": ("dir",),
    "rail": ("dir",),
    "case": ("dir", "case", "steps"),
    "xdmf": (),  # the sidecars are written next to the artefacts they describe
}


def check_export_options(args):
    """Refuse export options the target does not read, ``--file`` naming a folder and ``--dir`` a file.

    Raises
    ------
    InputError
        Naming the option, before anything is built.
    """
    used = EXPORT_OPTIONS[args.target]
    for option in ("dir", "file", "modes", "case", "steps"):
        value = getattr(args, option)
        if value not in (None, []) and option not in used:
            readers = [target for target, options in EXPORT_OPTIONS.items() if option in options]
            raise InputError(f"--{option}", f"does not apply to export {args.target} (it is read by export "
                                            f"{' / '.join(readers)}); leave it out")
    if args.file and Path(args.file).is_dir():
        raise InputError("--file", f"must name a file, {args.file!r} is a folder")
    if args.file and (Path(args.file).suffix.lower() in (".h5", ".hdf5") or _is_hdf5(args.file)):
        raise InputError("--file", f"{args.file!r} is (or would be taken for) an HDF5 artefact; an export never "
                                   "writes over one: name a .vtu file")
    if args.dir and Path(args.dir).exists() and not Path(args.dir).is_dir():
        raise InputError("--dir", f"must name a folder, {args.dir!r} is a file")


def _is_hdf5(path):
    """Whether ``path`` is an existing regular file that starts with the HDF5 signature."""
    try:
        if not Path(path).is_file():
            return False
        with open(path, "rb") as handle:
            return handle.read(8) == b"\x89HDF\r\n\x1a\n"
    except OSError:
        return False


def add_export_args(parser):
    """Arguments of ``export``."""
    parser.add_argument("target", choices=EXPORT_TARGETS, help="what to export")
    _export_options(parser)


def add_export_modes_args(parser):
    """Arguments of ``export-modes`` (the former name of ``export modes``)."""
    _export_options(parser)
    parser.set_defaults(target="modes")


# --------------------------------------------------------------------------- checks before running


_ADDRESS = re.compile(r"(?:(tcp|tls)://)?(\[[0-9A-Fa-f:.]+\]|[A-Za-z0-9](?:[A-Za-z0-9.-]*[A-Za-z0-9])?):(\d{1,5})")


def scheduler_endpoint(address):
    """Host and port of a Dask scheduler address ``[tcp://|tls://]HOST:PORT``.

    Raises
    ------
    InputError
        If the address is malformed.
    """
    match = _ADDRESS.fullmatch(address.strip())
    if not match or not 1 <= int(match.group(3)) <= 65535:
        raise InputError("--scheduler", f"expected tcp://HOST:PORT or tls://HOST:PORT with a port in [1, 65535], "
                                        f"got {address!r}")
    return match.group(2).strip("[]"), int(match.group(3))


def check_scheduler(address, timeout=None):
    """Fail fast (:class:`EnvironmentFault`) if nothing listens at a scheduler address.

    ``timeout`` (s) defaults to the engine's ``CONNECT_TIMEOUT``.
    """
    if timeout is None:
        timeout = _engine().CONNECT_TIMEOUT
    host, port = scheduler_endpoint(address)
    try:
        with socket.create_connection((host, port), timeout=timeout):
            pass
    except OSError as exc:
        raise EnvironmentFault(f"--scheduler: cannot reach {address} within {timeout:g} s "
                               f"({exc.strerror or exc.__class__.__name__})") from None


def check_output_folder(path, writing=True):
    """Refuse an output folder that is a file, lies below a file or cannot be written.

    Raises
    ------
    EnvironmentFault
        Naming ``--out`` and the offending path.
    """
    path = Path(path)
    if path.exists() and not path.is_dir():
        raise EnvironmentFault(f"--out: {path} is a file, not a folder")
    existing = path
    while not existing.exists():
        if existing.parent == existing:
            break
        existing = existing.parent
    if not existing.is_dir():
        raise EnvironmentFault(f"--out: {path} lies below {existing}, which is a file")
    if writing and not os.access(existing, os.W_OK | os.X_OK):
        raise EnvironmentFault(f"--out: {existing} is not writable (permission denied)")
    if writing and path.is_dir():
        from stages.folder import check_no_links  # lazy: loaded with the engine
        check_no_links(path)


_TEMPORARY = re.compile(r"\..+\.[a-z0-9_]{8}\.[A-Za-z0-9]+")


def remove_run_temporaries(out_dir, since):
    """Remove the temporary files (``.<name>.<random>.<suffix>``, see squealcore/artefacts.py) that
    this run created in ``out_dir`` and could not remove itself (a killed worker, compiled code
    stopped by Ctrl-C); returns how many were removed."""
    removed = 0
    root = Path(out_dir)
    if not root.is_dir():
        return 0
    for path in root.rglob(".*"):
        try:
            if _TEMPORARY.fullmatch(path.name) and path.is_file() and path.stat().st_mtime >= since - 1.0:
                path.unlink()
                removed += 1
        except OSError:  # gone meanwhile, or not ours to remove
            continue
    return removed


# --------------------------------------------------------------------------- interruption


class InterruptWatch:
    """Stop the process promptly on Ctrl-C even while the main thread is in compiled code.

    Python runs its SIGINT handler (raising KeyboardInterrupt) only between bytecodes; a case in
    a compiled loop would delay it by minutes. The signal also wakes a watch thread (through
    :func:`signal.set_wakeup_fd`); if the main thread has not started unwinding within
    :data:`INTERRUPT_GRACE` s, the thread removes this run's temporary files, says what finished
    and ends the process with status 130.

    Parameters
    ----------
    out_dir : Path
        Study folder whose temporary files are removed.
    finished : list of str
        What the run has finished so far (filled by the engine).
    release : callable, optional
        Releases the folder's lock; the temporary files are removed only while it is held
        (``holds()``).
    holds : callable, optional
        Whether this run holds the folder's lock (default: always).
    """

    def __init__(self, out_dir, finished, release=None, holds=None):
        self.out_dir = out_dir
        self.finished = finished
        self.release = release
        self.holds = holds
        self.started = time.time()
        self.unwinding = threading.Event()
        self._reader, self._writer = socket.socketpair()
        self._writer.setblocking(False)
        self._previous = None

    def __enter__(self):
        self._previous = signal.set_wakeup_fd(self._writer.fileno(), warn_on_full_buffer=False)
        threading.Thread(target=self._watch, name="interrupt-watch", daemon=True).start()
        return self

    def __exit__(self, *exc):
        signal.set_wakeup_fd(self._previous)
        self.unwinding.set()
        self._writer.close()
        return False

    def _watch(self):
        try:
            while True:
                data = self._reader.recv(16)
                if not data:
                    return
                received = [signum for signum in STOP_SIGNALS if signum in data]
                if received:
                    break
        except OSError:
            return
        if self.unwinding.wait(INTERRUPT_GRACE):
            return
        stop_child_processes()
        if self.holds is None or self.holds():
            remove_run_temporaries(self.out_dir, self.started)
        if self.release is not None:
            self.release()
        sys.stderr.write(f"error: {interrupted_message(self.finished, received[0])}\n")
        sys.stderr.flush()
        os._exit(interrupted_status(received[0]))


def child_processes():
    """Process ids of this process's children (Linux ``/proc``; empty elsewhere)."""
    me = os.getpid()
    children = []
    proc = Path("/proc")
    if not proc.is_dir():
        return children
    for entry in proc.iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except (OSError, IndexError):  # ended meanwhile
            continue
        if int(fields[1]) == me:
            children.append(int(entry.name))
    return children


def stop_child_processes():
    """Kill the processes this one started (local Dask workers, also those still starting)."""
    for pid in child_processes():
        try:
            os.kill(pid, signal.SIGKILL)
        except OSError:  # already gone
            pass


#: How the message after a stop signal names it.
SIGNAL_WORDS = {signal.SIGINT: "interrupted"}
SIGNAL_WORDS.update({getattr(signal, name): word for name, word in (("SIGTERM", "terminated (SIGTERM)"),
                                                                     ("SIGHUP", "hung up (SIGHUP)"))
                     if hasattr(signal, name)})


def interrupted_message(finished, signum=signal.SIGINT):
    """The line printed after Ctrl-C (SIGTERM, SIGHUP): what finished, and how to resume."""
    stages = [name for name in finished if not name.startswith("simulate:")]
    cases = len(finished) - len(stages)
    parts = stages + ([f"{cases} case(s)"] if cases else [])
    done = ", ".join(parts) if parts else "nothing new"
    return (f"{SIGNAL_WORDS.get(signum, 'interrupted')}: finished in this run: {done}; finished artefacts are kept, "
            "rerun the same command to resume")


# --------------------------------------------------------------------------- commands


def _progress(args):
    return not args.quiet


def _load_study(args, command="run", change=False):
    """The study of the folder ``--out`` (its record, ``stages/folder.py``) or of ``--config``,
    ``--quick`` and ``--set``; another study than the folder's is refused (InputError)."""
    from stages.folder import folder_study  # lazy: every package's parameters: 1.3 s (see the top)
    return folder_study(args.out, args.config, args.quick, args.assignments, change=change, command=command)[0]


def _command_line():
    """The command line as recorded in a lock (one line, at most 200 characters)."""
    return printable(" ".join(["pipeline.py", *sys.argv[1:]]), limit=200)


def run_command(args):
    """``run``: build what is stale; returns the exit status."""
    if args.jobs < 1:
        raise InputError("--jobs", f"must be an integer >= 1, got {args.jobs}")
    if args.scheduler is not None:
        scheduler_endpoint(args.scheduler)
    engine = _engine()
    if args.until is not None:
        engine.required_stages(args.until)
    out = Path(args.out)
    check_output_folder(out)
    study = _load_study(args, "run", change=args.change_study)
    if args.scheduler is not None:
        check_scheduler(args.scheduler)
    if args.jobs > 1 and args.scheduler is None:
        # killed local workers leave multiprocessing semaphores to the resource tracker, which
        # cleans them up; its warning about them is noise after Ctrl-C
        sys.warnoptions.append("ignore:resource_tracker:UserWarning")
    from stages.folder import FolderLock, given_configuration, write_record  # lazy: loaded with the engine
    lock = FolderLock(out, _command_line())

    previous = []  # the record replaced by this run, restored if a stage finds the new study's input bad

    def start(cases):
        """After the cases are planned (every input checked), before anything is written: lock, record."""
        lock.acquire()
        path = out / "study.json"
        before = path.read_bytes() if path.is_file() else None
        if write_record(out, study, given_configuration(args.config, args.quick, args.assignments)):
            previous.append(before)
            logger.info("recorded the study of %s in %s", out, path)

    finished = []
    watch = InterruptWatch(out, finished, lock.release, lambda: lock.held)
    try:
        with watch if threading.current_thread() is threading.main_thread() else _Null():
            try:
                # isolate: a case runs in a worker process, so Ctrl-C is answered at once even
                # while the case is in compiled code
                engine.run(study, out, args.until, progress=_progress(args), jobs=args.jobs,
                           scheduler=args.scheduler, record=finished, isolate=True, on_start=start)
            except engine.CasesFailed:
                lock.release()
                _summary(args, study, out, finished)
                raise
    except KeyboardInterrupt as exc:
        watch.unwinding.set()
        stop_child_processes()
        if lock.held:  # the temporary files in the folder are this run's only while it holds the lock
            remove_run_temporaries(out, watch.started)
        lock.release()
        signum = getattr(exc, "signum", signal.SIGINT)
        raise Interrupted(interrupted_message(finished, signum), signum) from None
    except BaseException as exc:
        if lock.held:
            remove_run_temporaries(out, watch.started)
            if isinstance(exc, InputError) and previous:  # the study was not adopted: the folder keeps its own
                from stages.folder import restore_record  # lazy: loaded with the engine
                restore_record(out, previous[0])
        raise
    finally:
        lock.release()
    _summary(args, study, out, finished)
    return EXIT_OK


class _Null:
    def __enter__(self):
        return self

    def __exit__(self, *exc):
        return False


def _summary(args, study, out, finished):
    """Where the results are, what to open first, and every squealing case with its WAV file."""
    logger.info("rebuilt: %s", ", ".join(finished) or "nothing (all fresh)")
    engine = _engine()
    if args.quiet:
        return
    if args.until is not None and args.until not in ("simulate", "report"):
        print(f"stages up to {args.until} are in {out}")
        return
    cases = engine.plan_cases(study, out)
    results = engine.case_results(cases, out)
    report = out / "report.md"
    where = f"results in {out}" + (f" - open {report} first" if report.exists() else "")
    print(where)
    squealing = [r for r in results if r["squeal"]]
    classes = [r["oscillation"] or "squeal" for r in squealing]
    print(f"{len(results)} of {len(cases)} case(s) computed, {len(squealing)} meet(s) the squeal criterion"
          + (f" (L_F2 > {study['simulation']['squeal_threshold']:g} dB, limit cycle): {classes.count('squeal')} "
             f"squeal at >= {study['simulation']['squeal_min_frequency']:g} Hz, "
             f"{classes.count('low-frequency oscillation')} low-frequency oscillation(s):" if squealing else ""))
    for result, kind in zip(squealing, classes):
        sound = f", sound {result['wav']}" if result["wav"] else ""
        bouncing = ""
        if result["regime"] == "bouncing":  # not plain squeal: the wheel leaves the rail or hammers it
            from stages.summary import case_regime  # lazy: the summary module imports the metrics
            bouncing = f", but {case_regime(result).describe('mu ')}"
        print(f"  {result['case_id']}: {kind} at {result['squeal_frequency']:.0f} Hz, "
              f"L_F2 = {result['L_F2']:.1f} dB{bouncing}{sound}")


def status_command(args):
    """``status``: one aligned line per stage, case and the report (and, in a folder with a map, per
    map structure, rail fit and chunk); 0 if all fresh, else 1."""
    check_output_folder(args.out, writing=False)
    study = _load_study(args, "status")
    from stages.folder import describe_holder, holder_stale, read_holder  # lazy: loaded with the engine
    holder = read_holder(args.out)
    if holder is not None and not holder_stale(holder):
        logger.warning("%s is being built by %s: what it has not finished yet shows as stale", args.out,
                       describe_holder(holder))
    rows = _engine().status(study, args.out)
    if (Path(args.out) / "maps").is_dir():  # the map's cached structures, rail fits and chunks
        from stages.maps import map_status  # lazy: the maps' modules (scipy.signal, scipy.stats), a folder with a map only
        rows += map_status(study, args.out)
    width = max(len(name) for name, _, _ in rows)
    for name, fresh, reason in rows:
        print(f"{name:<{width}}  {'fresh' if fresh else 'stale'}{'' if fresh else '  (' + reason + ')'}")
    sys.stdout.flush()
    return EXIT_OK if all(fresh for _, fresh, _ in rows) else EXIT_FAULT


def export_command(args):
    """``export TARGET``: write the files of artefacts that are fresh (it never builds: a missing or
    stale artefact is named, exit status 1)."""
    check_export_options(args)
    out = Path(args.out)
    check_output_folder(out)
    study = _load_study(args, "export")
    engine = _engine()
    import exports as export_library  # lazy: the writers of the exports: 2.2 s (see the top)
    variant = export_library.choose_variant(study, out, args.target, args.variant)
    if args.dir:
        target_dir = Path(args.dir)
    else:
        target_dir = out / "exports" / variant.label if variant.label else out / "exports"

    def build(until):
        """Check that the structural stages up to ``until`` are fresh (of the chosen variant only, in a
        sweep); an export never builds them (:class:`EnvironmentFault` naming the first that is not)."""
        for stage in engine.required_stages(until):
            if not stage.used(variant.study):
                continue
            fresh, reason, _, _ = engine.inspect(stage, variant.study, variant.folder)
            if not fresh:
                raise EnvironmentFault(f"{variant.folder / stage.filename}: {reason}; export {args.target} reads it "
                                       f"and never builds it: build it with 'pipeline.py run --until {stage.name} "
                                       f"--out {out}'")

    if args.target == "modes":
        build("wheel-modes")
        path = Path(args.file) if args.file else variant.folder / "wheel_modes.vtu"
        count = export_library.export_modes(variant.folder, path, args.modes)
        written = [f"{path} ({count} modes)"]
    elif args.target == "receptances":
        build("wheel-greens")
        build("rail-greens")
        written = export_library.export_receptances(variant.folder, target_dir)
    elif args.target == "rail":
        build("rail-mesh")
        written = export_library.export_rail(variant.study, variant.folder, target_dir)
    elif args.target == "case":
        if not args.case:
            raise InputError("--case", "export case needs --case ID (a file name in OUT/cases without .h5)")
        written = export_library.export_case(study, out, args.case, target_dir, tuple(args.steps))
    else:
        written = export_library.write_xdmf_sidecars(out)
    if not args.quiet:
        for path in written:
            print(f"wrote {path}")
    return EXIT_OK


def _own(add_args, func):
    """Loader of a command defined in this module."""
    return lambda: (add_args, func)


def _contact_command():
    from contact.lean_start import lean_start  # lazy: --version and --help import no physics package
    lean_start()  # before numba sets up itself: ~0.2 s less (contact/lean_start.py)
    import contact.cli as contact_cli  # lazy: contact models, numba: 1.3 s (see the top)
    return contact_cli.add_args, contact_cli.run_command


def _geometry_command():
    import cli.geometry as geometry_cli  # lazy: study parameters, profiles: 1.7 s (see the top)
    return geometry_cli.add_args, geometry_cli.command


def _curve_command():
    import cli.curve as curve_cli  # lazy: study parameters, profiles: 1.7 s, as geometry (see the top)
    return curve_cli.add_args, curve_cli.command


def _curve_map_command():
    import cli.curve_map as curve_map_cli  # lazy: engine, screen and curving: as stability (see the top)
    return curve_map_cli.add_args, curve_map_cli.command


def _stability_command():
    import cli.stability as stability_cli  # lazy: engine and screen: 1.7 s (see the top)
    return stability_cli.add_args, stability_cli.command


def _map_command():
    import cli.maps as maps_cli  # lazy: scipy.signal, scipy.stats: 3.6 s (see the top)
    return maps_cli.add_args, maps_cli.command


#: name -> (help, loader); ``loader()`` imports the command's module and returns (add_args, func).
COMMANDS = {
    "run": ("build the stale stages of a study", _own(add_run_args, run_command)),
    "status": ("which stages are fresh, and why the others are not (exit 1 if any is stale)",
               _own(add_status_args, status_command)),
    "export": ("write artefacts for other programs (CSV, VTU, XDMF)", _own(add_export_args, export_command)),
    "export-modes": ("the same as 'export modes'", _own(add_export_modes_args, export_command)),
    "contact": ("stand-alone contact problem from a TOML case file", _contact_command),
    "geometry": ("wheel/rail contact geometry (position, angle, radius, Hertz) at the operating displacement",
                 _geometry_command),
    "curve": ("each wheel's operating point (creepages, load, contact) in a curve, from the bogie's steady curving",
              _curve_command),
    "curve-map": ("squeal risk over curve radius, speed and friction: each wheel of the bogie screened",
                  _curve_map_command),
    "stability": ("linear stability screen of the study's configuration (wheel on the flexible rail)",
                  _stability_command),
    "map": ("squeal maps: the stability screen over the study's [map.grid] for every wheel model", _map_command),
}


class _VersionAction(argparse.Action):
    """``--version``: print ``curve-squeal <version>`` and exit (the version is looked up only then)."""

    def __init__(self, option_strings, dest=argparse.SUPPRESS, default=argparse.SUPPRESS, help=None):
        super().__init__(option_strings, dest=dest, default=default, nargs=0, help=help)

    def __call__(self, parser, namespace, values, option_string=None):
        from squealcore.artefacts import package_version  # lazy: h5py: 0.44 s (see the top)
        print(f"curve-squeal {package_version()}")
        parser.exit()


def chosen_commands(argv):
    """The command named in ``argv`` (its first word not starting with ``-``), as a list of 0 or 1 name.

    The top-level options (``--help``, ``--version``) take no value, so the first other word is
    the command.
    """
    return [word for word in argv if not word.startswith("-")][:1]


def build_parser(commands=None):
    """The argument parser: one subparser per entry of :data:`COMMANDS`.

    Parameters
    ----------
    commands : collection of str, optional
        Only these commands' modules are imported and only their subparsers get their arguments
        (the others are listed, with their help, for ``--help`` and for the choice of command);
        by default every command's.
    """
    parser = _Parser(prog=Path(sys.argv[0]).name if sys.argv and sys.argv[0] else "pipeline.py",
                     description="Railway curve squeal from geometry: build a study's stages, tell which are "
                                 "fresh, export artefacts, solve stand-alone contact problems.",
                     epilog="Exit status: 0 ok; 1 fault of the environment or failed case (status: something "
                            "stale); 2 bad input; 130 interrupted, 143 SIGTERM, 129 SIGHUP (rerun to resume); "
                            "141 output pipe closed.")
    parser.add_argument("--version", action=_VersionAction, help="show program's version number and exit")
    subparsers = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    common = _common_arguments()
    for name, (help_text, loader) in COMMANDS.items():
        sub = subparsers.add_parser(name, help=help_text, description=help_text, parents=[common])
        if commands is None or name in commands:
            add_args, func = loader()
            add_args(sub)
            sub.set_defaults(func=func)
    return parser


# --------------------------------------------------------------------------- logging and errors


class _TqdmHandler(logging.StreamHandler):
    """Log records to stderr without breaking an active progress bar; tracebacks only with --debug."""

    def __init__(self, tracebacks):
        super().__init__(sys.stderr)
        self.tracebacks = tracebacks

    def emit(self, record):
        if not self.tracebacks and record.exc_info:
            record = logging.makeLogRecord({**record.__dict__, "exc_info": None, "exc_text": None})
        try:
            text = self.format(record)
            bars = sys.modules.get("tqdm")  # a progress bar can only be active if tqdm was imported
            if bars is not None:
                bars.tqdm.write(text, file=sys.stderr)
            else:
                sys.stderr.write(text + "\n")
        except Exception:  # logging must never raise (closed stream at shutdown)
            self.handleError(record)


def configure_logging(args):
    """Library logs at WARNING (``--verbose``: INFO, ``--quiet``: ERROR); Python warnings of the
    libraries (numba, scipy, numpy) go to the log, shown with ``--verbose`` only
    (:func:`squealcore.library_output.route_library_warnings`).

    Dask's own chatter is set to ERROR by the engine where it starts Dask
    (:func:`stages.engine.quiet_dask_logs`).
    """
    level = logging.ERROR if args.quiet else logging.INFO if args.verbose else logging.WARNING
    handler = _TqdmHandler(args.debug)
    handler.setFormatter(logging.Formatter(LOG_FORMAT))
    logging.basicConfig(level=level, handlers=[handler], force=True)
    route_library_warnings(level <= logging.INFO)


#: numba's error when no folder can hold its cache of compiled kernels (``cache=True``): it looks
#: in NUMBA_CACHE_DIR, next to the sources (``__pycache__``), then in the user's cache folder.
_NO_NUMBA_CACHE = re.compile(r"cannot cache function .*no locator available")


def _fail(message, status, debug):
    """Print ``error: <message>`` (one line: control characters escaped, see
    :func:`squealcore.errors.printable`) and return ``status``; the traceback with ``--debug``."""
    if debug:
        traceback.print_exc()
    print(f"error: {printable(message)}", file=sys.stderr)
    return status


def _os_error_message(exc):
    where = exc.filename if exc.filename is not None else ""
    if exc.filename2 is not None:
        where = f"{where} -> {exc.filename2}"
    what = exc.strerror or str(exc)
    return f"{where}: {what}" if where else what


def main(argv=None):
    """Run the command line.

    Parameters
    ----------
    argv : list of str, optional
        Arguments (default ``sys.argv[1:]``).

    Returns
    -------
    int
        Exit status: 0 ok, 1 fault of the environment (or ``status``: something stale), 2 bad
        input, 130 interrupted (143 SIGTERM, 129 SIGHUP), 141 output pipe closed.
    """
    argv = list(sys.argv[1:] if argv is None else argv)
    debug = "--debug" in argv
    try:
        args = build_parser(chosen_commands(argv)).parse_args(argv)
        debug = args.debug
        configure_logging(args)
        with stop_signals_as_interrupts():
            return args.func(args)
    except SystemExit as exc:  # --help, --version
        return exc.code if isinstance(exc.code, int) else EXIT_OK
    except InputError as exc:
        return _fail(f"{exc.field}: {exc.message}", EXIT_INPUT, debug)
    except KeyboardInterrupt as exc:
        stop_child_processes()
        signum = getattr(exc, "signum", signal.SIGINT)
        return _fail(str(exc) or interrupted_message([], signum), interrupted_status(signum), debug)
    except BrokenPipeError:
        # the reader went away (status | head): silence the final flush of stdout too
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_PIPE
    except _loaded("stages.engine", "CasesFailed") as exc:
        return _fail(str(exc), EXIT_FAULT, debug)
    except (_loaded("squealcore.artefacts", "ArtefactError"), EnvironmentFault,
            _loaded("stages.folder", "FolderError")) as exc:
        return _fail(str(exc), EXIT_FAULT, debug)
    except ConnectionError as exc:
        return _fail(str(exc), EXIT_FAULT, debug)
    except OSError as exc:
        return _fail(_os_error_message(exc), EXIT_FAULT, debug)
    except Exception as exc:  # a bug: one line, the traceback with --debug
        if isinstance(exc, RuntimeError) and _NO_NUMBA_CACHE.search(str(exc)):  # not a bug: a read-only install
            return _fail("no writable folder for numba's cache of compiled kernels (the package's __pycache__ "
                         "folders and the user's cache folder are read-only): set NUMBA_CACHE_DIR to a writable "
                         "folder", EXIT_FAULT, debug)
        return _fail(f"internal error: {exc.__class__.__name__}: {exc} (rerun with --debug for the traceback)",
                     EXIT_FAULT, debug)


#: Commands that hold nothing to finish once :func:`main` returns (no cluster, no child process, every
#: file written and closed): their process ends at once, without the interpreter's teardown, which
#: spends longer releasing numba's compiled kernels and LLVM than a small contact problem takes
#: (docs/benchmarks.md, *Start-up*, *Ending at once*; benchmarks/startup.py).
QUICK_EXIT_COMMANDS = frozenset({"contact"})


def _exit_now(status):
    """End the process with ``status`` at once: logging and the standard streams flushed, no exit handlers.

    If the reader of stdout went away before the last of it was flushed, a successful command's
    status becomes ``EXIT_PIPE``, as when the reader goes away while the command prints.
    """
    logging.shutdown()
    try:
        sys.stdout.flush()
    except BrokenPipeError:
        if status == EXIT_OK:
            status = EXIT_PIPE
    sys.stderr.flush()
    os._exit(status)


def entry_point():
    """Console entry (``curve-squeal`` and ``python pipeline.py``): exit with :func:`main`'s status.

    After Ctrl-C the process ends at once (:func:`os._exit`), without the exit handlers of Dask,
    which would wait for a cluster whose workers were just stopped; so does a command of
    :data:`QUICK_EXIT_COMMANDS`, whose work is all written when :func:`main` returns.
    """
    argv = sys.argv[1:]
    status = main(argv)
    if status in {interrupted_status(signum) for signum in STOP_SIGNALS} or set(chosen_commands(argv)) & QUICK_EXIT_COMMANDS:
        _exit_now(status)
    sys.exit(status)


if __name__ == "__main__":
    entry_point()
