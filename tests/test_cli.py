"""The command line as a user meets it: bad input and faults, Ctrl-C, status, version, entry point.

Every entry of the catalogue runs ``python pipeline.py ...`` as a subprocess and checks the exit
status (2 bad input, 1 fault of the environment), that stderr holds no traceback but one line
naming the field or file, and that the output folder is unchanged (the SHA-256 of every file,
hidden ones included, before and after) - or, for a damaged artefact that can be rebuilt,
repaired. The catalogue runs concurrently (each entry is a separate process); the quick
structural artefacts are built once per module and copied.
"""

import fcntl
import hashlib
import importlib.metadata
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import meshio
import pytest

import pipeline
from stages import engine
from stages.config import load_study
from exports.modes import mode_name
from exports.variants import study_variants
from stages.wheel import read_modes

REPO = Path(__file__).resolve().parent.parent
ENV = dict(os.environ, PYTHONPATH=str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""), MPLBACKEND="Agg")
#: Interaction duration of the module's study, s: long enough that a case is still running when
#: the SIGINT test interrupts it (a point-contact case takes about as long as it simulates).
DURATION = "2.0"
QUICK = ["--quick", "--set", f"time.duration={DURATION}"]
ONE_CASE = '[sweep]\n"contact.friction" = [0.3]\n'
IS_ROOT = hasattr(os, "geteuid") and os.geteuid() == 0


def cli(*argv, timeout=300, **kwargs):
    """Run ``python pipeline.py ARGV`` in the repository; returns the CompletedProcess."""
    return subprocess.run([sys.executable, str(REPO / "pipeline.py"), *map(str, argv)], cwd=REPO, env=ENV,
                          capture_output=True, text=True, timeout=timeout, **kwargs)


def snapshot(folder):
    """``{relative path: SHA-256}`` of every file below ``folder`` (None if it does not exist)."""
    folder = Path(folder)
    if not folder.exists():
        return None
    if folder.is_file():
        return {".": hashlib.sha256(folder.read_bytes()).hexdigest()}
    return {str(p.relative_to(folder)): hashlib.sha256(p.read_bytes()).hexdigest()
            for p in sorted(folder.rglob("*")) if p.is_file()}


@pytest.fixture(scope="module")
def structure(copy_quick_structures, tmp_path_factory):
    """The quick study's structural artefacts: the session's (conftest.py), brought up to date for
    this module's study by the command line (they are fresh: the structures do not read
    ``time.duration``)."""
    out = copy_quick_structures(tmp_path_factory.mktemp("structure") / "out")
    for last in ("wheel-greens", "rail-greens"):
        result = cli("run", *QUICK, "--quiet", "--out", out, "--until", last, timeout=900)
        assert result.returncode == 0, result.stderr
    return out


# --------------------------------------------------------------------------- the catalogue


@dataclass
class Entry:
    """One bad input or fault: how to set it up, the command and what must happen."""

    name: str
    argv: list
    status: int
    mentions: tuple
    files: dict = field(default_factory=dict)  # name in the entry's folder -> text or bytes
    out: str = "out"  # output folder, relative to the entry's folder
    prepare: object = None  # callable(entry folder, structure folder)
    outcome: str = "unchanged"  # or "repaired": the rebuilt folder is fresh again
    stream: str = "stderr"  # where the mentions are: one "error:" line on stderr, or stdout
    marks: tuple = ()


def _free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _copy_structure(folder, structure):
    shutil.copytree(structure, folder / "out")


