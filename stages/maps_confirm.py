"""Time-domain confirmation of a squeal map: a sample of its points run as interaction cases.

A map point is one configuration of the grid with one wheel model. The sample holds the
borderline points first (the largest growth rate, the map's ``margin``, closest to zero: taken in
turn from each wheel model's growing and decaying points) and then points drawn at random
(seeded, reproducible). Each point runs in the time domain with each contact model asked for, as
a regular case (:func:`stages.engine.run_cases`): its study is the map's configuration with
``simulation.wheel_model`` and ``contact.model`` set and the duration of the confirmation; its
contact is the study's (``contact.geometry``), the one the screen linearises. Structures go to ``<out>/confirm/variants/<label>``
(the map's wheels and rails are copied where they match), cases to ``<out>/confirm/cases/``:
cached and resumable like the cases of ``pipeline.py run``.

Verdicts compared per point:

- squeal: the screen predicts it where the margin is > 0; the time domain shows it where the
  case's ``squeal`` flag is set (a limit cycle above the threshold) or where its dominant tone
  still grows over the second half of the run (:func:`envelope_growth`: the slope of the log
  envelope of the lateral force's tone > 0). A short run (default 1 s) may end before an
  unstable oscillation saturates, and the case's own ``growth`` (rms of the last
  ``simulation.rms_window`` over the window before) is dominated in a short run by the
  transient of switching the creepage on, so the envelope's slope decides; a stable
  configuration's tone decays (slope < 0);
- frequency, where both squeal: the tone's frequency (spectral peak over the fit window)
  within :data:`FREQUENCY_TOLERANCE` of the screen's pole frequency.

A point agrees when both verdicts agree. ``<out>/confirm.csv`` lists every point and contact
model; :func:`report_section` is the section "Time-domain confirmation" of ``maps.md``.
"""

from __future__ import annotations

import csv
import logging
import math
from pathlib import Path

import h5py
import numpy as np
from scipy.signal import hilbert

from interaction.metrics import (
    SQUEAL_MIN_FREQUENCY,
    band_part,
    dominant_frequency,
    tonal_part,
)
from squealcore.artefacts import atomic_output
from squealcore.errors import InputError
from squealcore.study import set_path
from contact.registry import contact_model_names, contact_spec
from stages import engine
from stages.cases import case_study, is_structural, make_case_id, structural_key
from stages.maps import grid_configurations, run_tasks

logger = logging.getLogger(__name__)

def confirmation_models():
    """Contact models the confirmation runs by default: every registered one, the fast ones first."""
    names = contact_model_names()
    return tuple(sorted(names, key=lambda name: not contact_spec(name).fast))


#: Duration of a confirmation case by default, s.
DEFAULT_DURATION = 1.0
#: Largest relative difference of the squeal frequencies for agreement.
FREQUENCY_TOLERANCE = 0.02
#: Folder of the confirmation's structures and cases, inside the map's output folder.
CONFIRM_DIR = "confirm"
SECTION_TITLE = "## Time-domain confirmation"
#: Fit window of the tone's envelope, fractions of the run: the second half without its last 10 %
#: (away from the ends of the filtered segment).
FIT_WINDOW = (0.5, 0.9)
#: Start of the segment the tone's band filter sees, fraction of the run.
FILTER_START = 0.25
#: Relative width of the tone's band (as the build-up time of interaction.metrics).
TONE_BAND = 0.05


