"""The functions and result types of :mod:`curve_squeal` (the Python API).

Each function wraps what the command line uses and adds no physics: :func:`load_study` is
:func:`stages.config.load_study`, :func:`run` is :func:`stages.engine.run` with the folder's study
record and lock of ``pipeline.py run`` (:mod:`stages.folder`), :func:`summary` reads the rows of
``summary.csv`` (:mod:`stages.summary`, :func:`stages.report.report_variants`), :func:`read_case`
a case artefact (:func:`exports.case.read_histories`, :func:`stages.summary.read_case_summary`)
and :func:`read_wheel` a wheel model of ``wheel_greens.h5`` (:func:`stages.wheel.read_greens`).
"""

from __future__ import annotations

import json
import math
import os
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

import numpy as np

from interaction.wheel_models import REFERENCE, wheel_model_names
from squealcore.artefacts import canonical_json
from squealcore.errors import InputError
from stages import config as study_config
from stages import engine, folder
from stages.summary import BASE_VARIANT, read_case_summary, summary_columns, verdict

__all__ = ["Study", "CaseResult", "WheelResponse", "load_study", "study_of", "run", "summary", "read_case",
           "read_wheel"]

#: What :func:`run` records as the command in the folder's lock.
LOCK_COMMAND = "curve_squeal.run (Python API)"


class Study(dict):
    """A validated study: its tables as nested dicts, e.g. ``study["contact"]["friction"]``.

    A :class:`dict` (pass it wherever a study is expected) that also remembers how it was given,
    which :func:`run` records in the study folder with the study.

    Attributes
    ----------
    given : dict or None
        ``{"config": path or None, "quick": bool, "set": [assignment, ...]}`` (the ``--set``
        equivalents of the overrides), or None if unknown.
    """

    def __init__(self, tables: Mapping[str, Any], given: dict | None = None):
        super().__init__(tables)
        self.given = given
        self._as_loaded = canonical_json(self)

    @property
    def edited(self) -> bool:
        """Whether the tables changed since the study was loaded (its ``given`` no longer says how)."""
        return canonical_json(self) != self._as_loaded


@dataclass(frozen=True)
class CaseResult:
    """One simulated case (``cases/<case_id>.h5``): histories and results.

    Forces, creepages and motions are in the contact frame (index 0 = x rolling direction,
    1 = y lateral, 2 = z normal; ``docs/conventions.md``). The arrays are read-only.

    Attributes
    ----------
    case_id : str
        The case's id (its sweep values and a hash of them).
    time : numpy.ndarray
        (nt,) time, s.
    force : numpy.ndarray
        (nt, 3) force of the rail on the wheel, N.
    creepage : numpy.ndarray
        (nt, 3) creepages ξ (1), η (1), spin φ (1/m).
    slip_fraction : numpy.ndarray
        (nt,) share of the contact area in slip, 1.
    wheel_displacement, rail_displacement : numpy.ndarray
        (nt, 3) displacements at the contact (deviations from static equilibrium), m.
    wheel_velocity, rail_velocity : numpy.ndarray
        (nt, 3) velocities at the contact, m/s.
    summary : Mapping
        The case's row as :func:`stages.summary.read_case_summary` gives it (every attribute of
        the artefact: ``L_F2`` dB re 1 N, ``squeal``, ``squeal_frequency`` Hz, ``oscillation``,
        ``regime``, ``friction``, ``lateral_creepage``, ``speed`` m/s, ``wheel_model``,
        ``overrides`` (the sweep values), ``variant``, ``L_W`` dB re 1 pW, ``L_pA`` dB(A) ...).
    """

    case_id: str
    time: np.ndarray
    force: np.ndarray
    creepage: np.ndarray
    slip_fraction: np.ndarray
    wheel_displacement: np.ndarray
    wheel_velocity: np.ndarray
    rail_displacement: np.ndarray
    rail_velocity: np.ndarray
    summary: Mapping[str, Any]

    @property
    def time_step(self) -> float:
        """The time step, s."""
        return float(self.time[1] - self.time[0]) if self.time.size > 1 else math.nan

    @property
    def L_F2(self) -> float:
        """Level of the lateral force's oscillation (the paper's squeal metric), dB re 1 N."""
        return float(self.summary["L_F2"])

    @property
    def squeal(self) -> bool:
        """Whether the case meets the squeal criterion (L_F2 above the threshold, a limit cycle)."""
        return bool(self.summary["squeal"])

    @property
    def squeal_frequency(self) -> float:
        """Frequency of the oscillation, Hz (whatever its class)."""
        return float(self.summary["squeal_frequency"])

    @property
    def verdict(self) -> str:
        """The verdict in words, e.g. ``squeal at 5042 Hz`` or ``quiet`` (:func:`stages.summary.verdict`)."""
        return verdict(self.summary, mu="mu ")


