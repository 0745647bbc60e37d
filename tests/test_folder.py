"""A results folder that defends itself (issue 36): one study per folder, a lock while a run builds,
read commands that never build, resource faults, stop signals and checksummed attributes.

Every test calls the command line in-process (``pipeline.main``) or as a subprocess, on a copy of
the quick study's run (``quick_run``, tests/conftest.py)."""

import errno
import json
import os
import shutil
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import h5py
import pytest

import pipeline
from squealcore import artefacts
from stages import engine, folder
from tests.test_cli import ENV, REPO, snapshot


@pytest.fixture
def q(quick_run, tmp_path):
    """A copy of the quick study's run folder (its study record included)."""
    out = tmp_path / "Q"
    shutil.copytree(quick_run, out)
    return out


def _artefacts(out):
    """Snapshot of the folder without the exports (what a read command must leave as it is)."""
    return {k: v for k, v in snapshot(out).items() if not k.startswith("exports/")}


def _error_lines(text):
    return [line for line in text.splitlines() if line.startswith("error:")]


# --------------------------------------------------------------------------- item 1: one study per folder


def test_the_first_run_records_its_study(q):
    record = json.loads((q / folder.RECORD).read_text())
    assert record["given"] == {"config": None, "quick": True, "set": []}
    assert record["study"]["time"]["duration"] == 1.0  # the quick preset's
    assert not (q / folder.LOCK).exists()  # released


def test_export_after_a_quick_run_uses_the_folders_study_and_builds_nothing(q, capsys):
    before = _artefacts(q)
    assert pipeline.main(["export", "receptances", "--quiet", "--out", str(q)]) == 0  # no --quick
    assert list((q / "exports").glob("*.csv"))
    assert _artefacts(q) == before
    assert pipeline.main(["status", "--out", str(q)]) == 0  # every artefact fresh
    assert "stale" not in capsys.readouterr().out
    # the same study given explicitly is the folder's
    assert pipeline.main(["status", "--quick", "--out", str(q)]) == 0


@pytest.mark.parametrize("command", [["status"], ["export", "rail"], ["run"], ["stability"], ["geometry"], ["map"]])
def test_another_study_is_refused_naming_the_difference(q, capsys, command):
    before = snapshot(q)
    status = pipeline.main([*command, "--quiet", "--quick", "--set", "operating.speed=3.5", "--out", str(q)])
    err = capsys.readouterr().err
    assert status == 2, err
    [line] = _error_lines(err)
    assert "holds another study" in line and "operating.speed is" in line and "3.5 here" in line, line
    assert "--quick" in line  # how the folder's study was given
    assert ("--change-study" in line) == (command == ["run"])
    assert snapshot(q) == before


def test_run_change_study_records_the_new_study(q):
    assert pipeline.main(["run", "--quiet", "--quick", "--set", "report.dpi=60", "--until", "wheel-mesh",
                          "--out", str(q)]) == 2
    assert pipeline.main(["run", "--quiet", "--quick", "--set", "report.dpi=60", "--until", "wheel-mesh",
                          "--change-study", "--out", str(q)]) == 0
    record = json.loads((q / folder.RECORD).read_text())
    assert record["study"]["report"]["dpi"] == 60 and record["given"]["set"] == ["report.dpi=60"]
    # the structures do not read [report]: still fresh; the report is stale for the new study
    rows = {name: fresh for name, fresh, _ in engine.status(record["study"], q)}
    assert rows["wheel-greens"] and not rows["report"]


def test_read_commands_never_build_a_stale_artefact(q, capsys):
    path = q / "wheel_modes.h5"
    path.write_bytes(path.read_bytes()[:1000])
    before = snapshot(q)
    assert pipeline.main(["export", "modes", "--quiet", "--out", str(q)]) == 1
    [line] = _error_lines(capsys.readouterr().err)
    assert str(path) in line and "run --until wheel-modes" in line, line
    assert snapshot(q) == before
    assert pipeline.main(["status", "--out", str(q)]) == 1
    assert snapshot(q) == before


def test_a_damaged_study_record_is_named(q, capsys):
    (q / folder.RECORD).write_text("{not json")
    assert pipeline.main(["status", "--out", str(q)]) == 1
    [line] = _error_lines(capsys.readouterr().err)
    assert str(q / folder.RECORD) in line and "unreadable" in line


# --------------------------------------------------------------------------- item 2: the lock


def _plant_lock(out, pid, host):
    (out / folder.LOCK).write_text(json.dumps({"pid": pid, "host": host, "started": "2026-01-01T00:00:00+00:00",
                                               "started_unix": time.time(), "command": "pipeline.py run"}))