def choose_points(data, count, seed):
    """The map points to confirm: borderline ones first, then random ones.

    Parameters
    ----------
    data : dict
        The map (:func:`stages.maps.read_maps`).
    count : int
        Points wanted (at most every configuration × wheel model).
    seed : int
        Seed of the random choice.

    Returns
    -------
    list of (int, str, str)
        ``(configuration index, wheel model, "borderline" or "random")``. The first
        ``ceil(count / 2)`` are borderline: the points with a finite margin, grouped by wheel
        model (the map's order) and sign (growing, then not growing), each group ordered by
        ``|margin|``, taken in turn from the groups. The others are drawn without replacement
        from the remaining points (``numpy.random.default_rng(seed)``, points in configuration
        order, wheel models in the map's order within a configuration).
    """
    models = data["models"]
    n = data["configuration"].shape[0]
    count = min(int(count), n * len(models))
    groups = []
    for model in models:
        margin = data[f"{model}/margin"]
        for growing in (True, False):
            sel = np.flatnonzero(np.isfinite(margin) & ((margin > 0) if growing else (margin <= 0)))
            order = sel[np.argsort(np.abs(margin[sel]), kind="stable")]
            groups.append([(int(i), model) for i in order])
    chosen = []
    n_border = (count + 1) // 2
    depth = 0
    while len(chosen) < n_border and any(depth < len(g) for g in groups):
        for group in groups:
            if depth < len(group) and len(chosen) < n_border:
                chosen.append((*group[depth], "borderline"))
        depth += 1
    taken = {(i, m) for i, m, _ in chosen}
    rest = [(i, m) for i in range(n) for m in models if (i, m) not in taken]
    rng = np.random.default_rng(seed)
    picks = rng.choice(len(rest), size=min(count - len(chosen), len(rest)), replace=False) if rest else []
    chosen += [(*rest[k], "random") for k in picks]
    return chosen


def confirm_study(study, duration):
    """The base study of the confirmation cases: the map's study without its ``[sweep]``, with
    ``time.duration = duration`` (s)."""
    base = {k: v for k, v in study.items() if k != "sweep"}
    return set_path(base, ["time", "duration"], float(duration))


def case_overrides(grid_overrides, wheel_model, contact_model):
    """The overrides of a point's case: its grid values, the wheel model and the contact model."""
    return {**grid_overrides, "simulation.wheel_model": wheel_model, "contact.model": contact_model}


def plan_confirmation(study, points, contact_models, out_dir, duration):
    """The cases of the confirmation (:class:`stages.engine.Case`), one per point and contact model.

    Cases with the same structural sections share a variant folder
    ``<out_dir>/confirm/variants/<label>`` (:func:`stages.engine.variant_label` of the point's
    structural grid values).

    Returns
    -------
    list of (tuple, Case)
        ``((index, wheel model, choice, contact model), case)``.
    """
    folder = Path(out_dir) / CONFIRM_DIR
    _, configurations = grid_configurations(study)
    base = confirm_study(study, duration)
    labels, out = {}, []
    for index, model, choice in points:
        grid = configurations[index][0]
        for contact in contact_models:
            overrides = case_overrides(grid, model, contact)
            config = case_study(base, overrides)
            structural = {k: v for k, v in overrides.items() if is_structural(k)}
            label = labels.setdefault(structural_key(config), engine.variant_label(structural))
            case = engine.Case(make_case_id(overrides), overrides, config, folder / "variants" / label, label)
            out.append(((index, model, choice, contact), case))
    return out


def prepare_variant(payload):
    """Task: bring a confirmation variant's structural artefacts up to date (copying fresh ones
    from the ``donors`` folders); returns ``{"label"}``."""
    engine.run_structural(payload["study"], Path(payload["folder"]), list(engine.STAGES), progress=False,
                          label=payload["label"], donors=[Path(d) for d in payload["donors"]])
    return {"label": payload["label"]}


