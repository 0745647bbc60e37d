"""``simulate`` stage: one interaction case, and the sweep that defines the cases.

A study's ``[sweep]`` table maps dotted configuration keys to lists of values; every
combination is one case, identified by a readable label of its values followed by a short hash
of their exact values (e.g. ``friction=0.3_lateral_creepage=-0.01_wheel_model=stationary-1a2b3c4d``),
so that values the label rounds alike (0.3 and 0.3000001) still make different ids. A case reads
the wheel and rail Green's artefacts of its structural variant and writes ``cases/<id>.h5``:

datasets ``time`` (s), ``force`` (nt, 3) N (rail on wheel, contact frame), ``creepage`` (nt, 3)
(ξ, η in -, φ in 1/m), ``slip_fraction``, ``wheel/displacement``, ``wheel/velocity``,
``rail/displacement``, ``rail/velocity`` (nt, 3; m, m/s; deviations from static equilibrium);
attributes ``case_id``, ``friction``, ``lateral_creepage``, ``wheel_model``, ``contact_model``,
``speed``, ``L_F2`` (dB re 1 N), ``squeal``, ``squeal_frequency`` (Hz, the oscillation's frequency
whatever its class), ``oscillation`` (``"squeal"``, ``"low-frequency oscillation"`` or ``"none"``:
:func:`interaction.metrics.oscillation_class` with ``simulation.squeal_min_frequency``), ``buildup_time`` (s),
``growth``, ``runtime`` (s), ``overrides`` (JSON), the contact regime of the ``L_F2`` window
(:func:`interaction.metrics.contact_regime`): ``contact_loss`` (share of the window out of
contact, -), ``peak_normal_force`` (N), ``peak_normal_ratio`` (over the static normal force, -),
``peak_lateral_ratio`` (peak ``|F_y|`` over ``mu`` times the static normal force, -), ``regime``
(``"bouncing"`` or ``"contact"``), and the contact the case used:
``contact_geometry`` (``"profiles"`` or ``"manual"``), ``contact_angle`` (rad), ``rolling_radius``
(m), ``normal_force`` (N, static), ``wheel_lateral``, ``rail_lateral`` (m), ``spin`` (1/m, the
imposed spin creepage), and with a curve (``curve.enabled``) ``curve``, the ``[curve]`` table as JSON. Forces, creepages and displacements are in the contact frame inclined
by the contact angle (docs/conventions.md).
"""

from __future__ import annotations

import hashlib
import itertools
import json
import logging
import math
import re
import time as _time
from pathlib import Path

import numpy as np

from squealcore.artefacts import ArtefactError, add_dataset, atomic_output, canonical_json, resource_fault
from squealcore.errors import InputError
from contact.registry import ContactSetup, contact_spec
from squealcore.study import set_path
from stages.config import validate
from stages.context import StageContext
from stages.curve import apply_curve, check_overrides, curve_enabled
from stages.greens_layout import GEOMETRY_KEY, study_geometry

logger = logging.getLogger(__name__)

CASE_VERSION = 7
"""Schema version of ``cases/<id>.h5``; 2: compiled half-space loop and the build-up time of the
squeal tone's envelope; 3: the half-space loop's first coupling pass starts from a linear
prediction of the force (histories move within the solver tolerance: a stored case of version 2
is rebuilt rather than mixed with new ones); 4: the tangential solver carries its mixing memory
from step to step (histories move within the solver tolerance, levels below it by up to 11 dB); 5:
the time loop's inner products summed in vector registers, the predictor's normal equations by a
sliding-window recursion, and the first pass of a limit cycle's steps started from predicted
tractions (histories move within the solver tolerance; the levels below it move, every other
result of the default study is unchanged to its printed digits); 6: the contact regime of the L_F2
window (attributes ``contact_loss``, ``peak_normal_force``, ``peak_normal_ratio``,
``peak_lateral_ratio``, ``regime``) and the build-up time on the tone's envelope (histories
unchanged; a stored case of version 5 lacks the attributes and is rebuilt); 7: the class of the
oscillation (attribute ``oscillation``, with ``simulation.squeal_min_frequency``)."""

