"""A study that names a curve: the steady curving of its bogie feeds the squeal cases.

With ``curve.enabled = true`` (:class:`stages.curve_params.CurveParams`) the cases of a study take
one wheel's operating point (``curve.wheel``, default the leading inner wheel) from the
quasi-static steady curving of the ``[curve]`` bogie on the study's wheel and rail profiles
(:func:`curving.solve_bogie`, :func:`curving.wheel_operating_points`). :func:`apply_curve`
writes it into the study, so the stage engine's hashes see it (a changed curve reruns what it
changes):

=====================================  ==========================================================
key                                    from the curving solution of the wheel
=====================================  ==========================================================
``contact.longitudinal_creepage``      ξ of its tread contact
``contact.lateral_creepage``           η of its tread contact (leading inner wheel: +ψ cos δ > 0)
``contact.spin``                       φ (rotation and the curve's yaw rate; the case imposes it
                                       instead of the profile contact's geometric spin)
``operating.wheel_load``               the tread's share of the wheel load, N cos δ (the case's
                                       static normal force is then the tread's N)
``operating.lateral_displacement``     the wheel's displacement on its rail (flange towards the
                                       gauge face positive): the contact-geometry stage puts the
                                       contact, and the Green's stages the structures, there
``operating.speed``                    ``curve.speed``, when given (else the curve runs at it)
=====================================  ==========================================================

Signs and frames are the study's (:mod:`curving.operating`). Setting one of these keys by hand
(a study file or ``--set`` value other than the default study's, or a sweep over it) together
with a curve is an :class:`~squealcore.errors.InputError` naming both; a sweep of the default
study or the ``--quick`` preset over them is dropped (logged). The curving solution is computed
once per distinct curve, wheel and rail in a process (:func:`study_curve`), so the cases of a
sweep over friction or wheel model share it; a sweep over ``curve.*`` keys makes structural
variants (the contact moves).
"""

from __future__ import annotations

import functools
import json
import logging
import math

from squealcore.artefacts import canonical_json
from squealcore.errors import InputError
from squealcore.study import get_section, set_path
from stages.context import key_value
from stages.curve_params import CurveParams
from stages.greens_layout import GEOMETRY_KEY

logger = logging.getLogger(__name__)

__all__ = ["FED_KEYS", "SPEED_KEY", "curve_enabled", "curve_requested", "fed_keys", "study_curve", "curve_point",
           "apply_curve", "check_hand_set", "check_overrides"]

#: The keys a curve sets in every study that names one.
FED_KEYS = ("contact.longitudinal_creepage", "contact.lateral_creepage", "contact.spin", "operating.wheel_load",
            "operating.lateral_displacement")
#: Set by the curve too when ``curve.speed`` is given.
SPEED_KEY = "operating.speed"


def _curve(study) -> CurveParams:
    return CurveParams.from_mapping(get_section(study, "curve"), "curve")


def curve_enabled(study) -> bool:
    """Whether the study (one case) names a curve: ``curve.enabled``."""
    return bool(key_value(study, "curve.enabled"))


def curve_requested(study) -> bool:
    """Whether the study or one case of its sweep names a curve."""
    swept = (study.get("sweep") or {}).get("curve.enabled")
    return curve_enabled(study) or (isinstance(swept, list) and True in swept)


def fed_keys(study) -> tuple:
    """The keys the curve sets for this study (:data:`FED_KEYS`, and ``operating.speed`` when
    ``curve.speed`` is given, in the study or its sweep)."""
    swept = (study.get("sweep") or {}).get("curve.speed")
    speed_given = bool(key_value(study, "curve.speed")) or (isinstance(swept, list) and any(swept))
    return FED_KEYS + ((SPEED_KEY,) if speed_given else ())


def _inputs(study) -> str:
    """Canonical JSON of what the curving solution depends on: ``[curve]``, ``[wheel]``, ``[rail]``
    and the speed."""
    curve = _curve(study)
    speed = curve.speed if curve.speed > 0.0 else float(study["operating"]["speed"])
    return canonical_json({"curve": get_section(study, "curve"), "wheel": get_section(study, "wheel"),
                           "rail": get_section(study, "rail"), "speed": speed})


@functools.lru_cache(maxsize=8)
def _geometry(wheel_rail: str, track_gauge: float):
    # the profile tables of a wheel on a rail (0.5 s): shared by every curve on them
    from curving import profile_geometry  # lazy: curving imports scipy.optimize and the point contact: 0.8 s

    return profile_geometry(json.loads(wheel_rail), track_gauge=track_gauge)