@dataclass(frozen=True)
class WheelResponse:
    """One wheel model of ``wheel_greens.h5`` at the study's contact point and speed.

    Receptances, residues and kernels are in the wheel's body frame at the contact (index 0 = x
    along the track, 1 = y lateral, 2 = z vertical; ``docs/conventions.md``): ``receptance[:, 1, 1]``
    is the lateral point receptance. The arrays are read-only.

    Attributes
    ----------
    model : str
        The wheel model (``stationary``, ``moving_load``, ``eulerian``: :mod:`interaction.wheel_models`).
    spin : float
        The wheel's angular speed, rad/s.
    time_step : float
        Time step of the kernel, s.
    time_stepping : str
        How the time loop steps the wheel (``recursion``: exact modal recursion; else the kernel).
    poles : numpy.ndarray
        (m,) complex poles, rad/s.
    residues : numpy.ndarray
        (m, 3, 3) complex residues, m/(N s).
    contact_shape : numpy.ndarray
        (modes, 3) mass-normalised mode shapes at the contact, m/√kg.
    frequency : numpy.ndarray
        (nf,) frequencies of the receptance, Hz.
    receptance : numpy.ndarray
        (nf, 3, 3) complex receptance, m/N.
    kernel : numpy.ndarray
        (nt, 3, 3) discrete Green's kernel (displacement per impulse of one time step), m/N.
    """

    model: str
    spin: float
    time_step: float
    time_stepping: str
    poles: np.ndarray
    residues: np.ndarray
    contact_shape: np.ndarray
    frequency: np.ndarray
    receptance: np.ndarray
    kernel: np.ndarray


# --------------------------------------------------------------------------- studies


def _toml_value(key: str, value: Any) -> str:
    """A Python value as TOML text for ``stages.config.load_study``'s ``key=value`` assignments."""
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        number = float(value)
        if math.isnan(number):
            return "nan"
        return ("inf" if number > 0 else "-inf") if math.isinf(number) else repr(number)
    if isinstance(value, (str, os.PathLike)):
        return json.dumps(os.fsdecode(value))  # a JSON string is a TOML basic string
    if isinstance(value, np.ndarray):
        value = value.tolist()
    if isinstance(value, (list, tuple)):
        return "[" + ", ".join(_toml_value(key, item) for item in value) + "]"
    raise InputError(key, f"must be a number, true/false, text, a path or a list of them, got {type(value).__name__}")


def _assignments(overrides: Mapping[str, Any] | None) -> list[str]:
    if overrides is None:
        return []
    if not isinstance(overrides, Mapping):
        raise InputError("overrides", f"must be a mapping of dotted keys to values, got {type(overrides).__name__}")
    assignments = []
    for key, value in overrides.items():
        if not isinstance(key, str) or not key.strip() or "=" in key:
            raise InputError("overrides", f"keys must be dotted keys such as 'contact.friction', got {key!r}")
        assignments.append(f"{key.strip()}={_toml_value(key.strip(), value)}")
    return assignments


def load_study(config: str | os.PathLike | None = None, *, quick: bool = False,
               overrides: Mapping[str, Any] | None = None) -> Study:
    """Build and validate a study, as ``pipeline.py run --config ... --quick --set ...`` does.

    Parameters
    ----------
    config : str or path-like, optional
        A study file (TOML) merged over the defaults (``studies/paper.toml``); relative file
        paths in it are taken from its folder.
    quick : bool
        Merge the quick preset (``studies/quick.toml``: coarse meshes, point contact) first.
    overrides : mapping, optional
        ``{dotted key: value}`` applied last, like ``--set``: e.g. ``{"contact.friction": 0.6}``
        (values in the parameters' units, ``docs/parameters.md``), ``{"sweep.contact.friction":
        [0.3, 0.6]}`` (a sweep list; setting a swept key replaces its sweep), ``{"wheel.tread_profile":
        Path("my.txt")}`` (relative to the working folder). Values: numbers, booleans, text, paths,
        lists of them.

    Returns
    -------
    Study
        The complete validated study (a dict of tables).

    Raises
    ------
    InputError
        For an unknown key, a value of the wrong kind or out of range, a missing study file.
    """
    assignments = _assignments(overrides)
    tables = study_config.load_study(config, quick, assignments)
    return Study(tables, folder.given_configuration(config, quick, assignments))


