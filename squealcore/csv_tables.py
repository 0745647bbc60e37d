"""Plain-text tables for users' own tools: comma-separated values with ``#`` comment lines.

Layout of every file written here::

    # free-text lines describing the data: source artefact, units, frame, conventions
    name_1,name_2,...
    1.5,-2.25e-10,...

Numbers are written with Python's ``repr`` of a binary64 float: the shortest decimal string
that reads back to the very same number (``float(text) == value`` exactly), so a table read
back equals the HDF5 data bit for bit. Non-finite values appear as ``nan``, ``inf`` or
``-inf``, which ``float()``, numpy and spreadsheet importers understand.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from squealcore.artefacts import atomic_output


def write_csv(path, columns, comments=()):
    """Write named columns of numbers as a CSV file (atomically).

    Parameters
    ----------
    path : Path
        Output file.
    columns : sequence of (str, array_like)
        Column name (with its unit, e.g. ``"frequency_Hz"``) and its values, all of one length.
    comments : sequence of str
        Lines written first, each prefixed with ``"# "``.

    Returns
    -------
    Path
        ``path``.
    """
    names = [name for name, _ in columns]
    table = np.column_stack([np.asarray(values, dtype=float).ravel() for _, values in columns])
    # tolist() gives Python floats, whose repr is the shortest exact round-trip text
    return write_table(path, names, ([repr(v) for v in row] for row in table.tolist()), comments)


def write_table(path, names, rows, comments=()):
    """Write a table of text cells as a CSV file with ``#`` comment lines first (atomically).

    The layout of the module docstring; :func:`write_csv` (numbers) and ``summary.csv``
    (:mod:`stages.summary`, text and numbers) both write through it.

    Parameters
    ----------
    path : Path
        Output file.
    names : sequence of str
        Column names.
    rows : iterable of sequence of str
        Cells, already formatted, one sequence per row, each as long as ``names``.
    comments : sequence of str
        Lines written first, each prefixed with ``"# "``.

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    ValueError
        If a name or a cell contains a comma or a line break, or a row has the wrong length.
    """
    names = list(names)
    for name in names:
        _check_cell(name, "column name")
    with atomic_output(path) as tmp, open(tmp, "w", encoding="utf-8", newline="\n") as handle:
        handle.writelines(f"# {line}\n" if line else "#\n" for line in comments)
        handle.write(",".join(names) + "\n")
        for row in rows:
            row = list(row)
            if len(row) != len(names):
                raise ValueError(f"row of {len(row)} cells for {len(names)} columns")
            for cell in row:
                _check_cell(cell, "cell")
            handle.write(",".join(row) + "\n")
    return path


def _check_cell(text, what):
    if "," in text or "\n" in text:
        raise ValueError(f"{what} {text!r} contains a comma or a line break")


def artefact_provenance(handle):
    """One comment line naming an open HDF5 artefact and its provenance attributes."""
    attrs = handle.attrs
    return (f"source: {Path(handle.filename).name} (schema {attrs.get('schema')}, "
            f"version {attrs.get('schema_version')}, created {attrs.get('created')}, "
            f"code {attrs.get('code_version')}, parameters sha256 {attrs.get('params_sha256')})")
