"""The study configuration: defaults, presets, user files, ``--set`` overrides and validation.

The default study is ``studies/paper.toml`` (shipped with the package); ``--quick`` merges
``studies/quick.toml`` over it. A user's study file and ``--set`` overrides are merged on top.
Every section is then checked by the parameter class of the package that uses it, so a bad value
is reported before anything is computed or written.
"""

from __future__ import annotations

from squealcore.errors import InputError
from squealcore.study import Field, choice, get_section, integer, load_toml, merge, number, set_path, parse_assignment, validate_fields
from studies import study_path

WHEEL_FE_FIELDS = {
    "solver": choice("hex20", "axisymmetric"),
    "hex20_method": choice("cyclic", "full"),
    "youngs_modulus": number(0.0, 1e13, "Pa", low_open=True),
    "poisson_ratio": number(-1.0, 0.5, low_open=True, high_open=True),
    "f_max": number(0.0, 50e3, "Hz", low_open=True),
    "damping_ratio": number(0.0, 1.0, high_open=True),
    "damping_ratio_low_order": number(0.0, 1.0, high_open=True),
    "low_order_max_n": integer(0, 100),
}

ROTATION_FIELDS = {
    "gyroscopic": Field("boolean"),
    "spin_softening": Field("boolean"),
    "centrifugal_stiffening": Field("boolean"),
    "moving_load_path": choice("harmonic", "interpolated"),
}

OPERATING_FIELDS = {
    "speed": number(0.0, 150.0, "m/s", low_open=True),
    "wheel_load": number(0.0, 1e6, "N", low_open=True),
}

TIME_FIELDS = {
    "time_step": number(0.0, 1e-3, "s", low_open=True),
    "duration": number(0.0, 100.0, "s", low_open=True),
    "wheel_kernel_duration": number(0.0, 10.0, "s", low_open=True),
}

CONTACT_FIELDS = {
    "model": choice("halfspace", "point"),
    "friction": number(0.0, 5.0),
    "longitudinal_creepage": number(-0.5, 0.5),
    "lateral_creepage": number(-0.5, 0.5),
    "spin": number(-100.0, 100.0, "1/m"),
    "rail_head_radius": number(0.0, 100.0, "m", low_open=True),
    "wheel_transverse_curvature": number(-100.0, 100.0, "1/m"),
    "grid_dy": number(0.0, 0.01, "m", low_open=True),
    "youngs_modulus": number(0.0, 1e13, "Pa", low_open=True),
    "poisson_ratio": number(0.0, 0.5, high_open=True),
}

WHEEL_MODELS = ("stationary", "moving_load", "eulerian")
"""Wheel models of the interaction: stationary wheel, stationary wheel with a rotating load, Eulerian."""

SIMULATION_FIELDS = {
    "wheel_model": choice(*WHEEL_MODELS),
    "rms_window": number(0.0, 100.0, "s", low_open=True),
    "squeal_threshold": number(-300.0, 300.0, "dB"),
    "write_wav": Field("boolean"),
    "tolerance": number(1e-12, 1e-3),
}

REPORT_FIELDS = {
    "dpi": integer(30, 600),
    "receptance_f_min": number(0.0, 1e5, "Hz", low_open=True),
    "receptance_f_max": number(0.0, 1e5, "Hz", low_open=True),
}


def _wheel(section, prefix):
    from mesh.wheel_section import WheelParams

    WheelParams.from_mapping(section, prefix)


def _rail(section, prefix):
    from mesh.rail_section import RailParams

    RailParams.from_mapping(section, prefix)


def _track(section, prefix):
    from waveguide.params import TrackParams

    TrackParams.from_mapping(section, prefix)


def _fields(spec):
    return lambda section, prefix: validate_fields(section, spec, prefix)


def _report(section, prefix):
    values = validate_fields(section, REPORT_FIELDS, prefix)
    if values["receptance_f_max"] <= values["receptance_f_min"]:
        raise InputError(f"{prefix}.receptance_f_max", "must be larger than receptance_f_min")


#: section -> validator(flat section mapping, dotted prefix); raises InputError.
VALIDATORS = {
    "wheel": _wheel,
    "wheel.fe": _fields(WHEEL_FE_FIELDS),
    "wheel.rotation": _fields(ROTATION_FIELDS),
    "rail": _rail,
    "track": _track,
    "operating": _fields(OPERATING_FIELDS),
    "time": _fields(TIME_FIELDS),
    "contact": _fields(CONTACT_FIELDS),
    "simulation": _fields(SIMULATION_FIELDS),
    "report": _report,
}


def default_study(quick=False):
    """The default study (``paper.toml``), with the ``quick.toml`` preset merged if asked."""
    study = load_toml(study_path("paper.toml"))
    if quick:
        study = merge(study, load_toml(study_path("quick.toml")))
    return study


def load_study(config=None, quick=False, assignments=()):
    """Build and validate a study.

    Parameters
    ----------
    config : str or Path, optional
        User study file merged over the defaults.
    quick : bool
        Merge the quick preset first.
    assignments : sequence of str
        ``section.key=value`` overrides, applied last (values read as TOML, bare words as strings).

    Returns
    -------
    dict
        The complete, validated study.

    Raises
    ------
    InputError
        For unknown keys, values of the wrong kind or out of range.
    """
    study = default_study(quick)
    if config is not None:
        study = merge(study, load_toml(config))
    for assignment in assignments:
        path, value = parse_assignment(assignment)
        study = set_path(study, path, value)
    validate(study)
    from stages.cases import case_study, expand_sweep

    for _, overrides in expand_sweep(study):  # every case must be valid before anything runs
        case_study(study, overrides)
    return study


def validate(study):
    """Run every section's validator (raises :class:`InputError`)."""
    for section, validator in VALIDATORS.items():
        validator(get_section(study, section), section)
    contact = study["contact"]
    if contact["rail_head_radius"] * contact["wheel_transverse_curvature"] <= -1.0:
        raise InputError("contact.wheel_transverse_curvature",
                         "a hollow tread must curve less than the rail head (curvature > -1/rail_head_radius)")
