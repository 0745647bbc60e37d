"""The case summary: one row per case, read from ``cases/<id>.h5``, written as ``summary.csv``.

``summary.csv`` has the layout of :mod:`squealcore.csv_tables` (``#`` comment lines, then the
header, then one line per case). Its second comment line lists the unit of every column, in the
order of the header::

    # summary.csv: one row per case of the study; the units of the columns, in order:
    # units: -,-,m,1,1,-,-,-,1,1,m/s,dB re 1 N,-,Hz,-,s,1,-,1,N,1,1,s,dB re 1 pW,dB(A) re 20 uPa
    case_id,variant,wheel.rolling_radius,contact.friction,...

(``-``: text or a yes/no flag, ``1``: a dimensionless number). Read it with
``pandas.read_csv(path, comment="#")`` or ``csv.DictReader`` over the lines that do not start
with ``#``.

The columns are ``case_id``, ``variant`` (the structural variant's folder name under
``variants/``, ``base`` when the study has one structure), one column per swept key named by
its dotted key (``wheel.rolling_radius``; the unit from the schema), then the fixed columns of
:data:`SUMMARY_COLUMNS`. To add a column, add one :class:`SummaryColumn` to that tuple; its
getter receives the case summary of :func:`read_case_summary` (every attribute of the case
artefact, e.g. ``SummaryColumn("L_W", "dB re 1 pW", case_attribute("L_W"))`` for an attribute
``L_W`` written by the case stage).
"""

from __future__ import annotations

import json
from collections.abc import Callable
from dataclasses import dataclass
from operator import itemgetter
from typing import Any

import numpy as np

from interaction.metrics import (DEFAULT_SQUEAL_MIN_FREQUENCY, NO_OSCILLATION, ContactRegime, contact_regime,
                                 oscillation_class, squeal_metrics)
from squealcore.artefacts import open_artefact, read_dataset
from squealcore.schema import spec_of
from stages.cases import CASE_VERSION
from stages.config import STUDY_SECTIONS
from squealcore.csv_tables import write_table
from stages.radiation import radiation_levels

#: Unit written for text columns and yes/no flags.
TEXT_UNIT = "-"
#: Unit written for dimensionless numbers.
DIMENSIONLESS_UNIT = "1"
#: Variant name of the cases of a study with a single structure.
BASE_VARIANT = "base"


@dataclass(frozen=True)
class SummaryColumn:
    """One column of ``summary.csv``.

    Attributes
    ----------
    name : str
        Header of the column.
    unit : str
        Its unit (``"-"`` text or flag, ``"1"`` dimensionless).
    value : callable
        Case summary (dict of :func:`read_case_summary`) -> the cell's value (str, bool, int or float).
    """

    name: str
    unit: str
    value: Callable[[dict], Any]


def case_attribute(name):
    """Getter of a case summary entry (an attribute of ``cases/<id>.h5``)."""
    return itemgetter(name)


#: The columns after ``case_id``, ``variant`` and the swept keys, in order.
SUMMARY_COLUMNS = (
    SummaryColumn("wheel_model", TEXT_UNIT, case_attribute("wheel_model")),
    SummaryColumn("contact_model", TEXT_UNIT, case_attribute("contact_model")),
    SummaryColumn("friction", DIMENSIONLESS_UNIT, case_attribute("friction")),
    SummaryColumn("lateral_creepage", DIMENSIONLESS_UNIT, case_attribute("lateral_creepage")),
    SummaryColumn("speed", "m/s", case_attribute("speed")),
    SummaryColumn("L_F2", "dB re 1 N", case_attribute("L_F2")),
    SummaryColumn("squeal", TEXT_UNIT, case_attribute("squeal")),
    SummaryColumn("squeal_frequency", "Hz", case_attribute("squeal_frequency")),
    SummaryColumn("oscillation", TEXT_UNIT, case_attribute("oscillation")),
    SummaryColumn("buildup_time", "s", case_attribute("buildup_time")),
    SummaryColumn("growth", DIMENSIONLESS_UNIT, case_attribute("growth")),
    SummaryColumn("regime", TEXT_UNIT, case_attribute("regime")),
    SummaryColumn("contact_loss", DIMENSIONLESS_UNIT, case_attribute("contact_loss")),
    SummaryColumn("peak_normal_force", "N", case_attribute("peak_normal_force")),
    SummaryColumn("peak_normal_ratio", DIMENSIONLESS_UNIT, case_attribute("peak_normal_ratio")),
    SummaryColumn("peak_lateral_ratio", DIMENSIONLESS_UNIT, case_attribute("peak_lateral_ratio")),
    SummaryColumn("runtime", "s", case_attribute("runtime")),
    SummaryColumn("L_W", "dB re 1 pW", case_attribute("L_W")),
    SummaryColumn("L_pA", "dB(A) re 20 uPa", case_attribute("L_pA")),
)

