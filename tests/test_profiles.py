"""Profiles as inputs: the wheel's tread profile, the rail inclination, bad profile files, and the
contents of input files in the stage hashes (issue 14, parts 1 and 5).

Independent references: the S1002 closed form (``s1002_height``, the published piecewise
definition, integrated here with scipy's adaptive quadrature), the outline points of the
parametric section saved before the tread profile existed (``tests/data``), and hashlib.
"""

import hashlib
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from contact_geometry.wheel_surface import parametric_wheel_profile, wheel_profile_from_params
from mesh.wheel_section import (MIN_RIM_THICKNESS, WheelParams, build_outline, outline_mass,
                                section_outline)
from profiles.rail_head import rail_profile_from_params
from profiles.rail_section import RailParams
from profiles.s1002 import S1002_JOINTS_MM, S1002_TAPE_OFFSET, s1002_height
from squealcore.errors import InputError
from stages import engine
from stages.config import STUDY_SECTIONS, load_study
from stages.input_files import input_file_hashes

DATA = Path(__file__).parent / "data"
S1002 = WheelParams().replace(tread_profile="S1002")
#: Lateral extent of the shipped S1002 samples (m from the flange back): the first 0.5 mm of the
#: vertical flange back is left out (profiles/s1002.py).
Y0, Y1 = 0.0005, 0.130


def s1002_m(y):
    """S1002 height above the tape circle (m) at y from the flange back (m): the closed form."""
    return s1002_height((np.asarray(y, dtype=float) - S1002_TAPE_OFFSET) * 1e3) * 1e-3


# --------------------------------------------------------------------------- the default stays


def test_parametric_default_outline_is_unchanged():
    # saved from section_outline(WheelParams()) before tread_profile existed: bit for bit
    reference = np.loadtxt(DATA / "parametric_wheel_outline.txt")
    points, labels = section_outline(WheelParams())
    assert WheelParams().tread_profile == "parametric"
    assert np.array_equal(points, reference)
    assert labels["bore"].tolist() == [311, 312] and labels["contact"] == 214


# --------------------------------------------------------------------------- the S1002 wheel


def test_s1002_outline_follows_the_closed_form_and_keeps_hub_and_web():
    outline = build_outline(S1002)
    tread = np.vstack([s.points for s in outline.segments if s.kind == "spline"])
    r, y = tread[:, 0], tread[:, 1]
    # the chain holds the shipped samples (10 significant digits in the file: 1e-12 m)
    assert np.abs(r - S1002.rolling_radius - s1002_m(y)).max() < 1e-9
    assert y.min() == pytest.approx(Y0, abs=1e-12) and y.max() == pytest.approx(Y1, abs=1e-12)
    # contact node at the tape circle, where S1002 has height 0
    assert np.allclose(outline.contact_point, [S1002.rolling_radius, S1002.contact_offset], atol=1e-12)
    # hub and web as in the parametric wheel: the bore edge and the arcs of the fillets agree
    parametric = build_outline(WheelParams())
    assert np.array_equal(outline.segments[outline.bore_segment].points,
                          parametric.segments[parametric.bore_segment].points)
    arcs = [s.points for s in outline.segments if s.kind == "arc"]
    arcs_parametric = [s.points for s in parametric.segments if s.kind == "arc"
                       and s.points[:, 0].max() <= WheelParams().rim_inner_radius + 1e-12]
    assert len(arcs) == 4 and all(np.array_equal(a, b) for a, b in zip(arcs, arcs_parametric))


def _rim_top_moment(params):
    """int r dA (m^3) of the rim above r = rim_inner_radius, from the S1002 closed form.

    The rim top is {0 <= y <= rim_width, ri <= r <= R(y)} with R = r0 + F(y) on the profile
    and the straight joins (ri, 0)-(first sample) and (last sample)-(ri, rim_width); each
    piece of F is integrated by adaptive quadrature, the joins exactly.
    """
    r0, ri, width = params.rolling_radius, params.rim_inner_radius, params.rim_width
    edges = np.r_[Y0, S1002_JOINTS_MM[1:-1] * 1e-3 + S1002_TAPE_OFFSET, Y1]
    f = lambda y: 0.5 * ((r0 + float(s1002_m(y))) ** 2 - ri ** 2)  # noqa: E731
    total = sum(quad(f, a, b, epsabs=1e-15, epsrel=1e-13, limit=200)[0] for a, b in zip(edges[:-1], edges[1:]))

    def join(length, ra, rb):  # int (R^2 - ri^2)/2 dy for R linear from ra to rb
        return 0.5 * length * ((ra * ra + ra * rb + rb * rb) / 3.0 - ri * ri)

    return (total + join(Y0, ri, r0 + float(s1002_m(Y0)))
            + join(width - Y1, r0 + float(s1002_m(Y1)), ri))