def _existing_folder(out: str | os.PathLike) -> Path:
    out = Path(out)
    if not out.is_dir():
        raise InputError("out", f"{out}: no such study folder" if not out.exists() else f"{out} is not a folder")
    return out


def study_of(out: str | os.PathLike) -> Study:
    """The study a folder records (``OUT/study.json``, written by its first run).

    Parameters
    ----------
    out : str or path-like
        A study folder.

    Returns
    -------
    Study
        The recorded study, validated for this version.

    Raises
    ------
    InputError
        If the folder does not exist, has no record, or its study is not valid for this version.
    RecordError
        If the record is unreadable.
    """
    out = _existing_folder(out)
    record = folder.read_record(out)
    if record is None:
        raise InputError("out", f"{out}: no study record ({folder.RECORD}); it is written by the folder's first run")
    try:
        study_config.validate(record["study"])
    except InputError as exc:
        raise InputError("out", f"{folder.record_path(out)}: the recorded study is not valid for this version "
                                f"({exc.field}: {exc.message})") from None
    given = record.get("given")
    return Study(record["study"], given if isinstance(given, dict) else None)


def _validated(study: Mapping[str, Any]) -> dict:
    """``study`` as a plain dict of plain tables, checked like a loaded study."""
    if not isinstance(study, Mapping):
        raise InputError("study", f"must be a study (curve_squeal.load_study), got {type(study).__name__}")
    tables = json.loads(canonical_json(study))
    study_config.check_input_files(tables)
    study_config.validate(tables)
    return tables


def _study_tables(out: Path, study: Mapping[str, Any] | None) -> dict:
    """The given study, else the folder's."""
    return _validated(study) if study is not None else dict(study_of(out))


# --------------------------------------------------------------------------- running


def run(study: Mapping[str, Any], out: str | os.PathLike, *, until: str | None = None, jobs: int = 1,
        progress: bool = False, change_study: bool = False) -> list[str]:
    """Build what is stale of ``study`` in the folder ``out``, as ``pipeline.py run`` does.

    Only what the study changed is rebuilt; a run interrupted (Ctrl-C) resumes where it stopped.
    The folder records the study (``OUT/study.json``) and is locked while the run builds.

    Parameters
    ----------
    study : Study or mapping
        The study (:func:`load_study` or :func:`study_of`); a plain mapping is validated first.
    out : str or path-like
        The study folder (created if missing); nothing is written outside it.
    until : str, optional
        The last stage to build (``contact-geometry``, ``wheel-mesh``, ``wheel-modes``,
        ``wheel-greens``, ``rail-mesh``, ``rail-greens``, ``simulate``, ``radiation``); default:
        everything, with the report.
    jobs : int
        Local worker processes for the cases (use at most the number of cores).
    progress : bool
        Show progress bars on stderr.
    change_study : bool
        Let a folder that records another study take this one (``run --change-study``): what
        the change makes stale is rebuilt.

    Returns
    -------
    list of str
        What was rebuilt: stage names (``name@variant`` for structural variants),
        ``simulate:<case_id>``, ``radiation:<case_id>`` and ``report``; empty if all was fresh.

    Raises
    ------
    InputError
        For a bad argument or study value, or a folder that records another study (unless
        ``change_study``).
    FolderBusy
        If another run holds the folder's lock.
    CasesFailed
        After the other cases finished, if some cases failed.
    ArtefactError
        If an input artefact is damaged beyond rebuilding.
    """
    if isinstance(jobs, bool) or not isinstance(jobs, (int, np.integer)) or jobs < 1:
        raise InputError("jobs", f"must be an integer >= 1, got {jobs!r}")
    try:
        engine.required_stages(until)
    except InputError as exc:
        raise InputError("until", exc.message) from None
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise InputError("out", f"{out} is a file, not a folder")
    tables = _validated(study)
    given = study.given if isinstance(study, Study) and not study.edited else None
    if out.is_dir():
        folder.check_no_links(out)
        record = folder.read_record(out)
        found = [] if record is None or change_study else folder.differences(record["study"], tables)
        if found:
            raise InputError("out", f"{out} holds another study ({folder.RECORD}, "
                                    f"{folder.describe_given(record.get('given'))}): "
                                    f"{folder.describe_differences(found)}; use curve_squeal.study_of({str(out)!r}) "
                                    "for the folder's study, choose another folder, or pass change_study=True to "
                                    "rebuild this one for the new study")
    lock = folder.FolderLock(out, LOCK_COMMAND)
    previous = []  # the record this run replaced, put back if the new study's input proves bad

    def start(cases):
        """Once every case is planned and checked, before anything is written: lock, record."""
        lock.acquire()
        path = folder.record_path(out)
        before = path.read_bytes() if path.is_file() else None
        if folder.write_record(out, tables, given):
            previous.append(before)

    try:
        return engine.run(tables, out, until, progress=progress, jobs=int(jobs), on_start=start)
    except InputError:
        if lock.held and previous:  # the study was not adopted: the folder keeps its own
            folder.restore_record(out, previous[0])
        raise
    finally:
        lock.release()


