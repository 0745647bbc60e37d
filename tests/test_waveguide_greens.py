"""Green's kernels of the rail: the moving kernel's static sum, the v -> 0 limit, and its
spectrum against the moving receptance from an independent wavenumber integration at
Doppler-shifted frequencies, G~(Omega) = 1/(2 pi) int H^(kappa, Omega + kappa v) dkappa, in
real and imaginary part (Kramers-Kronig: the kernel is built from Re H only); the same checks
for the ordinary (fixed-point) kernels g(x, t) at x = 0 and 0.5 m; the automatic truncation."""

import numpy as np
import pytest

from mesh.rail_mesh import mesh_rail_section
from profiles.rail_section import RailParams
from squealcore.errors import InputError
from waveguide.greens import band_partition, foh_factor, grid_top_frequency, moving_kernel, ordinary_kernel
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


def moving_receptance_kint(wg, omega, v, quality="default"):
    """G~(Omega) by direct integration over real kappa (second method).

    ``quality``: ``"default"``, dense uniform panels up to 50 rad/m; ``"refined"``, panels
    also refined around the lightly damped waves at Omega (their peaks in kappa are narrow;
    for the kHz range); ``"coarse"``, half the points, for the far aliases of the held
    spectrum whose weight sinc^2 is a few per cent at most."""
    length = wg.track.load_patch_length

    def integrand(k):  # all wavenumbers at once (RailWaveguide.receptance_kappa_many)
        return wg.receptance_kappa_many(k, omega + k * v)

    if quality == "coarse":
        return wavenumber_integral(integrand, [0.0], length, 2e4, (), n_per_panel=8,
                                   panel_width=1.0, vectorized=True)[0].reshape(3, 3)
    bps = []
    if quality == "refined":
        # kappa v shifts the frequency by < 1 % here, so the poles sit near the waves at Omega
        bps = [(abs(k.real), max(4 * abs(k.imag), 0.02)) for k in wg.waves(abs(omega)).kappa
               if abs(k.imag) < 0.3 * abs(k.real) + 1]
        return wavenumber_integral(integrand, [0.0], length, 2e4, bps, n_per_panel=6,
                                   panel_width=1.0, vectorized=True)[0].reshape(3, 3)
    # kappa v shifts the frequency by at most 1e3 rad/s for |kappa| < 70 rad/m; the waves
    # at Omega lie below ~40 rad/m here: dense panels there, sparse beyond
    return wavenumber_integral(integrand, [0.0], length, 2e4, (), n_per_panel=16,
                               panel_width=0.5, vectorized=True)[0].reshape(3, 3)


def held_spectrum(receptance, f, dt, j_max=6):
    """The spectrum a ramp-invariant kernel must have (docs/design.md §3), the held and aliased
    receptance ``sum_j S(f_j) R(f_j)``, f_j = f + j / dt, S = sinc^2(pi f_j dt), over
    |j| <= j_max (R(-f) = conj R(f)). ``receptance(omega, near)`` returns R at omega > 0 (rad/s);
    ``near`` is True for j = 0 and -1 (the image folded about 1/(2 dt)), which carry nearly all
    of the weight, so the other aliases may be integrated more coarsely."""
    out = 0
    for j in range(-j_max, j_max + 1):
        fj = f + j / dt
        r = receptance(2 * np.pi * abs(fj), j in (0, -1))
        out = out + foh_factor(2 * np.pi * fj, dt) * (r if fj >= 0 else np.conj(r))
    return out


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
    # stationary kernel by a plain FFT of the point receptance H(0, f) (receptance_along), on
    # one uniform grid up to the kernels' grid top 8/dt (the held spectrum's aliases; for this
    # short kernel every band of moving_kernel uses that grid)
    df = 1 / (2 * t_len)
    f = np.arange(int(round(grid_top_frequency(DT) / df)) + 1) * df
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
    # the library's ordinary kernel at x = 0 (checked on its own in
    # test_ordinary_kernel_sum_and_spectrum) is that limit too
    ordinary = ordinary_kernel(model, [0.0], DT, t_len)["kernel"][0]
    assert np.abs(slow - ordinary).max() < 1e-6 * peak


