"""The contact regime of a case (impact/bouncing or in contact) and the class of its oscillation
(squeal, low-frequency oscillation, none) on constructed force histories: their numbers in closed
form, the case artefact's attributes, summary.csv and the report's verdict."""

import csv

import numpy as np
import pytest

from interaction.metrics import LATERAL_SWING_LIMIT, contact_regime, oscillation_class
from squealcore.artefacts import add_dataset, write_artefact
from stages.cases import CASE_VERSION
from stages.report import case_label, case_table
from stages.summary import read_case_summary, verdict, write_summary

DT = 3.6e-5
Q = 50e3  # static normal force, N
MU = 0.6
F = 5043.0  # Hz


def _time(duration=1.0):
    return np.arange(int(round(duration / DT))) * DT


def bouncing_history(t):
    """A limit cycle with loss of contact: the normal force a train of half-sine impacts at F, each
    lasting 60 % of a period (out of contact the other 40 %), peaking at 2.5 Q; the lateral force
    saturated at mu F_n with the sign of a 15 Hz swing."""
    phase = (F * t) % 1.0
    normal = np.where(phase < 0.6, 2.5 * Q * np.sin(np.pi * phase / 0.6), 0.0)
    lateral = MU * normal * np.sign(np.sin(2 * np.pi * 15 * t) + 1e-9)
    return np.column_stack([np.zeros_like(t), lateral, normal])


def clean_history(t):
    """A squeal limit cycle in contact: F_n = Q (1 + 0.05 sin), F_y = 0.98 mu F_n."""
    normal = Q * (1 + 0.05 * np.sin(2 * np.pi * F * t))
    return np.column_stack([np.zeros_like(t), 0.98 * MU * normal, normal])


def test_bouncing_history_loses_contact():
    t = _time()
    regime = contact_regime(bouncing_history(t), DT, MU, Q, window=0.15)
    assert regime.contact_loss == pytest.approx(0.4, abs=0.01)  # 40 % of every period
    assert regime.peak_normal_force == pytest.approx(2.5 * Q, rel=2e-3)  # the sampled peak of the half-sine
    assert regime.peak_normal_ratio == pytest.approx(2.5, rel=2e-3)
    assert regime.peak_lateral_ratio == pytest.approx(2.5, rel=2e-3)
    assert regime.bouncing and regime.regime == "bouncing"
    assert regime.describe().startswith("impact/bouncing (out of contact 40 % of the window, peak F_n 2.50 Q")


def test_clean_limit_cycle_stays_in_contact():
    t = _time()
    regime = contact_regime(clean_history(t), DT, MU, Q, window=0.15)
    assert regime.contact_loss == 0.0
    assert regime.peak_normal_ratio == pytest.approx(1.05, rel=1e-4)
    assert regime.peak_lateral_ratio == pytest.approx(0.98 * 1.05, rel=1e-4)
    assert not regime.bouncing and regime.regime == "contact" and regime.describe() == "in contact"


def test_lateral_swing_beyond_the_friction_limit_is_bouncing():
    # in contact throughout, but the normal force swings to 1.5 Q and F_y = mu F_n with it:
    # |F_y| reaches 1.5 mu Q > LATERAL_SWING_LIMIT mu Q
    t = _time()
    normal = Q * (1 + 0.5 * np.sin(2 * np.pi * F * t))
    force = np.column_stack([np.zeros_like(t), MU * normal, normal])
    regime = contact_regime(force, DT, MU, Q, window=0.15)
    assert regime.contact_loss == 0.0 and regime.peak_lateral_ratio == pytest.approx(1.5, rel=1e-4)
    assert 1.5 > LATERAL_SWING_LIMIT and regime.bouncing
    # the same swing within the limit is not
    force[:, 1] *= 0.7
    assert not contact_regime(force, DT, MU, Q, window=0.15).bouncing


