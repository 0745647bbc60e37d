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
    for name in names:
        if "," in name or "\n" in name:
            raise ValueError(f"column name {name!r} contains a comma or a line break")
    table = np.column_stack([np.asarray(values, dtype=float).ravel() for _, values in columns])
    with atomic_output(path) as tmp:
        with open(tmp, "w", encoding="utf-8", newline="\n") as handle:
            for line in comments:
                handle.write(f"# {line}\n" if line else "#\n")
            handle.write(",".join(names) + "\n")
            # tolist() gives Python floats, whose repr is the shortest exact round-trip text
            handle.writelines(",".join(map(repr, row)) + "\n" for row in table.tolist())
    return path


def artefact_provenance(handle):
    """One comment line naming an open HDF5 artefact and its provenance attributes."""
    attrs = handle.attrs
    return (f"source: {Path(handle.filename).name} (schema {attrs.get('schema')}, "
            f"version {attrs.get('schema_version')}, created {attrs.get('created')}, "
            f"code {attrs.get('code_version')}, parameters sha256 {attrs.get('params_sha256')})")
