"""Study configuration: defaults, merging, --set parsing and validation messages."""

import dataclasses

import pytest

from squealcore.errors import InputError
from squealcore.study import merge, parse_assignment, parse_value
from stages.config import default_study, load_study


def test_paper_defaults_match_parameter_classes():
    # studies/paper.toml is the embedded default: its [wheel] table must equal WheelParams'
    # defaults so that the library API and the pipeline describe the same wheel.
    from mesh.wheel_section import WheelParams

    study = default_study()
    wheel = {k: v for k, v in study["wheel"].items() if not isinstance(v, dict)}
    assert wheel == dataclasses.asdict(WheelParams())


def test_quick_preset_is_valid_and_differs():
    quick = load_study(quick=True)
    assert quick["wheel"]["fe"]["solver"] == "axisymmetric"
    assert load_study()["wheel"]["fe"]["solver"] == "hex20"


@pytest.mark.parametrize(
    "text, value",
    [("0.4", 0.4), ("3", 3), ("true", True), ("[0.3, 0.6]", [0.3, 0.6]), ("axisymmetric", "axisymmetric"),
     ('"hex20"', "hex20")],
)
def test_set_values_are_read_as_toml(text, value):
    assert parse_value(text) == value


def test_set_overrides_and_errors():
    study = load_study(assignments=["wheel.rolling_radius=0.385", "wheel.fe.solver=axisymmetric"])
    assert study["wheel"]["rolling_radius"] == 0.385
    assert study["wheel"]["fe"]["solver"] == "axisymmetric"
    with pytest.raises(InputError) as err:
        load_study(assignments=["wheel.rolling_radiuss=0.3"])
    assert err.value.field == "wheel.rolling_radiuss"
    with pytest.raises(InputError) as err:
        load_study(assignments=["wheel.web_thickness=-0.01"])
    assert err.value.field == "wheel.web_thickness"
    with pytest.raises(InputError) as err:
        load_study(assignments=["wheel.rim_inner_radius=0.40"])
    assert err.value.field.startswith("wheel.")
    with pytest.raises(InputError) as err:
        load_study(assignments=["operating.speed=fast"])
    assert err.value.field == "operating.speed" and "number" in err.value.message
    with pytest.raises(InputError) as err:
        load_study(assignments=["wheel.fe.solver=abaqus"])
    assert err.value.field == "wheel.fe.solver" and "hex20" in err.value.message
    with pytest.raises(InputError):
        parse_assignment("wheel")


@pytest.mark.parametrize("key", ["sweep.contact.friction", 'sweep."contact.friction"', 'sweep . "contact.friction"'])
def test_set_gives_a_sweep_list(key):
    """``--set sweep.KEY=[...]`` sets the sweep over KEY (dotted, or one quoted part as in a study file)."""
    from stages.cases import expand_sweep

    before = load_study(quick=True)["sweep"]
    study = load_study(quick=True, assignments=[f"{key}=[0.3, 0.5]"])
    assert study["sweep"] == {**before, "contact.friction": [0.3, 0.5]}  # the other entries kept
    cases = expand_sweep(study)
    assert len(cases) == 2 * len(expand_sweep(load_study(quick=True)))
    assert sorted({overrides["contact.friction"] for _, overrides in cases}) == [0.3, 0.5]


@pytest.mark.parametrize("value, message", [('"x"', "non-empty list"), ("[0.3, 0.3]", "twice"), ("[]", "non-empty")])
def test_set_sweep_list_errors_name_the_sweep_entry(value, message):
    from stages.cases import expand_sweep

    with pytest.raises(InputError) as err:
        expand_sweep(load_study(quick=True, assignments=[f"sweep.contact.friction={value}"]))
    assert err.value.field == "sweep.contact.friction" and message in err.value.message


