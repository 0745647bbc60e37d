"""Stand-alone contact command: ``python pipeline.py contact CASE.toml [MORE.toml ...] [--json] [--out F.h5] [--plot F.png]``.

``add_args(parser)`` and ``run_command(args)`` wire it into another command line; ``main(argv)`` runs
it alone.

Solves one contact problem or a sequence of steps from a TOML case (see config.py) and
prints the results (JSON with ``--json``). Several case files are solved one after the other in
the same process, so the start-up (Python, numba, the compiled kernels: about half a second once
numba's cache exists, docs/benchmarks.md) is paid once, as with a CONTACT input file holding
several cases; ``python pipeline.py contact`` ends its process at once when done
(``pipeline.QUICK_EXIT_COMMANDS``). Bad input: one line on stderr naming
the field, exit status 2, before any case is solved.
"""

from __future__ import annotations

import argparse
import json
import logging
import sys
from pathlib import Path

from squealcore.errors import InputError

from contact.config import load_case
from contact.halfspace.normal import NotConvergedError
from contact.registry import DEFAULT_MODEL

log = logging.getLogger(__name__)

KEYS = ("Fx", "Fy", "Fn", "Mz", "pmax", "n_contact", "n_stick", "n_slip", "slip_fraction",
        "iterations", "residual", "approach")


def run_case(case):
    """Solve all steps of a :class:`~contact.config.Case`; return the results list."""
    model = case.model
    state = model.initial_state()
    results = []
    for _ in range(case.steps):
        res = model.solve(state, creepage=case.creepage, shift=case.shift, **case.load)
        results.append(res)
        state = res.new_state
    return results


def summarise(case, results) -> dict:
    """JSON-ready summary: scalars for one step, lists for sequences (SI units)."""
    rows = []
    for r in results:
        d = r.diagnostics
        rows.append({"Fx": float(r.force[0]), "Fy": float(r.force[1]), "Fn": float(r.force[2]),
                     "Mz": float(r.spin_moment), "pmax": d.pmax, "n_contact": d.n_contact,
                     "n_stick": d.n_stick, "n_slip": d.n_slip, "slip_fraction": d.slip_fraction,
                     "iterations": d.iterations, "residual": d.residual, "approach": d.approach})
    out = {"model": case.config.get("model", DEFAULT_MODEL), "kind": case.config.get("kind", "steady"),
           "steps": len(rows)}
    if len(rows) == 1:
        out.update(rows[0])
    else:
        out.update({k: [row[k] for row in rows] for k in KEYS})
    if case.hertz is not None:
        h = case.hertz
        out["hertz"] = {"a": h.a, "b": h.b, "p0": float(h.p0), "approach": float(h.approach),
                        "normal_force": h.normal_force}
    return out


def plot_format(path) -> str:
    """The figure format of ``--plot`` from its file extension (one that matplotlib can write).

    Raises
    ------
    InputError
        Naming ``--plot`` and the allowed extensions.
    """
    from matplotlib.figure import Figure  # lazy: matplotlib, 1.7 s of start-up (measured)
    formats = sorted(Figure().canvas.get_supported_filetypes())
    extension = Path(path).suffix.lower().lstrip(".")
    if extension not in formats:
        raise InputError("--plot", f"must end in one of .{', .'.join(formats)} (the figure format), got {path!r}")
    return extension


def add_args(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the contact command's arguments (case files, ``--json``, ``--out``, ``--plot``) to ``parser``."""
    parser.add_argument("case", nargs="+", help="TOML case file(s) (keys: docs/parameters.md); several are solved "
                                                "in one process, one after the other")
    parser.add_argument("--json", action="store_true", help="print the results as JSON")
    parser.add_argument("--out", help="write traction fields to this HDF5 file")
    parser.add_argument("--plot", help="draw pressure, traction and stick/slip (half-space model; the forces per "
                                       "step for the point model) to this file; format from its extension "
                                       "(png, pdf, svg, ...)")
    return parser


def run_command(args) -> int:
    """Run the contact command from parsed arguments; returns the exit status.

    0 ok, 2 bad input (one line on stderr naming the field or file; every case file is read and
    checked before any is solved), 1 solver failure of any case (the others are still solved
    and reported).
    """
    paths = [args.case] if isinstance(args.case, str) else list(args.case)
    try:
        for option in ("out", "plot"):
            target = getattr(args, option)
            if target and len(paths) > 1:
                raise InputError(f"--{option}", f"writes the fields of one case: give one case file, not {len(paths)}")
            if target and Path(target).is_dir():
                raise InputError(f"--{option}", f"must name a file, {target!r} is a folder")
        fmt = plot_format(args.plot) if args.plot else None
        cases = [load_case(path) for path in paths]
    except InputError as exc:
        print(f"error: {exc.field}: {exc.message}", file=sys.stderr)
        return 2
    status = 0
    summaries = []
    for path, case in zip(paths, cases):
        try:
            results = run_case(case)
        except NotConvergedError as exc:
            print(f"error: {path}: {exc}" if len(paths) > 1 else f"error: {exc}", file=sys.stderr)
            summaries.append({"case": str(path), "error": str(exc)})
            status = 1
            continue
        summary = summarise(case, results)
        if len(paths) > 1:
            summary = {"case": str(path), **summary}
        summaries.append(summary)
        if not args.json:
            last = results[-1]
            prefix = f"{path}: " if len(paths) > 1 else ""
            print(f"{prefix}{summary['model']} {summary['kind']}: {len(results)} step(s); last: "
                  f"Fx = {last.force[0]:.6g} N, Fy = {last.force[1]:.6g} N, Fn = {last.force[2]:.6g} N, "
                  f"pmax = {last.diagnostics.pmax:.4g} Pa, contact/stick/slip = {last.diagnostics.n_contact}/"
                  f"{last.diagnostics.n_stick}/{last.diagnostics.n_slip}")
        if args.out:
            from contact.output import write_results  # lazy: h5py, 0.12 s of start-up (measured)
            write_results(args.out, results, case.config)
        if args.plot:
            from contact.plots import plot_fields, plot_forces  # lazy: matplotlib, 1.7 s of start-up (measured)
            title = f"{summary['model']} {summary['kind']}"
            if results[-1].fields is None:
                plot_forces(results, args.plot, title=title, fmt=fmt)
            else:
                plot_fields(results[-1].fields, args.plot, title=title, fmt=fmt)
    if args.json:
        if len(paths) == 1:
            if summaries[0].get("error") is None:
                print(json.dumps(summaries[0]))
        else:
            print(json.dumps(summaries))
    return status


def main(argv=None) -> int:
    """Entry point; returns the exit status (0 ok, 2 bad input, 1 solver failure)."""
    parser = add_args(argparse.ArgumentParser(prog="contact", description="Solve a rolling contact case."))
    return run_command(parser.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
