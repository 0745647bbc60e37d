"""The boundary-element reference (radiation/bem.py, bempp-cl) against closed forms (spheres, the
baffled piston), and the fast wheel model against it.

Slow (minutes: the first use compiles bempp-cl's numba kernels, and each frequency assembles four
dense operators): run with ``pytest -m slow tests/test_radiation_bem.py``.
"""

import pytest

import pipeline
from radiation import bem
from radiation.bem_compare import compare_axial_modes
from radiation.bem_wheel_solves import solves
from radiation.thin_disc import baffled_piston_efficiency
from stages.wheel import read_mesh, read_modes

pytestmark = [pytest.mark.slow, pytest.mark.skipif(not bem.available(), reason="bempp-cl not installed")]


@pytest.mark.parametrize("order", [0, 1])
@pytest.mark.parametrize("ka", [0.5, 1.0, 3.0])
def test_sphere_radiation_efficiency_matches_the_closed_form(order, ka):
    """Pulsating (order 0) and oscillating (order 1) sphere: σ within 2 % of σ_l = 1/((ka)²|h_l'(ka)|²).
    2048 flat triangles (about 20 per wavelength at ka = 3; with 512 the inscribed polyhedron's
    smaller radius costs the dipole 3.5 % at ka = 0.5, σ ∝ (ka)⁴); ka = 3 is within 5 % of the
    first interior resonance (π), which the Burton-Miller form removes."""
    sigma = bem.sphere_efficiency_bem(order, ka, refine=4)
    assert sigma == pytest.approx(bem.sphere_efficiency_exact(order, ka), rel=0.02)


#: The thin disc (t/a = 0.05, about 2940 triangles) against the baffled piston: its first-order
#: thickness error, measured -0.7 … -2.5 % (ka = 0.5 … 3; at t/a = 0.1 twice that, -1.5 … -4.3 %),
#: plus the discretisation error (below 0.7 %: the extrapolated values).
THIN_DISC_TOLERANCE = 0.03
#: The linear extrapolation to zero thickness, 2σ(t) - σ(2t): measured -0.16 … -0.61 % (ka = 0.5 … 3;
#: -0.69 % at ka = 5); a third thickness (t/a = 0.2) puts the second-order term at ≤ 0.3 % of it.
EXTRAPOLATED_TOLERANCE = 0.01


@pytest.mark.parametrize("ka", [0.5, 1.0, 2.0, 3.0])
def test_thin_disc_radiates_like_a_baffled_piston(ka):
    """Two faces of a thin closed disc moving outwards, its rim at rest: by symmetry each half-space
    sees a baffled piston, σ = 1 - J₁(2ka)/(ka) (Rayleigh), as t → 0. The disc at t/a = 0.05 within
    THIN_DISC_TOLERANCE, the extrapolation from t/a = 0.05 and 0.1 within EXTRAPOLATED_TOLERANCE;
    the thinner disc always radiates less than the piston (its faces stand t/2 off the baffle
    plane, with the rim as a step), so the extrapolation moves towards the closed form."""
    exact = baffled_piston_efficiency(ka)
    result = bem.baffled_piston_efficiency_extrapolated(ka)
    assert result["thin"]["info"] == 0 and result["thick"]["info"] == 0  # GMRES converged
    assert result["thick"]["sigma"] < result["thin"]["sigma"] < exact
    assert result["thin"]["sigma"] == pytest.approx(exact, rel=THIN_DISC_TOLERANCE)
    assert result["sigma"] == pytest.approx(exact, rel=EXTRAPOLATED_TOLERANCE)


@pytest.fixture(scope="module")
def quick_wheel(tmp_path_factory):
    """The quick study's wheel mesh and modes (the default geometry; 3264 surface triangles)."""
    out = tmp_path_factory.mktemp("bem_wheel")
    assert pipeline.main(["run", "--quick", "--quiet", "--until", "wheel-modes", "--out", str(out)]) == 0
    return out


#: Fast model vs BEM for the wheel's n = 0…3 axial modes, dB: the one-parameter law
#: 1/(1 + (κ/ka)^p) (p = 4 for n = 0, 2n + 2 for n = 1…3) fitted (minimax in dB) to the BEM at the
#: modes' own frequency and half of it leaves ±1.34 (n = 0), ±1.03 (n = 1), ±1.24 (n = 2) and
#: ±1.84 dB (n = 3) on this mesh; at least 0.15 dB of room for the rounding of κ to three digits
#: and for the mesh or the modes changing a little (the issue's target: 3 dB).
TOLERANCE_DB = {0: 1.5, 1: 1.5, 2: 1.5, 3: 2.0}
#: The BEM again against the solves the fit was made on (radiation/bem_wheel_solves.py): the same
#: mesh and modes give the same σ to the GMRES tolerance; 5 % (0.2 dB) for the mesh or the modes
#: changing a little.
STORED_TOLERANCE = 0.05


@pytest.mark.parametrize("factor", [1.0, 0.5])
@pytest.mark.parametrize("n", [0, 1, 2, 3])
def test_fast_model_matches_the_bem_for_the_wheels_n_0_to_3_axial_modes(quick_wheel, n, factor):
    """The wheel's n = 0 (umbrella), 1, 2 and 3 axial modes with no nodal circle, driven at their own
    frequency (204.5, 137.9, 396.4 and 1115 Hz on this mesh, ka = 1.57, 1.06, 3.03, 8.53) and at half
    of it: the BEM gives the stored σ (σ_BEM 0.333 / 0.0151 for n = 0, 0.00172 / 0.000154 for
    n = 1, 0.0557 / 0.000812 for n = 2, 0.354 / 0.0664 for n = 3) and the fast model is within
    TOLERANCE_DB[n] of it. The fast model's n = 0…3 corners were fitted to these eight solves
    (radiation/efficiency.py), so this holds the fit and its stated residual; the rim-corner
    model it replaced was +3.9 / +12.3 dB (n = 0), +10.6 / +3.2 dB (n = 1), +9.0 / +7.0 dB (n = 2)
    and +3.7 / +8.8 dB (n = 3) off."""
    mesh = read_mesh(quick_wheel / "wheel_mesh.h5")
    modes = read_modes(quick_wheel / "wheel_modes.h5", with_shapes=True)
    [row] = compare_axial_modes(mesh, modes, harmonics=(n,), frequency_factor=factor)
    [stored] = [r for r in solves(n) if r["factor"] == factor]
    assert row["frequency"] == pytest.approx(stored["frequency"], rel=1e-3)
    assert row["sigma_bem"] == pytest.approx(stored["sigma_bem"], rel=STORED_TOLERANCE), row
    assert abs(row["difference_db"]) <= TOLERANCE_DB[n], row
