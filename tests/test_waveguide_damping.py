"""Track damping models (waveguide.damping): loss factors against their targets, the
Kramers-Kronig dispersion of a constant loss factor against its closed form, and input
validation. The kernel-level Kramers-Kronig check is in test_waveguide_greens.py."""

import numpy as np
import pytest

from squealcore.errors import InputError
from waveguide.damping import TrackDamping, hysteretic_factor, viscous_factor, zener_fit
from waveguide.params import TrackParams

BAND = (20.0, 20000.0, 200.0)  # Hz: the default low, high and reference frequencies


@pytest.mark.parametrize("eta,tol", [(0.01, 0.01), (0.25, 0.01), (1.0, 0.03)])
def test_zener_loss_factor_is_constant_over_the_band(eta, tol):
    series = zener_fit(eta, *BAND)
    w = 2 * np.pi * np.geomspace(BAND[0], BAND[1], 400)
    err = np.abs(series.loss_factor(w) / eta - 1)
    # 1 % (3 % for eta = 1) of eta everywhere in the band: 3 relaxation terms per decade;
    # measured max 0.22 %, 0.49 %, 1.6 %
    assert err.max() < tol
    assert series(2 * np.pi * BAND[2]).real == pytest.approx(1.0, rel=1e-12)  # nominal at f_ref
    assert np.all(series.weights >= 0) and series.e0 > 0  # passive springs and dashpots


@pytest.mark.parametrize("eta", [0.01, 0.25, 1.0])
def test_zener_storage_follows_constant_q_dispersion(eta):
    """Kramers-Kronig: a loss factor constant over all frequencies forces the modulus
    (i w)^(2 gamma), gamma = arctan(eta) / pi (Kjartansson 1979), so the storage modulus
    rises as (f2 / f1)^(2 gamma). The band-limited series follows it well inside the band."""
    series = zener_fit(eta, *BAND)
    gamma = np.arctan(eta) / np.pi
    f1, f2 = 100.0, 4000.0  # well inside the band (the series' edges are at 20 Hz and 20 kHz)
    ratio = series(2 * np.pi * f2).real / series(2 * np.pi * f1).real
    # 0.5 %: band-edge effects of the finite relaxation spectrum; measured <= 0.05 %
    assert ratio == pytest.approx((f2 / f1) ** (2 * gamma), rel=0.005)


def test_zener_is_real_and_passive():
    series = zener_fit(0.25, *BAND)
    w = 2 * np.pi * np.geomspace(0.1, 1e6, 200)
    # real impulse response: e(-w) = conj e(w); static limit real; loss factor > 0
    np.testing.assert_allclose(series(-w), np.conj(series(w)), rtol=1e-14)
    assert series(0.0).imag == 0.0 and series(0.0).real == pytest.approx(series.e0)
    assert np.all(series(w).imag > 0)
    # beyond the band the loss factor falls off (a finite relaxation spectrum)
    assert series.loss_factor(2 * np.pi * 0.2) < 0.25 * 0.25  # 0.015 measured


def test_viscous_and_hysteretic_factors():
    w = 2 * np.pi * np.array([-100.0, 0.0, 50.0, 200.0, 800.0])
    v = viscous_factor(1.0, w, 200.0)
    np.testing.assert_allclose(v.real, 1.0)  # storage stiffness nominal at every frequency
    np.testing.assert_allclose(v.imag, w / (2 * np.pi * 200.0))  # eta at f_ref, linear in f
    h = hysteretic_factor(0.25, w)
    np.testing.assert_allclose(h, [1 - 0.25j, 1 + 0.25j, 1 + 0.25j, 1 + 0.25j, 1 + 0.25j])


def test_track_damping_layers():
    t = TrackParams()
    d = TrackDamping(t)
    assert t.damping_model == "causal" and d.causal
    w = 2 * np.pi * t.damping_reference_frequency
    # at the reference frequency every layer has its nominal stiffness and loss factor
    for layer, eta in (("rail", t.loss_factor), ("pad", t.pad_loss_factor),
                       ("ballast", t.ballast_loss_factor)):
        e = complex(d.factor(layer, w))
        assert e.real == pytest.approx(1.0, rel=1e-9), layer
        assert e.imag == pytest.approx(eta, rel=0.02), layer  # Zener fit: 0.02 % measured
    assert complex(d.factor("ballast", 0.0)) == 1.0  # viscous ballast: static stiffness nominal
    assert not TrackDamping(TrackParams(damping_model="hysteretic")).causal
    z = TrackDamping(TrackParams(damping_model="zener"))
    assert z.kinds["ballast"] == "zener"


def test_damping_params_validation():
    with pytest.raises(InputError) as e:
        TrackParams.from_mapping({"damping_model": "viscoelastic"})
    assert e.value.field == "track.damping_model"
    with pytest.raises(InputError) as e:
        TrackParams.from_mapping({"damping_low_frequency": 500.0, "damping_high_frequency": 400.0})
    assert e.value.field == "track.damping_low_frequency"
    with pytest.raises(InputError) as e:
        TrackParams.from_mapping({"damping_reference_frequency": -1.0})
    assert e.value.field == "track.damping_reference_frequency"
    t = TrackParams.from_mapping({"damping_model": "hysteretic", "damping_reference_frequency": 300})
    assert t.damping_model == "hysteretic" and t.damping_reference_frequency == 300.0