def _spectrum_errors(model, kernel, f, v=13.89):
    """DTFT of the kernel at f (Hz) and the reference: the held, aliased moving receptance
    (:func:`held_spectrum`) from the independent wavenumber integration. Like with like: the
    kernel's grid runs to 8 / dt, so its spectrum contains the aliases beyond 1/(2 dt) too."""
    om = 2 * np.pi * f
    k = kernel["kernel"]
    m = np.arange(len(k))
    dtft = np.einsum("m,mij->ij", np.exp(-1j * om * m * DT), k)
    ref = held_spectrum(lambda w, near: moving_receptance_kint(model, w, v, "default" if near else "coarse"),
                        f, DT)
    return dtft, ref


@pytest.mark.parametrize("f", [200.0, 800.0])
def test_kernel_spectrum_matches_moving_receptance(model, kernel, f):
    """Kramers-Kronig check: the kernel is built from Re H only; with the causal track
    damping (the default) its spectrum must reproduce the complex moving receptance, i.e.
    also the imaginary part that it never saw."""
    dtft, ref = _spectrum_errors(model, kernel, f)
    for i in (1, 2):
        # real part, 3 %: trapezoid rule, tail truncation and the aliases beyond the grid top
        # 8/dt and beyond |j| = 6 in the reference (measured <= 1.3 %,
        # lateral at 800 Hz)
        assert abs(dtft[i, i].real - ref[i, i].real) < 0.03 * abs(ref[i, i]), i
        # imaginary part, 5 %: the same discretisation errors plus the Hilbert transform of
        # Re H truncated at 8/dt (measured <= 1.5 %). The hysteretic model fails this
        # by 10-34 % (test_hysteretic_kernel_is_not_kramers_kronig)
        assert abs(dtft[i, i].imag - ref[i, i].imag) < 0.05 * abs(ref[i, i]), i


DT_KHZ = 5e-5  # s: Nyquist 10 kHz, so that 2-8 kHz (the squeal band) lies in the spectrum


@pytest.fixture(scope="module")
def model_khz():
    """Waveguide for the kHz check: track.max_frequency 6 kHz < 1/dt = 20 kHz, as in the
    default study (10 kHz, 1/dt = 27.8 kHz); contact 15 mm off the rail's centre line so that
    the yz coupling is not a mesh-asymmetry residue (it is 1e-4 of zz and yy at y = 0)."""
    mesh = mesh_rail_section(RailParams(element_size=0.02))
    track = TrackParams(max_frequency=6000.0, contact_lateral_position=0.015)
    return RailWaveguide(mesh, track, basis_frequency=1.25 * track.max_frequency)


@pytest.fixture(scope="module")
def kernel_khz(model_khz):
    return moving_kernel(model_khz, 13.89, DT_KHZ)  # the default: automatic length and bands


@pytest.mark.parametrize("f", [2500.0, 5000.0, 8000.0])
def test_kernel_spectrum_in_squeal_band(model_khz, kernel_khz, f):
    """In the squeal band the default kernel's spectrum is the held, aliased moving receptance
    of the wavenumber integration, real and imaginary part (the damping that the time
    stepping sees) of zz, yy and yz. Each part within 5 % of itself, the accuracy asked of
    the default study's kernel in the squeal band. Measured: the kernel is within 0.6 % of the
    reference here (aliases |j| <= 6) and within 2.0 % of one with the aliases to |j| = 200
    (those beyond 6 from the wave sum), which the reference here misses by up to 1.9 % (Re yz
    at 8 kHz; zz and yy 0.6 %). The former kernel (grid cut at max_frequency, absolute
    cutoff of the wave series) fails: Im zz by -28 % at 2.5 kHz and -117 % at 5 kHz (the
    Hilbert transform of the truncated Re H), Re yy by -12 % and -25 %, everything by
    ~100 % at 8 kHz (above its grid)."""
    k = kernel_khz["kernel"]
    m = np.arange(len(k))
    dtft = np.einsum("m,mij->ij", np.exp(-2j * np.pi * f * m * DT_KHZ), k)
    ref = held_spectrum(lambda w, near: moving_receptance_kint(
        model_khz, w, 13.89, "refined" if near else "coarse"), f, DT_KHZ)
    for i, j in ((2, 2), (1, 1), (1, 2)):
        d = dtft[i, j] - ref[i, j]
        assert abs(d.real) < 0.05 * abs(ref[i, j].real), (f, i, j, d.real / ref[i, j].real)
        assert abs(d.imag) < 0.05 * abs(ref[i, j].imag), (f, i, j, d.imag / ref[i, j].imag)


