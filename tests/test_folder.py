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