def test_study_file_sweep_keys_may_be_written_without_quotes(tmp_path):
    """``contact.friction = [...]`` in ``[sweep]`` (a nested table to TOML) is the dotted key, as
    ``"contact.friction"``; a file parameter swept that way is still resolved against the file's folder."""
    (tmp_path / "quoted.toml").write_text('[sweep]\n"contact.friction" = [0.3, 0.5]\n"wheel.profile_file" = ["p.csv"]\n')
    (tmp_path / "plain.toml").write_text("[sweep]\ncontact.friction = [0.3, 0.5]\nwheel.profile_file = ['p.csv']\n")
    quoted = load_study(str(tmp_path / "quoted.toml"), quick=True)
    plain = load_study(str(tmp_path / "plain.toml"), quick=True)
    assert plain["sweep"] == quoted["sweep"]
    assert plain["sweep"]["contact.friction"] == [0.3, 0.5]
    assert plain["sweep"]["wheel.profile_file"] == [str(tmp_path / "p.csv")]


def test_map_grid_keys_without_quotes_and_one_axis_from_set(tmp_path):
    """``[map.grid]`` is a free table like ``[sweep]``: unquoted dotted keys, and ``--set map.grid.KEY=[...]``
    replaces that axis only."""
    (tmp_path / "map.toml").write_text('[map.grid]\ncontact.friction = [0.3, 0.6]\n"operating.speed" = [5.0, 10.0]\n')
    study = load_study(str(tmp_path / "map.toml"), quick=True)
    assert study["map"]["grid"] == {"contact.friction": [0.3, 0.6], "operating.speed": [5.0, 10.0]}
    study = load_study(str(tmp_path / "map.toml"), quick=True, assignments=["map.grid.operating.speed=[20.0]"])
    assert study["map"]["grid"] == {"contact.friction": [0.3, 0.6], "operating.speed": [20.0]}
    assert load_study(quick=True, assignments=['map.grid."contact.friction"=[0.4]'])["map"]["grid"] == {
        "contact.friction": [0.4]}


def test_set_key_is_read_as_a_toml_dotted_key():
    assert parse_assignment('sweep."wheel.rolling_radius"=[0.4]') == (["sweep", "wheel.rolling_radius"], [0.4])
    assert parse_assignment("wheel.fe.solver=hex20") == (["wheel", "fe", "solver"], "hex20")
    for bad in ['wheel."rolling_radius=1', "wheel.=1", ".x=1", "wheel..x=1"]:
        with pytest.raises(InputError) as err:
            parse_assignment(bad)
        assert err.value.field == "--set"


def test_merge_refuses_unknown_and_wrong_kind():
    base = {"a": {"x": 1.0, "s": "t"}}
    assert merge(base, {"a": {"x": 2}})["a"]["x"] == 2
    with pytest.raises(InputError):
        merge(base, {"a": {"y": 1}})
    with pytest.raises(InputError):
        merge(base, {"a": {"x": "one"}})
    with pytest.raises(InputError):
        merge(base, {"a": 3})


def test_rail_and_track_defaults_match_parameter_classes():
    from profiles.rail_section import RailParams
    from waveguide.params import TrackParams

    study = default_study()
    assert study["rail"] == dataclasses.asdict(RailParams())
    assert study["track"] == dataclasses.asdict(TrackParams())


def test_validate_returns_the_typed_sections():
    from contact.params import ContactParams, Friction
    from stages.config import validate

    sections = validate(load_study(assignments=["contact.friction=0.45"]))
    contact = sections["contact"]
    assert isinstance(contact, ContactParams) and contact.friction == 0.45
    assert contact.to_friction() == Friction(0.45, 0.45)
    material = contact.to_material()
    assert material.shear_modulus == pytest.approx(210e9 / 2.6, rel=1e-15)  # G = E / (2 (1 + nu))
    assert sections["wheel"].rolling_radius == 0.39 and sections["wheel.fe"].solver == "hex20"


def test_sweep_is_expanded_by_the_caller_not_by_load_study(tmp_path):
    # load_study checks the sections; a bad sweep value is found when the cases are planned
    from stages.cases import case_study, expand_sweep

    config = tmp_path / "study.toml"
    config.write_text('[sweep]\n"contact.friction" = [0.3, -1.0]\n')
    study = load_study(config)
    cases = expand_sweep(study)
    assert len(cases) == 2
    with pytest.raises(InputError) as err:
        for _, overrides in cases:
            case_study(study, overrides)
    assert err.value.field == "contact.friction" and "(0, 5]" in err.value.message