def test_a_live_holder_refuses_a_second_run_and_status_runs_beside_it(q, capsys):
    sleeper = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"])
    try:
        _plant_lock(q, sleeper.pid, socket.gethostname())
        lock = (q / folder.LOCK).read_bytes()
        start = time.monotonic()
        assert pipeline.main(["run", "--quiet", "--out", str(q)]) == 1
        assert time.monotonic() - start < 20
        [line] = _error_lines(capsys.readouterr().err)
        assert f"process {sleeper.pid} on host {socket.gethostname()}" in line and "remove" in line, line
        assert (q / folder.LOCK).read_bytes() == lock  # not the second run's to remove
        assert pipeline.main(["status", "--out", str(q)]) == 0  # read commands run beside it
        assert f"is being built by process {sleeper.pid}" in capsys.readouterr().err
        assert pipeline.main(["export", "rail", "--quiet", "--out", str(q)]) == 0
        for command in (["stability"], ["geometry", "--json"], ["map"]):  # the other builders wait their turn
            assert pipeline.main([*command, "--out", str(q)]) == 1, command
    finally:
        sleeper.kill()
        sleeper.wait()


def test_a_lock_from_another_host_is_not_taken_over(q, capsys):
    _plant_lock(q, os.getpid(), "elsewhere.example")
    assert pipeline.main(["run", "--quiet", "--until", "wheel-mesh", "--out", str(q)]) == 1
    assert "on host elsewhere.example" in capsys.readouterr().err


def test_a_stale_lock_is_taken_over_and_released(q, caplog):
    dead = subprocess.Popen([sys.executable, "-c", "pass"])
    dead.wait()
    _plant_lock(q, dead.pid, socket.gethostname())
    assert pipeline.main(["run", "--quiet", "--until", "wheel-mesh", "--out", str(q)]) == 0
    assert not (q / folder.LOCK).exists()
    garbage = q / folder.LOCK  # an unreadable, old lock is stale too
    garbage.write_text("\x00")
    os.utime(garbage, (time.time() - 60, time.time() - 60))
    assert pipeline.main(["run", "--quiet", "--until", "wheel-mesh", "--out", str(q)]) == 0
    assert not garbage.exists()


def test_two_runs_started_together(q, tmp_path, capsys):
    """The second is refused at once naming the first; the first completes; everything is fresh."""
    case = sorted((q / "cases").glob("*.h5"))[0]
    case.unlink()  # the first run has a case to compute
    errors = tmp_path / "first.txt"
    with open(errors, "w") as err_file:
        first = subprocess.Popen([sys.executable, str(REPO / "pipeline.py"), "run", "--out", str(q)], cwd=REPO,
                                 env=ENV, stdout=subprocess.DEVNULL, stderr=err_file)
        deadline = time.monotonic() + 120
        while not (q / folder.LOCK).exists() and first.poll() is None and time.monotonic() < deadline:
            time.sleep(0.02)
        assert first.poll() is None, errors.read_text()
        assert pipeline.main(["run", "--quiet", "--out", str(q)]) == 1
        assert f"process {first.pid} on host" in capsys.readouterr().err
        assert first.wait(timeout=600) == 0, errors.read_text()
    assert not (q / folder.LOCK).exists()
    assert pipeline.main(["status", "--out", str(q)]) == 0


# --------------------------------------------------------------------------- item 3: resource faults


def _temporaries(out):
    return [p for p in Path(out).rglob(".*") if p.is_file()]


def _full_disk_in(monkeypatch, part):
    """Make the next HDF5 artefact whose temporary name holds ``part`` meet a full disk half-way."""
    original = artefacts.write_image

    def write(tmp_name, image):
        if part not in str(tmp_name):
            return original(tmp_name, image)
        with open(tmp_name, "wb") as handle:
            handle.write(image[: len(image) // 2])
        raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))

    monkeypatch.setattr(artefacts, "write_image", write)


def _one_error(capsys):
    err = capsys.readouterr().err
    assert "Traceback" not in err and "HDF5" not in err, err
    [line] = _error_lines(err)
    return line


