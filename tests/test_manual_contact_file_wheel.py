"""The hand-set contact with a user's own wheel section (issue 33, item 4).

With ``contact.geometry = "manual"`` no profile contact search runs (the ``contact-geometry``
stage is not part of the study), so a section file whose outer edge meets no rail head still
gives its receptances; with the computed contact the error names the file that was given.
"""

import h5py
import numpy as np
import pytest

import pipeline
from contact_geometry.study import pair_from_study
from contact_geometry.wheel_surface import outline_wheel_profile, wheel_tape_radius
from mesh.wheel_section import WheelParams
from squealcore.errors import InputError
from stages import engine
from stages.config import load_study
from stages.greens_layout import GEOMETRY_ATTRIBUTE

#: An annulus with a rim, (r, z) in m, closed: hub r 0.08..0.10, web, rim r 0.30..0.36 only
#: 50 mm wide. Its outer edge (z 0..0.05 from the flange back) lies on the field side of the
#: rail's gauge corner, so it meets no rail head with the wheelset centred.
NARROW_RIM = [(0.08, 0.0), (0.10, 0.0), (0.10, 0.01), (0.30, 0.01), (0.30, 0.0), (0.36, 0.0), (0.36, 0.05),
              (0.30, 0.05), (0.30, 0.03), (0.10, 0.03), (0.10, 0.05), (0.08, 0.05), (0.08, 0.0)]
#: Small mesh, the tape circle inside the rim.
SMALL = ["--set", "wheel.section_element_size=0.02", "--set", "wheel.elements_around=12",
         "--set", "wheel.contact_offset=0.03"]


def _write(path, points):
    path.write_text("# r (m)  z (m)\n" + "\n".join(f"{r:.6f} {z:.6f}" for r, z in points) + "\n")
    return path


@pytest.fixture
def section(tmp_path):
    return _write(tmp_path / "my wheel.txt", NARROW_RIM)


def test_hand_set_contact_builds_the_wheel_greens_of_any_section(section, tmp_path, capsys):
    out = tmp_path / "out"
    argv = ["--quick", "--set", f"wheel.profile_file={section}", *SMALL, "--set", 'contact.geometry="manual"',
            "--out", str(out)]
    assert pipeline.main(["run", "--quiet", *argv, "--until", "wheel-greens"]) == 0
    assert "error" not in capsys.readouterr().err
    # no profile search: no contact_geometry.h5, and the Green's functions are at the hand-set contact
    assert not (out / "contact_geometry.h5").exists()
    assert {p.name for p in out.iterdir()} >= {"wheel_mesh.h5", "wheel_modes.h5", "wheel_greens.h5"}
    with h5py.File(out / "wheel_greens.h5", "r") as f:
        assert f.attrs[GEOMETRY_ATTRIBUTE] == "manual"
        assert np.isfinite(f["stationary/receptance"][()]).all()
    # status leaves the unused stage out and finds the wheel fresh
    pipeline.main(["status", *argv])
    rows = {line.split()[0]: line.split()[1] for line in capsys.readouterr().out.splitlines()}
    assert "contact-geometry" not in rows
    assert rows["wheel-greens"] == "fresh"


def test_hand_set_contact_skips_the_contact_geometry_stage(section, tmp_path):
    study = load_study(quick=True, assignments=[f"wheel.profile_file={section}", "wheel.contact_offset=0.03",
                                                 "contact.geometry=manual"])
    stage = engine.STAGE_BY_NAME["contact-geometry"]
    assert not stage.used(study) and stage.used(load_study(quick=True))
    assert engine.run(study, tmp_path / "out", "contact-geometry", progress=False) == []
    assert not (tmp_path / "out" / "contact_geometry.h5").exists()


def test_computed_contact_error_names_the_section_file(section, tmp_path, capsys):
    argv = ["--quick", "--set", f"wheel.profile_file={section}", *SMALL]
    assert pipeline.main(["geometry", *argv]) == 2
    err = capsys.readouterr().err
    assert str(section) in err and "parametric" not in err
    assert "operating.lateral_displacement" in err and 'contact.geometry = "manual"' in err
    out = tmp_path / "out"
    assert pipeline.main(["run", "--quiet", *argv, "--out", str(out), "--until", "wheel-greens"]) == 2
    err = capsys.readouterr().err
    assert str(section) in err and "parametric" not in err
    assert not (out / "contact_geometry.h5").exists()


def test_outer_edge_of_a_section_file_is_its_running_surface(tmp_path):
    # a rim with a 1:20 tread and a flange, between the flange back (z = 0) and the field face
    # (z = 0.13); the hub is wider than the rim (its faces are cut off as cliffs)
    tread = [(0.40 - (z - 0.07) / 20, z) for z in np.linspace(0.13, 0.035, 20)]
    outline = [(0.08, -0.02), (0.12, -0.02), (0.12, 0.06), (0.33, 0.06), (0.33, 0.13), *tread, (0.4085, 0.031),
               (0.425, 0.012), (0.425, 0.004), (0.4075, 0.0), (0.33, 0.0), (0.33, 0.04), (0.12, 0.04),
               (0.12, 0.15), (0.08, 0.15), (0.08, -0.02)]
    path = _write(tmp_path / "flanged.txt", outline)
    params = WheelParams.from_mapping({"profile_file": str(path), "contact_offset": 0.07})
    profile = outline_wheel_profile(params)
    assert wheel_tape_radius(params) == pytest.approx(0.40)
    assert str(path) in profile.name
    y0, y1 = profile.bounds
    assert y0 == 0.0 and y1 == pytest.approx(0.13)  # the rim's corners, not the hub beyond
    on_tread = np.linspace(0.04, 0.125, 30)
    np.testing.assert_allclose(profile.height(on_tread), -(on_tread - 0.07) / 20, atol=2e-6)
    assert profile.height(0.004) == pytest.approx(0.025, abs=1e-9)  # the flange top
    assert profile.height(0.0) > 0.0
    # the pair uses the section's outer radius at contact_offset, not wheel.rolling_radius (0.39)
    study = load_study(quick=True, assignments=[f"wheel.profile_file={path}", "wheel.contact_offset=0.07"])
    assert pair_from_study(study).nominal_radius == pytest.approx(0.40)


def test_outer_edge_without_running_surface_is_refused(tmp_path):
    # a 1 mm tooth at the contact offset, between steep faces: fewer than 4 points of running surface
    outline = [(0.1, 0.0), (0.3, 0.0), (0.3, 0.0290), (0.4, 0.0295), (0.4, 0.0305), (0.3, 0.031), (0.3, 0.06),
               (0.1, 0.06), (0.1, 0.0)]
    path = _write(tmp_path / "tooth.txt", outline)
    params = WheelParams.from_mapping({"profile_file": str(path), "contact_offset": 0.03})
    with pytest.raises(InputError) as err:
        outline_wheel_profile(params, step=1e-3)
    assert err.value.field == "wheel.profile_file" and str(path) in err.value.message
