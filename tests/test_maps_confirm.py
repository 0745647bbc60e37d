"""Time-domain confirmation of a squeal map (``pipeline.py map --confirm``).

References: the points are checked against the selection rule recomputed here from ``maps.h5``;
each confirmation row against the same case run independently through the normal pipeline
(``stages.engine.run`` with the point's values as ``--set`` overrides, its own output folder);
the envelope growth rate against a synthetic tone of known growth rate and frequency.
"""

import re
import shutil

import numpy as np
import pytest

from squealcore.errors import InputError
from squealcore.study import set_path
from stages import engine
from stages.cases import make_case_id
from stages.config import load_study
from stages.maps import read_maps, run_map
from stages.maps_confirm import (
    case_verdict,
    check_options,
    envelope_growth,
    read_csv,
    run_confirmation,
)

TINY_GRID = """
[map]
rail_frequencies = 80
rail_pole_pairs = 14
rail_iterations = 10

[map.grid]
"wheel.rolling_radius" = [0.39]
"operating.speed" = [5.0, 13.9]
"contact.friction" = [0.6]
"contact.lateral_creepage" = [-0.01]
"""
SEED = 3
DURATION = 0.3  # s: the quick study's 5 kHz instability grows at about 20 1/s


@pytest.fixture(scope="module")
def confirmed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("confirm")
    config = folder / "grid.toml"
    config.write_text(TINY_GRID)
    study = load_study(config, True, [])
    out = folder / "map"
    run_map(study, out, progress=False)
    rows = run_confirmation(study, out, read_maps(out / "maps.h5"), 2, ("point",), SEED, DURATION, progress=False)
    return study, folder, out, rows


def test_points_are_the_borderline_then_the_random_one(confirmed):
    """--confirm 2: the stationary wheel's growing point with the smallest growth rate (the
    first borderline group), then one drawn by default_rng(seed) from the other points."""
    _, _, out, rows = confirmed
    data = read_maps(out / "maps.h5")
    margin = data["stationary/margin"]
    growing = np.flatnonzero(margin > 0)
    assert growing.size, "the tiny map must have a growing stationary point"
    border = (int(growing[np.argmin(margin[growing])]), "stationary")
    rest = [(i, m) for i in range(margin.size) for m in data["models"] if (i, m) != border]
    drawn = rest[int(np.random.default_rng(SEED).choice(len(rest), size=1, replace=False)[0])]
    assert [(r["index"], r["wheel_model"], r["choice"]) for r in rows] == [(*border, "borderline"),
                                                                            (*drawn, "random")]
    assert all(r["contact_model"] == "point" for r in rows)
    assert [(int(r["index"]), r["wheel_model"]) for r in read_csv(out / "confirm.csv")] == [border, drawn]
    for r in rows:
        assert (out / "confirm" / "cases" / f"{r['case_id']}.h5").stat().st_size > 0


def test_rows_equal_the_case_run_by_the_pipeline(confirmed):
    """Each csv row: the verdict of the same case run by ``engine.run`` with the point's values
    (grid values, wheel and contact model, duration) set, exactly; the
    structures are copied from the confirmation's variant (deterministic builds) to keep the
    test short, the case runs anew."""
    study, folder, out, rows = confirmed
    csv_rows = read_csv(out / "confirm.csv")
    for k, (row, written) in enumerate(zip(rows, csv_rows)):
        grid = {key: float(written[key]) for key in read_maps(out / "maps.h5")["keys"]}
        overrides = {**grid, "simulation.wheel_model": row["wheel_model"], "contact.model": row["contact_model"]}
        single = set_path(study, ["sweep"], {key: [value] for key, value in overrides.items()})
        single = set_path(single, ["time", "duration"], DURATION)
        again = folder / f"again{k}"
        variants = [p for p in (out / "confirm" / "variants").iterdir()
                    if f"speed={grid['operating.speed']:g}" in p.name]
        assert len(variants) == 1
        shutil.copytree(variants[0], again)
        rebuilt = engine.run(single, again, until="simulate", progress=False)
        case_id = make_case_id(overrides)
        assert case_id == row["case_id"] and rebuilt == [f"simulate:{case_id}"]
        td = case_verdict(again / "cases" / f"{case_id}.h5", float(written["screen_frequency"]))
        assert written["td_squeal"] == str(td["squeal"]) and written["td_squeal_flag"] == str(td["flag"])
        assert float(written["td_frequency"]) == td["frequency"]
        assert float(written["td_growth_rate"]) == td["growth_rate"]
        assert float(written["td_screen_tone_growth_rate"]) == td["screen_tone_growth_rate"]
        screen_squeal = float(written["screen_margin"]) > 0
        assert written["screen_squeal"] == str(screen_squeal)
        both = screen_squeal and td["squeal"]
        agree = screen_squeal == td["squeal"] and (
            not both or abs(td["frequency"] / float(written["screen_frequency"]) - 1) <= 0.02)
        assert written["agree"] == str(agree)