def envelope_growth(force, time_step, window=FIT_WINDOW, min_frequency=SQUEAL_MIN_FREQUENCY, band=TONE_BAND,
                    frequency=None):
    """Growth rate and frequency of the dominant tone of a lateral-force history.

    The tone is the force without its slow part (:func:`interaction.metrics.tonal_part`: the
    quasi-static rise of the creep force when the creepage is switched on) in a Gaussian band
    (relative width ``band``) around its spectral peak above ``min_frequency`` over the fit
    window; its growth rate is the slope of the logarithm of its Hilbert envelope over that
    window, a least-squares line. The band filter is applied to the run from
    :data:`FILTER_START` on, without its last period of ``min_frequency`` (where the moving
    average is cut off), zero-padded to twice its length (no wrap-around of the switch-on
    transient into the window).

    Parameters
    ----------
    force : (nt,) array_like
        Lateral force, N.
    time_step : float
        s.
    window : (float, float)
        The fit window as fractions of the run (default :data:`FIT_WINDOW`).
    min_frequency : float
        Lowest squeal frequency, Hz.
    band : float
        Relative width of the tone's band (-).
    frequency : float, optional
        Centre of the band, Hz (default: the spectral peak).

    Returns
    -------
    (float, float)
        Growth rate (1/s; > 0: the tone grows) and frequency (Hz).
    """
    force = np.asarray(force, dtype=float)
    tonal = tonal_part(force, time_step, min_frequency)
    start = round(FILTER_START * force.size)
    first, last = (round(w * force.size) for w in window)
    if frequency is None:
        frequency = dominant_frequency(tonal[first:last], time_step, min_frequency)
    if not np.isfinite(frequency):
        return -math.inf, math.nan
    edge = round(1.0 / (min_frequency * time_step))  # where tonal_part's moving average is cut off
    segment = tonal[start:force.size - edge]
    padded = np.concatenate([segment - segment.mean(), np.zeros(segment.size)])
    envelope = np.abs(hilbert(band_part(padded, time_step, frequency, band)))[first - start:last - start]
    t = np.arange(first, last) * time_step
    rate = np.polyfit(t, np.log(np.maximum(envelope, 1e-300)), 1)[0]
    return float(rate), float(frequency)


def case_verdict(path, screen_frequency=math.nan):
    """The time domain's verdict of a case artefact.

    ``screen_frequency`` (Hz) adds a diagnostic that does not enter the verdict:
    ``screen_tone_growth_rate`` (1/s), the envelope growth rate of the force's tone at that
    frequency (:func:`envelope_growth`; NaN without it), which shows whether the screen's pole
    grows in the time domain even where other tones dominate.

    Returns
    -------
    dict
        ``squeal`` (bool: the case's ``squeal`` flag, a limit cycle above the threshold, or a
        tone still growing, :func:`envelope_growth` > 0), ``flag`` (the case's ``squeal``
        attribute), ``growth_rate`` (1/s) and ``frequency`` (Hz) of :func:`envelope_growth`,
        ``screen_tone_growth_rate`` (1/s), ``L_F2`` (dB re 1 N).
    """
    with h5py.File(path, "r") as f:
        attrs = dict(f.attrs)
        time = f["time"][()]
        force = f["force"][:, 1]
    flag = bool(attrs["squeal"])
    dt = float(time[1] - time[0])
    rate, frequency = envelope_growth(force, dt)
    screen_rate = envelope_growth(force, dt, frequency=screen_frequency)[0] if np.isfinite(screen_frequency) \
        else math.nan
    return {"squeal": flag or rate > 0.0, "flag": flag, "growth_rate": rate, "frequency": frequency,
            "screen_tone_growth_rate": screen_rate, "L_F2": float(attrs["L_F2"])}


def compare(screen_squeal, screen_frequency, td):
    """Agreement of the screen and the time domain at one point.

    Returns
    -------
    (bool, float)
        Whether the verdicts agree (squeal or not; and, where both squeal, frequencies within
        :data:`FREQUENCY_TOLERANCE`), and the relative frequency difference (NaN unless both squeal).
    """
    if screen_squeal != td["squeal"]:
        return False, math.nan
    if not screen_squeal:
        return True, math.nan
    error = abs(td["frequency"] - screen_frequency) / screen_frequency
    return bool(error <= FREQUENCY_TOLERANCE), float(error)


CSV_COLUMNS = ("index", "wheel_model", "contact_model", "choice", "screen_margin", "screen_squeal",
               "screen_frequency", "td_squeal", "td_squeal_flag", "td_growth_rate", "td_screen_tone_growth_rate",
               "td_L_F2", "td_frequency",
               "frequency_error", "agree", "case_id", "error")


def check_options(count, contact_models, duration):
    """Refuse a count < 1, unknown or repeated contact models and a duration <= 0 s
    (:class:`InputError` naming the command-line option)."""
    if count < 1:
        raise InputError("--confirm", f"must be an integer >= 1, got {count}")
    if not contact_models or any(m not in contact_model_names() for m in contact_models) \
            or len(set(contact_models)) != len(contact_models):
        raise InputError("--confirm-models", f"must list distinct contact models among "
                                             f"{', '.join(confirmation_models())}, "
                                             f"got {','.join(contact_models)!r}")
    if not duration > 0:
        raise InputError("--confirm-duration", f"must be > 0 s, got {duration}")