# --------------------------------------------------------------------------- results


def _case_paths(out: Path) -> dict[str, Path]:
    """``{case_id: path}`` of the case artefacts in ``out/cases`` (temporary files left out)."""
    cases = out / "cases"
    if not cases.is_dir():
        return {}
    return {p.stem: p for p in sorted(cases.glob("*.h5")) if not p.name.startswith(".") and p.is_file()}


def summary(out: str | os.PathLike, *, study: Mapping[str, Any] | None = None, as_frame: bool = False):
    """The summary table of a study folder: one row per case, the columns of ``summary.csv``.

    The squeal metrics are recomputed from each case's lateral force with the study's
    ``[simulation]`` settings, as the report does. Cases not (yet) simulated are left out.

    Parameters
    ----------
    out : str or path-like
        The study folder.
    study : Study or mapping, optional
        The study (default: the one the folder records).
    as_frame : bool
        Return a :class:`pandas.DataFrame` (needs pandas, not a dependency of curve-squeal),
        the columns' units in ``frame.attrs["units"]``.

    Returns
    -------
    list of dict or pandas.DataFrame
        Rows ``{column: value}`` in the order of the sweep: ``case_id``, ``variant``, one column
        per swept key (its dotted key), then ``wheel_model``, ``contact_model``, ``friction``,
        ``lateral_creepage``, ``speed`` (m/s), ``L_F2`` (dB re 1 N), ``squeal`` (bool),
        ``squeal_frequency`` (Hz), ``oscillation``, ``buildup_time`` (s), ``growth``, ``regime``,
        ``contact_loss``, ``peak_normal_force`` (N), ``peak_normal_ratio``, ``peak_lateral_ratio``,
        ``runtime`` (s), ``L_W`` (dB re 1 pW), ``L_pA`` (dB(A) re 20 µPa) (:data:`stages.summary.SUMMARY_COLUMNS`).

    Raises
    ------
    InputError
        If the folder does not exist, or records no study and none is given.
    ArtefactError
        If a case artefact is damaged.
    ModuleNotFoundError
        With ``as_frame`` if pandas is not installed.
    """
    from stages.report import report_variants  # lazy: the report's figure modules (matplotlib), ~3 s

    out = _existing_folder(out)
    tables = _study_tables(out, study)
    found = _case_paths(out)
    paths = [found[case.case_id] for case in engine.plan_cases(tables, out) if case.case_id in found]
    summaries = [s for variant in report_variants(tables, out, paths, out) for s in variant.summaries]
    columns = summary_columns(sorted(tables.get("sweep", {})))
    rows = [{column.name: column.value(s) for column in columns} for s in summaries]
    if not as_frame:
        return rows
    try:
        import pandas
    except ModuleNotFoundError:
        raise ModuleNotFoundError("curve_squeal.summary(as_frame=True) needs pandas (pip install pandas); "
                                  "without it, summary() returns a list of dicts") from None
    frame = pandas.DataFrame(rows, columns=[column.name for column in columns])
    frame.attrs["units"] = {column.name: column.unit for column in columns}
    return frame


