"""A report built from an incomplete set of cases says which are missing (issue 36, item 6)."""

from __future__ import annotations

import pytest

from stages import cases, engine
from stages.config import load_study


def test_report_and_summary_name_the_cases_without_a_result(tmp_path, monkeypatch, copy_quick_structures):
    # Two cases of the quick structures (0.05 s); the second fails. The report and summary.csv are
    # built from the first, and both name the second as missing (the table alone would look
    # complete: one row, no hint of the planned two).
    study_file = tmp_path / "two.toml"
    study_file.write_text('[time]\nduration = 0.05\n\n[sweep]\n"contact.lateral_creepage" = [-0.003, -0.015]\n'
                          '"simulation.wheel_model" = ["stationary"]\n')
    study = load_study(study_file, quick=True)
    out = copy_quick_structures(tmp_path / "out")  # the quick structures: only the cases are built here
    planned = [c.case_id for c in engine.plan_cases(study, out)]
    failing = next(c for c in planned if "-0.015" in c)
    build = cases.build_case

    def build_or_fail(context, case_id, overrides):
        if case_id == failing:
            raise RuntimeError("injected failure")
        return build(context, case_id, overrides)

    monkeypatch.setattr(cases, "build_case", build_or_fail)
    with pytest.raises(engine.CasesFailed):
        engine.run(study, out, progress=False)
    report = (out / "report.md").read_text()
    assert "**Incomplete:** 1 of the study's 2 cases have no result" in report and failing in report
    summary = (out / "summary.csv").read_text().splitlines()
    assert any(line.startswith("# missing: 1 of the study's 2 cases") and failing in line for line in summary)
    assert sum(1 for line in summary if not line.startswith("#")) == 2  # the header and one row


def test_every_output_gives_a_case_the_same_metrics(tmp_path, copy_quick_structures):
    # One place for a case's metrics (issue 36, item 5): the run writes them as checksummed
    # attributes (the closing lines, the radiation stage's WAV decision and `status` read those);
    # the report and summary.csv recompute them from the stored force with the study's
    # [simulation], which is part of the case's hash. The two must agree on every field.
    from stages.summary import read_case_summary
    study_file = tmp_path / "one.toml"
    study_file.write_text('[time]\nduration = 0.4\n\n[contact]\nfriction = 0.6\n\n[sweep]\n'
                          '"contact.lateral_creepage" = [-0.015]\n"simulation.wheel_model" = ["stationary"]\n')
    study = load_study(study_file, quick=True)
    out = copy_quick_structures(tmp_path / "out")
    engine.run(study, out, progress=False)
    (case,) = (out / "cases").glob("*.h5")
    written, recomputed = read_case_summary(case), read_case_summary(case, study["simulation"])
    for key in ("L_F2", "squeal", "squeal_frequency", "oscillation", "regime", "contact_loss", "peak_normal_force"):
        assert written[key] == recomputed[key], key
    closing = engine.case_results([c for c in engine.plan_cases(study, out)], out)[0]
    assert closing["L_F2"] == written["L_F2"] and closing["squeal"] == written["squeal"]
