"""Two finished studies compared case by case on their ``summary.csv``, to the printed digits.

A change of a solver or of the code's order of operations moves results at round-off; what
counts is whether a result moves at the digits the report prints. :func:`summary_differences`
reads the ``summary.csv`` of two study folders (layout: :mod:`stages.summary`), pairs the cases
by their id without its parameter hash, and describes every case whose printed result differs
(the columns of :data:`PRINTED`, formatted as printed) or that only one study has. The run
time is not a result and is not compared. ``python -m benchmarks.simulate --compare-studies A B``
prints the list.

This module sits in ``stages/`` because it reads an artefact of the report stage (the study's
``summary.csv``, written by :mod:`stages.summary`); it imports nothing but the standard library.
"""

from __future__ import annotations

import csv
import os

__all__ = ["PRINTED", "summary_differences"]

PRINTED = {"L_F2": "{:.1f}", "squeal": "{}", "squeal_frequency": "{:.0f}", "buildup_time": "{:.2f}",
           "growth": "{:.2f}", "L_W": "{:.1f}", "L_pA": "{:.1f}"}
"""The result columns of a study's summary.csv that are compared, with the format they are printed in."""


def summary_rows(folder):
    """The rows of ``folder``/summary.csv by case id without its parameter hash (comment lines skipped)."""
    with open(os.path.join(folder, "summary.csv"), newline="") as f:
        lines = [line for line in f if not line.startswith("#")]
    return {row["case_id"].rsplit("-", 1)[0]: row for row in csv.DictReader(lines)}


def _printed(column, value):
    try:
        return PRINTED[column].format(float(value)) if column != "squeal" else value
    except ValueError:  # empty or non-numeric (e.g. no build-up time)
        return value


def summary_differences(folder_a, folder_b):
    """The cases of two finished studies whose results differ to their printed digits.

    Parameters
    ----------
    folder_a, folder_b : str or os.PathLike
        Study folders, each with a ``summary.csv``.

    Returns
    -------
    lines : list of str
        One line per case that moved, in case order: ``"<case>: only in <folder>"`` for a case of
        one study only, else ``"<case>: <column> <before> -> <after>; ..."`` with the printed values.
    n_cases : int
        How many distinct cases the two studies have together.
    """
    a, b = summary_rows(folder_a), summary_rows(folder_b)
    lines = []
    for case in sorted(set(a) | set(b)):
        if case not in a or case not in b:
            lines.append(f"{case}: only in {folder_a if case in a else folder_b}")
            continue
        changes = [f"{column} {_printed(column, a[case][column])} -> {_printed(column, b[case][column])}"
                   for column in PRINTED if column in a[case] and column in b[case]
                   and _printed(column, a[case][column]) != _printed(column, b[case][column])]
        if changes:
            lines.append(f"{case}: " + "; ".join(changes))
    return lines, len(set(a) | set(b))
