"""Start-up of the command line: what a command imports, and that compiled kernels come from the cache.

Nothing here is timed (timings belong to ``benchmarks/startup.py``): the tests check the causes of
a slow start instead, the modules a command imports and numba's cache being used.
"""

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import numba
import pytest

import pipeline

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "contact" / "examples"

#: Packages the contact command has no use for (plots and HDF5 output import theirs on demand).
NOT_FOR_CONTACT = ("matplotlib", "dask", "distributed", "gmsh", "h5py", "meshio", "tqdm", "stages", "fe",
                   "waveguide", "radiation", "scipy.interpolate", "scipy.optimize", "scipy.signal", "scipy.stats")


def _modules_after(code):
    """Names in ``sys.modules`` after running ``code`` in a fresh interpreter of this repository."""
    script = f"import json, sys\n{code}\nprint(json.dumps(sorted(sys.modules)))"
    env = {**os.environ, "PYTHONPATH": str(REPO), "MPLBACKEND": "Agg"}
    result = subprocess.run([sys.executable, "-c", script], cwd=REPO, env=env, capture_output=True, text=True,
                            timeout=300)
    assert result.returncode == 0, result.stderr
    return set(json.loads(result.stdout.splitlines()[-1]))


def _heavy(modules, names=NOT_FOR_CONTACT):
    """The packages of ``names`` (a package or ``package.module``) found among ``modules``."""
    return sorted(name for name in names if any(m == name or m.startswith(name + ".") for m in modules))


def test_checker_sees_a_heavy_import():
    """Control: the plots module of the contact command does pull matplotlib, and the check sees it."""
    modules = _modules_after("import contact.plots")
    assert "matplotlib" in _heavy(modules)


def test_contact_cli_imports_no_heavy_module():
    modules = _modules_after("import contact.cli")
    assert "contact.halfspace.model" in modules  # the import did happen
    assert _heavy(modules) == []


def test_pipeline_contact_command_imports_only_the_contact_modules():
    # --help parses the contact command's arguments (its module is imported) and stops there
    modules = _modules_after("import pipeline\ntry:\n    pipeline.main(['contact', '--help'])\nexcept SystemExit:\n"
                             "    pass")
    assert "contact.cli" in modules
    assert _heavy(modules) == []


def test_contact_command_solves_without_scipy_fft_linalg_special(tmp_path):
    """The contact command's lean start (contact/lean_start.py) and solvers need neither
    scipy.fft, scipy.linalg nor scipy.special (the Hertz integrals by the arithmetic-geometric mean,
    the axis ratio by bisection): a steady case (the user guide's small case: FFT normal product) and
    a transient one (Hertz from curvatures, compiled FFT products) are solved in a fresh process with
    none of them imported; the kernels loaded or compiled there use rocket-fft's numpy.fft overloads."""
    spec = importlib.util.spec_from_file_location("startup_benchmark", REPO / "benchmarks" / "startup.py")
    benchmark = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(benchmark)
    small = tmp_path / "small.toml"
    small.write_text(benchmark.SMALL_CASE, encoding="utf-8")
    cases = [str(small), str(EXAMPLES / "transient.toml")]
    modules = _modules_after(f"import pipeline\nstatus = pipeline.main(['contact', *{cases!r}])\nassert status == 0, status")
    assert {"contact.halfspace.model", "contact.halfspace.fft_products", "rocket_fft"} <= modules
    assert _heavy(modules, ("scipy.fft", "scipy.linalg", "scipy.special")) == []


