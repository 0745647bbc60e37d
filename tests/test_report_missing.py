"""A report built from an incomplete set of cases says which are missing (issue 36, item 6)."""

from __future__ import annotations

import pytest

from stages import cases, engine
from stages.config import load_study


def test_report_and_summary_name_the_cases_without_a_result(tmp_path, monkeypatch):
    # Two cases of the quick structures (0.05 s); the second fails. The report and summary.csv are
    # built from the first, and both name the second as missing (the table alone would look
    # complete: one row, no hint of the planned two).
    study_file = tmp_path / "two.toml"
    study_file.write_text('[time]\nduration = 0.05\n\n[sweep]\n"contact.lateral_creepage" = [-0.003, -0.015]\n'
                          '"simulation.wheel_model" = ["stationary"]\n')
    study = load_study(study_file, quick=True)
    out = tmp_path / "out"
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
