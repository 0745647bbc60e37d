"""Start-up of the command line: ``--version`` and the contact command on small examples, cold and warm.

The examples: ``small`` (the user guide's small case, steady rolling on the half-space, a coarse
grid: docs/user-guide.md, "The contact command") and ``point.toml`` (the point model, 20 transient
steps), or any case file of ``contact/examples``.

Every run is a fresh process (``python pipeline.py ...`` as a subprocess), timed from outside: the
wall time, and the processor time of the process (user + system, from ``resource.getrusage`` of
the children). Rows:

* ``pipeline.py --version``;
* ``pipeline.py contact <example>`` **cold**: numba's cache emptied before every run (each run
  gets a new empty ``NUMBA_CACHE_DIR``), so every kernel the case calls is compiled;
* the same **warm**: one run fills a ``NUMBA_CACHE_DIR``, the timed runs load from it;
* **batch**, warm: ``pipeline.py contact <example> <example> ...`` (``--batch`` copies, default 10)
  in one process; the row gives the time of each further case, (batch - one case) / (copies - 1),
  the median of that difference over the repeats, each repeat's two runs taken one after the
  other (a value within a few ms of zero, either sign, is below the runs' noise):
  what a case costs once the process has started, as in a CONTACT input file of several cases;

and, for scale, the floors of any such command: ``python -c pass`` (the interpreter), and
``numba floor``: a script that imports numpy and numba and calls one trivial kernel from numba's
cache (numba sets up its compiler's registries before it can load a cached kernel), ending as a
script ends (the interpreter's teardown, which releases numba's kernels and LLVM), like the
contact command (``pipeline.QUICK_EXIT_COMMANDS``) at once with :func:`os._exit`, and that again
after the contact command's lean start (rocket-fft without scipy.fft, numba's registries without
scipy.linalg: contact/lean_start.py), the floor of that command.

"Warm" means every cache a user's install has after a first run: numba's compiled kernels and
Python's bytecode (``__pycache__``); the runs are made without ``PYTHONDONTWRITEBYTECODE``, which
some containers set and which would make every run compile this repository's modules again.

The rows are run in turn, ``--repeats`` times (5), so that a change of the machine's speed falls
on all of them alike. Medians are printed beside issue 16's target for a small problem once
the caches exist (0.5 s end to end) and CONTACT's process time for such a problem (0.04 s), with
the ratios. The machine's load average is printed before and after: on a shared machine the wall
time grows with the load, the processor time much less.

Run: ``python benchmarks/startup.py [--repeats N] [--examples small point.toml] [--skip-cold] [--batch N]``.
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
EXAMPLES = REPO / "contact" / "examples"
#: The user guide's small case (docs/user-guide.md, "The contact command"), kept equal to it.
SMALL_CASE = """model = "halfspace"
kind = "steady"
[geometry]
semi_axes = [0.006, 0.004]
[grid]
dx = 0.0008
dy = 0.0008
[load]
normal_force = 50e3
[friction]
coefficient = 0.3
[rolling]
creepage = [0.0, -0.002, 0.0]
speed = 13.9
"""

#: Issue 16, "What to build" 5: a small problem end to end, once the caches exist (s, wall).
TARGET_S = 0.5
#: Issue 16, "Why": CONTACT (Vollebregt's Fortran code, built with gfortran -O2) solves the
#: command's small problem in this process time on the same 2-core machine (s).
CONTACT_PROCESS_S = 0.04


#: The numba floor's script: one trivial kernel, cached.
FLOOR_SCRIPT = """import numba
import numpy


@numba.njit(cache=True)
def total(values):
    s = 0.0
    for v in values:
        s += v
    return s


total(numpy.ones(3))
"""
#: The same, ending at once as the contact command does (no teardown of numba's kernels and LLVM).
FLOOR_QUICK_EXIT_SCRIPT = FLOOR_SCRIPT + """
import os
os._exit(0)
"""
#: The same again after the contact command's lean start (contact/lean_start.py): the
#: floor of that command.
FLOOR_LEAN_SCRIPT = """from contact.lean_start import lean_start

