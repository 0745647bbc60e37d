"""The report's check of the paper's findings, on summaries with known outcomes."""

import numpy as np

from stages.report import findings


def _case(model, mu, eta, level, squeal, buildup=np.nan):
    return {"wheel_model": model, "friction": mu, "lateral_creepage": eta, "L_F2": level, "squeal": squeal,
            "buildup_time": buildup}


def test_findings_state_each_paper_claim_with_our_numbers():
    summaries = [
        _case("stationary", 0.3, -0.01, 60.0, True, 0.50),
        _case("stationary", 0.3, -0.015, 62.0, True, 0.40),
        _case("stationary", 0.3, -0.003, -30.0, False),
        _case("moving_load", 0.3, -0.01, 61.0, True, 0.80),  # +1 dB, 300 ms later
        _case("moving_load", 0.3, -0.015, -20.0, False),  # suppressed
        _case("moving_load", 0.3, -0.003, -31.0, False),
        _case("eulerian", 0.3, -0.01, 59.5, True, 0.70),
        _case("eulerian", 0.3, -0.015, -21.0, False),
        _case("eulerian", 0.3, -0.003, -30.5, False),
    ]
    text = "\n".join(findings(summaries))
    assert "yes, 2 of 3 stationary-wheel cases squeal" in text
    # moving load: over the two cases where either squeals, +1 dB and -82 dB: not close
    assert "(moving_load vs stationary, paper: almost identical): no, L_F2 differences -82.0 to +1.0 dB" in text
    assert "build-up time minus the stationary one +300 to +300 ms" in text  # moving load
    assert "build-up time minus the stationary one +200 to +200 ms" in text  # eulerian
    assert "in 1 of the 2 cases where the stationary wheel squeals, the eulerian model builds up no squeal" in text
    assert "squeal/no squeal the same in 3 of 3 cases, L_F2 (moving load − Eulerian) -0.5 to +1.5 dB" in text


def test_findings_call_close_levels_close():
    summaries = [_case("stationary", 0.3, -0.01, 60.0, True, 0.5), _case("eulerian", 0.3, -0.01, 58.0, True, 0.6)]
    text = "\n".join(findings(summaries))
    assert "(eulerian vs stationary, paper: almost identical): yes, L_F2 differences -2.0 to -2.0 dB" in text
    assert "no squeal within" not in text