#: Sections read by the structural stages: sweeping one of them makes a new structural variant
#: (``[curve]`` through the contact position it sets in ``[operating]``, stages/curve.py).
STRUCTURAL_SECTIONS = ("wheel", "rail", "track", "operating", "time", "geometry", "curve")
#: Single keys of other sections the structural stages read (the Green's stages build the
#: structures at the contact ``contact.geometry`` selects): sweeping one makes a new variant too.
STRUCTURAL_KEYS = (GEOMETRY_KEY,)
#: Sections a case reads (besides the Green's artefacts).
CASE_SECTIONS = ("wheel", "contact", "simulation", "operating", "time")


CASE_HASH_LENGTH = 8
"""Hexadecimal digits of the value hash in a case id (32 bits: collisions need ~65000 cases)."""

CASE_LABEL_LENGTH = 150
"""The readable part of a case id is cut to this many characters (file names stay < 255 bytes;
the hash keeps cut ids distinct)."""


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _label(value):
    if isinstance(value, float):
        return f"{value:g}"
    return str(value)


def _exact(value):
    """A sweep value as hashed into case ids: numbers as floats (so 1 and 1.0 give one id)."""
    return float(value) if _is_number(value) else value


def make_case_id(overrides):
    """The id of the case with these sweep values.

    A readable label ``key=value`` joined by ``_`` (last part of each dotted key, floats with 6
    significant digits, characters other than ``A-Za-z0-9_.=+-`` replaced by ``_``; ``base``
    without overrides), then ``-`` and the first :data:`CASE_HASH_LENGTH` hex digits of the
    SHA-256 of the canonical JSON of ``{dotted key: exact value}`` (floats by ``repr``, numbers
    as floats). Equal for equal values in every run; different whenever a value differs.

    Parameters
    ----------
    overrides : dict
        ``{dotted key: value}``.

    Returns
    -------
    str
    """
    parts = [f"{key.split('.')[-1]}={_label(value)}" for key, value in sorted(overrides.items())]
    label = re.sub(r"[^A-Za-z0-9_.=+-]", "_", "_".join(parts))[:CASE_LABEL_LENGTH] or "base"
    exact = canonical_json({key: _exact(value) for key, value in overrides.items()})
    return f"{label}-{hashlib.sha256(exact.encode('ascii')).hexdigest()[:CASE_HASH_LENGTH]}"


def _check_sweep_values(key, values):
    """Refuse an empty or non-list sweep entry and values repeated in it."""
    if not isinstance(values, list) or not values:
        raise InputError(f"sweep.{key}", "must be a non-empty list of values")
    seen = {}
    for index, value in enumerate(values):
        identity = ("number", float(value)) if _is_number(value) else ("value", canonical_json(value))
        if identity in seen:
            raise InputError(f"sweep.{key}", f"lists the value {value!r} twice (items {seen[identity] + 1} and "
                                             f"{index + 1}); every value must be distinct")
        seen[identity] = index


def table_size(table):
    """Combinations of a sweep-like table (``{dotted key: list of values}``) and their breakdown.

    Returns
    -------
    (int, str)
        The count (the product of the lists' lengths; a key without a list counts once) and
        ``"3 (key) x 10 (key)"`` for messages.
    """
    counts = {key: len(values) for key, values in table.items() if isinstance(values, list)}
    total = 1
    for count in counts.values():
        total *= max(count, 1)
    return total, " x ".join(f"{count} ({key})" for key, count in sorted(counts.items()))


def expand_sweep(study):
    """The cases of a study: list of ``(case_id, overrides)`` with overrides ``{dotted key: value}``.

    Case ids are made by :func:`make_case_id`.

    Raises
    ------
    InputError
        If a sweep entry is not a non-empty list or lists a value twice (numbers equal as floats
        count as the same value).
    """
    sweep = study.get("sweep", {})
    keys = sorted(sweep)
    for key in keys:
        _check_sweep_values(key, sweep[key])
    cases = []
    for combination in itertools.product(*(sweep[k] for k in keys)):
        overrides = dict(zip(keys, combination))
        cases.append((make_case_id(overrides), overrides))
    return cases