@pytest.mark.slow
def test_hysteretic_kernel_is_not_kramers_kronig():
    """The same check with hysteretic damping fails: Re H and Im H of k (1 + i eta sign w)
    are not a Hilbert pair (shows that the check above can fail)."""
    mesh = mesh_rail_section(RailParams(element_size=0.02))
    track = TrackParams(max_frequency=FMAX, damping_model="hysteretic")
    wg = RailWaveguide(mesh, track, basis_frequency=1.25 * FMAX)
    ker = moving_kernel(wg, 13.89, DT, duration=0.06)
    dtft, ref = _spectrum_errors(wg, ker, 200.0)
    err = np.abs(dtft.imag - ref.imag) / np.abs(ref)
    # measured: lateral 10 %, vertical 34 % of |G~| at 200 Hz; the real parts agree (< 1 %)
    assert err[2, 2] > 0.2 and err[1, 1] > 0.05
    assert abs(dtft[2, 2].real - ref[2, 2].real) < 0.03 * abs(ref[2, 2])


def test_two_band_kernel_matches_single_grid(model):
    """The default kernel (two bands: a short high band on a coarse frequency grid plus a
    long low band below 450 Hz) against one fine grid up to 1/dt (a second method)."""
    split = moving_kernel(model, 13.89, DT, duration=0.1)
    single = moving_kernel(model, 13.89, DT, duration=0.1, split_frequency=None)
    assert 0 < split["high_band_duration"] < 0.1
    assert len(split["solve_frequency"]) < 0.6 * len(single["solve_frequency"])  # 346 vs 601
    n = min(len(split["kernel"]), len(single["kernel"]))
    peak = np.abs(single["kernel"]).max()
    # 2e-4 of the peak: the high band is cut where its tail is below kernel_tolerance (1e-3)
    # times its peak, and it has no static part; measured 4e-5
    assert np.abs(split["kernel"][:n] - single["kernel"][:n]).max() < 2e-4 * peak


def test_batched_kappa_solves_and_band_partition(model):
    """The wavenumber integrations above use RailWaveguide.receptance_kappa_many: the same
    solves as receptance_kappa (supported causal, hysteretic and free rail); and the bands of
    the moving kernel are a partition of unity."""
    k = np.linspace(-300.0, 300.0, 41)
    w = 2 * np.pi * 2000.0 + 13.89 * k
    mesh = model.mesh
    for wg in (model,
               RailWaveguide(mesh, TrackParams(max_frequency=FMAX, damping_model="hysteretic"), 1.25 * FMAX),
               RailWaveguide(mesh, TrackParams(max_frequency=FMAX, supported=False), 1.25 * FMAX)):
        one = np.array([wg.receptance_kappa(ki, wi) for ki, wi in zip(k, w)])
        np.testing.assert_allclose(wg.receptance_kappa_many(k, w), one, rtol=0, atol=1e-10 * np.abs(one).max())
    f = np.linspace(0.0, 3e5, 3001)
    bands = band_partition(f, [300.0, 1e4, 2.78e4])
    np.testing.assert_allclose(bands.sum(axis=0), 1.0, atol=1e-14)
    assert np.all(bands >= 0) and bands[0, f > 450].max() == 0 and bands[3, f < 13.9e3].max() == 0


def test_bad_speed(model):
    with pytest.raises(InputError) as e:
        moving_kernel(model, -1.0, DT)
    assert e.value.field == "operating.speed"
    with pytest.raises(InputError) as e:
        moving_kernel(model, 10.0, 0.0)
    assert e.value.field == "time.time_step"