@pytest.mark.parametrize("turned", [0.37, 0.36])
def test_turning_changes_the_mass_as_pappus_of_the_closed_form_predicts(turned):
    # Turning = the same S1002 at a smaller rolling radius; only the rim top changes, so
    # dm = rho 2 pi [M(r0) - M(r_turned)] with M from the closed form. The outline is the
    # polyline of the 0.05 mm samples; its chord error (h^2 kappa / 12 per unit length, h <=
    # 0.22 mm on the flange back, kappa <= 1/12 mm) is ~1e-8 of dm, hence 1e-6 relative.
    smaller = S1002.replace(rolling_radius=turned)
    dm = outline_mass(S1002) - outline_mass(smaller)
    expected = S1002.density * 2.0 * math.pi * (_rim_top_moment(S1002) - _rim_top_moment(smaller))
    assert dm == pytest.approx(expected, rel=1e-6)
    assert dm > 0.0


def test_a_wheel_turned_too_far_is_refused_naming_rolling_radius_and_the_limit():
    lowest = float(s1002_m(Y1))  # the field-side chamfer end is the lowest point of S1002
    limit = S1002.rim_inner_radius + MIN_RIM_THICKNESS - lowest
    S1002.replace(rolling_radius=limit + 1e-6)  # just thick enough
    with pytest.raises(InputError) as err:
        S1002.replace(rolling_radius=limit - 1e-6)
    assert err.value.field == "wheel.rolling_radius"
    assert f"{limit:.6g}" in err.value.message and "rim" in err.value.message


def test_one_source_for_mesh_and_contact():
    # the contact search's wheel profile is the chain the wheel section is built on
    profile = wheel_profile_from_params(S1002)
    outline = build_outline(S1002)
    ri = S1002.rim_inner_radius
    pieces = [s.points for s in outline.segments if s.kind != "arc" and s.points[:, 0].min() > ri + 1e-9]
    chain = np.vstack([pieces[0][:1]] + [p[1:] for p in pieces])
    assert np.array_equal(chain[:, 1], profile.y)
    assert np.array_equal(chain[:, 0], S1002.rolling_radius + profile.z)
    # parametric: the resampled outline, as before
    default = wheel_profile_from_params(WheelParams())
    reference = parametric_wheel_profile(WheelParams())
    assert np.array_equal(default.y, reference.y) and np.array_equal(default.z, reference.z)


# --------------------------------------------------------------------------- tread files


def _write(path, text):
    path.write_text(text)
    return str(path)


def test_tread_file_in_millimetres_gives_the_same_wheel_as_in_metres(tmp_path):
    y = np.linspace(0.0, 130.0, 131)
    cone = np.c_[y, -(y - 70.0) / 40.0]
    mm = _write(tmp_path / "cone_mm.txt", "# units: mm\n# a 1:40 cone\n" + "\n".join(f"{a}, {b}" for a, b in cone))
    m = _write(tmp_path / "cone_m.txt", "\n".join(f"{a * 1e-3} {b * 1e-3}" for a, b in cone))
    a, b = WheelParams().replace(tread_profile=mm), WheelParams().replace(tread_profile=m)
    assert outline_mass(a) == pytest.approx(outline_mass(b), rel=1e-12)
    # a cone: the rim top is a trapezoid in y with R linear, int (R^2 - ri^2)/2 dy exactly
    r0, ri, width = a.rolling_radius, a.rim_inner_radius, a.rim_width
    R = lambda yy: r0 - (yy - 0.070) / 40.0  # noqa: E731
    top = 0.5 * 0.130 * ((R(0) ** 2 + R(0) * R(0.130) + R(0.130) ** 2) / 3 - ri ** 2)
    top += 0.5 * (width - 0.130) * ((R(0.130) ** 2 + R(0.130) * ri + ri ** 2) / 3 - ri ** 2)
    turned = a.replace(rolling_radius=0.38)
    R2 = lambda yy: 0.38 - (yy - 0.070) / 40.0  # noqa: E731
    top2 = 0.5 * 0.130 * ((R2(0) ** 2 + R2(0) * R2(0.130) + R2(0.130) ** 2) / 3 - ri ** 2)
    top2 += 0.5 * (width - 0.130) * ((R2(0.130) ** 2 + R2(0.130) * ri + ri ** 2) / 3 - ri ** 2)
    dm = outline_mass(a) - outline_mass(turned)
    assert dm == pytest.approx(a.density * 2 * math.pi * (top - top2), rel=1e-10)


BAD_TREADS = {
    "not a number": ("0 0\n0.01 x\n0.02 0\n0.03 0\n", "not a number"),
    "three columns": ("0 0 0\n0.01 0 0\n", "expected 2 columns"),
    "too few points": ("0 0\n0.05 0\n0.10 0\n", "too few points"),
    "non-monotonic": ("0 0.01\n0.02 0\n0.01 -0.001\n0.05 -0.001\n0.08 -0.002\n", "non-monotonic"),
    "self-intersecting": ("0 0\n0.1 0\n0.1 0.01\n0.05 -0.01\n0.12 -0.01\n", "self-intersecting"),
    "closed outline": ("0 0\n0.1 0\n0.1 0.02\n0 0.02\n0 0\n", "lateral positions must increase"),
    "empty": ("# nothing\n", "too few points"),
    "unknown units": ("# units: inch\n0 0\n1 0\n2 0\n3 0\n", "units must be one of"),
}