#: Attributes of a case artefact a summary needs (written by stages/cases.py).
REQUIRED_ATTRIBUTES = ("case_id", "wheel_model", "contact_model", "friction", "lateral_creepage", "speed", "L_F2",
                       "squeal", "squeal_frequency", "buildup_time", "growth", "runtime", "normal_force",
                       "contact_loss", "peak_normal_force", "peak_normal_ratio", "peak_lateral_ratio", "regime", "oscillation")
#: Float entries of a case summary.
FLOAT_ATTRIBUTES = ("friction", "lateral_creepage", "speed", "L_F2", "squeal_frequency", "buildup_time", "growth",
                    "runtime", "normal_force", "contact_loss", "peak_normal_force", "peak_normal_ratio",
                    "peak_lateral_ratio")


def key_unit(key):
    """Unit of a dotted study key from the schema (``"1"`` for dimensionless numbers, ``"-"`` for text).

    Raises
    ------
    KeyError
        If no study section declares the key.
    """
    section, _, name = key.rpartition(".")
    for cls in STUDY_SECTIONS:
        if cls.SECTION == section and name in spec_of(cls):
            spec = spec_of(cls)[name]
            if spec.unit:
                return spec.unit
            return DIMENSIONLESS_UNIT if spec.kind in ("number", "integer", "numbers") else TEXT_UNIT
    raise KeyError(f"no study parameter {key!r}")


def swept_column(key):
    """The column of a swept key: header = the dotted key, value = the case's value of it."""
    return SummaryColumn(key, key_unit(key), lambda summary: summary["overrides"][key])


def summary_columns(swept_keys, fixed=None):
    """All columns of ``summary.csv`` for a study sweeping ``swept_keys`` (in that order).

    ``fixed``: the columns after the swept ones (default :data:`SUMMARY_COLUMNS`).
    """
    return ((SummaryColumn("case_id", TEXT_UNIT, case_attribute("case_id")),
             SummaryColumn("variant", TEXT_UNIT, case_attribute("variant")))
            + tuple(swept_column(key) for key in swept_keys) + tuple(SUMMARY_COLUMNS if fixed is None else fixed))


def _plain(value):
    """An HDF5 attribute as a plain Python value (numpy scalars and bytes converted)."""
    if isinstance(value, bytes):
        return value.decode("utf-8")
    if isinstance(value, np.generic):
        return value.item()
    return value


