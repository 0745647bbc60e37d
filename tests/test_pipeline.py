"""Pipeline behaviour: caching, invalidation, artefact checks, atomic writes and bad input."""

import shutil

import h5py
import numpy as np
import pytest

import pipeline
from squealcore.artefacts import ArtefactError, open_artefact, write_artefact
from stages import engine
from stages.cases import make_case_id
from stages.config import load_study

QUICK = ["--quick", "--quiet"]
#: Interaction duration of this module's study, s: what is rerun does not depend on it, so the
#: quick study's cases are cut to this (>= simulation.rms_window) to keep the reruns short.
DURATION = "0.25"


@pytest.fixture(scope="module")
def built(copy_quick_structures, tmp_path_factory):
    """The quick study with short cases, run to the end, on a copy of the session's quick
    structures (conftest.py; the structures do not read ``time.duration``)."""
    out = copy_quick_structures(tmp_path_factory.mktemp("quick") / "out")
    assert pipeline.main(["run", *QUICK, "--set", f"time.duration={DURATION}", "--out", str(out)]) == 0
    return out


def _study(*assignments):
    return load_study(quick=True, assignments=[f"time.duration={DURATION}", *assignments])


CASES = ["simulate:" + make_case_id({"contact.friction": 0.6, "contact.lateral_creepage": eta,
                                     "simulation.wheel_model": model})
         for eta in (-0.003, -0.015) for model in ("stationary", "moving_load", "eulerian")]
#: The radiation stage of every case runs after the cases, in their order, before the report.
RADIATION = ["radiation:" + case.split(":", 1)[1] for case in CASES]


def test_first_run_writes_every_artefact(built):
    for name in ("wheel_mesh.h5", "wheel_modes.h5", "wheel_greens.h5", "rail_mesh.h5", "rail_greens.h5", "report.h5",
                 "wheel.msh", "wheel.vtu", "modes.csv", "modes.md", "report.md", "summary.csv",
                 "figures/wheel_receptance.png", "figures/wheel_section_mesh.png", "figures/rail_dispersion.png",
                 "figures/rail_receptance.png", "figures/rail_moving_kernel.png", "figures/rail_section_mesh.png",
                 "figures/fig1_wheel_receptance_rotation.png", "figures/fig2_force_level.png",
                 "figures/fig3_level_difference.png", "figures/fig4_lateral_force.png",
                 "figures/rotation_campbell.png", "figures/radiation_spectra.png"):
        assert (built / name).exists(), name
    assert len(list((built / "cases").glob("*.h5"))) == len(CASES)
    assert sorted(p.stem for p in (built / "radiation").glob("*.h5")) == sorted(c.split(":", 1)[1] for c in CASES)
    summary = [line for line in (built / "summary.csv").read_text().splitlines() if not line.startswith("#")]
    assert len(summary) == len(CASES) + 1 and summary[0].startswith("case_id,")
    assert summary[0].endswith(",L_W,L_pA")
    with h5py.File(built / "wheel_greens.h5") as f:
        assert f.attrs["schema"] == "wheel_greens"
        assert f["stationary/receptance"].attrs["units"] == "m/N"
        assert len(f.attrs["params_sha256"]) == 64


def test_second_run_recomputes_nothing(built):
    assert engine.run(_study(), built, progress=False) == []
    assert all(fresh for _, fresh, _ in engine.status(_study(), built))


def test_a_copied_study_folder_stays_fresh(tmp_path, built):
    # no recorded hash depends on where the study folder is (the report's neither)
    out = tmp_path / "elsewhere" / "copy"
    shutil.copytree(built, out)
    assert engine.run(_study(), out, progress=False) == []


