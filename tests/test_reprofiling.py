"""A sweep over the wheel's rolling radius (reprofiling): summary.csv, modes.csv, report.md and the
figures name the variant and the swept value of every case, checked against the case and wheel
artefacts they come from."""

import csv
import json
import struct

import h5py
import numpy as np
import pytest

import pipeline
from interaction.plots import plot_force_level, plot_variant_comparison
from stages import engine
from stages.config import load_study
from stages.summary import (SUMMARY_COLUMNS, SummaryColumn, case_attribute, key_unit, read_case_summary,
                            summary_columns, write_summary)
from stages.wheel import read_modes

RADII = (0.39, 0.37)
CREEPAGES = (-0.003, -0.01)
#: The quick preset (coarse axisymmetric wheel, point contact), two radii, one friction, two
#: creepages, the stationary wheel only, 0.1 s per case.
STUDY = f"""
[time]
duration = 0.1

[sweep]
"wheel.rolling_radius" = {list(RADII)}
"contact.friction" = [0.6]
"contact.lateral_creepage" = {list(CREEPAGES)}
"simulation.wheel_model" = ["stationary"]
"""
SWEPT = ["contact.friction", "contact.lateral_creepage", "simulation.wheel_model", "wheel.rolling_radius"]


@pytest.fixture(scope="module")
def built(copy_quick_structures, tmp_path_factory):
    root = tmp_path_factory.mktemp("reprofiling")
    config = root / "study.toml"
    config.write_text(STUDY)
    out = root / "out"
    # the variant of the quick study's radius has the quick study's structures (conftest.py)
    for case in engine.plan_cases(load_study(str(config), quick=True), out):
        if case.overrides["wheel.rolling_radius"] == load_study(quick=True)["wheel"]["rolling_radius"]:
            copy_quick_structures(case.variant_dir)
    assert pipeline.main(["run", "--quick", "--quiet", "--config", str(config), "--out", str(out)]) == 0
    study = load_study(str(config), quick=True)
    return out, study, engine.plan_cases(study, out)


def _summary_csv(path):
    lines = path.read_text().splitlines()
    comments = [line for line in lines if line.startswith("#")]
    units_line = [line for line in comments if line.startswith("# units: ")]
    assert len(units_line) == 1
    rows = list(csv.DictReader(line for line in lines if not line.startswith("#")))
    header = next(csv.reader([next(line for line in lines if not line.startswith("#"))]))
    units = units_line[0][len("# units: "):].split(",")
    assert len(units) == len(header)
    return rows, dict(zip(header, units)), header


def _case_overrides(out, case_id):
    with h5py.File(out / "cases" / f"{case_id}.h5", "r") as f:
        return json.loads(f.attrs["overrides"])


def test_summary_has_a_column_per_swept_key_with_its_unit(built):
    out, _, cases = built
    rows, units, header = _summary_csv(out / "summary.csv")
    assert header[:2] == ["case_id", "variant"]
    assert header[2:2 + len(SWEPT)] == SWEPT
    assert units["wheel.rolling_radius"] == "m"
    assert units["contact.friction"] == "1" and units["simulation.wheel_model"] == "-"
    assert units["L_F2"] == "dB re 1 N" and units["squeal_frequency"] == "Hz" and units["speed"] == "m/s"
    assert all(unit for unit in units.values())  # every column carries a unit
    assert len(rows) == len(cases) == len(RADII) * len(CREEPAGES)
    variant_of = {case.case_id: case.variant_label for case in cases}
    for row in rows:
        # the swept values as the case artefact records them (the run's overrides)
        recorded = _case_overrides(out, row["case_id"])
        assert float(row["wheel.rolling_radius"]) == recorded["wheel.rolling_radius"]
        assert float(row["contact.lateral_creepage"]) == recorded["contact.lateral_creepage"]
        assert float(row["contact.friction"]) == float(row["friction"]) == 0.6
        assert row["variant"] == variant_of[row["case_id"]]
        assert (out / "variants" / row["variant"] / "wheel_greens.h5").is_file()
    # two cases on each radius, each radius in its own variant
    for radius in RADII:
        mine = [row for row in rows if float(row["wheel.rolling_radius"]) == radius]
        assert sorted(float(row["lateral_creepage"]) for row in mine) == sorted(CREEPAGES)
        assert len({row["variant"] for row in mine}) == 1
    assert len({row["variant"] for row in rows}) == len(RADII)


def _variants(cases):
    """{rolling radius: (variant name, folder)} from the plan."""
    return {case.overrides["wheel.rolling_radius"]: (case.variant_label, case.variant_dir) for case in cases}


