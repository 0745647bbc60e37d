"""Track and wheelset gauge geometry: where the wheel stands on the rail at zero displacement.

Standard gauge (EN 13848-1, UIC): the **track gauge** is 1435 mm, measured between the gauge
faces of the two rails 14 mm below the top of the rail. The wheelset's **back-to-back distance**
(inside distance between the flange backs, EN 13260 / EN 15313) is nominally 1360 mm; with the
S1002 flange thickness of 32.5 mm (measured 10 mm above the tape circle) the flange-face
distance is 1360 + 2 x 32.5 = 1425 mm, so a centred wheelset has 5 mm of flangeway clearance on
each side before the flange touches.

With the wheelset centred on the track, the flange back of a wheel lies
``(gauge - back_to_back) / 2 = 37.5 mm`` to the gauge side of the rail's gauge point.
"""

from __future__ import annotations

from squealcore.errors import require_range

__all__ = ["TRACK_GAUGE", "BACK_TO_BACK", "flange_back_position"]

#: Nominal track gauge (m), between the gauge faces 14 mm below the top of the rail.
TRACK_GAUGE = 1.435
#: Nominal wheelset back-to-back (flange back to flange back) distance (m).
BACK_TO_BACK = 1.360


def flange_back_position(rail_gauge_point: float, gauge: float = TRACK_GAUGE,
                         back_to_back: float = BACK_TO_BACK) -> float:
    """Lateral position (m, rail frame) of the wheel's flange back for a centred wheelset.

    Parameters
    ----------
    rail_gauge_point : float
        Lateral position of the rail's gauge face at the gauge-measuring depth, rail frame
        (m, negative: on the gauge side of the centre line); see
        :func:`profiles.rail_head.gauge_point`.
    gauge : float
        Track gauge (m), in [1.0, 1.7].
    back_to_back : float
        Wheelset back-to-back distance (m), in [0.9, gauge).

    Returns
    -------
    float
        ``rail_gauge_point - (gauge - back_to_back) / 2`` (m).
    """
    gauge = require_range("geometry.track_gauge", gauge, 1.0, 1.7, unit="m")
    back_to_back = require_range("geometry.back_to_back", back_to_back, 0.9, gauge, high_open=True, unit="m")
    return float(rail_gauge_point) - 0.5 * (gauge - back_to_back)