def _truncate(name):
    def prepare(folder, structure):
        _copy_structure(folder, structure)
        path = folder / "out" / name
        data = path.read_bytes()
        path.write_bytes(data[: len(data) // 3])
    return prepare


def _directory_instead_of(name):
    def prepare(folder, structure):
        _copy_structure(folder, structure)
        (folder / "out" / name).unlink()
        (folder / "out" / name).mkdir()
        (folder / "out" / name / "keep").write_text("x")
    return prepare


def _foreign(name, donor):
    def prepare(folder, structure):
        _copy_structure(folder, structure)
        shutil.copy(folder / "out" / donor, folder / "out" / name)
    return prepare


def _file_as_out(folder, structure):
    (folder / "out").write_text("not a folder")


def _file_above_out(folder, structure):
    (folder / "blocker").write_text("a file")


def _locked_by(pid):
    """A copy of the structure whose lock is held by process ``pid`` of this host (1: init, always alive)."""
    def prepare(folder, structure):
        _copy_structure(folder, structure)
        (folder / "out" / ".lock").write_text(json.dumps({"pid": pid, "host": socket.gethostname(),
                                                          "started": "2026-01-01T00:00:00+00:00",
                                                          "started_unix": time.time(), "command": "pipeline.py run"}))
    return prepare


def _fifo(folder, structure):
    os.mkfifo(folder / "fifo")


def _linked_figures(folder, structure):
    _copy_structure(folder, structure)
    (folder / "elsewhere").mkdir()
    (folder / "out" / "figures").symlink_to(folder / "elsewhere")


def _read_only_out(folder, structure):
    (folder / "out").mkdir()
    (folder / "out").chmod(0o555)


RUN = ["run", "--quick"]
CONFIG = ["--config", "{dir}/study.toml"]
TREAD_STUDY = '[wheel]\ntread_profile = "tread.txt"\n'  # relative to the study file's folder
RADIUS_SWEEP = '[sweep]\n"wheel.rolling_radius" = [0.39, 0.37]\n'  # two structural variants
CATALOGUE = [
    # --- study files
    Entry("config missing", [*RUN, "--config", "{dir}/absent.toml"], 2, ("absent.toml",)),
    Entry("config is a directory", [*RUN, "--config", "{dir}"], 2, ("{dir}",)),
    Entry("config binary", [*RUN, *CONFIG], 2, ("study.toml",), files={"study.toml": bytes(range(256))}),
    Entry("config bad TOML", [*RUN, *CONFIG], 2, ("study.toml",), files={"study.toml": "[wheel\nx = "}),
    Entry("config unknown key", [*RUN, *CONFIG], 2, ("wheel.colour",), files={"study.toml": "[wheel]\ncolour = 1\n"}),
    Entry("config unknown section", [*RUN, *CONFIG], 2, ("wheels", "known tables here: ", "wheel"),
          files={"study.toml": "[wheels]\nx = 1\n"}),
    Entry("config out of range", [*RUN, *CONFIG], 2, ("operating.speed",),
          files={"study.toml": "[operating]\nspeed = -1.0\n"}),
    Entry("config inf", [*RUN, *CONFIG], 2, ("operating.speed",), files={"study.toml": "[operating]\nspeed = inf\n"}),
    Entry("config nan", [*RUN, *CONFIG], 2, ("contact.friction",), files={"study.toml": "[contact]\nfriction = nan\n"}),
    Entry("config wrong type", [*RUN, *CONFIG], 2, ("operating.speed",),
          files={"study.toml": '[operating]\nspeed = "fast"\n'}),
    Entry("config bad choice", [*RUN, *CONFIG], 2, ("contact.model",),
          files={"study.toml": '[contact]\nmodel = "kalker"\n'}),
    # --- --set
    Entry("set without =", [*RUN, "--set", "wheel.rolling_radius"], 2, ("--set",)),
    Entry("set without section", [*RUN, "--set", "speed=3"], 2, ("--set",)),
    Entry("set unknown key", [*RUN, "--set", "wheel.colour=1"], 2, ("wheel.colour",)),
    Entry("set not a number", [*RUN, "--set", "wheel.rolling_radius=abc"], 2, ("wheel.rolling_radius",)),
    Entry("set out of range", [*RUN, "--set", "time.time_step=1"], 2, ("time.time_step",)),
    Entry("set inf", [*RUN, "--set", "operating.speed=inf"], 2, ("operating.speed",)),
    Entry("set negative load", [*RUN, "--set", "operating.wheel_load=-5e4"], 2, ("operating.wheel_load",)),
    Entry("set bad wheel model", [*RUN, "--set", "simulation.wheel_model=rigid"], 2, ("simulation.wheel_model",)),
    Entry("set negative squeal frequency", [*RUN, "--set", "simulation.squeal_min_frequency=-1"], 2,
          ("simulation.squeal_min_frequency", "Hz")),
    # --- sweeps
    Entry("sweep empty list", [*RUN, *CONFIG], 2, ("sweep.contact.friction",),
          files={"study.toml": '[sweep]\n"contact.friction" = []\n'}),
    Entry("sweep unknown key", [*RUN, *CONFIG], 2, ("contact.frction",),
          files={"study.toml": '[sweep]\n"contact.frction" = [0.3]\n'}),
    Entry("sweep key without its section", [*RUN, *CONFIG], 2,
          ("sweep.friction", "known tables here: ", "dotted parameter names", '"contact.friction"'),
          files={"study.toml": '[sweep]\nfriction = [0.3]\n'}),
    Entry("sweep not a list", [*RUN, *CONFIG], 2, ("sweep.contact.friction",),
          files={"study.toml": '[sweep]\n"contact.friction" = 0.3\n'}),
    Entry("sweep value out of range", [*RUN, *CONFIG], 2, ("contact.friction",),
          files={"study.toml": '[sweep]\n"contact.friction" = [0.3, -1.0]\n'}),
    Entry("sweep path-like value", [*RUN, *CONFIG], 2, ("wheel.rolling_radius",),
          files={"study.toml": '[sweep]\n"wheel.rolling_radius" = ["../../etc"]\n'}),
    Entry("sweep duplicate values", [*RUN, *CONFIG], 2, ("sweep.contact.friction",),
          files={"study.toml": '[sweep]\n"contact.friction" = [0.3, 0.30]\n'}),
    # --- options
    Entry("jobs 0", [*RUN, "--jobs", "0"], 2, ("--jobs",)),
    Entry("jobs negative", [*RUN, "--jobs", "-3"], 2, ("--jobs",)),
    Entry("jobs not a number", [*RUN, "--jobs", "two"], 2, ("--jobs",)),
    Entry("until unknown stage", [*RUN, "--until", "nonsense"], 2, ("--until",)),
    Entry("unknown subcommand", ["frobnicate"], 2, ("frobnicate",)),
    Entry("no subcommand", [], 2, ("COMMAND",)),
    Entry("unknown option", [*RUN, "--frobnicate"], 2, ("--frobnicate",)),
    Entry("quiet and verbose", [*RUN, "--quiet", "--verbose"], 2, ("--verbose",)),
    Entry("export unknown target", ["export", "pictures", "--quick"], 2, ("target",)),
    Entry("export case without id", ["export", "case", "--quick"], 2, ("--case",)),
    Entry("export variant not chosen", ["export", "modes", "--quick", *CONFIG], 2,
          ("--variant", "rolling_radius=0.39-", "rolling_radius=0.37-"), files={"study.toml": RADIUS_SWEEP}),
    Entry("export variant unknown", ["export", "receptances", "--quick", *CONFIG, "--variant", "radius=1"], 2,
          ("--variant", "'radius=1'", "rolling_radius=0.39-", "rolling_radius=0.37-"),
          files={"study.toml": RADIUS_SWEEP}),
    Entry("export variant of one structure", ["export", "rail", "--quick", "--variant", "x"], 2,
          ("--variant", "one structure")),
    Entry("export variant of xdmf", ["export", "xdmf", "--quick", *CONFIG, "--variant", "rolling_radius=0.39"], 2,
          ("--variant", "'xdmf'"), files={"study.toml": RADIUS_SWEEP}),
    Entry("export option of another target", ["export", "receptances", "--quick", "--file", "m.vtu"], 2,
          ("--file", "export receptances", "export modes")),
    Entry("export xdmf with a folder", ["export", "xdmf", "--quick", "--dir", "{dir}/x"], 2,
          ("--dir", "export xdmf", "leave it out")),
    Entry("export modes to a folder", ["export", "modes", "--quick", "--file", "{dir}"], 2,
          ("--file", "must name a file", "{dir}")),
    Entry("export into a file", ["export", "rail", "--quick", "--dir", "{dir}/note.txt"], 2,
          ("--dir", "must name a folder", "{dir}/note.txt"), files={"note.txt": "x"}),
    # --- schedulers
    Entry("scheduler malformed", [*RUN, "--scheduler", "not an address"], 2, ("--scheduler",)),
    Entry("scheduler bad port", [*RUN, "--scheduler", "tcp://127.0.0.1:99999"], 2, ("--scheduler",)),
    Entry("scheduler unreachable", [*RUN, "--scheduler", "tcp://127.0.0.1:{port}"], 1, ("--scheduler",)),
    # --- output folders
    Entry("out is a file", RUN, 1, ("--out", "out"), prepare=_file_as_out),
    Entry("out below a file", RUN, 1, ("--out", "blocker"), out="blocker/out", prepare=_file_above_out),
    Entry("status out is a file", ["status", "--quick"], 1, ("--out",), prepare=_file_as_out),
    Entry("out read-only", RUN, 1, ("out",), prepare=_read_only_out,
          marks=(pytest.mark.skipif(IS_ROOT, reason="permissions are not enforced for root"),)),
    # --- damaged artefacts
    Entry("truncated artefact is rebuilt", [*RUN[:1], *QUICK, "--until", "wheel-mesh"], 0, (),
          prepare=_truncate("wheel_mesh.h5"), outcome="repaired"),
    Entry("foreign artefact is rebuilt", [*RUN[:1], *QUICK, "--until", "wheel-mesh"], 0, (),
          prepare=_foreign("wheel_mesh.h5", "rail_mesh.h5"), outcome="repaired"),
    Entry("status names a damaged artefact", ["status", *QUICK], 1, ("wheel-modes", "stale", "unreadable"),
          prepare=_truncate("wheel_modes.h5"), stream="stdout"),
    Entry("directory instead of an artefact", [*RUN[:1], *QUICK, "--until", "wheel-mesh"], 1, ("wheel_mesh.h5",),
          prepare=_directory_instead_of("wheel_mesh.h5")),
    # --- contact case files
    Entry("contact missing file", ["contact", "{dir}/absent.toml"], 2, ("absent.toml",)),
    Entry("contact file is a directory", ["contact", "{dir}"], 2, ("{dir}",)),
    Entry("contact bad TOML", ["contact", "{dir}/case.toml"], 2, ("case.toml",), files={"case.toml": "model = \n"}),
    Entry("contact bad model", ["contact", "{dir}/case.toml"], 2, ("model",), files={"case.toml": 'model = "x"\n'}),
    Entry("contact without case", ["contact"], 2, ("case",)),
    # --- contact geometry: the wheel (narrowed to 90 mm) does not reach the rail 20 mm to the field side
    Entry("geometry no contact", ["geometry", "--quick", "--set", "wheel.rim_width=0.09", "--set",
                                  "operating.lateral_displacement=-0.02"], 2,
          ("operating.lateral_displacement", "parametric wheel", "allowed range")),
    # another study than the folder's (issue 36): with --change-study, the error of the stage that finds
    # the input bad, and the folder keeps its study record
    Entry("run geometry no contact", [*RUN, "--until", "contact-geometry", "--set", "wheel.rim_width=0.09", "--set",
                                      "operating.lateral_displacement=-0.02", "--change-study"], 2,
          ("operating.lateral_displacement", "allowed range"), prepare=_copy_structure),
    Entry("run another study", [*RUN, "--until", "wheel-mesh"], 2,
          ("--out", "holds another study", "time.duration is 2.0 there, 1.0 here", "--change-study"),
          prepare=_copy_structure),
    Entry("export another study", ["export", "rail", "--quick"], 2, ("--out", "holds another study"),
          prepare=_copy_structure),
    Entry("export of a stale artefact", ["export", "modes", *QUICK], 1,
          ("wheel_modes.h5", "unreadable", "run --until wheel-modes"), prepare=_truncate("wheel_modes.h5")),
    Entry("run beside a live run", [*RUN[:1], *QUICK, "--until", "wheel-mesh"], 1,
          ("another run holds this folder", "process 1 on host"), prepare=_locked_by(1)),
    # --- issue 36: inputs that are not regular files, links out of --out, exports over artefacts
    Entry("profile is /dev/zero", [*RUN, "--set", "wheel.tread_profile=/dev/zero"], 2,
          ("wheel.tread_profile", "/dev/zero", "a device")),
    Entry("profile is a FIFO", [*RUN, "--set", "rail.profile={dir}/fifo"], 2, ("rail.profile", "{dir}/fifo", "FIFO"),
          prepare=_fifo),
    Entry("config is a FIFO", [*RUN, "--config", "{dir}/fifo"], 2, ("{dir}/fifo", "FIFO"), prepare=_fifo),
    Entry("profile too large", [*RUN, "--set", "wheel.tread_profile={dir}/big.txt"], 2,
          ("wheel.tread_profile", "bytes, more than"), files={"big.txt": b"0 0\n" * (5 << 20)}),
    Entry("symlinked sub-folder of out", [*RUN[:1], *QUICK, "--until", "wheel-mesh"], 1,
          ("{dir}/out/figures", "symbolic link", "{dir}/elsewhere"), prepare=_linked_figures),
    Entry("export over an artefact", ["export", "modes", *QUICK, "--file", "{dir}/out/wheel_modes.h5"], 2,
          ("--file", "HDF5 artefact"), prepare=_copy_structure),
    Entry("set a string read as a number", [*RUN, "--set", "rail.profile=60E1"], 2,
          ("rail.profile", "600.0", "quote strings", 'rail.profile="60E1"')),
    Entry("sweep too large", ["status", "--quick", *CONFIG], 2, ("sweep", "3000000 cases", "than the 10000"),
          files={"study.toml": "[sweep]\n" + "".join(f'"{key}" = [{", ".join(f"{0.1 + k * 1e-4:.4f}" for k in range(n))}]\n'
                                                  for key, n in (("contact.friction", 300), ("operating.speed", 100),
                                                                 ("contact.lateral_creepage", 100)))}),
    Entry("control characters in a key", [*RUN, *CONFIG], 2, ("wheel.col\\x1b[2J\\nerror: all good\\x07",),
          files={"study.toml": '[wheel]\n"col\\u001b[2J\\nerror: all good\\u0007" = 1\n'}),
    Entry("geometry displacement out of range", ["geometry", "--set", "operating.lateral_displacement=0.05"], 2,
          ("operating.lateral_displacement", "[-0.02, 0.02] m")),
    # --- profile files (issue 14): one line naming the key, the file and the problem
    Entry("tread file not a number", [*RUN, *CONFIG], 2, ("wheel.tread_profile", "{dir}/tread.txt", "not a number"),
          files={"study.toml": TREAD_STUDY, "tread.txt": "0 0\n0.05 x\n0.09 -0.001\n0.13 -0.0015\n"}),
    Entry("tread file too few points", [*RUN, *CONFIG], 2, ("wheel.tread_profile", "{dir}/tread.txt", "too few"),
          files={"study.toml": TREAD_STUDY, "tread.txt": "0 0\n0.07 0\n0.13 -0.0015\n"}),
    Entry("tread file non-monotonic", [*RUN, *CONFIG], 2, ("wheel.tread_profile", "{dir}/tread.txt", "non-monotonic"),
          files={"study.toml": TREAD_STUDY, "tread.txt": "0 0.02\n0.04 0\n0.03 -0.001\n0.09 -0.001\n0.13 -0.002\n"}),
    Entry("tread file self-intersecting", [*RUN, *CONFIG], 2,
          ("wheel.tread_profile", "{dir}/tread.txt", "self-intersecting"),
          files={"study.toml": TREAD_STUDY, "tread.txt": "0 0\n0.1 0\n0.1 0.01\n0.05 -0.01\n0.12 -0.01\n"}),
    Entry("tread file missing", [*RUN, *CONFIG], 2, ("wheel.tread_profile", "{dir}/tread.txt", "cannot read"),
          files={"study.toml": TREAD_STUDY}),
    Entry("tread file wider than the rim", [*RUN, *CONFIG], 2, ("wheel.rim_width", "{dir}/tread.txt"),
          files={"study.toml": TREAD_STUDY, "tread.txt": "0 0.02\n0.05 0\n0.1 -0.001\n0.2 -0.003\n"}),
    Entry("tread turned too far", [*RUN, "--set", "wheel.tread_profile=S1002", "--set", "wheel.rolling_radius=0.35"],
          2, ("wheel.rolling_radius", "0.357636")),
    Entry("sweep over a bad tread file", [*RUN, *CONFIG], 2, ("wheel.tread_profile", "{dir}/bad.txt", "too few"),
          files={"study.toml": '[sweep]\n"wheel.tread_profile" = ["S1002", "bad.txt"]\n', "bad.txt": "0 0\n"}),
    Entry("outline file open", [*RUN, "--set", "wheel.profile_file={dir}/outline.txt"], 2,
          ("wheel.profile_file", "{dir}/outline.txt", "open"), files={"outline.txt": "0.1 0\n0.1 0.1\n0.3 0.1\n0.3 0\n"}),
    Entry("outline file self-intersecting", [*RUN, "--set", "wheel.profile_file={dir}/outline.txt"], 2,
          ("wheel.profile_file", "{dir}/outline.txt", "self-intersecting"),
          files={"outline.txt": "0.1 0\n0.3 0.1\n0.3 0\n0.1 0.1\n0.1 0\n"}),
    Entry("rail inclination not allowed", [*RUN, "--set", "rail.inclination=25"], 2, ("rail.inclination", "(0, 20, 30, 40)")),
]


def _expand(text, folder, port):
    return str(text).replace("{dir}", str(folder)).replace("{port}", str(port))


def _run_entry(entry, folder, structure, port):
    folder.mkdir(parents=True)
    for name, content in entry.files.items():
        target = folder / name
        target.write_bytes(content) if isinstance(content, bytes) else target.write_text(content)
    if entry.prepare is not None:
        entry.prepare(folder, structure)
    out = folder / entry.out
    argv = [_expand(a, folder, port) for a in entry.argv]
    if argv and argv[0] in ("run", "status", "export"):
        argv += ["--out", str(out)]
    watched = folder if entry.out == "out" else folder / "blocker"
    before = snapshot(out if entry.out == "out" else watched)
    start = time.perf_counter()
    result = cli(*argv, timeout=600)
    seconds = time.perf_counter() - start
    after = snapshot(out if entry.out == "out" else watched)
    return {"result": result, "before": before, "after": after, "seconds": seconds, "out": out, "argv": argv}


@pytest.fixture(scope="module")
def catalogue(structure, tmp_path_factory):
    """Every entry run once, four at a time; ``{name: outcome}``."""
    root = tmp_path_factory.mktemp("catalogue")
    port = _free_port()
    skipped = {e.name for e in CATALOGUE if e.name == "out read-only" and IS_ROOT}
    entries = [e for e in CATALOGUE if e.name not in skipped]
    with ThreadPoolExecutor(max_workers=4) as pool:
        futures = {e.name: pool.submit(_run_entry, e, root / f"entry{k:02d}", structure, port)
                   for k, e in enumerate(entries)}
    outcomes = {name: future.result() for name, future in futures.items()}
    for name, outcome in outcomes.items():
        if name == "out read-only":
            outcome["out"].chmod(0o755)
    return outcomes


@pytest.mark.parametrize("entry", [pytest.param(e, id=e.name, marks=e.marks) for e in CATALOGUE])
def test_bad_input_and_faults(catalogue, entry):
    outcome = catalogue[entry.name]
    result = outcome["result"]
    err = result.stderr
    assert "Traceback" not in err, err
    assert result.returncode == entry.status, f"{outcome['argv']}: {err}"
    if entry.stream == "stdout":
        line = next(line for line in result.stdout.splitlines() if line.startswith(entry.mentions[0] + " "))
        assert all(text in line for text in entry.mentions), line
    elif entry.status:
        errors = [line for line in err.splitlines() if line.startswith("error:")]
        assert len(errors) == 1, err
        folder = str(outcome["out"].parent)
        for text in entry.mentions:
            assert text.replace("{dir}", folder) in errors[0], errors[0]
    if entry.outcome == "unchanged":
        assert outcome["after"] == outcome["before"]
    else:
        status = cli("status", *QUICK, "--out", outcome["out"])
        rows = {line.split()[0]: line.split()[1] for line in status.stdout.splitlines()}
        assert rows["wheel-mesh"] == "fresh", status.stdout


def test_unreachable_scheduler_fails_within_a_few_seconds(catalogue):
    # the connect timeout, plus the start-up of Python and the check of the study
    assert catalogue["scheduler unreachable"]["seconds"] < engine.CONNECT_TIMEOUT + 20


# --------------------------------------------------------------------------- Ctrl-C


def _default_sigint():
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _temporaries(folder):
    return [p for p in Path(folder).rglob(".*") if p.is_file()]


@pytest.mark.parametrize("contact_model", ["point", pytest.param("halfspace", marks=pytest.mark.slow)])
def test_ctrl_c_stops_within_two_seconds_and_the_rerun_resumes(structure, tmp_path, contact_model):
    """Ctrl-C during a case; the half-space variant is slow because the rerun computes its 2 s case
    to the end (a few minutes)."""
    out = tmp_path / "out"
    shutil.copytree(structure, out)
    config = tmp_path / "one.toml"
    config.write_text(ONE_CASE + f'[contact]\nmodel = "{contact_model}"\n')
    # the folder records the module's study (one case of it here): --change-study (issue 36)
    argv = [sys.executable, str(REPO / "pipeline.py"), "run", *QUICK, "--config", str(config), "--out", str(out),
            "--change-study"]
    errors = tmp_path / "stderr.txt"
    with open(errors, "w") as err_file:
        # a terminal's Ctrl-C: SIGINT at its default, even where the test runner ignores it (pytest-xdist
        # workers do, and an ignored SIGINT is inherited across exec, so Python would never see it)
        process = subprocess.Popen(argv, cwd=REPO, env=ENV, stdout=subprocess.DEVNULL, stderr=err_file,
                                   preexec_fn=_default_sigint)
        deadline = time.monotonic() + 120
        while "cases:" not in errors.read_text() and time.monotonic() < deadline and process.poll() is None:
            time.sleep(0.05)
        # inside the case: the point case is reading, compiling or stepping; the half-space case
        # (its compiled loop cached by then) is in its time loop
        time.sleep(0.5 if contact_model == "point" else 5.0)
        assert process.poll() is None, "the case finished before the signal: make DURATION longer"
        process.send_signal(signal.SIGINT)
        sent = time.monotonic()
        status = process.wait(timeout=30)
        elapsed = time.monotonic() - sent
    err = errors.read_text()
    assert status == 130, err
    assert elapsed < 2.0, f"stopped {elapsed:.2f} s after the signal"
    assert "Traceback" not in err
    assert "rerun the same command" in err
    assert _temporaries(out) == []
    assert not list((out / "cases").glob("*.h5")) if (out / "cases").exists() else True
    rerun = cli(*argv[2:], "--quiet", timeout=600)
    assert rerun.returncode == 0, rerun.stderr
    assert len(list((out / "cases").glob("*.h5"))) == 1
    assert (out / "report.md").exists()
    status = cli("status", *QUICK, "--config", config, "--out", out)
    assert status.returncode == 0, status.stdout  # everything fresh
    assert status.stdout.splitlines()[-1].split()[:2] == ["report", "fresh"]


# --------------------------------------------------------------------------- status, version, entry point


def test_status_is_aligned_and_exits_1_when_something_is_stale(structure):
    result = cli("status", *QUICK, "--out", structure)
    assert result.returncode == 1
    lines = result.stdout.splitlines()
    assert lines[-1].startswith("report") and any(line.startswith("simulate:") for line in lines)
    columns = {len(line.split("  ")[0].rstrip()) for line in lines}
    starts = {line.index(" fresh") if " fresh" in line else line.index(" stale") for line in lines}
    assert len(starts) == 1 and max(columns) < starts.pop() + 1


def test_status_into_a_closed_pipe_prints_no_traceback(tmp_path):
    # `status | head -1`: the pipe is shrunk to one page (Linux), so that the rows of 150 cases
    # overflow it and the writer meets the closed pipe
    config = tmp_path / "many.toml"
    config.write_text('[sweep]\n"contact.friction" = [' + ", ".join(f"{0.01 * k:.2f}" for k in range(1, 151)) + "]\n")
    read_end, write_end = os.pipe()
    if hasattr(fcntl, "F_SETPIPE_SZ"):
        fcntl.fcntl(write_end, fcntl.F_SETPIPE_SZ, 4096)
    process = subprocess.Popen([sys.executable, str(REPO / "pipeline.py"), "status", "--quick", "--config",
                                str(config), "--out", str(tmp_path / "out")], cwd=REPO, env=ENV,
                               stdout=write_end, stderr=subprocess.PIPE)
    os.close(write_end)
    with os.fdopen(read_end, "rb") as reader:
        reader.readline()
    err = process.stderr.read().decode()
    process.wait(timeout=300)
    assert "Traceback" not in err and "BrokenPipe" not in err, err
    assert process.returncode == 141


def test_version_is_the_package_version():
    result = cli("--version")
    assert result.returncode == 0
    assert result.stdout.strip() == f"curve-squeal {importlib.metadata.version('curve-squeal')}"


def test_console_script_works_like_pipeline_py(tmp_path):
    script = shutil.which("curve-squeal")
    if script is None:
        pytest.skip("the console script curve-squeal is not on PATH")
    for argv in (["--version"], ["run", "--quick", "--jobs", "0"], ["status", "--quick", "--out", str(tmp_path)]):
        own = cli(*argv)
        console = subprocess.run([script, *argv], cwd=REPO, env=ENV, capture_output=True, text=True, timeout=300)
        assert (console.returncode, console.stdout) == (own.returncode, own.stdout)
        assert console.stderr.replace("curve-squeal", "pipeline.py") == own.stderr


def test_export_modes_alias_is_wired(structure, tmp_path):
    out = tmp_path / "out"
    shutil.copytree(structure, out)
    result = cli("export-modes", *QUICK, "--quiet", "--out", out, "--modes", "1", "2")
    assert result.returncode == 0, result.stderr
    assert (out / "wheel_modes.vtu").stat().st_size > 0


def test_export_modes_of_one_variant(structure, tmp_path):
    """``export modes --variant`` reads (and builds) that variant's folder only."""
    config = tmp_path / "study.toml"
    config.write_text(RADIUS_SWEEP)
    out = tmp_path / "out"
    study = load_study(str(config), quick=True, assignments=QUICK[2:])
    labels = {v.study["wheel"]["rolling_radius"]: label for label, v in study_variants(study, out).items()}
    assert sorted(labels) == [0.37, 0.39]
    # the 0.39 m variant is the quick study's own wheel: its fresh artefacts are the module's structure
    chosen = out / "variants" / labels[0.39]
    shutil.copytree(structure, chosen)
    before = snapshot(chosen / "wheel_modes.h5")
    result = cli("export", "modes", *QUICK, "--quiet", "--config", config, "--out", out,
                 "--variant", labels[0.39].rsplit("-", 1)[0], "--modes", "1", "3")
    assert result.returncode == 0, result.stderr
    modes = read_modes(chosen / "wheel_modes.h5")
    vtu = meshio.read(chosen / "wheel_modes.vtu")
    assert sorted(vtu.point_data) == sorted(mode_name(modes, k) for k in (0, 2))
    assert snapshot(chosen / "wheel_modes.h5") == before  # fresh: read, not rebuilt
    assert not (out / "variants" / labels[0.37]).exists()  # the other variant is not built


# --------------------------------------------------------------------------- variant folders


@pytest.mark.parametrize("overrides", [{"wheel.fe.solver": "../../etc"}, {"wheel.x": "a/b"}, {"wheel.r": 0.375},
                                       {"wheel.name": "." * 5}, {"wheel.long": "x" * 500}])
def test_variant_folder_names_are_safe(overrides, tmp_path):
    label = engine.variant_label(overrides)
    assert "/" not in label and "\\" not in label and ".." not in label and not label.startswith(".")
    assert len(label) <= 60
    assert (tmp_path / label).resolve().parent == tmp_path.resolve()


def test_variant_labels_tell_apart_values_that_print_alike():
    # 0.1 + 0.2 and 0.3 print alike with %g but are different values
    assert engine.variant_label({"wheel.r": 0.1 + 0.2}) != engine.variant_label({"wheel.r": 0.3})
    assert engine.variant_label({"wheel.r": 0.3}) == engine.variant_label({"wheel.r": 0.3})


# --------------------------------------------------------------------------- profile files (issue 14)

#: A 1:40 cone without flange as a tread profile file (y from the flange back, height, m).
CONE = "\n".join(f"{y:.4f} {-(y - 0.07) / 40:.6f}" for y in [0.005 * k for k in range(27)]) + "\n"


def _rows(capsys):
    return {line.split()[0]: line.split()[1] for line in capsys.readouterr().out.splitlines()}


def test_editing_a_tread_file_makes_exactly_the_wheel_stale(tmp_path, capsys):
    tread = tmp_path / "tread.txt"
    tread.write_text(CONE)
    config = tmp_path / "study.toml"
    config.write_text('[wheel]\ntread_profile = "tread.txt"\n')
    args = ["--quick", "--config", str(config), "--out", str(tmp_path / "out")]
    for last in ("wheel-mesh", "rail-mesh"):
        assert pipeline.main(["run", "--quiet", *args, "--until", last]) == 0
    capsys.readouterr()
    assert pipeline.main(["status", *args]) == 1  # the later stages are not built
    rows = _rows(capsys)
    assert rows["wheel-mesh"] == "fresh" and rows["rail-mesh"] == "fresh"
    # same file name, new contents (the tread turned into a 1:20 cone)
    tread.write_text("\n".join(f"{y:.4f} {-(y - 0.07) / 20:.6f}" for y in [0.005 * k for k in range(27)]) + "\n")
    assert pipeline.main(["status", *args]) == 1
    rows = _rows(capsys)
    assert rows["wheel-mesh"] == "stale" and rows["rail-mesh"] == "fresh"
    # rebuilt, it is fresh again
    assert pipeline.main(["run", "--quiet", *args, "--until", "wheel-mesh"]) == 0
    capsys.readouterr()
    pipeline.main(["status", *args])
    assert _rows(capsys)["wheel-mesh"] == "fresh"


def test_path_valued_sweeps_write_nothing_outside_out(tmp_path, monkeypatch):
    work = tmp_path / "work"
    work.mkdir()
    (tmp_path / "x.txt").write_text(CONE)
    config = work / "study.toml"
    config.write_text('[sweep]\n"wheel.tread_profile" = ["../x.txt", "S1002"]\n')
    out = work / "out"
    outside = lambda: {k: v for k, v in snapshot(tmp_path).items()  # noqa: E731
                       if not k.startswith(("work/out/", "work/out2/"))}
    before = outside()
    assert pipeline.main(["run", "--quick", "--quiet", "--config", str(config), "--out", str(out),
                          "--until", "wheel-mesh"]) == 0
    assert outside() == before
    meshes = sorted(out.rglob("wheel_mesh.h5"))
    assert len(meshes) == 2
    for mesh in meshes:  # variants/<safe label>/wheel_mesh.h5, right below --out
        assert mesh.resolve().parent.parent == (out / "variants").resolve()
        assert ".." not in mesh.parent.name and "/" not in mesh.parent.name
    # the same path given with --set (relative to the working folder)
    monkeypatch.chdir(work)
    out2 = work / "out2"
    before = outside()
    assert pipeline.main(["run", "--quick", "--quiet", "--set", "wheel.tread_profile=../x.txt", "--out", str(out2),
                          "--until", "wheel-mesh"]) == 0
    assert outside() == before
    assert (out2 / "wheel_mesh.h5").is_file()
