"""The Green's artefacts hold the structures at one contact, the one ``contact.geometry`` selects;
switching it reruns the Green's stages, the rail fit at the contact (stage ``rail-fit``) and the
cases, and nothing else."""

import h5py
import pytest

from squealcore.artefacts import ArtefactError
from stages import engine
from stages.cases import is_structural
from stages.config import load_study
from stages.greens_layout import GEOMETRY_ATTRIBUTE
from stages.rail import read_rail_greens
from interaction.wheel_models import wheel_model_names
from stages.wheel import read_greens

GREENS = ("wheel-greens", "rail-greens")


def _stale(study, out):
    return {name for name, fresh, _ in engine.status(study, out) if not fresh}


def test_the_artefacts_hold_the_computed_contact_only(quick_structures):
    # the quick study's contact.geometry is the default, "profiles"
    assert load_study(quick=True)["contact"]["geometry"] == "profiles"
    for name in ("wheel_greens.h5", "rail_greens.h5"):
        with h5py.File(quick_structures / name, "r") as f:
            assert f.attrs[GEOMETRY_ATTRIBUTE] == "profiles"
    wheel, rail = quick_structures / "wheel_greens.h5", quick_structures / "rail_greens.h5"
    for model in wheel_model_names():
        held = read_greens(wheel, model)
        asked = read_greens(wheel, model, "profiles")
        assert (held["poles"] == asked["poles"]).all() and (held["residues"] == asked["residues"]).all()
    # the other contact is not there: a clear error that says how to get it, not a KeyError
    with pytest.raises(ArtefactError, match="contact.geometry = 'manual'"):
        read_greens(wheel, "stationary", "manual")
    with pytest.raises(ArtefactError, match="contact.geometry = 'manual'"):
        read_rail_greens(rail, "manual")
    assert (read_rail_greens(rail)["kernel"] == read_rail_greens(rail, "profiles")["kernel"]).all()


def test_switching_the_contact_reruns_the_greens_and_the_cases_only(quick_run):
    manual = load_study(quick=True, assignments=["contact.geometry=manual"])
    stale = _stale(manual, quick_run)
    # the rail fit is the rail's receptance at the contact: it follows the contact too
    assert {"wheel-greens", "rail-greens", "rail-fit", "report"} <= stale
    assert not stale & {"contact-geometry", "wheel-mesh", "wheel-modes", "rail-mesh"}
    # the radiation of a case follows its simulation
    assert all(name.startswith(("simulate:", "radiation:")) for name in stale - {*GREENS, "rail-fit", "report"})


def test_contact_angle_and_duration_rerun_only_the_cases(quick_run):
    for assignment in ("contact.contact_angle=0.1", "time.duration=0.5"):
        stale = _stale(load_study(quick=True, assignments=[assignment]), quick_run)
        assert stale and all(name.startswith(("simulate:", "radiation:")) or name == "report" for name in stale), assignment


def test_the_hand_set_contact_does_not_read_the_contact_geometry(copy_quick_structures, tmp_path):
    out = copy_quick_structures(tmp_path / "out")
    manual = load_study(quick=True, assignments=["contact.geometry=manual"])
    assert engine.run(manual, out, until="wheel-greens", progress=False) == ["wheel-greens"]
    with h5py.File(out / "wheel_greens.h5", "r") as f:
        assert f.attrs[GEOMETRY_ATTRIBUTE] == "manual"
    read_greens(out / "wheel_greens.h5", "eulerian", "manual")
    # new contact-geometry tables: the computed contact's structures would be rebuilt; with the
    # hand-set contact no profile search runs at all (issue 33)
    tables = ["contact.geometry=manual", "geometry.displacement_count=101"]
    assert engine.run(load_study(quick=True, assignments=tables), out, until="wheel-greens",
                      progress=False) == []
    for stage in (*GREENS, "simulate"):
        declared = engine.CASE_STAGE if stage == "simulate" else engine.STAGE_BY_NAME[stage]
        assert "contact-geometry" not in declared.upstream_for(manual)
        assert "contact-geometry" in declared.upstream_for(load_study(quick=True))


def test_a_sweep_over_the_contact_makes_a_variant_per_contact(tmp_path):
    config = tmp_path / "study.toml"
    config.write_text('[sweep]\n"contact.geometry" = ["manual", "profiles"]\n"contact.friction" = [0.3, 0.6]\n')
    cases = engine.plan_cases(load_study(str(config), quick=True), tmp_path / "out")
    assert is_structural("contact.geometry") and not is_structural("contact.friction")
    folders = {case.overrides["contact.geometry"]: case.variant_dir for case in cases}
    assert len(cases) == 4 and len(set(folders.values())) == 2
    assert all(case.variant_dir == folders[case.overrides["contact.geometry"]] for case in cases)