def case_study(study, overrides):
    """The study of one case: ``study`` with the overrides applied (checked like ``--set``) and, if it
    names a curve, the curve's operating point written in (:func:`stages.curve.apply_curve`; the
    curving solution is computed once per distinct curve)."""
    out = study
    for key, value in overrides.items():
        try:
            out = set_path(out, key.split("."), value)
        except InputError as exc:
            hint = "" if "." in key else "; sweep keys are dotted parameter names, e.g. \"contact.friction\""
            raise InputError(f"sweep.{key}", exc.message + hint) from None
    validate(out)
    if curve_enabled(out):
        check_overrides(out, overrides)
        out = apply_curve(out)
        validate(out)
    return out


def is_structural(key):
    """True when the dotted key is read by a structural stage (sweeping it makes a new variant)."""
    return key.split(".")[0] in STRUCTURAL_SECTIONS or key in STRUCTURAL_KEYS


def structural_key(study):
    """Canonical JSON of the sections and keys the structural stages read (equal key: same artefacts)."""
    return canonical_json({**{s: study.get(s) for s in STRUCTURAL_SECTIONS}, GEOMETRY_KEY: study_geometry(study)})


GRID_LOAD_FACTOR = 3.0
"""The half-space grid covers the Hertz patch at this multiple of the wheel load (plus 10 %), so
that dynamic loads stay inside it (squeal with lift-off reached 2.6 Q in the point-contact study);
larger loads stop the case with a message that the contact reached the grid edge."""


def contact_params(study):
    """The study's ``[contact]`` section as the typed :class:`contact.params.ContactParams` (the one
    place a case turns it into an object; the case passes the object on)."""
    from contact.params import ContactParams  # lazy: ~2 s (numba)

    return ContactParams.from_mapping(study["contact"], "contact")


def manual_contact(study, params=None):
    """The hand-set contact of a study (``contact.geometry = "manual"``) as a ``ContactPoint``.

    Position ``wheel.contact_offset`` on the wheel and ``track.contact_lateral_position`` on the
    (upright) rail, ``wheel.rolling_radius``, the curvatures of ``contact.rail_head_radius`` and
    ``contact.wheel_transverse_curvature``, ``contact.contact_angle`` in both the track and the
    rail section frame, the normal force of :func:`interaction.frame.static_normal_force` and the
    Hertz semi-axes at it. ``spin`` is the geometric spin ``sin(angle) / r`` (the interaction
    imposes ``contact.spin`` in this mode, see :func:`imposed_creepage`).
    """
    from contact.hertz import hertz_from_curvatures  # lazy: ~2 s (numba)
    from contact.params import contact_curvatures  # lazy: ~2 s (numba)
    from contact_geometry.contact_point import ContactPoint  # lazy: ~2 s (numba, contact_geometry package)
    from interaction.frame import static_normal_force  # lazy: ~2 s (numba, interaction package)

    contact = contact_params(study) if params is None else params
    radius = study["wheel"]["rolling_radius"]
    curvature_x, curvature_y = contact_curvatures(radius, contact.wheel_transverse_curvature,
                                                  contact.rail_head_radius)
    angle = contact.contact_angle
    normal = static_normal_force(study["operating"]["wheel_load"], angle)
    hertz = hertz_from_curvatures(curvature_x, curvature_y, normal, contact.to_material().contact_modulus)
    rail_lateral = float(study.get("track", {}).get("contact_lateral_position", 0.0))
    return ContactPoint(lateral_displacement=float(study["operating"].get("lateral_displacement", 0.0)),
                        wheel_lateral=float(study["wheel"]["contact_offset"]), rail_lateral=rail_lateral,
                        rail_section_lateral=rail_lateral, rail_section_height=math.nan, rolling_radius=float(radius),
                        contact_angle=float(angle), rail_section_angle=float(angle),
                        curvature_long=2.0 * curvature_x, curvature_lat=2.0 * curvature_y, semi_axis_a=hertz.a,
                        semi_axis_b=hertz.b, normal_force=normal, spin=math.sin(angle) / radius, n_contacts=1)