@functools.lru_cache(maxsize=64)
def _solve(inputs: str):
    from curving import CurvingError, CurvingParams, solve_bogie, wheel_operating_points  # lazy: 0.8 s (_geometry)

    data = json.loads(inputs)
    curve = CurveParams.from_mapping(data["curve"], "curve")
    geometry = _geometry(canonical_json({"wheel": data["wheel"], "rail": data["rail"]}), curve.track_gauge)
    speed = data["speed"]
    if not 0.0 < speed <= 100.0:
        raise InputError("operating.speed", f"must lie in (0, 100] m/s with a curve (curve.enabled; or give "
                                            f"curve.speed), got {speed:g}")
    rigid = curve.rigid_bogie
    params = CurvingParams(
        radius=curve.radius, speed=speed, cant=curve.cant, wheelbase=curve.wheelbase, axle_load=curve.axle_load,
        centre_of_gravity_height=curve.centre_of_gravity_height,
        longitudinal_stiffness=math.inf if rigid else curve.longitudinal_stiffness,
        lateral_stiffness=math.inf if rigid else curve.lateral_stiffness,
        axlebox_half_spacing=curve.axlebox_half_spacing, friction=curve.friction,
        flange_friction=None if curve.flange_friction < 0.0 else curve.flange_friction, geometry=geometry)
    try:
        result = solve_bogie(params)
    except CurvingError as exc:
        raise InputError("curve.radius", f"{exc} (the bogie of [curve] on the study's profiles)") from None
    logger.info("steady curving at R = %g m, V = %g m/s: leading angle of attack %.3g mrad", curve.radius, speed,
                1e3 * result["wheelsets"][0]["angle_of_attack"])
    return result, wheel_operating_points(result)


def study_curve(study):
    """The steady-curving solution of a study's ``[curve]`` bogie (computed once per distinct curve,
    profiles and speed in this process).

    Parameters
    ----------
    study : dict
        A validated study (``curve.enabled`` need not be set).

    Returns
    -------
    (dict, dict)
        :func:`curving.solve_bogie`'s result and :func:`curving.wheel_operating_points` of it
        (label -> :class:`curving.WheelOperatingPoint`).

    Raises
    ------
    InputError
        For a bad ``[curve]`` value, a speed outside (0, 100] m/s, or a curve without equilibrium
        (field ``curve.radius``).
    """
    return _solve(_inputs(study))


def curve_point(study):
    """The operating point of the study's ``curve.wheel`` (:class:`curving.WheelOperatingPoint`)."""
    return study_curve(study)[1][_curve(study).wheel]


def fed_values(study) -> dict:
    """``{dotted key: value}`` the curve sets in the study (table in the module docstring)."""
    point = curve_point(study)
    if not point.tread_load > 0.0:
        raise InputError("curve.wheel", f"the {point.label} wheel carries no load on its tread in this curve "
                                        f"(N cos delta = {point.tread_load:.4g} N): choose another wheel or curve")
    values = {"contact.longitudinal_creepage": point.longitudinal_creepage,
              "contact.lateral_creepage": point.lateral_creepage, "contact.spin": point.spin,
              "operating.wheel_load": point.tread_load, "operating.lateral_displacement": point.wheel_displacement}
    if _curve(study).speed > 0.0:
        values[SPEED_KEY] = point.speed
    return values


def apply_curve(study):
    """The study with the curve's operating point written in (the study itself without a curve).

    Raises
    ------
    InputError
        With ``contact.geometry = "manual"`` (the curve places the contact on the profiles), for a
        wheel whose tread carries no load (``curve.wheel``), or from :func:`study_curve`.
    """
    if not curve_enabled(study):
        return study
    if key_value(study, GEOMETRY_KEY) != "profiles":
        raise InputError("curve.enabled", f"a curve places the contact on the wheel and rail profiles: it needs "
                                          f"{GEOMETRY_KEY} = \"profiles\", got {key_value(study, GEOMETRY_KEY)!r}")
    out = study
    for key, value in fed_values(study).items():
        out = set_path(out, key.split("."), value)
    return out


def check_hand_set(study, default):
    """Refuse values a curve would set that the user set by hand; drop the default's sweeps over them.

    Parameters
    ----------
    study : dict
        The study as loaded (study file and ``--set`` merged over ``default``).
    default : dict
        The default study it was merged over (schema, ``paper.toml``, the ``--quick`` preset).

    Returns
    -------
    dict
        ``study``, less the default's sweep entries over the keys the curve sets.

    Raises
    ------
    InputError
        Naming the key set by hand (or ``sweep.<key>``) and the curve.
    """
    if not curve_requested(study):
        return study
    sweep = dict(study.get("sweep") or {})
    default_sweep = default.get("sweep") or {}
    for key in fed_keys(study):
        value = key_value(study, key)
        if value != key_value(default, key):
            raise InputError(key, f"is set by hand ({value!r}) and by the curve (curve.enabled = true): with a curve "
                                  f"the cases take it from the curving solution of curve.wheel; remove {key} or "
                                  "the curve")
        if key in sweep:
            if sweep[key] != default_sweep.get(key):
                raise InputError(f"sweep.{key}", f"sweeps a value the curve sets (curve.enabled = true): remove "
                                                 f"the sweep over {key} or the curve")
            logger.info("the curve sets %s: the default study's sweep over it (%r) is dropped", key, sweep[key])
            del sweep[key]
    return {**study, "sweep": sweep}


def check_overrides(study, overrides):
    """Refuse sweep or map-grid values of keys the curve sets, when the case names a curve.

    Raises
    ------
    InputError
        Naming ``sweep.<key>`` and the curve.
    """
    if not curve_enabled(study):
        return
    for key in overrides:
        if key in fed_keys(study):
            raise InputError(f"sweep.{key}", f"sweeps a value the curve sets (curve.enabled = true): remove the "
                                             f"sweep over {key} or the curve")