def receptance_kint(model, omega, distances, coarse=False):
    """H(x, Omega) (n_x, 3, 3) by direct integration over real kappa (second method); the
    panels are refined around the lightly damped waves (their peaks in kappa are narrow).
    ``coarse``: no refinement and half the points, for the far aliases (see held_spectrum)."""
    def solve(k):
        return model.receptance_kappa_many(k, omega)

    if coarse:
        return wavenumber_integral(solve, distances, model.track.load_patch_length, 2e4, (),
                                   n_per_panel=8, panel_width=1.0, vectorized=True).reshape(-1, 3, 3)
    bps = []
    if omega > 0:
        bps = [(abs(k.real), max(4 * abs(k.imag), 0.02)) for k in model.waves(omega).kappa
               if abs(k.imag) < 0.3 * abs(k.real) + 1]
    return wavenumber_integral(solve, distances, model.track.load_patch_length, 2e4, bps,
                               n_per_panel=16, panel_width=0.5, vectorized=True).reshape(-1, 3, 3)


def test_ordinary_kernel_sum_and_spectrum(model):
    """Ordinary Green's kernels g(x, t) at x = 0 and 0.5 m (issue 3, item 5) against the
    wavenumber integration: their sums are the static receptances H(x, 0), and their spectra
    are the held, aliased receptances (held_spectrum), in real part and (Kramers-Kronig, the
    kernel is built from Re H only) imaginary part."""
    x = np.array([0.0, 0.5])
    res = ordinary_kernel(model, x, DT, 0.06)
    k = res["kernel"]
    assert k.shape == (2, 180, 3, 3)
    np.testing.assert_allclose(res["static_compliance"], k.sum(axis=1))
    static = receptance_kint(model, 0.0, x)
    for ix in range(2):
        for i in range(3):
            # 2 %, as for the moving kernel: trapezoid rule and the truncated tail (last
            # quarter 2-3 % of the peak at 0.06 s, but oscillating); measured <= 0.14 %
            assert res["static_compliance"][ix, i, i] == pytest.approx(static[ix, i, i].real, rel=0.02)
    m = np.arange(k.shape[1])
    for f in (200.0, 800.0):
        om = 2 * np.pi * f
        ref = held_spectrum(lambda w, near: receptance_kint(model, w, x, coarse=not near), f, DT)
        dtft = np.einsum("m,xmij->xij", np.exp(-1j * om * m * DT), k)
        for ix in range(2):
            for i in (0, 1, 2):
                # real part 3 % (as for the moving kernel; measured <= 1.8 %)
                assert abs(dtft[ix, i, i].real - ref[ix, i, i].real) < 0.03 * abs(ref[ix, i, i]), (f, ix, i)
                # imaginary part 5 % (measured <= 1.6 %). The longitudinal component is checked
                # too since the grid runs to 8/dt: its patch compliance is nearly frequency
                # independent, and truncating it at 1/dt = 3 kHz (the former grid) cost 8 % in
                # Im H_xx at 800 Hz, x = 0
                assert abs(dtft[ix, i, i].imag - ref[ix, i, i].imag) < 0.05 * abs(ref[ix, i, i]), (f, ix, i)


def test_automatic_truncation_converges(model):
    """Without a prescribed duration the kernel is doubled until its last quarter is below
    track.kernel_tolerance (1e-3) times the peak; the truncated kernel's sum then matches the
    moving static compliance of the wavenumber integration closer than the fixed 0.06 s
    kernel of test_kernel_sum_is_moving_static_compliance does (0.9 % off, tail 1.7e-2)."""
    auto = moving_kernel(model, 13.89, DT)
    assert auto["tail"] < model.track.kernel_tolerance
    assert len(auto["kernel"]) * DT > 0.06  # it did have to grow
    g0 = moving_receptance_kint(model, 0.0, 13.89)
    s = auto["kernel"].sum(axis=0)
    for i in range(3):
        # 0.5 %: what is left beyond a tail of 1e-3 of the peak plus the trapezoid rule;
        # measured <= 0.23 % (longitudinal)
        assert s[i, i] == pytest.approx(g0[i, i].real, rel=0.005), i


def test_kernel_plot(kernel, tmp_path):
    from waveguide.plots import plot_kernel

    out = tmp_path / "kernel.png"
    plot_kernel(kernel, out)
    assert out.stat().st_size > 10_000