def read_case_summary(path, simulation=None, variant=BASE_VARIANT):
    """One case artefact as a dict: every attribute of the file, plus ``variant``.

    Parameters
    ----------
    path : path-like
        ``cases/<id>.h5``.
    simulation : dict, optional
        The study's ``[simulation]`` table. When given, the squeal metrics are recomputed from the
        stored lateral force with the current :func:`interaction.metrics.squeal_metrics` (so a
        report always applies one definition to every case); otherwise those written by the run.
    variant : str
        Name of the case's structural variant.

    Returns
    -------
    dict
        At least :data:`REQUIRED_ATTRIBUTES` (``friction``, ``L_F2`` (dB re 1 N), ... as floats,
        ``squeal`` as bool, names as str), ``overrides`` (dict: the case's sweep values),
        ``variant``, the contact regime (``contact_loss``, ``peak_normal_force`` (N),
        ``peak_normal_ratio``, ``peak_lateral_ratio``, ``regime``: recomputed with the metrics
        when ``simulation`` is given), and ``L_W`` (dB re 1 pW, wheel + rail) and ``L_pA`` (dB(A) at the pass-by
        position) from the case's radiation artefact (:func:`stages.radiation.radiation_levels`:
        NaN without one).
    """
    with open_artefact(path, "case", CASE_VERSION) as f:
        summary = {key: _plain(value) for key, value in f.attrs.items()}
        missing = [key for key in REQUIRED_ATTRIBUTES if key not in summary]
        if missing:
            raise KeyError(f"{path}: case attributes {', '.join(missing)} missing")
        if simulation is not None:
            time = read_dataset(f, "time", "s", (None,))
            force = read_dataset(f, "force", "N", (None, 3))
            dt = time[1] - time[0]
            m = squeal_metrics(force[:, 1], dt, window=simulation["rms_window"],
                               threshold_db=simulation["squeal_threshold"])
            summary.update(L_F2=m.L_F2, squeal=m.squeal, squeal_frequency=m.squeal_frequency,
                           buildup_time=m.buildup_time, growth=m.growth,
                           oscillation=oscillation_class(m.squeal, m.squeal_frequency,
                                                         simulation.get("squeal_min_frequency",
                                                                        DEFAULT_SQUEAL_MIN_FREQUENCY)))
            regime = contact_regime(force, dt, float(summary["friction"]), float(summary["normal_force"]),
                                    window=simulation["rms_window"])
            summary.update(contact_loss=regime.contact_loss, peak_normal_force=regime.peak_normal_force,
                           peak_normal_ratio=regime.peak_normal_ratio, peak_lateral_ratio=regime.peak_lateral_ratio,
                           regime=regime.regime)
    for key in FLOAT_ATTRIBUTES:
        summary[key] = float(summary[key])
    summary["squeal"] = bool(summary["squeal"])
    for key in ("case_id", "wheel_model", "contact_model", "regime", "oscillation"):
        summary[key] = str(summary[key])
    summary["overrides"] = json.loads(summary.get("overrides", "{}"))
    summary["variant"] = variant
    summary.update(radiation_levels(path))
    return summary


def case_regime(summary):
    """The :class:`interaction.metrics.ContactRegime` of a case summary (or case result) dict."""
    return ContactRegime(float(summary["contact_loss"]), float(summary["peak_normal_force"]),
                         float(summary["peak_normal_ratio"]), float(summary["peak_lateral_ratio"]),
                         str(summary["regime"]))


def class_label(summary):
    """The class of a case's oscillation for tables: ``squeal``, ``low-frequency oscillation`` or
    ``quiet`` (class ``none``)."""
    return "quiet" if summary["oscillation"] == NO_OSCILLATION else summary["oscillation"]


def verdict(summary, mu="μ"):
    """A case's verdict in words: the class of its oscillation (:func:`class_label`) with its
    frequency, followed, for impact/bouncing, by the regime
    (:meth:`interaction.metrics.ContactRegime.describe`), e.g. ``squeal at 5047 Hz, but
    impact/bouncing (out of contact 11 % of the window, ...)``."""
    text = class_label(summary)
    if summary["oscillation"] != NO_OSCILLATION:
        text += f" at {summary['squeal_frequency']:.0f} Hz"
    regime = case_regime(summary)
    return text + (f", but {regime.describe(mu)}" if regime.bouncing else "")


def _cell(value):
    return f"{value:.6g}" if isinstance(value, float) else str(value)


def write_summary(summaries, path, swept_keys=(), columns=None, missing=()):
    """Write ``summary.csv``: the units comment, the header and one row per case.

    Parameters
    ----------
    summaries : list of dict
        Case summaries (:func:`read_case_summary`).
    path : Path
        Output file.
    swept_keys : sequence of str
        Dotted keys of the study's ``[sweep]``, one column each.
    columns : sequence of SummaryColumn, optional
        All the columns (default :func:`summary_columns` of ``swept_keys``).
    missing : sequence of str
        Ids of the study's cases without a result (failed or not run): a comment line names
        them, so that a table of fewer rows than planned says so.
    """
    columns = summary_columns(swept_keys) if columns is None else columns
    comments = ["summary.csv: one row per case of the study; the units of the columns, in order:",
                "units: " + ",".join(column.unit for column in columns)]
    if missing:
        comments.insert(1, f"missing: {len(missing)} of the study's {len(missing) + len(summaries)} cases have no "
                           f"result (failed or not run): {' '.join(missing)}")
    write_table(path, [column.name for column in columns],
                ([_cell(column.value(s)) for column in columns] for s in summaries), comments)