def case_contact(study, geometry_path=None, params=None):
    """The contact a case uses: :func:`manual_contact` or the operating contact of ``contact_geometry.h5``.

    Parameters
    ----------
    study : dict
        The case's study.
    geometry_path : path-like, optional
        ``contact_geometry.h5``. Without it the operating contact is computed here from the
        study's profiles (the same :func:`contact_geometry.study.main_contact` of
        :func:`contact_geometry.study.operating_contacts` the stage stores; its cost: docs/benchmarks.md,
        the contact-geometry rows): the squeal maps' configurations have no artefact of their own.

    Returns
    -------
    contact_geometry.ContactPoint
    """
    from contact_geometry.study import main_contact, operating_contacts  # lazy: ~2 s (numba)
    from stages.geometry import read_operating_contact  # lazy: ~2 s (numba, contact_geometry package)

    if study["contact"].get("geometry", "profiles") == "manual":
        return manual_contact(study, params)
    if geometry_path is None:
        return main_contact(operating_contacts(study))
    return read_operating_contact(geometry_path)


def imposed_creepage(study, point):
    """The imposed creepages (ξ, η, φ) of a case, in the contact frame (φ in 1/m).

    ξ and η are the study's ``contact.longitudinal_creepage`` and ``contact.lateral_creepage``
    (creepages of the contact plane). The spin: ``contact.spin`` for the hand-set contact and for
    a study that names a curve (the curving's spin, with the curve's yaw rate, stages/curve.py);
    for the computed one the geometric spin of the wheel relative to the rail, ``φ = -sin(α) / r``:
    the wheel turns at ``v / r`` about the axle (+y), whose component along the inclined normal
    ``n = (0, -sin α, cos α)`` is ``-(v / r) sin α`` (docs/conventions.md).
    """
    contact = study["contact"]
    hand_set = contact.get("geometry", "profiles") == "manual" or curve_enabled(study)
    spin = contact["spin"] if hand_set else -point.spin
    return (contact["longitudinal_creepage"], contact["lateral_creepage"], spin)


def contact_hertz(study, point=None, params=None):
    """Material and Hertz solution of a study's contact at its static normal force.

    Parameters
    ----------
    study : dict
    point : contact_geometry.ContactPoint, optional
        The contact (:func:`case_contact`); default :func:`manual_contact`.
    params : contact.params.ContactParams, optional
        The study's ``[contact]`` already parsed (:func:`contact_params`); default: parsed here.

    Returns
    -------
    (Material, HertzSolution)
        Gap curvatures half the contact's relative curvatures, normal force ``point.normal_force``
        (the wheel load over the cosine of the contact angle).
    """
    from contact.hertz import hertz_from_curvatures  # lazy: ~2 s (numba)

    params = contact_params(study) if params is None else params
    point = manual_contact(study, params) if point is None else point
    material = params.to_material()
    hertz = hertz_from_curvatures(0.5 * point.curvature_long, 0.5 * point.curvature_lat, point.normal_force,
                                  material.contact_modulus)
    check_contact_shape(study, hertz.a / hertz.b)
    return material, hertz


#: Semi-axis ratios a/b of the contact ellipse that Kalker's creep coefficients cover (the
#: contact models' tables, contact/kalker.py).
A_OVER_B_RANGE = (0.1, 10.0)


def check_contact_shape(study, a_over_b):
    """Refuse a contact ellipse outside :data:`A_OVER_B_RANGE`, naming the keys of the study that
    made it (an internal quantity the user never set would not tell what to change)."""
    low, high = A_OVER_B_RANGE
    if low <= a_over_b <= high:
        return
    if study_geometry(study) == "profiles":
        source = ("operating.lateral_displacement", study["operating"]["lateral_displacement"], "m",
                  "puts the contact where the profiles' curvatures make")
    else:
        source = ("contact.rail_head_radius", study["contact"]["rail_head_radius"], "m",
                  "with contact.wheel_transverse_curvature = "
                  f"{study['contact']['wheel_transverse_curvature']:g} 1/m and wheel.rolling_radius makes")
    key, value, unit, how = source
    raise InputError(key, f"{value:g} {unit} {how} a contact ellipse of a/b = {a_over_b:.3g}, outside the "
                          f"[{low:g}, {high:g}] that Kalker's creep coefficients cover (a nearly conformal "
                          "contact, e.g. on the flange root); choose another value")