def _read_only(array) -> np.ndarray:
    array = np.array(array)
    array.setflags(write=False)
    return array


def read_case(out: str | os.PathLike, case_id: str, *, study: Mapping[str, Any] | None = None) -> CaseResult:
    """One case of a study folder: its time histories and results.

    Parameters
    ----------
    out : str or path-like
        The study folder.
    case_id : str
        The case's id (a ``case_id`` of :func:`summary`, the file name of ``cases/<case_id>.h5``).
    study : Study or mapping, optional
        The study, whose ``[simulation]`` settings recompute the squeal metrics as
        :func:`summary` does (default: the folder's record; without one, the metrics stored in
        the case).

    Returns
    -------
    CaseResult

    Raises
    ------
    InputError
        If the folder does not exist or holds no case ``case_id`` (the message lists its cases).
    ArtefactError
        If the case artefact is damaged or of an older layout.
    """
    from exports.case import read_histories  # lazy: the export's mesh writer and time loop, ~1 s

    out = _existing_folder(out)
    found = _case_paths(out)
    if not isinstance(case_id, str) or case_id not in found:
        listed = ", ".join(found) or "none (run the study first)"
        raise InputError("case_id", f"no case {case_id!r} in {out / 'cases'}; its cases: {listed}")
    path = found[case_id]
    if study is None and folder.read_record(out) is not None:
        study = study_of(out)
    tables = None if study is None else _validated(study)
    variant = BASE_VARIANT
    if tables is not None:
        planned = {case.case_id: case for case in engine.plan_cases(tables, out)}
        if case_id in planned and planned[case_id].variant_label:
            variant = planned[case_id].variant_label
    data, _ = read_histories(path)
    row = read_case_summary(path, None if tables is None else tables["simulation"], variant)
    return CaseResult(case_id, _read_only(data["time"]), _read_only(data["force"]), _read_only(data["creepage"]),
                      _read_only(data["slip_fraction"]), _read_only(data["wheel/displacement"]),
                      _read_only(data["wheel/velocity"]), _read_only(data["rail/displacement"]),
                      _read_only(data["rail/velocity"]), MappingProxyType(row))


def read_wheel(out: str | os.PathLike, model: str = REFERENCE, *, variant: str | None = None) -> WheelResponse:
    """A wheel model of a study folder (``wheel_greens.h5``): poles, residues, receptance, kernel.

    Parameters
    ----------
    out : str or path-like
        The study folder (built at least ``until="wheel-greens"``).
    model : str
        A registered wheel model: ``stationary`` (the default), ``moving_load`` or ``eulerian``.
    variant : str, optional
        The structural variant (a folder name under ``OUT/variants``, the ``variant`` column of
        :func:`summary`) of a study that sweeps the structure; default: the folder's own.

    Returns
    -------
    WheelResponse

    Raises
    ------
    InputError
        For a folder that does not exist, an unknown model or variant.
    ArtefactError
        If the artefact is missing (not built yet) or damaged.
    """
    from stages.wheel import read_greens  # lazy: the wheel's finite-element modules, ~1 s

    out = _existing_folder(out)
    if model not in wheel_model_names():
        raise InputError("model", f"no wheel model {model!r}; the models: {', '.join(wheel_model_names())}")
    root = out / "variants"
    variants = sorted(p.name for p in root.iterdir() if p.is_dir() and not p.is_symlink()) if root.is_dir() else []
    if variant is None:
        path = out / "wheel_greens.h5"
        if not path.exists() and variants:
            raise InputError("variant", f"{out} holds a study with structural variants: pass variant= one of "
                                        f"{', '.join(variants)}")
    elif variant in variants:
        path = root / variant / "wheel_greens.h5"
    else:
        raise InputError("variant", f"no variant {variant!r} in {root}; its variants: {', '.join(variants) or 'none'}")
    greens = read_greens(path, model)
    return WheelResponse(model, float(greens["spin"]), float(greens["time_step"]), str(greens["time_stepping"]),
                         _read_only(greens["poles"]), _read_only(greens["residues"]),
                         _read_only(greens["contact_shape"]), _read_only(greens["frequency"]),
                         _read_only(greens["receptance"]), _read_only(greens["kernel"]))
