"""Moving Green's kernel of the rail: static sum, the v -> 0 limit, and its spectrum against
the moving receptance from an independent wavenumber integration at Doppler-shifted
frequencies, G~(Omega) = 1/(2 pi) int H^(kappa, Omega + kappa v) dkappa."""

import numpy as np
import pytest

from mesh.rail_mesh import mesh_rail_section
from mesh.rail_section import RailParams
from squealcore.errors import InputError
from waveguide.greens import foh_factor, moving_kernel
from waveguide.params import TrackParams
from waveguide.response import receptance_along, wavenumber_integral
from waveguide.waves import RailWaveguide

DT = 1.0 / 3000.0  # s: 1/dt = 3 kHz keeps the test small
FMAX = 3000.0


@pytest.fixture(scope="module")
def model():
    mesh = mesh_rail_section(RailParams(element_size=0.02))
    track = TrackParams(max_frequency=FMAX)
    return RailWaveguide(mesh, track, basis_frequency=1.25 * FMAX)


def moving_receptance_kint(wg, omega, v):
    """G~(Omega) by direct integration over real kappa (second method)."""
    length = wg.track.load_patch_length

    def integrand(k):
        return wg.receptance_kappa(k, omega + k * v)

    # kappa v shifts the frequency by at most 1e3 rad/s for |kappa| < 70 rad/m; the waves
    # at Omega lie below ~40 rad/m here: dense panels there, sparse beyond
    return wavenumber_integral(integrand, [0.0], length, 2e4, (), n_per_panel=16,
                               panel_width=0.5)[0].reshape(3, 3)


@pytest.fixture(scope="module")
def kernel(model):
    return moving_kernel(model, 13.89, DT, duration=0.06)


def test_kernel_sum_is_moving_static_compliance(model, kernel):
    g0 = moving_receptance_kint(model, 0.0, 13.89)
    s = kernel["kernel"].sum(axis=0)
    for i in range(3):
        # 2 %: trapezoid rule in frequency and the kernel's truncated tail (< 1e-3 of peak)
        assert s[i, i] == pytest.approx(g0[i, i].real, rel=0.02), i
    np.testing.assert_allclose(kernel["static_compliance"], s)


def test_small_speed_tends_to_stationary_kernel(model):
    nt, t_len = 60, 60 * DT
    slow = moving_kernel(model, 1e-3, DT, duration=t_len)["kernel"]
    # stationary kernel by a plain FFT of the point receptance H(0, f) (receptance_along)
    df = 1 / (2 * t_len)
    f = np.arange(int(round(FMAX / df)) + 1) * df
    h = receptance_along(model, np.r_[1e-9, f[1:]], [0.0])[0]
    w = np.full(len(f), 2 * np.pi * df)
    w[[0, -1]] *= 0.5
    phase = np.exp(1j * np.outer(np.arange(nt) * DT, 2 * np.pi * f))
    # causal kernel from Re H (see waveguide.greens): 2 dt/pi int Re H S cos, half at m = 0
    ref = 2 * DT / np.pi * np.real(phase).__matmul__((w * foh_factor(2 * np.pi * f, DT))[:, None] * h.reshape(-1, 9).real)
    ref[0] *= 0.5
    ref = ref.reshape(nt, 3, 3)
    peak = np.abs(ref).max()
    # v = 1 mm/s moves 0.08 mm over the kernel: only round-off should remain (1e-6 of peak)
    assert np.abs(slow - ref).max() < 1e-6 * peak


@pytest.mark.parametrize("f", [200.0, 800.0])
def test_kernel_spectrum_matches_moving_receptance(model, kernel, f):
    v = 13.89
    om = 2 * np.pi * f
    k = kernel["kernel"]
    m = np.arange(len(k))
    dtft = np.einsum("m,mij->ij", np.exp(-1j * om * m * DT), k)
    g = moving_receptance_kint(model, om, v)
    om_alias = 2 * np.pi / DT - om  # the folded image of -Omega
    g_alias = np.conj(moving_receptance_kint(model, om_alias, v))
    ref = foh_factor(om, DT) * g + foh_factor(om_alias, DT) * g_alias
    for i in (1, 2):
        # real part, 3 %: aliases beyond 1/dt (first-order-hold side lobes < 5 %) are not
        # in the kernel, plus trapezoid and tail truncation. Only the real part: the kernel
        # is the causal response with the same Re H, whereas the hysteretic model's Im H
        # is not the Hilbert transform of its Re H (measured Im differences up to ~20 %
        # of |G~| for the lateral term with the ballast loss factor 1.0)
        assert abs(dtft[i, i].real - ref[i, i].real) < 0.03 * abs(ref[i, i]), i


def test_bad_speed(model):
    with pytest.raises(InputError) as e:
        moving_kernel(model, -1.0, DT)
    assert e.value.field == "operating.speed"
    with pytest.raises(InputError) as e:
        moving_kernel(model, 10.0, 0.0)
    assert e.value.field == "time.time_step"