def run_confirmation(study, out_dir, data, count, contact_models=None, seed=0,
                     duration=DEFAULT_DURATION, jobs=1, scheduler=None, progress=True):
    """Confirm ``count`` points of a map in the time domain; writes ``confirm.csv`` and the
    section of ``maps.md``.

    Parameters
    ----------
    study : dict
        The map's study (with its ``[map.grid]``).
    out_dir : Path
        The map's output folder (``maps.h5``, ``maps.md``).
    data : dict
        The map (:func:`stages.maps.read_maps`).
    count : int
        Points to confirm (>= 1).
    contact_models : sequence of str
        Contact models each point runs with (``point``, ``halfspace``).
    seed : int
        Seed of the random points.
    duration : float
        Duration of each case, s.
    jobs, scheduler
        As for :func:`stages.engine.run_cases`.
    progress : bool
        Progress bars.

    Returns
    -------
    list of dict
        The rows of ``confirm.csv`` (``agree`` None where the case failed).

    Raises
    ------
    InputError
        ``--confirm`` < 1, an unknown or repeated contact model, a duration <= 0 or a map that
        does not match the study's grid.
    """
    contact_models = confirmation_models() if contact_models is None else contact_models
    check_options(count, contact_models, duration)
    out_dir = Path(out_dir)
    keys, configurations = grid_configurations(study)
    if keys != data["keys"] or len(configurations) != data["configuration"].shape[0]:
        raise InputError("--confirm", "maps.h5 does not hold the study's grid; run the map first")
    points = choose_points(data, count, seed)
    planned = plan_confirmation(study, points, contact_models, out_dir, duration)
    cases = [case for _, case in planned]
    folder = out_dir / CONFIRM_DIR
    engine.remove_stale_temporaries(folder)
    variants = {}
    for case in cases:
        variants.setdefault(case.variant_dir, case)
    donors = sorted(str(p) for p in (out_dir / "maps" / "wheels").glob("*")) + \
        sorted(str(p) for p in (out_dir / "maps" / "rails").glob("*")) + [str(v) for v in variants]
    payloads = [{"label": c.variant_label, "folder": str(v), "study": c.study, "donors": donors}
                for v, c in variants.items()]
    logger.info("confirmation: %d points × %d contact models, %d structural variants", len(points),
                len(contact_models), len(payloads))
    run_tasks(prepare_variant, payloads, [f"confirm-variant-{p['label']}" for p in payloads],
              lambda result: None, jobs, scheduler)
    _, failed = engine.run_cases(cases, folder, jobs, scheduler, progress)
    rows = []
    for (index, model, choice, contact), case in planned:
        margin = float(data[f"{model}/margin"][index])
        screen_frequency = float(data[f"{model}/frequency"][index])
        row = {"index": index, "wheel_model": model, "contact_model": contact, "choice": choice,
               "screen_margin": margin, "screen_squeal": margin > 0, "screen_frequency": screen_frequency,
               "case_id": case.case_id, "error": failed.get(case.case_id, ""),
               **{key: configurations[index][0][key] for key in keys}}
        if row["error"]:
            row.update(td_squeal=None, td_squeal_flag=None, td_growth_rate=math.nan,
                       td_screen_tone_growth_rate=math.nan, td_L_F2=math.nan, td_frequency=math.nan,
                       frequency_error=math.nan, agree=None)
        else:
            td = case_verdict(folder / "cases" / f"{case.case_id}.h5", screen_frequency)
            agree, error = compare(row["screen_squeal"], screen_frequency, td)
            row.update(td_squeal=td["squeal"], td_squeal_flag=td["flag"], td_growth_rate=td["growth_rate"],
                       td_screen_tone_growth_rate=td["screen_tone_growth_rate"],
                       td_L_F2=td["L_F2"], td_frequency=td["frequency"], frequency_error=error, agree=agree)
        rows.append(row)
    write_csv(out_dir / "confirm.csv", rows, keys)
    append_section(out_dir / "maps.md", report_section(rows, keys, duration))
    return rows