def test_lean_start_leaves_scipy_and_numba_whole():
    """After the lean start scipy.fft and scipy.linalg import and work, and numba compiles numpy.fft
    (rocket-fft), np.dot (BLAS) and np.linalg.solve (LAPACK) correctly; np.correlate (the one function
    that keeps numba's answer 'no BLAS') too."""
    modules = _modules_after(
        "from contact.lean_start import lean_start\n"
        "assert lean_start() is True\n"
        "assert not {'scipy.fft', 'scipy.linalg', 'scipy.special'} & set(sys.modules)\n"
        "assert 'rocket_fft' in sys.modules\n"
        "import numba, numpy as np, scipy.fft, scipy.linalg\n"
        "x = np.arange(1.0, 9.0)\n"
        "m = np.diag(x) + 0.5\n"
        "assert np.allclose(scipy.fft.rfft(x), np.fft.rfft(x))\n"
        "assert np.allclose(scipy.linalg.solve(m, x), np.linalg.solve(m, x))\n"
        "assert np.allclose(numba.njit(lambda a: np.fft.rfft(a))(x), np.fft.rfft(x))\n"
        "assert np.allclose(numba.njit(lambda a, b: np.dot(a, b))(m, x), m @ x)\n"
        "assert np.allclose(numba.njit(lambda a, b: np.linalg.solve(a, b))(m, x), np.linalg.solve(m, x))\n"
        "assert np.allclose(numba.njit(lambda a, b: np.correlate(a, b))(x, x[:3]), np.correlate(x, x[:3]))")
    assert {"scipy.fft", "scipy.linalg"} <= modules


def test_lean_start_with_another_numba_leaves_numba_to_its_usual_start():
    """If numba's CPU target lacks the set-up that the lean start calls (another numba version's
    internals), the lean start skips it, masks nothing, and numba sets itself up as usual."""
    modules = _modules_after("import numba, numba.core.registry, numpy as np\n"
                             "original = numba.core.registry.cpu_target\n"
                             "numba.core.registry.cpu_target = object()  # no target_context\n"
                             "from contact.lean_start import set_up_numba_without_scipy_linalg\n"
                             "assert set_up_numba_without_scipy_linalg() is False\n"
                             "assert sys.modules.get('scipy.linalg', 0) is not None\n"
                             "numba.core.registry.cpu_target = original\n"
                             "x = np.arange(1.0, 5.0)\n"
                             "assert numba.njit(lambda a: np.dot(a, a))(x) == 30.0")
    assert "scipy.linalg" in modules  # numba's usual set-up imported it


@pytest.mark.parametrize("first", ["import threading\nstop = threading.Event()\n"
                                   "threading.Thread(target=stop.wait).start()\n",
                                   "import scipy.fft, scipy.linalg\n"])
def test_lean_start_only_when_safe(first):
    """Nothing is masked while another thread runs (it could import scipy.fft or scipy.linalg meanwhile),
    nor once the modules are imported: rocket-fft is then left to numba's usual import."""
    modules = _modules_after(first + "from contact.lean_start import lean_start\n"
                             "assert lean_start() is False\n"
                             "if 'stop' in globals():\n    stop.set()")
    assert "rocket_fft" not in modules


@pytest.mark.parametrize("argv", [["--version"], ["--help"]])
def test_version_and_help_import_no_command(argv):
    modules = _modules_after(f"import pipeline\npipeline.main({argv!r})")
    # --version reads the version through squealcore.artefacts, which imports h5py
    allowed = ("h5py",) if argv == ["--version"] else ()
    names = tuple(n for n in NOT_FOR_CONTACT if n not in allowed) + ("numba", "interaction", "mesh", "scipy")
    assert _heavy(modules, names) == []


def test_second_contact_run_loads_every_kernel_from_the_cache(tmp_path):
    """The second run of a case compiles nothing: numba reports only loads from its cache."""
    env = {**os.environ, "PYTHONPATH": str(REPO), "MPLBACKEND": "Agg", "NUMBA_DEBUG_CACHE": "1"}
    argv = [sys.executable, str(REPO / "pipeline.py"), "contact", str(EXAMPLES / "point.toml")]
    runs = [subprocess.run(argv, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=600)
            for _ in range(2)]
    for run in runs:
        assert run.returncode == 0, run.stderr
    second = runs[1].stdout + runs[1].stderr
    assert "[cache] data loaded from" in second
    assert "[cache] data saved to" not in second, second


def _numba_without_cache_folder():
    """numba's own error when no folder can hold a kernel's cache: a function with no source file has none."""
    namespace = {}
    exec(compile("def kernel(x):\n    return x\n", "<no source file>", "exec"), namespace)
    try:
        numba.njit(cache=True)(namespace["kernel"])
    except RuntimeError as exc:
        return exc
    raise AssertionError("numba cached a function that has no source file")