def test_modes_csv_names_the_variant_of_every_mode(built):
    out, _, cases = built
    with open(out / "modes.csv", newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert rows[0].keys() >= {"variant", "mode", "frequency_hz", "nodal_diameters", "family"}
    variants = _variants(cases)
    for name, folder in variants.values():
        modes = read_modes(folder / "wheel_modes.h5")
        mine = [row for row in rows if row["variant"] == name]
        assert len(mine) == modes["frequency"].size
        np.testing.assert_allclose([float(r["frequency_hz"]) for r in mine], modes["frequency"], atol=0.05)
    assert {row["variant"] for row in rows} == {name for name, _ in variants.values()}
    # turning the wheel changes its modes: the tables differ
    first, second = (read_modes(folder / "wheel_modes.h5")["frequency"] for _, folder in variants.values())
    assert not np.allclose(first[:10], second[:10])


def _section(report, name):
    start = report.index(f"## Variant `{name}`")
    end = report.find("\n## ", start + 1)
    return report[start:end if end > 0 else len(report)]


def test_report_has_a_section_per_variant_and_a_comparison(built):
    out, _, cases = built
    report = (out / "report.md").read_text()
    assert report.count("## Variant `") == len(RADII)
    assert "## Comparison of the variants" in report
    for radius, (name, folder) in _variants(cases).items():
        section = _section(report, name)
        assert section.splitlines()[0] == f"## Variant `{name}`: wheel.rolling_radius = {radius:g} m"
        own = [c.case_id for c in cases if c.variant_label == name]
        other = [c.case_id for c in cases if c.variant_label != name]
        assert all(f"| {cid} |" in section for cid in own)
        assert not any(cid in section for cid in other)
        assert f"figures/{name}/wheel_section_mesh.png" in section
        mass = read_modes(folder / "wheel_modes.h5")["mass"]
        assert f"mass {mass:.1f} kg" in section
        # the comparison row of this variant: its radius, mass, then for n = 2..7 the mode with the
        # largest lateral contact amplitude, then the one with the largest vertical one
        modes = read_modes(folder / "wheel_modes.h5")
        row = next(line for line in report.splitlines() if line.startswith(f"| `{name}` |"))
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert float(cells[1]) == radius
        assert cells[2] == f"{mass:.1f}"
        for k, n in enumerate(range(2, 8)):
            mine = np.flatnonzero(modes["nodal_diameters"] == n)
            lateral = mine[np.argmax(np.abs(modes["contact_shape"][mine, 1]))]
            vertical = mine[np.argmax(np.abs(modes["contact_shape"][mine, 2]))]
            assert cells[3 + k] == f"{modes['frequency'][lateral]:.0f}"
            assert cells[9 + k] == f"{modes['frequency'][vertical]:.0f}"
    assert "![comparison of the variants](figures/variant_comparison.png)" in report
    for name in ("variant_comparison.png", "fig2_force_level.png"):
        data = (out / "figures" / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n"
        width, height = struct.unpack(">II", data[16:24])
        assert width > 300 and height > 300


def test_figure_2_draws_one_group_per_variant(built, tmp_path):
    out, study, cases = built
    variants = _variants(cases)
    summaries = [read_case_summary(out / "cases" / f"{c.case_id}.h5", study["simulation"], c.variant_label)
                 for c in cases]
    titles = {name: f"r = {radius:g} m" for radius, (name, _) in variants.items()}
    fig = plot_force_level(summaries, tmp_path / "fig2.png", 60, titles)
    panels = [ax for ax in fig.axes if ax.get_title()]
    assert [ax.get_title() for ax in panels] == list(titles.values())
    for ax, name in zip(panels, titles):
        mine = sorted((s for s in summaries if s["variant"] == name), key=lambda s: abs(s["lateral_creepage"]))
        heights = [patch.get_height() for patch in ax.patches]
        np.testing.assert_allclose(heights, [s["L_F2"] for s in mine])  # one bar per case of this variant


def test_comparison_figure_plots_the_given_values(tmp_path):
    x = [0.39, 0.38, 0.37]
    modes = {"axial n = 2": [400.0, 395.0, 390.0]}
    case = {"L_F2": [90.0, 30.0, 88.0], "squeal": [True, False, True], "squeal_frequency": [5046.0, 700.0, 5010.0]}
    fig = plot_variant_comparison(x, "wheel.rolling_radius (m)", modes, {"stationary": case}, tmp_path / "c.png", dpi=40)
    ax_m, ax_f, ax_l = fig.axes
    np.testing.assert_array_equal(ax_m.lines[0].get_ydata(), modes["axial n = 2"])
    frequency = ax_f.lines[0].get_ydata()  # quiet cases have no squeal frequency
    np.testing.assert_array_equal(frequency[[0, 2]], [5046.0, 5010.0])
    assert np.isnan(frequency[1])
    assert ax_l.get_xlabel() == "wheel.rolling_radius (m)"
    assert (tmp_path / "c.png").stat().st_size > 0


def test_adding_a_summary_column_is_one_entry(built, tmp_path):
    out, _, cases = built
    summaries = [read_case_summary(out / "cases" / f"{c.case_id}.h5", None, c.variant_label) for c in cases]
    extra = SummaryColumn("runtime_again", "s", case_attribute("runtime"))
    columns = summary_columns(["wheel.rolling_radius"], SUMMARY_COLUMNS + (extra,))
    write_summary(summaries, tmp_path / "s.csv", columns=columns)
    rows, units, header = _summary_csv(tmp_path / "s.csv")
    assert header[-2:] == [SUMMARY_COLUMNS[-1].name, "runtime_again"] and units["runtime_again"] == "s"
    assert [float(r["runtime_again"]) for r in rows] == pytest.approx([s["runtime"] for s in summaries], rel=1e-5)


def test_units_come_from_the_schema():
    assert key_unit("wheel.rolling_radius") == "m"
    assert key_unit("operating.speed") == "m/s"
    assert key_unit("contact.friction") == "1"
    assert key_unit("wheel.fe.solver") == "-"
    with pytest.raises(KeyError):
        key_unit("wheel.colour")