@pytest.mark.parametrize("name", BAD_TREADS)
def test_bad_tread_files_name_the_file_and_the_problem(tmp_path, name):
    text, words = BAD_TREADS[name]
    path = _write(tmp_path / "bad.txt", text)
    with pytest.raises(InputError) as err:
        load_study(assignments=[f"wheel.tread_profile={path}"])
    assert err.value.field == "wheel.tread_profile"
    assert path in err.value.message and words in err.value.message


def test_tread_profile_not_fitting_the_rim_is_refused(tmp_path):
    with pytest.raises(InputError) as err:
        load_study(assignments=["wheel.tread_profile=" + str(tmp_path / "absent.txt")])
    assert err.value.field == "wheel.tread_profile" and "cannot read" in err.value.message
    wide = _write(tmp_path / "wide.txt", "\n".join(f"{y} 0" for y in np.linspace(0, 0.2, 11)))
    with pytest.raises(InputError) as err:
        load_study(assignments=[f"wheel.tread_profile={wide}"])
    assert err.value.field == "wheel.rim_width" and "0.2" in err.value.message
    narrow = _write(tmp_path / "narrow.txt", "\n".join(f"{y} 0" for y in np.linspace(0, 0.05, 11)))
    with pytest.raises(InputError) as err:
        load_study(assignments=[f"wheel.tread_profile={narrow}"])
    assert err.value.field == "wheel.contact_offset"


# --------------------------------------------------------------------------- the rail


@pytest.mark.parametrize("n", [20, 30, 40])
def test_rail_profile_from_params_is_tilted_by_the_inclination(n):
    profile = rail_profile_from_params(RailParams.from_mapping({"inclination": n}))
    # the crown's slope at the centre line is the tilt 1/n (the upright crown is flat there)
    assert profile.height(0.0, 1) == pytest.approx(1.0 / n, rel=1e-6)
    upright = rail_profile_from_params(RailParams.from_mapping({"inclination": 0}))
    assert upright.height(0.0, 1) == pytest.approx(0.0, abs=1e-9)


def test_default_inclination_is_1_in_30_and_others_are_refused():
    assert load_study()["rail"]["inclination"] == 30
    for bad in ("25", "-30", "30.5", '"30"'):
        with pytest.raises(InputError) as err:
            load_study(assignments=[f"rail.inclination={bad}"])
        assert err.value.field == "rail.inclination"


# --------------------------------------------------------------------------- file contents in the hashes


def test_relative_tread_paths_in_a_study_file_are_taken_from_its_folder(tmp_path, monkeypatch):
    folder = tmp_path / "study"
    folder.mkdir()
    cone = "\n".join(f"{y} {-(y - 0.07) / 40}" for y in np.linspace(0, 0.13, 27))
    _write(tmp_path / "common_tread.txt", cone)
    _write(folder / "own.txt", cone)
    (folder / "study.toml").write_text('[wheel]\ntread_profile = "own.txt"\n'
                                       '[sweep]\n"wheel.tread_profile" = ["../common_tread.txt", "S1002"]\n')
    monkeypatch.chdir(tmp_path.parent)  # elsewhere: the paths must not depend on the working folder
    study = load_study(folder / "study.toml")
    assert Path(study["wheel"]["tread_profile"]) == folder / "own.txt"
    assert Path(study["sweep"]["wheel.tread_profile"][0]).resolve() == tmp_path / "common_tread.txt"
    assert study["sweep"]["wheel.tread_profile"][1] == "S1002"


def test_file_hashes_are_those_of_the_contents_and_only_in_the_sections_that_name_them(tmp_path):
    tread = _write(tmp_path / "t.txt", "\n".join(f"{y} {-(y - 0.07) / 40}" for y in np.linspace(0, 0.13, 27)))
    study = load_study(assignments=[f"wheel.tread_profile={tread}"])
    digest = hashlib.sha256(Path(tread).read_bytes()).hexdigest()
    assert input_file_hashes(study, ("wheel",), STUDY_SECTIONS) == {"wheel.tread_profile": digest}
    assert input_file_hashes(study, ("rail",), STUDY_SECTIONS) == {}
    assert input_file_hashes(load_study(), ("wheel", "rail"), STUDY_SECTIONS) == {}  # built-in names
    # the stage hash follows the contents: same name, new bytes -> new hash for wheel-mesh only
    wheel, rail = engine.STAGE_BY_NAME["wheel-mesh"], engine.STAGE_BY_NAME["rail-mesh"]
    before = {s.name: engine.inspect(s, study, tmp_path)[2] for s in (wheel, rail)}
    Path(tread).write_text(Path(tread).read_text() + "# edited\n")
    after = {s.name: engine.inspect(s, study, tmp_path)[2] for s in (wheel, rail)}
    assert after["wheel-mesh"] != before["wheel-mesh"] and after["rail-mesh"] == before["rail-mesh"]