def test_read_only_install_without_cache_folder_is_one_line_naming_numba_cache_dir(monkeypatch, capsys):
    """A kernel module that cannot be cached (read-only install, no NUMBA_CACHE_DIR) gives one line saying
    what to set, not an internal error."""
    error = _numba_without_cache_folder()

    def loader():
        raise error

    monkeypatch.setitem(pipeline.COMMANDS, "contact", ("solve", loader))
    assert pipeline.main(["contact", "case.toml"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "NUMBA_CACHE_DIR" in err[0] and "internal error" not in err[0], err


def test_benchmark_small_case_is_the_user_guides():
    """benchmarks/startup.py times the user guide's small case: the two texts agree (comments aside)."""
    spec = importlib.util.spec_from_file_location("startup_benchmark", REPO / "benchmarks" / "startup.py")
    benchmark = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(benchmark)
    guide = (REPO / "docs" / "user-guide.md").read_text(encoding="utf-8")
    block = guide.split("cat > small.toml <<'EOF'\n", 1)[1].split("\nEOF\n", 1)[0]

    def lines(text):
        return [line.split("#", 1)[0].rstrip() for line in text.strip().splitlines()]

    assert lines(block) == lines(benchmark.SMALL_CASE)


def test_contact_command_ends_at_once_with_its_output_complete(tmp_path):
    """The contact command skips the interpreter's teardown (``pipeline.QUICK_EXIT_COMMANDS``): the JSON it
    prints, the HDF5 file it writes and its exit status are those of the same case solved in this process,
    and an exit handler registered before the command does not run (the teardown was skipped)."""
    case = tmp_path / "shift.toml"
    case.write_text((EXAMPLES / "shift.toml").read_text(encoding="utf-8"), encoding="utf-8")
    h5 = tmp_path / "res.h5"
    marker = tmp_path / "exit-handler-ran"
    script = ("import atexit, pathlib, sys\n"
              f"atexit.register(pathlib.Path({str(marker)!r}).touch)\n"
              "import pipeline\n"
              f"sys.argv = ['pipeline.py', 'contact', {str(case)!r}, '--json', '--out', {str(h5)!r}]\n"
              "pipeline.entry_point()\n")
    # stdout block-buffered, as when a user pipes it: what is printed must be flushed before the exit
    env = {**{k: v for k, v in os.environ.items() if k != "PYTHONUNBUFFERED"}, "PYTHONPATH": str(REPO),
           "MPLBACKEND": "Agg"}
    run = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=600)
    assert run.returncode == 0, run.stderr
    assert not marker.exists()  # the process ended without its exit handlers: the quick exit was taken
    printed = json.loads(run.stdout)

    from contact.cli import run_case, summarise
    from contact.config import load_case
    here = load_case(str(case))
    expected = summarise(here, run_case(here))
    assert printed == json.loads(json.dumps(expected))  # every value, to the last printed digit
    import h5py
    with h5py.File(h5) as f:
        assert f.attrs["complete"] and f.attrs["schema"] == "contact"
        assert f["force"][-1, 1] == expected["Fy"][-1]
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(["shift.toml", "res.h5"])


def test_other_commands_keep_the_interpreters_exit(tmp_path):
    """Control of the test above: ``--version`` (no quick-exit command) runs the exit handlers."""
    marker = tmp_path / "exit-handler-ran"
    script = ("import atexit, pathlib, sys\n"
              f"atexit.register(pathlib.Path({str(marker)!r}).touch)\n"
              "import pipeline\n"
              "sys.argv = ['pipeline.py', '--version']\n"
              "pipeline.entry_point()\n")
    env = {**os.environ, "PYTHONPATH": str(REPO)}
    run = subprocess.run([sys.executable, "-c", script], cwd=tmp_path, env=env, capture_output=True, text=True,
                         timeout=300)
    assert run.returncode == 0, run.stderr
    assert marker.exists()
