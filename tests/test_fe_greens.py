"""Modal receptances and ramp-invariant kernels against independent evaluations."""

import numpy as np
import pytest
from scipy.integrate import quad

from fe import greens


def _modes(seed=1, m=6):
    rng = np.random.default_rng(seed)
    f = np.sort(rng.uniform(200.0, 6000.0, m))
    zeta = rng.uniform(1e-4, 5e-2, m)
    phi = rng.normal(size=(m, 3)) * 0.05
    return f, zeta, phi


def test_receptance_equals_modal_sum():
    # Pole-residue form against the textbook modal sum written out directly.
    f, zeta, phi = _modes()
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    freq = np.linspace(10.0, 8000.0, 301)
    w = 2 * np.pi * freq
    wr = 2 * np.pi * f
    direct = np.einsum(
        "fm,mi,mj->fij", 1.0 / (wr[None] ** 2 - w[:, None] ** 2 + 2j * zeta * wr * w[:, None]), phi, phi
    )
    assert np.allclose(greens.receptance(poles, res, freq), direct, rtol=1e-12, atol=0)


def test_static_limit_and_reciprocity():
    f, zeta, phi = _modes(2)
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    h0 = greens.receptance(poles, res, [0.0])[0]
    expected = np.einsum("mi,mj,m->ij", phi, phi, 1.0 / (2 * np.pi * f) ** 2)
    # Static limit of the modal sum: sum phi phi^T / omega^2 (exact identity, round-off only).
    assert np.allclose(h0.real, expected, rtol=1e-12)
    assert np.allclose(greens.static_compliance(poles, res), expected, rtol=1e-12)
    h = greens.receptance(poles, res, np.linspace(1, 7000, 50))
    assert np.allclose(h, np.swapaxes(h, 1, 2), rtol=1e-13)


def test_impulse_response_closed_form():
    f, zeta, phi = _modes(3)
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    t = np.linspace(0, 0.01, 200)
    wr = 2 * np.pi * f
    wd = wr * np.sqrt(1 - zeta**2)
    direct = np.einsum("tm,mi,mj->tij", np.exp(-zeta * wr * t[:, None]) * np.sin(wd * t[:, None]) / wd, phi, phi)
    assert np.allclose(greens.impulse_response(poles, res, t), direct, rtol=1e-10, atol=1e-18)


def test_kernel_against_numerical_hat_integral():
    # k[m] = integral of g(m dt - tau) against the hat function of width 2 dt (docs/design.md §3),
    # evaluated by adaptive quadrature of the closed-form g(t): an independent path.
    f, zeta, phi = _modes(4, m=3)
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    dt = 3.6e-5
    kernel = greens.ramp_invariant_kernel(poles, res, dt, 40)

    def g(t, i, j):
        return greens.impulse_response(poles, res, [t])[0, i, j] if t >= 0 else 0.0

    for m in (0, 1, 7, 39):
        for i, j in ((0, 0), (1, 2), (2, 2)):
            val = quad(lambda tau: g(m * dt - tau, i, j) * (1 - abs(tau) / dt), -dt, dt, points=[0.0],
                       epsabs=1e-22, epsrel=1e-11)[0]
            assert kernel[m, i, j] == pytest.approx(val, rel=1e-7, abs=1e-20)


def test_small_pole_series_matches_exact_formula():
    # |p dt| < 1e-3 switches to series; both branches must agree where they meet.
    dt = 1.0
    p = np.array([-1e-3 + 0.99e-3j, -1.2e-3 + 0.1e-3j])
    z, k0, k1 = greens._first_order_hold_factors(p, dt)
    z2 = np.exp(p * dt)
    assert np.allclose(k0, (z2 - 1 - p * dt) / (p**2 * dt), rtol=1e-9)
    assert np.allclose(k1, (z2 - 1) ** 2 / (p**2 * dt), rtol=1e-9)


def test_kernel_spectrum_matches_held_receptance():
    # The kernel's DTFT must equal the receptance seen through linear interpolation and
    # sampling, sum_k H(w + k ws) sinc^2(...). Tolerance 1e-6: only the alias-sum truncation
    # (terms decay as k^-4) differs.
    f, zeta, phi = _modes(5)
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    dt = 3.6e-5
    n = int(np.ceil(60.0 / (zeta.min() * 2 * np.pi * f.min()) / dt))  # kernel decayed to e^-60
    kernel = greens.ramp_invariant_kernel(poles, res, dt, n)
    freq = np.linspace(50.0, 0.25 / dt, 40)
    ks = greens.kernel_spectrum(kernel, freq, dt)
    held = greens.held_spectrum(poles, res, freq, dt, n_alias=400)
    assert np.allclose(ks, held, rtol=1e-6, atol=1e-6 * np.abs(held).max())
    # And at low frequency, where the hold factor is ~1 and aliases are negligible, the kernel
    # spectrum is the receptance itself within 1 % (sinc^2 deviation < 0.2 % below fs/50).
    low = np.linspace(20.0, 0.02 / dt, 30)
    h = greens.receptance(poles, res, low)
    ksl = greens.kernel_spectrum(kernel, low, dt)
    assert np.all(np.abs(ksl - h) <= 0.01 * np.abs(h) + 1e-3 * np.abs(h).max())


def test_recursion_equals_convolution():
    f, zeta, phi = _modes(6)
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    dt = 3.6e-5
    nt = 3000
    rng = np.random.default_rng(0)
    force = rng.normal(size=(nt, 3)) * 1e3
    kernel = greens.ramp_invariant_kernel(poles, res, dt, nt)
    conv = np.zeros((nt, 3))
    for i in range(3):
        for j in range(3):
            conv[:, i] += np.convolve(kernel[:, i, j], force[:, j])[:nt]
    z, w, k0 = greens.recursion_coefficients(poles, res, dt)
    h = np.zeros((len(z), 3), dtype=complex)
    rec = np.zeros((nt, 3))
    for n in range(nt):
        if n:
            h = z[:, None] * (h + force[n - 1][None, :])
        rec[n] = k0 @ force[n] + 2 * np.real(np.einsum("mij,mj->i", w, h))
    assert np.allclose(rec, conv, rtol=0, atol=1e-10 * np.abs(conv).max())


def test_closed_form_dtft_equals_long_kernel_transform():
    f, zeta, phi = _modes(7)
    zeta = np.maximum(zeta, 1e-2)  # short decay so that a finite kernel converges
    poles, res = greens.modal_poles_residues(f, zeta, phi)
    dt = 3.6e-5
    n = int(np.ceil(40.0 / (zeta.min() * 2 * np.pi * f.min()) / dt))
    freq = np.linspace(10.0, 0.45 / dt, 25)
    long = greens.kernel_spectrum(greens.ramp_invariant_kernel(poles, res, dt, n), freq, dt)
    closed = greens.kernel_dtft(poles, res, dt, freq)
    # Truncation at e^-40 of the slowest mode: agreement to ~1e-12 of the peak.
    assert np.allclose(closed, long, rtol=1e-9, atol=1e-12 * np.abs(closed).max())