@pytest.mark.parametrize("stage, artefact", [("wheel-modes", "wheel_modes.h5"), ("radiation", "radiation/")])
def test_a_full_disk_stops_the_run_with_one_line_and_the_rerun_resumes(q, monkeypatch, capsys, stage, artefact):
    victim = q / artefact if stage != "radiation" else sorted((q / "radiation").glob("*.h5"))[0]
    victim.unlink()
    kept = {k: v for k, v in snapshot(q).items() if k not in ("report.h5", "study.json")}
    _full_disk_in(monkeypatch, "wheel_modes.h5" if stage == "wheel-modes" else victim.name)
    until = ["--until", stage] if stage == "wheel-modes" else []
    assert pipeline.main(["run", "--quiet", *until, "--out", str(q)]) == 1
    line = _one_error(capsys)
    assert line == f"error: {victim}: {os.strerror(errno.ENOSPC)}", line
    assert not victim.exists() and _temporaries(q) == []  # nothing truncated published, no temporary left
    after = snapshot(q)
    assert all(after.get(k) == v for k, v in kept.items())  # the completed artefacts are kept
    monkeypatch.undo()
    assert pipeline.main(["run", "--quiet", *until, "--out", str(q)]) == 0  # space freed: resumes
    assert victim.exists()
    if stage == "radiation":
        assert pipeline.main(["status", "--out", str(q)]) == 0


def test_a_file_a_library_writes_onto_a_full_disk_is_not_published(q, monkeypatch, capsys):
    """The report's figures (matplotlib) and tables: the first one written on a full disk stops the run."""
    (q / "report.h5").unlink()
    figures = snapshot(q / "figures")
    monkeypatch.setattr(artefacts, "free_bytes", lambda folder: 0)
    assert pipeline.main(["run", "--quiet", "--out", str(q)]) == 1
    line = _one_error(capsys)
    assert str(q) in line and "No space left on device" in line and "not published" in line, line
    assert snapshot(q / "figures") == figures and not (q / "report.h5").exists() and _temporaries(q) == []
    assert not (q / folder.LOCK).exists()
    monkeypatch.undo()
    assert pipeline.main(["run", "--quiet", "--out", str(q)]) == 0
    assert pipeline.main(["status", "--out", str(q)]) == 0


def test_a_case_meeting_a_full_disk_in_a_worker_stops_the_sweep():
    sweep = engine.Sweep(2, False)
    outcome = {"case_id": "c", "ok": False, "error": "x", "seconds": 0.0,
               "fault": [errno.ENOSPC, os.strerror(errno.ENOSPC), "/o/cases/c.h5"]}
    with pytest.raises(OSError) as caught:
        sweep.collect(outcome)
    assert (caught.value.errno, caught.value.filename) == (errno.ENOSPC, "/o/cases/c.h5")
    assert sweep.failed == {}  # not a failed case: the rerun computes it


# --------------------------------------------------------------------------- item 4: stop signals


def _children(pid):
    children = []
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if int((entry / "stat").read_text().rsplit(")", 1)[1].split()[1]) == pid:
                    children.append(int(entry.name))
            except (OSError, IndexError):
                continue
    return children


def _default_signals():
    for signum in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(signum, signal.SIG_DFL)


@pytest.mark.parametrize("signum, status, jobs", [(signal.SIGTERM, 143, 2), (signal.SIGHUP, 129, 1)])
def test_sigterm_and_sighup_stop_like_ctrl_c(q, tmp_path, signum, status, jobs):
    for case in sorted((q / "cases").glob("*.h5"))[:2]:
        case.unlink()
    argv = [sys.executable, str(REPO / "pipeline.py"), "run", "--jobs", str(jobs), "--out", str(q)]
    errors = tmp_path / "stderr.txt"
    with open(errors, "w") as err_file:
        process = subprocess.Popen(argv, cwd=REPO, env=ENV, stdout=subprocess.PIPE, stderr=err_file,
                                   preexec_fn=_default_signals)  # output piped, as under a batch scheduler
        deadline = time.monotonic() + 180
        while "cases:" not in errors.read_text() and time.monotonic() < deadline and process.poll() is None:
            time.sleep(0.05)
        time.sleep(1.0)
        assert process.poll() is None, errors.read_text()
        children = _children(process.pid)
        assert children  # the case workers
        process.send_signal(signum)
        sent = time.monotonic()
        assert process.wait(timeout=60) == status, errors.read_text()
        elapsed = time.monotonic() - sent
    err = errors.read_text()
    assert elapsed < 10, elapsed
    assert "Traceback" not in err and "rerun the same command" in err
    assert {1: "hung up (SIGHUP)", 2: "terminated (SIGTERM)"}[jobs] in err
    time.sleep(1.0)
    assert [pid for pid in children if Path(f"/proc/{pid}").exists()
            and "Z" not in Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]] == []
    assert _temporaries(q) == [] and not (q / folder.LOCK).exists()
    if jobs == 1:
        rerun = subprocess.run(argv[:2] + ["run", "--quiet", "--out", str(q)], cwd=REPO, env=ENV, capture_output=True,
                               text=True, timeout=600)
        assert rerun.returncode == 0, rerun.stderr
        assert pipeline.main(["status", "--out", str(q)]) == 0