def test_report_rate_equals_the_csv(confirmed):
    _, _, out, _ = confirmed
    written = read_csv(out / "confirm.csv")
    agree = sum(r["agree"] == "True" for r in written)
    text = (out / "maps.md").read_text()
    assert text.count("## Time-domain confirmation") == 1 and text.index("# Squeal maps") == 0
    assert f"| point | all | {agree} of {len(written)} ({100 * agree / len(written):.0f} %) |" in text
    for r in written:
        if r["agree"] == "False":
            assert f"configuration {r['index']} " in text
    # a rerun reuses the cases (not rewritten) and replaces the section
    study, _, _, rows = confirmed
    cases = sorted((out / "confirm" / "cases").glob("*.h5"))
    stamps = [p.stat().st_mtime_ns for p in cases]
    again = run_confirmation(study, out, read_maps(out / "maps.h5"), 2, ("point",), SEED, DURATION, progress=False)
    assert [p.stat().st_mtime_ns for p in cases] == stamps
    assert [(a["case_id"], a["agree"]) for a in again] == [(b["case_id"], b["agree"]) for b in rows]
    assert (out / "maps.md").read_text().count("## Time-domain confirmation") == 1


def test_envelope_growth_of_a_known_tone():
    """A 2 kHz tone growing at 15 1/s on a step (the creep force switched on) and a decaying
    800 Hz tone: the growth rate within 1 % and the frequency within 0.1 %; the decaying tone
    alone gives its decay rate."""
    dt = 3.6e-5
    t = np.arange(int(0.4 / dt)) * dt
    growing = 1.0 * np.exp(15.0 * t) * np.sin(2 * np.pi * 2000.0 * t)
    decaying = 50.0 * np.exp(-8.0 * t) * np.sin(2 * np.pi * 800.0 * t + 0.3)
    force = 3e4 * (1 - np.exp(-t / 0.002)) + growing + decaying
    rate, frequency = envelope_growth(force, dt)
    assert rate == pytest.approx(15.0, rel=0.01)
    assert frequency == pytest.approx(2000.0, rel=1e-3)
    rate, frequency = envelope_growth(3e4 + decaying, dt)
    assert rate == pytest.approx(-8.0, rel=0.01) and frequency == pytest.approx(800.0, rel=1e-3)
    # the band at a given frequency: the decaying tone under the growing one
    rate, frequency = envelope_growth(force, dt, frequency=800.0)
    assert rate == pytest.approx(-8.0, rel=0.01) and frequency == 800.0


def test_bad_options():
    with pytest.raises(InputError) as e:
        check_options(2, ("point", "rigid"), 1.0)
    assert e.value.field == "--confirm-models"
    with pytest.raises(InputError) as e:
        check_options(0, ("point",), 1.0)
    assert e.value.field == "--confirm"
    with pytest.raises(InputError) as e:
        check_options(2, ("point",), -1.0)
    assert e.value.field == "--confirm-duration"


def test_cli_refuses_bad_models_before_the_map(tmp_path, capsys):
    from pipeline import main

    assert main(["map", "--quick", "--out", str(tmp_path), "--confirm", "2", "--confirm-models", "rigid"]) == 2
    assert re.search(r"--confirm-models", capsys.readouterr().err)
    assert not (tmp_path / "maps.h5").exists()