lean_start()
""" + FLOOR_QUICK_EXIT_SCRIPT


def timed_run(argv, env, program=None):
    """Run ``python pipeline.py ARGV`` (or ``python ARGV`` with ``program=[]``) once; (wall s, processor s)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    program = [str(REPO / "pipeline.py")] if program is None else program
    result = subprocess.run([sys.executable, *program, *argv], cwd=REPO, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if result.returncode != 0:
        raise SystemExit(f"{' '.join(program + argv)} failed ({result.returncode}): {result.stderr.strip()}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def round_robin(runs, repeats):
    """(wall, processor) seconds of every repeat of each run, the runs taken in turn ``repeats`` times.

    ``runs``: (argv, env, program, cold) tuples as :func:`timed_run` takes them (``cold``: a new
    empty numba cache for every run). Returns, per run, the lists of wall and processor times.
    Taking the rows in turn, not each row's repeats together, keeps a change of the machine's
    speed (a shared machine's spells) from falling on one row.
    """
    walls = [[] for _ in runs]
    cpus = [[] for _ in runs]
    for _ in range(repeats):
        for k, (argv, env, program, cold) in enumerate(runs):
            if cold:
                with tempfile.TemporaryDirectory(prefix="numba-cold-") as cache:
                    wall, cpu = timed_run(argv, {**env, "NUMBA_CACHE_DIR": cache}, program)
            else:
                wall, cpu = timed_run(argv, env, program)
            walls[k].append(wall)
            cpus[k].append(cpu)
    return list(zip(walls, cpus))


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5, help="runs per row (median), default 5")
    parser.add_argument("--examples", nargs="+", default=["small", "point.toml"],
                        help="'small' or case files of contact/examples; default small point.toml")
    parser.add_argument("--skip-cold", action="store_true", help="leave out the cold rows (compilation)")
    parser.add_argument("--batch", type=int, default=10, help="copies of a case in the batch rows (>= 2; default 10)")
    args = parser.parse_args(argv)
    env = {**os.environ, "PYTHONPATH": str(REPO) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           "MPLBACKEND": "Agg"}
    env.pop("NUMBA_CACHE_DIR", None)
    env.pop("PYTHONDONTWRITEBYTECODE", None)  # warm: Python's bytecode cache too, as in a user's install
    timed_run(["--version"], env)  # writes the bytecode of the modules --version needs
    load_before = os.getloadavg()
    copies = max(args.batch, 2)
    with tempfile.TemporaryDirectory(prefix="numba-warm-") as cache:
        warm_env = {**env, "NUMBA_CACHE_DIR": cache}
        scripts = {}
        for name, text in (("numba_floor.py", FLOOR_SCRIPT), ("numba_floor_quick_exit.py", FLOOR_QUICK_EXIT_SCRIPT),
                           ("numba_floor_lean.py", FLOOR_LEAN_SCRIPT)):
            scripts[name] = Path(cache) / name
            scripts[name].write_text(text)
            timed_run([str(scripts[name])], warm_env, program=[])  # compiles and caches the kernel
        small = Path(cache) / "small.toml"
        small.write_text(SMALL_CASE)
        rows = [("python -c pass", (["-c", "pass"], env, [], False)),
                ("numba floor (numpy, numba, one cached kernel)", ([str(scripts["numba_floor.py"])], warm_env, [], False)),
                ("numba floor, ending at once (os._exit)", ([str(scripts["numba_floor_quick_exit.py"])], warm_env, [], False)),
                ("numba floor after the contact command's lean start, ending at once",
                 ([str(scripts["numba_floor_lean.py"])], warm_env, [], False)),
                ("pipeline.py --version", (["--version"], env, None, False))]
        batches = []
        for example in args.examples:
            command = ["contact", str(small if example == "small" else EXAMPLES / example)]
            if not args.skip_cold:
                rows.append((f"pipeline.py contact {example}, cold", (command, env, None, True)))
            timed_run(command, warm_env)  # fills the caches (numba's, Python's bytecode)
            rows.append((f"pipeline.py contact {example}, warm", (command, warm_env, None, False)))
            batches.append((len(rows) - 1, f"pipeline.py contact {example} x {copies} in one process, warm, each further case"))
            rows.append((batches[-1][1], (command + command[1:] * (copies - 1), warm_env, None, False)))
        timings = round_robin([run for _, run in rows], args.repeats)
    for one, name in batches:  # the batch rows: what each further case costs, paired repeat by repeat
        (one_walls, one_cpus), (batch_walls, batch_cpus) = timings[one], timings[one + 1]
        timings[one + 1] = ([(b - a) / (copies - 1) for a, b in zip(one_walls, batch_walls)],
                            [(b - a) / (copies - 1) for a, b in zip(one_cpus, batch_cpus)])
    timings = [(statistics.median(walls), statistics.median(cpus)) for walls, cpus in timings]
    load_after = os.getloadavg()
    print(f"load average (1, 5, 15 min) before: {', '.join(f'{x:.2f}' for x in load_before)}; "
          f"after: {', '.join(f'{x:.2f}' for x in load_after)}; {os.cpu_count()} cores; "
          f"median of {args.repeats} runs, the rows taken in turn")
    print(f"| command | wall (s) | process time (s) | wall / target {TARGET_S} s | "
          f"process time / CONTACT {CONTACT_PROCESS_S} s |")
    print("|---|---|---|---|---|")
    for (name, _), (wall, cpu) in zip(rows, timings):
        digits = 3 if wall < 0.1 else 2  # the batch rows: milliseconds
        print(f"| {name} | {wall:.{digits}f} | {cpu:.{digits}f} | {wall / TARGET_S:.{digits - 1}f} | "
              f"{cpu / CONTACT_PROCESS_S:.{digits - 2}f} |")


if __name__ == "__main__":
    main()