def test_status_lists_the_report(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    assert ("report", True, "") in engine.status(_study(), out)
    (out / "report.h5").unlink()
    assert ("report", False, "missing") in engine.status(_study(), out)


def test_plot_option_reruns_only_the_report(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    assert engine.run(_study("report.dpi=80"), out, progress=False) == ["report"]


def test_rolling_radius_reruns_from_the_mesh(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    study = _study("wheel.rolling_radius=0.385")
    rows = dict((name, fresh) for name, fresh, _ in engine.status(study, out))
    # the rail section is untouched; the rail's Green's functions read the contact geometry, which
    # reads the wheel's radius, so they are rebuilt with it
    assert rows["rail-mesh"]
    assert not any(fresh for name, fresh in rows.items() if name != "rail-mesh")
    # (the rail fit, stage rail-fit, reads the contact geometry too: the rail's contact position)
    assert engine.run(study, out, progress=False) == ["contact-geometry", "wheel-mesh", "wheel-modes", "wheel-greens",
                                                      "rail-greens", "rail-fit", *CASES, *RADIATION, "report"]


def test_damping_reruns_from_the_modes(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    assert engine.run(_study("wheel.fe.damping_ratio=2e-4"), out, progress=False) == [
        "wheel-modes", "wheel-greens", *CASES, *RADIATION, "report"]


def test_track_parameter_reruns_only_the_rail_and_the_cases(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    assert engine.run(_study("track.pad_vertical_stiffness=300e6"), out, progress=False) == [
        "rail-greens", "rail-fit", *CASES, *RADIATION, "report"]


def test_contact_parameter_reruns_only_the_cases(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    assert engine.run(_study("contact.rail_head_radius=0.25"), out, progress=False) == [*CASES, *RADIATION, "report"]


def test_interrupted_sweep_recomputes_only_unfinished_cases(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    victim = out / "cases" / (CASES[1].split(":", 1)[1] + ".h5")
    victim.unlink()  # as if the run had been killed before this case was written
    others = {p: p.stat().st_mtime_ns for p in (out / "cases").glob("*.h5")}
    assert engine.run(_study(), out, progress=False) == [CASES[1], RADIATION[1], "report"]
    assert victim.exists()
    assert all(p.stat().st_mtime_ns == before for p, before in others.items())


def test_truncated_and_foreign_artefacts_are_rebuilt(tmp_path, built):
    out = tmp_path / "o"
    shutil.copytree(built, out)
    data = (out / "wheel_greens.h5").read_bytes()
    (out / "wheel_greens.h5").write_bytes(data[: len(data) // 2])
    shutil.copy(out / "wheel_mesh.h5", out / "wheel_modes.h5")
    reasons = {name: reason for name, _, reason in engine.status(_study(), out)}
    assert "foreign" in reasons["wheel-modes"]
    with pytest.raises(ArtefactError):
        open_artefact(out / "wheel_greens.h5", "wheel_greens")
    assert engine.run(_study(), out, progress=False) == ["wheel-modes", "wheel-greens", *CASES, *RADIATION, "report"]


@pytest.mark.parametrize(
    "assignment, field",
    [("wheel.web_thickness=-0.01", "wheel.web_thickness"),
     ("wheel.rim_inner_radius=0.39", "wheel."),
     ("wheel.colour=1", "wheel.colour"),
     ("wheel.rolling_radius=abc", "wheel.rolling_radius")],
)
def test_bad_input_exits_2_and_writes_nothing(tmp_path, capsys, assignment, field):
    out = tmp_path / "never"
    assert pipeline.main(["run", *QUICK, "--out", str(out), "--set", assignment]) == 2
    assert field in capsys.readouterr().err
    assert not out.exists()


def test_unknown_stage_and_missing_config_exit_2(tmp_path):
    assert pipeline.main(["run", *QUICK, "--out", str(tmp_path), "--until", "nonsense"]) == 2
    assert pipeline.main(["run", "--quiet", "--config", str(tmp_path / "missing.toml"), "--out", str(tmp_path)]) == 2


def test_interrupted_write_leaves_nothing(tmp_path):
    target = tmp_path / "a.h5"
    with pytest.raises(RuntimeError):
        with write_artefact(target, "x", 1, "0" * 64) as f:
            f["data"] = [1, 2, 3]
            raise RuntimeError("killed")
    assert list(tmp_path.iterdir()) == []


def _case_forces(folder):
    out = {}
    for path in sorted((folder / "cases").glob("*.h5")):
        with h5py.File(path) as f:
            out[path.name] = f["force"][()]
    return out


def test_sweep_on_a_dask_scheduler_matches_the_local_run(tmp_path, built):
    # A scheduler and one worker on loopback, started here; the cases run on the worker and
    # give the same forces as the local run (the time stepping is deterministic).
    import json
    import os
    import subprocess
    import sys
    import time
    from pathlib import Path

    out = tmp_path / "o"
    shutil.copytree(built, out)
    shutil.rmtree(out / "cases")
    repo = str(Path(pipeline.__file__).resolve().parent)
    env = dict(os.environ, PYTHONPATH=repo + os.pathsep + os.environ.get("PYTHONPATH", ""))
    scheduler_file = tmp_path / "scheduler.json"
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                               "--port", "0", "--no-dashboard", "--scheduler-file", str(scheduler_file)],
                              env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        for _ in range(300):
            if scheduler_file.exists() and scheduler_file.stat().st_size > 0:
                break
            time.sleep(0.1)
        address = json.loads(scheduler_file.read_text())["address"]
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address, "--nworkers", "1",
                                       "--nthreads", "1", "--no-dashboard", "--host", "127.0.0.1"],
                                      env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
        rebuilt = engine.run(_study(), out, progress=False, scheduler=address)
    finally:
        for proc in reversed(procs):
            proc.terminate()
            proc.wait(timeout=30)
    assert sorted(rebuilt) == sorted([*CASES, *RADIATION, "report"])
    local, remote = _case_forces(built), _case_forces(out)
    assert local.keys() == remote.keys() and len(local) == len(CASES)
    for name in local:
        assert np.array_equal(local[name], remote[name])


def test_a_failing_case_is_reported_and_the_others_finish(tmp_path, built, monkeypatch):
    import stages.cases

    out = tmp_path / "o"
    shutil.copytree(built, out)
    shutil.rmtree(out / "cases")
    real = stages.cases.build_case

    def flaky(ctx, case_id, overrides):
        if "-0.003" in case_id:
            raise RuntimeError("injected failure")
        return real(ctx, case_id, overrides)

    monkeypatch.setattr(stages.cases, "build_case", flaky)
    with pytest.raises(engine.CasesFailed) as err:
        engine.run(_study(), out, progress=False)
    names = [c.split(":", 1)[1] for c in CASES]
    assert sorted(err.value.failed) == sorted(names[:3])  # the three cases at eta = -0.3 %
    assert all("injected failure" in err.value.failed[name] for name in names[:3])
    assert sorted(p.name for p in (out / "cases").glob("*.h5")) == sorted(name + ".h5" for name in names[3:])
    assert (out / "report.md").exists()


def _reprofiling_study(tmp_path):
    """The quick study swept over two rolling radii (a reprofiling sweep)."""
    config = tmp_path / "reprofiling.toml"
    config.write_text('[sweep]\n"wheel.rolling_radius" = [0.4125, 0.375]\n"contact.friction" = [0.3]\n')
    return load_study(config, quick=True)


def test_reprofiling_sweep_builds_one_wheel_variant_per_radius(tmp_path):
    # A sweep over a structural key gives each value its own folder of structural artefacts,
    # built from that value (the mass changes with the rolling radius).
    study = _reprofiling_study(tmp_path)
    out = tmp_path / "o"
    rebuilt = engine.run(study, out, until="wheel-mesh", progress=False)
    labels = [engine.variant_label({"wheel.rolling_radius": r}) for r in (0.4125, 0.375)]
    assert labels[0].startswith("rolling_radius=0.4125-") and labels[1].startswith("rolling_radius=0.375-")
    assert rebuilt == [f"wheel-mesh@{labels[0]}", f"wheel-mesh@{labels[1]}"]
    masses = []
    for label, radius in zip(labels, (0.4125, 0.375)):
        with h5py.File(out / "variants" / label / "wheel_mesh.h5") as f:
            position = f["contact/position"][()]
            masses.append(f["mass"][()])
        assert -position[2] == pytest.approx(radius, rel=1e-12)
    assert masses[0] > masses[1]  # a reprofiled (smaller) wheel is lighter
    assert engine.run(study, out, until="wheel-mesh", progress=False) == []


def test_reprofiling_sweep_shares_the_rail(tmp_path):
    # The rail does not depend on the wheel's radius: the second variant copies the first's rail
    # artefact (same parameters and inputs, so fresh there too) instead of rebuilding it.
    study = _reprofiling_study(tmp_path)
    out = tmp_path / "o"
    rebuilt = engine.run(study, out, until="rail-mesh", progress=False)
    labels = [engine.variant_label({"wheel.rolling_radius": r}) for r in (0.4125, 0.375)]
    assert rebuilt == [f"rail-mesh@{labels[0]}"]
    first, second = (out / "variants" / label / "rail_mesh.h5" for label in labels)
    assert first.read_bytes() == second.read_bytes()
    assert engine.run(study, out, until="rail-mesh", progress=False) == []
