"""The radiation columns of ``summary.csv`` (for stages/export_csv.py, which owns the file)."""

from __future__ import annotations

import math
from pathlib import Path

from squealcore.artefacts import ArtefactError
from stages.radiation import radiation_path, read_radiation

#: Column names and units of :func:`summary_columns`.
SUMMARY_COLUMNS = (("L_W", "dB re 1 pW, wheel + rail"), ("L_pA", "dB(A) re 20 µPa at 7.5 m, 1.2 m"))


def summary_columns(case_h5, study=None):
    """``{"L_W": dB re 1 pW, "L_pA": dB(A)}`` of a case, NaN if its radiation artefact is missing.

    Parameters
    ----------
    case_h5 : path
        ``<study folder>/cases/<id>.h5``; the radiation artefact is
        ``<study folder>/radiation/<id>.h5``.
    study : dict, optional
        The study (unused: the levels are those stored; kept for the export's calling convention).

    Returns
    -------
    dict
    """
    case_h5 = Path(case_h5)
    path = radiation_path(case_h5.parent.parent, case_h5.stem)
    try:
        levels = read_radiation(path)
    except (ArtefactError, OSError, KeyError):
        return {name: math.nan for name, _ in SUMMARY_COLUMNS}
    return {name: float(levels[name]) for name, _ in SUMMARY_COLUMNS}