def contact_model(study, point=None, params=None):
    """The contact model of a study's ``[contact]`` section at the static normal force.

    Parameters
    ----------
    study : dict
    point : contact_geometry.ContactPoint, optional
        The contact (:func:`case_contact`); default :func:`manual_contact`.
    params : contact.params.ContactParams, optional
        The study's ``[contact]`` already parsed (:func:`contact_params`); default: parsed here.

    Returns
    -------
    ContactModel
        The registered model ``contact.model`` (:mod:`contact.registry`), transient,
        time step = ``[time].time_step``.
    """
    return contact_spec(study["contact"]["model"]).hook("build")(contact_setup(study, point, params))


def contact_setup(study, point=None, params=None):
    """What the study's contact model is built from (:class:`contact.registry.ContactSetup`):
    material and Hertz solution at the static normal force (:func:`contact_hertz`), friction,
    speed, time step, tolerance and the ``[contact]`` section; ``point`` and ``params`` as for
    :func:`contact_model`."""
    contact = contact_params(study) if params is None else params
    material, hertz = contact_hertz(study, point, contact)
    return ContactSetup(material, contact.to_friction(), hertz, study["operating"]["speed"],
                        study["time"]["time_step"], study["simulation"]["tolerance"], contact, GRID_LOAD_FACTOR)


def case_structures(study, inputs):
    """What :func:`interaction.simulate.simulate` needs for a case, in the contact frame.

    The wheel's and the rail's Green's functions at the case's contact (:func:`case_contact`:
    the hand-set or the computed one, ``contact.geometry``), turned into the contact frame once
    (:func:`interaction.frame.to_contact_frame`: the wheel's by the contact angle, the rail's by
    the angle in its upright section), the contact model and the static normal force.

    Parameters
    ----------
    study : dict
        The case's study.
    inputs : dict
        Paths of ``"wheel-greens"``, ``"rail-greens"`` and ``"contact-geometry"``.

    Returns
    -------
    (wheel, rail, contact, kwargs, point)
        Structures, contact model, the keyword arguments ``speed``, ``wheel_load`` (the static
        normal force, N), ``creepage``, ``tolerance`` of ``simulate``, and the ContactPoint.

    Raises
    ------
    ArtefactError
        If a Green's artefact is damaged or was computed with another time step than the study's.
    """
    from interaction.frame import to_contact_frame  # lazy: ~2 s (numba, interaction package)
    from interaction.structures import ConvolutionStructure, ModalStructure  # lazy: ~2 s (numba)
    from stages.rail import read_rail_greens  # lazy: ~2 s (numba)
    from stages.wheel import read_greens  # lazy: ~2 s (numba)

    geometry = study_geometry(study)
    dt = study["time"]["time_step"]
    wheel = read_greens(inputs["wheel-greens"], study["simulation"]["wheel_model"], geometry)
    rail = read_rail_greens(inputs["rail-greens"], geometry)
    for stage, step in (("wheel-greens", wheel["time_step"]), ("rail-greens", rail["time_step"])):
        if not math.isclose(step, dt, rel_tol=1e-9):
            raise ArtefactError(f"{inputs[stage]}: time step {step} s, the study's [time].time_step is {dt} s "
                                "(rebuild it with this study)")
    params = contact_params(study)  # [contact] as an object, once per case
    point = case_contact(study, inputs.get("contact-geometry"), params)
    if wheel["time_stepping"] == "convolution":
        wheel_structure = ConvolutionStructure(to_contact_frame(wheel["kernel"], point.contact_angle), dt)
    else:
        wheel_structure = ModalStructure(wheel["poles"], to_contact_frame(wheel["residues"], point.contact_angle), dt)
    rail_structure = ConvolutionStructure(to_contact_frame(rail["kernel"], point.rail_section_angle), dt)
    kwargs = {"speed": study["operating"]["speed"], "wheel_load": point.normal_force,
              "creepage": imposed_creepage(study, point), "tolerance": study["simulation"]["tolerance"]}
    return wheel_structure, rail_structure, contact_model(study, point, params), kwargs, point