# --------------------------------------------------------------------------- item 5: checksummed attributes


def test_an_edited_metric_is_named_by_status_and_recomputed_by_run(q, capsys):
    case = sorted((q / "cases").glob("*.h5"))[0]
    with h5py.File(case, "r") as f:
        level = float(f.attrs["L_F2"])
    with h5py.File(case, "r+") as f:
        f.attrs["L_F2"] = 123.4
    assert pipeline.main(["status", "--out", str(q)]) == 1
    rows = {line.split()[0]: line for line in capsys.readouterr().out.splitlines()}
    assert "attribute L_F2 changed" in rows[f"simulate:{case.stem}"], rows[f"simulate:{case.stem}"]
    # the closing lines do not believe it either, and the run computes the case again
    assert [r["case_id"] for r in engine.case_results(engine.plan_cases(json.loads(
        (q / folder.RECORD).read_text())["study"], q), q)].count(case.stem) == 0
    assert pipeline.main(["run", "--quiet", "--out", str(q)]) == 0
    with h5py.File(case, "r") as f:
        assert float(f.attrs["L_F2"]) == pytest.approx(level, abs=0.05)
    assert pipeline.main(["status", "--out", str(q)]) == 0


# --------------------------------------------------------------------------- smaller: variant labels


def test_variant_labels_show_a_files_name_never_its_folder():
    label = engine.variant_label({"wheel.tread_profile": "/home/someone/profiles/worn tread.txt"})
    assert label.startswith("tread_profile=worn_tread.txt-") and "home" not in label and "profiles" not in label
    # files of the same name in two folders are two variants
    assert label != engine.variant_label({"wheel.tread_profile": "/elsewhere/worn tread.txt"})


# --------------------------------------------------------------------------- item 10: a quiet terminal


def test_what_a_library_prints_goes_to_the_log(capfd, caplog):
    import logging

    from squealcore.library_output import stdout_to_log

    with caplog.at_level(logging.INFO):
        with stdout_to_log(logging.getLogger("lib"), "lib"):
            os.write(1, b"WARNING: shrinks.length==shrinks_max=28\n")
    assert "shrinks" not in capfd.readouterr().out
    assert "lib: WARNING: shrinks.length==shrinks_max=28" in caplog.text


def test_library_warnings_reach_the_terminal_only_with_verbose(capfd):
    # numpy's floating-point warning stands for numba's and scipy's (all through the warnings module)
    import argparse
    import logging
    import warnings

    import numpy as np

    logging.captureWarnings(False)  # an earlier test's command line captured them under pytest's own recorder
    try:
        for verbose in (False, True):
            pipeline.configure_logging(argparse.Namespace(quiet=False, verbose=verbose, debug=False))
            with warnings.catch_warnings():
                warnings.simplefilter("always")
                with np.errstate(divide="warn"):
                    np.log(np.zeros(1))
            err = capfd.readouterr().err
            assert ("divide by zero" in err) == verbose, err
            if verbose:
                assert "py.warnings" in err  # a log record, not a bare warning print
    finally:
        logging.captureWarnings(False)


@pytest.mark.parametrize("level, shown", [("WARNING", False), ("INFO", True)])
def test_the_case_worker_logs_library_warnings_as_the_command_line(level, shown):
    # the worker process the cases run in (spawned) sets up its logging as the command line's
    script = ("import logging, warnings, numpy as np\n"
              "from squealcore.library_output import configure_worker_logging\n"
              f"configure_worker_logging(logging.{level})\n"
              "warnings.simplefilter('always')\n"
              "np.seterr(divide='warn'); np.log(np.zeros(1))\n"
              "logging.getLogger('stages.cases').warning('a warning of the project')\n")
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120,
                          cwd=Path(pipeline.__file__).resolve().parent)
    assert done.returncode == 0, done.stderr
    assert ("divide by zero" in done.stderr) == shown, done.stderr
    assert "WARNING stages.cases: a warning of the project" in done.stderr


def test_meshing_the_wheel_prints_nothing_on_stdout(tmp_path, capfd):
    assert pipeline.main(["run", "--quick", "--quiet", "--until", "wheel-mesh", "--out", str(tmp_path / "o")]) == 0
    captured = capfd.readouterr()
    assert captured.out == "" and captured.err == "", captured