def test_only_the_window_counts():
    # contact lost before the L_F2 window (a start transient), not in it
    t = _time()
    force = clean_history(t)
    force[t < 0.5, 2] = 0.0
    assert contact_regime(force, DT, MU, Q, window=0.15).contact_loss == 0.0
    assert contact_regime(force, DT, MU, Q, window=0.6).contact_loss == pytest.approx(1 / 6, abs=1e-3)


def _write_case(path, force, t):
    # a case artefact as stages.cases.build_case writes it, with the attributes a summary needs
    with write_artefact(path, "case", CASE_VERSION, "0" * 64, {}) as f:
        f.attrs.update({"case_id": path.stem, "friction": MU, "lateral_creepage": -0.01, "wheel_model": "stationary",
                        "contact_model": "point", "speed": 13.9, "L_F2": 0.0, "squeal": False,
                        "squeal_frequency": 0.0, "buildup_time": 0.0, "growth": 1.0, "runtime": 1.0,
                        "normal_force": Q, "contact_loss": -1.0, "peak_normal_force": -1.0,
                        "peak_normal_ratio": -1.0, "peak_lateral_ratio": -1.0, "regime": "stale", "oscillation": "stale",
                        "overrides": "{}"})
        add_dataset(f, "time", t, "s")
        add_dataset(f, "force", force, "N")


@pytest.mark.parametrize("history, bouncing", [(bouncing_history, True), (clean_history, False)])
def test_summary_and_report_state_the_regime(tmp_path, history, bouncing):
    t = _time()
    path = tmp_path / "cases" / f"{history.__name__}.h5"
    _write_case(path, history(t), t)
    simulation = {"rms_window": 0.15, "squeal_threshold": 40.0}
    summary = read_case_summary(path, simulation)  # the regime recomputed from the stored force
    assert summary["squeal"]  # both are limit cycles far above 40 dB
    assert summary["regime"] == ("bouncing" if bouncing else "contact")
    assert summary["contact_loss"] == pytest.approx(0.4 if bouncing else 0.0, abs=0.01)
    assert summary["peak_normal_force"] == pytest.approx((2.5 if bouncing else 1.05) * Q, rel=2e-3)
    assert read_case_summary(path)["regime"] == "stale"  # without [simulation]: the attributes as written
    write_summary([summary], tmp_path / "summary.csv")
    lines = [line for line in (tmp_path / "summary.csv").read_text().splitlines() if not line.startswith("#")]
    row = next(csv.DictReader(lines))
    assert row["regime"] == summary["regime"]
    assert float(row["contact_loss"]) == pytest.approx(summary["contact_loss"])
    assert float(row["peak_normal_ratio"]) == pytest.approx(summary["peak_normal_ratio"], rel=1e-5)
    assert float(row["peak_lateral_ratio"]) == pytest.approx(summary["peak_lateral_ratio"], rel=1e-5)
    table = "\n".join(case_table([summary]))
    assert case_label(summary) == ("squeal, impact/bouncing" if bouncing else "squeal")  # ~5 kHz: squeal
    assert (f"| {summary['case_id']} |" in table) and (f"| yes | {case_label(summary)} |" in table)
    assert verdict(summary).startswith(f"squeal at {summary['squeal_frequency']:.0f} Hz"
                                       + (", but impact/bouncing" if bouncing else ""))
    assert summary["squeal_frequency"] > 5000.0  # the impacts' frequency: the class is squeal
    assert ("impact/bouncing" in verdict(summary)) == bouncing


def test_oscillation_class():
    assert oscillation_class(True, 5043.0, 1000.0) == "squeal"
    assert oscillation_class(True, 203.0, 1000.0) == "low-frequency oscillation"
    assert oscillation_class(True, 1000.0, 1000.0) == "squeal"  # from the limit on
    assert oscillation_class(True, 203.0, 100.0) == "squeal"  # a lower limit classes it squeal
    assert oscillation_class(False, 5043.0, 1000.0) == "none"  # the criterion not met: no oscillation
    assert oscillation_class(True, float("nan"), 1000.0) == "low-frequency oscillation"