def build_case(ctx, case_id, overrides):
    """Run one case and write ``cases/<case_id>.h5`` (and ``sounds/<case_id>.wav`` if it squeals).

    Returns
    -------
    dict
        ``{"L_F2": dB re 1 N, "squeal": bool, "squeal_frequency": Hz, "oscillation": class,
        "regime": "bouncing" or "contact", "wav": path or ""}``.

    Raises
    ------
    ArtefactError
        If a Green's artefact is damaged or was computed with another time step than the study's.
    """
    # Imported here, not at the top: the interaction package compiles with numba (about 2 s to
    # import, measured with python -X importtime), which ``pipeline.py status`` and input errors,
    # which import this module, should not pay.
    from interaction.metrics import contact_regime, oscillation_class, squeal_metrics  # lazy: ~2 s (numba)
    from interaction.simulate import simulate  # lazy: ~2 s (numba)

    study = ctx.study
    sim = study["simulation"]
    dt = study["time"]["time_step"]
    speed = study["operating"]["speed"]
    wheel_structure, rail_structure, contact, kwargs, point = case_structures(study, ctx.inputs)
    n_steps = int(round(study["time"]["duration"] / dt))
    start = _time.perf_counter()
    result = simulate(wheel_structure, rail_structure, contact, n_steps=n_steps, progress=ctx.progress, **kwargs)
    runtime = _time.perf_counter() - start
    metrics = squeal_metrics(result.force[:, 1], dt, window=sim["rms_window"], threshold_db=sim["squeal_threshold"])
    regime = contact_regime(result.force, dt, study["contact"]["friction"], point.normal_force, window=sim["rms_window"])
    oscillation = oscillation_class(metrics.squeal, metrics.squeal_frequency, sim["squeal_min_frequency"])
    logger.info("case %s: L_F2 = %.1f dB, squeal %s at %.0f Hz, %s (%.1f s)", case_id, metrics.L_F2, metrics.squeal,
                metrics.squeal_frequency, regime.describe("mu "), runtime)
    with ctx.writer() as f:
        attrs = {
            "case_id": case_id, "friction": study["contact"]["friction"],
            "lateral_creepage": study["contact"]["lateral_creepage"], "wheel_model": sim["wheel_model"],
            "contact_model": study["contact"]["model"], "speed": speed, "L_F2": metrics.L_F2,
            "squeal": metrics.squeal, "squeal_frequency": metrics.squeal_frequency, "oscillation": oscillation,
            "buildup_time": metrics.buildup_time, "growth": metrics.growth, "runtime": runtime,
            "overrides": json.dumps(overrides, sort_keys=True),
            "contact_geometry": study["contact"].get("geometry", "profiles"),
            "contact_angle": point.contact_angle, "rolling_radius": point.rolling_radius,
            "normal_force": point.normal_force, "wheel_lateral": point.wheel_lateral,
            "rail_lateral": point.rail_lateral, "spin": kwargs["creepage"][2],
            "contact_loss": regime.contact_loss, "peak_normal_force": regime.peak_normal_force,
            "peak_normal_ratio": regime.peak_normal_ratio, "peak_lateral_ratio": regime.peak_lateral_ratio,
            "regime": regime.regime,
        }
        if curve_enabled(study):  # the curve whose operating point the case runs at (stages/curve.py)
            attrs["curve"] = canonical_json(study["curve"])
        f.attrs.update(attrs)
        add_dataset(f, "time", result.time, "s")
        add_dataset(f, "force", result.force, "N", compress=True)
        add_dataset(f, "creepage", result.creepage, "1", compress=True)
        add_dataset(f, "slip_fraction", result.slip_fraction, "1", compress=True)
        for body in ("wheel", "rail"):
            add_dataset(f, f"{body}/displacement", getattr(result, f"{body}_displacement"), "m", compress=True)
            add_dataset(f, f"{body}/velocity", getattr(result, f"{body}_velocity"), "m/s", compress=True)
    wav = ""
    if metrics.squeal and sim["write_wav"]:
        wav = str(ctx.out_dir / "sounds" / f"{case_id}.wav")
        write_wav(wav, result.force[:, 1], dt)
    return {"L_F2": float(metrics.L_F2), "squeal": bool(metrics.squeal),
            "squeal_frequency": float(metrics.squeal_frequency), "oscillation": oscillation, "regime": regime.regime,
            "wav": wav}


