"""The fast wheel model against the stored BEM solves of the default wheel's axial modes (no bempp-cl).

radiation/bem_wheel_solves.py holds the boundary-element solves (quick-study mesh, each axial mode
with no nodal circle at its own frequency and at half of it) with the modes' surface integrals;
these tests evaluate the fast model (radiation/efficiency.py) on them. tests/test_radiation_bem.py
(slow) solves them again with the BEM.
"""

import numpy as np
import pytest

from radiation.acoustics import SOUND_SPEED
from radiation.bem_wheel_solves import difference_db, fit_axial_corner, solves
from radiation.efficiency import LOW_ORDER_AXIAL_CORNER_KA, axial_corner, axial_exponent

#: Largest |fast - BEM| (dB) per n: the one-parameter fit's own minimax residual on these solves
#: (n = 0: 1.34, n = 1: 1.03, n = 2: 1.24, n = 3: 1.84 dB; two solves, one corner each) plus at
#: least 0.15 dB of room for the rounding of κ to three digits and for the mesh or the modes
#: changing a little (the slow test solves them again). The issue's target is 3 dB.
TOLERANCE_DB = {0: 1.5, 1: 1.5, 2: 1.5, 3: 2.0}
TARGET_DB = 3.0


@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_fast_model_is_within_its_tolerance_of_the_stored_wheel_bem(n):
    """Each stored solve of the n-th axial mode (own frequency and half of it): the fast model
    within TOLERANCE_DB[n] of σ_BEM (the rim-corner model was +9.0 / +7.0 dB off for n = 2 and
    +3.7 / +8.8 dB for n = 3)."""
    rows = solves(n)
    assert sorted(row["factor"] for row in rows) == [0.5, 1.0]
    for row in rows:
        assert abs(difference_db(row)) <= TOLERANCE_DB[n] < TARGET_DB, row


@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_axial_corners_are_the_minimax_fits_to_the_stored_solves(n):
    """κ_n in the fast model is the corner that minimises the largest |fast - BEM| in dB over the two
    solves with the model's own exponent (to its rounding), and the fitted law with that exponent
    (4 for n = 0, 2n + 2 for n = 1…3) leaves the stated residual; the free disc's exponent 2n + 4
    would leave more for n = 3 (2.1 dB)."""
    kappa, residual = fit_axial_corner(n, float(axial_exponent(n)))
    assert LOW_ORDER_AXIAL_CORNER_KA[n] == pytest.approx(kappa, abs=0.01)
    assert residual <= TOLERANCE_DB[n] - 0.15
    assert axial_exponent(n) == (4.0 if n == 0 else 2.0 * n + 2.0)


def test_the_rim_corners_of_n_4_and_up_are_unchanged():
    """From n = 4 on the axial law keeps k a = n + 1 and the free disc's exponent 2n + 4."""
    n = np.arange(4, 12)
    radius = 0.418
    ka = 2 * np.pi * axial_corner(n, radius) * radius / SOUND_SPEED
    assert np.allclose(ka, n + 1.0)
    assert np.array_equal(axial_exponent(n), 2.0 * n + 4.0)