def write_csv(path, rows, keys):
    """Write the confirmation rows (grid values after :data:`CSV_COLUMNS`'s first four columns)."""
    columns = list(CSV_COLUMNS[:4]) + list(keys) + list(CSV_COLUMNS[4:])
    with atomic_output(path) as tmp, open(tmp, "w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        for row in rows:
            writer.writerow({c: ("" if row[c] is None else row[c]) for c in columns})


def read_csv(path):
    """The rows of ``confirm.csv`` as dicts of strings."""
    with open(path, newline="", encoding="utf-8") as handle:
        return list(csv.DictReader(handle))


def agreement(rows):
    """``(agreeing, compared)`` over rows (those whose case failed are not compared)."""
    compared = [r for r in rows if r["agree"] is not None]
    return sum(1 for r in compared if r["agree"]), len(compared)


def _verdict(squeal, frequency):
    return f"squeal at {frequency:.0f} Hz" if squeal else "no squeal"


def report_section(rows, keys, duration):
    """The Markdown of the section "Time-domain confirmation" of ``maps.md``."""
    lines = [SECTION_TITLE, "",
             f"{len({(r['index'], r['wheel_model']) for r in rows})} map points (configuration and wheel model: "
             "the borderline ones, largest growth rate closest to 0, then random ones) run in the time domain "
             f"for {duration:g} s with the study's contact, each contact model (`confirm/cases/`, every row in "
             "`confirm.csv`). Time-domain squeal: the case's squeal flag (limit cycle above the threshold) or a "
             "lateral-force tone still growing over the second half of the run (slope of its log envelope > 0, "
             f"`td_growth_rate`; the growth rate of the tone at the screen's frequency, "
             "`td_screen_tone_growth_rate`, is listed as a diagnostic); where both squeal, the frequencies must "
             f"agree within {100 * FREQUENCY_TOLERANCE:g} %.", "",
             "| contact model | wheel model | agreement |", "|---|---|---|"]
    contacts = list(dict.fromkeys(r["contact_model"] for r in rows))
    models = list(dict.fromkeys(r["wheel_model"] for r in rows))
    for contact in contacts:
        for model in models:
            sel = [r for r in rows if r["contact_model"] == contact and r["wheel_model"] == model]
            if sel:
                lines.append(f"| {contact} | {model} | {_rate(*agreement(sel))} |")
        lines.append(f"| {contact} | all | {_rate(*agreement([r for r in rows if r['contact_model'] == contact]))} |")
    failed = [r for r in rows if r["agree"] is None]
    differ = [r for r in rows if r["agree"] is False]
    lines += ["", "Disagreements:" if differ else "No disagreement.", ""]
    for r in differ:
        values = ", ".join(f"{k.split('.')[-1]} = {r[k]:g}" for k in keys)
        lines.append(f"- configuration {r['index']} ({values}), {r['wheel_model']}, {r['contact_model']} contact "
                     f"({r['choice']}): screen {_verdict(r['screen_squeal'], r['screen_frequency'])} "
                     f"(growth rate {r['screen_margin']:.1f} 1/s), time domain "
                     f"{_verdict(r['td_squeal'], r['td_frequency'])} (envelope growth rate "
                     f"{r['td_growth_rate']:.1f} 1/s, at the screen's frequency "
                     f"{r['td_screen_tone_growth_rate']:.1f} 1/s, L_F2 {r['td_L_F2']:.1f} dB)")
    for r in failed:
        lines.append(f"- configuration {r['index']}, {r['wheel_model']}, {r['contact_model']}: case failed "
                     f"({r['error']})")
    lines.append("")
    return "\n".join(lines)


def _rate(agree, total):
    return f"{agree} of {total} ({100.0 * agree / total:.0f} %)" if total else "no case"


def append_section(path, section):
    """Put ``section`` at the end of ``maps.md``, replacing an earlier confirmation section."""
    path = Path(path)
    text = path.read_text(encoding="utf-8")
    head = text.split("\n" + SECTION_TITLE + "\n", 1)[0].rstrip("\n")
    with atomic_output(path) as tmp:
        Path(tmp).write_text(head + "\n\n" + section, encoding="utf-8")