def write_wav(path, signal, time_step, rate=44100):
    """Write a signal (mean removed, peak-normalised) as a 16-bit mono WAV resampled to ``rate`` Hz."""
    import wave
    from fractions import Fraction

    from scipy.signal import resample_poly

    x = np.asarray(signal, dtype=float)
    x = x - x.mean()
    source_rate = 1.0 / time_step
    # rational approximation of rate / source_rate for polyphase resampling
    ratio = Fraction(rate / source_rate).limit_denominator(1000)
    y = resample_poly(x, ratio.numerator, ratio.denominator)
    peak = np.abs(y).max()
    pcm = np.zeros(y.size, dtype="<i2") if peak == 0 else np.round(0.9 * 32767 * y / peak).astype("<i2")
    with atomic_output(path) as tmp:
        with wave.open(str(tmp), "wb") as handle:
            handle.setnchannels(1)
            handle.setsampwidth(2)
            handle.setframerate(rate)
            handle.writeframes(pcm.tobytes())


def execute_case(payload):
    """Run one case from a plain-data payload (see ``stages.engine.case_payload``); never raises.

    Returns
    -------
    dict
        Plain data: ``case_id``; ``ok`` (bool); ``seconds`` (s, wall time); ``error`` (``""`` or
        ``"ExceptionType: message"``); ``L_F2`` (dB re 1 N), ``squeal`` (bool),
        ``squeal_frequency`` (Hz), ``oscillation``, ``regime`` and ``wav`` (path of the sound file
        written, or ``""``) of the case (NaN, False, NaN and ``""`` when it failed).
    """
    start = _time.perf_counter()
    out_dir = Path(payload["out_dir"])
    variant = Path(payload["variant_dir"])
    case_id = payload["case_id"]
    context = StageContext(study=payload["study"], out_dir=out_dir, output=out_dir / "cases" / f"{case_id}.h5",
                           inputs={"wheel-greens": variant / "wheel_greens.h5",
                                   "rail-greens": variant / "rail_greens.h5",
                                   "contact-geometry": variant / "contact_geometry.h5"},
                           schema=payload["schema"], schema_version=payload["schema_version"],
                           params_sha256=payload["params_sha256"], input_hashes=payload["input_hashes"],
                           progress=payload["progress"], sections=CASE_SECTIONS)
    outcome = {"case_id": case_id, "ok": False, "seconds": 0.0, "error": "", "L_F2": math.nan, "squeal": False,
               "squeal_frequency": math.nan, "oscillation": "", "regime": "", "wav": ""}
    try:
        outcome.update(build_case(context, case_id, payload["overrides"]))
        outcome["ok"] = True
    except Exception as exc:  # a failing case is reported; the sweep goes on
        fault = resource_fault(exc, context.output)
        if fault is not None:  # a full disk, a lost permission: not the case's failure, the run stops
            outcome["fault"] = [fault.errno, fault.strerror, getattr(exc, "filename", None) or fault.filename]
            outcome["error"] = f"{fault.filename}: {fault.strerror}"
        else:
            logger.exception("case %s failed", case_id)
            outcome["error"] = f"{type(exc).__name__}: {exc}"
    outcome["seconds"] = _time.perf_counter() - start
    return outcome