def _tone_history(t, f, amplitude):
    """In contact, a steady tone of ``amplitude`` (N) at ``f`` on a saturated creep force."""
    normal = np.full_like(t, Q)
    return np.column_stack([np.zeros_like(t), 0.9 * MU * Q + amplitude * np.sin(2 * np.pi * f * t), normal])


@pytest.mark.parametrize("f, amplitude, expected", [(5043.0, 300.0, "squeal"), (203.0, 170.0, "low-frequency oscillation"),
                                                    (203.0, 10.0, "none")])
def test_class_in_summary_and_report(tmp_path, f, amplitude, expected):
    # 300 N and 170 N amplitudes: L_F2 = 46.5 and 41.6 dB, above the 40 dB threshold; 10 N: 17 dB
    t = _time()
    path = tmp_path / "cases" / f"tone_{f:g}_{amplitude:g}.h5"
    _write_case(path, _tone_history(t, f, amplitude), t)
    simulation = {"rms_window": 0.15, "squeal_threshold": 40.0, "squeal_min_frequency": 1000.0}
    summary = read_case_summary(path, simulation)
    assert summary["squeal"] == (expected != "none")  # the paper's criterion ignores the frequency
    assert summary["squeal_frequency"] == pytest.approx(f, abs=2.0)
    assert summary["oscillation"] == expected and summary["regime"] == "contact"
    assert read_case_summary(path, {**simulation, "squeal_min_frequency": 100.0})["oscillation"] == (
        "squeal" if expected != "none" else "none")
    write_summary([summary], tmp_path / "summary.csv")
    lines = [line for line in (tmp_path / "summary.csv").read_text().splitlines() if not line.startswith("#")]
    row = next(csv.DictReader(lines))
    assert row["oscillation"] == expected and row["squeal"] == str(expected != "none")
    table = "\n".join(case_table([summary], 1000.0))
    label = "quiet" if expected == "none" else expected
    assert f"| {'yes' if expected != 'none' else 'no'} | {label} |" in table
    counts = {"squeal": "1 squeal, 0", "low-frequency oscillation": "0 squeal, 1", "none": "0 squeal, 0"}[expected]
    assert f"cases meet the squeal criterion: {counts} low-frequency" in table


# --- The report's comparison of the flexible-rail screen with the time domain (stages.report.screen_agreement)

def _result(*poles, margin=-1.0, margin_frequency=400.0):
    return {"poles": [{"frequency": f, "growth_rate": g} for f, g in poles], "margin": margin,
            "margin_frequency": margin_frequency}


def _domain(squeal, frequency=5047.0, growth=1.0):
    return {"squeal": squeal, "squeal_frequency": frequency, "growth": growth}


@pytest.mark.parametrize("result, domain, expected", [
    (_result((5044.0, 20.0)), _domain(True), "agrees"),  # the growing pole is the limit cycle's
    (_result(), _domain(False), "agrees"),  # stable and quiet
    (_result((5044.0, 20.0)), _domain(True, 2011.0), "disagrees: the time domain oscillates at 2011 Hz"),
    (_result((5044.0, 20.0)), _domain(False, growth=1.6), "agrees (still growing"),  # no limit cycle yet
    (_result((5044.0, 20.0)), _domain(False, growth=0.6), "disagrees: a pole grows"),
    (_result((204.0, 0.5)), _domain(False), "undecided: the fastest pole grows by 4.3 dB over the 1 s run"),
    (_result(), _domain(True), "disagrees: stable in the screen"),
])
def test_screen_agreement(result, domain, expected):
    screen, agreement = screen_agreement_of(result, domain)
    assert agreement.startswith(expected)
    if result["poles"]:
        assert screen.startswith(f"{result['poles'][0]['frequency']:.0f} Hz, {result['poles'][0]['growth_rate']:.1f}/s")
    else:
        assert screen == "stable (least damped -1.0/s at 400 Hz)"


def screen_agreement_of(result, domain, duration=1.0):
    from stages.report import screen_agreement

    return screen_agreement(domain, result, duration)
