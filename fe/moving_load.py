r"""Stationary wheel with a rotating load: moving Green's functions, two paths.

Spin convention (as :mod:`fe.rotation`): the wheel rolls in +x, its material moves towards
decreasing θ at Ω = v/r0 > 0, so on the (non-rotating) model wheel the contact point travels
towards **increasing** θ: ``θ_c(t) = θ_0 + Ωt``. The moving Green's function is the response at
the *current* contact point to a unit impulse at the contact point of time 0,

.. math::  \tilde g_{ij}(t) = g_{ij}(\theta_0 + \Omega t, \theta_0, t),

with components in the local contact frame of each point (x = e_θ, y = e_z, z = −e_r), so the
force and displacement directions turn with the contact point. By axial symmetry it does not
depend on θ_0 (θ_0 = 0 below).

Path (b), exact from axisymmetric harmonics
--------------------------------------------
A mode of harmonic n has the local-frame shape ``ψ(θ) = α cos nθ + β sin nθ`` with, from the
section amplitudes (U_r, U_z, U_θ) at the contact node, ``a = (0, U_z, −U_r)``,
``b = (U_θ, 0, 0)``: ``α = a, β = b`` for the "cos" member and ``α = −b, β = a`` for the "sin"
member (docs/conventions.md). Its term of g̃ is ``ψ(Ωt) α^T h(t)`` with
``h(t) = 2 Re(R e^{pt})``, ``R = 1/(2iω_d)``; writing cos and sin with ``e^{±inΩt}`` gives two
poles ``p ± inΩ`` with residues ``R (α ∓ iβ) α^T / 2`` (n = 0: the pole is unchanged).
Summed over a pair, ``g̃ = [S cos nΩt − Q sin nΩt] h(t)`` with ``S = aa^T + bb^T`` (the
stationary pair residue ×2iω_d) and ``Q = ab^T − ba^T``. For y–y (``Q_yy = 0``) each split
peak carries half the stationary residue, i.e. half the peak height when the split is large
compared with the bandwidth.

For purely axial modes (U_r = U_θ = 0) the rotating wheel's Coriolis and centrifugal inertial
forces vanish (u̇ ∥ Ω), so this model coincides with the Eulerian model of :mod:`fe.rotation`
with the gyroscopic and convective terms on, K_σ off and material-frame damping
(``damping="material"``): same poles ``p ± inΩ`` and residues, to round-off.

Path (a), interpolated 3D modes (as in the paper)
-------------------------------------------------
From hex20 modes, the local-frame shapes at the tread ring through the contact node (all nodes
with the contact node's (r, z)) are interpolated in angle with the element's own quadratic
interpolation along each circumferential edge (corner, mid-edge, corner; the edge parameter is
linear in θ). The interpolated shape ``ψ̃_r(θ)`` is periodic, so
``g̃(t) = Σ_r ψ̃_r(Ωt) φ_r(0)^T h_r(t)`` is evaluated directly in time; the ramp-invariant
kernel is its numerical quadrature against the hat function (Gauss–Legendre per time step).
The receptance follows from the Fourier series ``ψ̃_r(θ) = Σ_q c_{rq} e^{iqθ}`` (FFT of the
finely sampled interpolant, truncated at |q| ≤ q_max): poles ``p_r + iqΩ`` with residues
``R_r c_{rq} φ_r(0)^T`` — the exact Fourier transform of the truncated series. The harmonics
that the interpolation adds (q ≠ n) are the spurious peaks the paper reports; they vanish as
the ring is refined.
"""

from __future__ import annotations

import logging

import numpy as np

from fe.classify import cylindrical_components
from squealcore.errors import InputError, require_range

logger = logging.getLogger(__name__)


def _modal_pole(frequency_hz, damping_ratio):
    omega = 2.0 * np.pi * np.asarray(frequency_hz, dtype=float)
    zeta = np.broadcast_to(np.asarray(damping_ratio, dtype=float), omega.shape)
    if np.any(omega <= 0) or np.any((zeta < 0) | (zeta >= 1)):
        raise InputError("wheel.modes", "modes need f > 0 Hz and damping ratios in [0, 1)")
    omega_d = omega * np.sqrt(1.0 - zeta**2)
    return -zeta * omega + 1j * omega_d, 1.0 / (2j * omega_d)


# --------------------------------------------------------------------------- path (b)


def local_shape_coefficients(contact_amplitude, family):
    """Coefficients α, β of the local contact-frame shape ``ψ(θ) = α cos nθ + β sin nθ``.

    Parameters
    ----------
    contact_amplitude : (m, 3) array_like
        Section amplitudes (U_r, U_z, U_θ) at the contact node, m/√kg.
    family : (m,) sequence of {"cos", "sin"}

    Returns
    -------
    alpha, beta : (m, 3) ndarray
        Contact-frame (x, y, z) coefficients, m/√kg; ``alpha`` is the shape at θ = 0.
    """
    u = np.asarray(contact_amplitude, dtype=float)
    a = np.column_stack([np.zeros(len(u)), u[:, 1], -u[:, 0]])
    b = np.column_stack([u[:, 2], np.zeros(len(u)), np.zeros(len(u))])
    is_cos = (np.asarray(family, dtype=str) == "cos")[:, None]
    return np.where(is_cos, a, -b), np.where(is_cos, b, a)


def moving_poles_residues_axisymmetric(frequency_hz, damping_ratio, harmonic, family, contact_amplitude, spin):
    """Exact moving-load poles and residues from axisymmetric modes (path b).

    Parameters
    ----------
    frequency_hz : (m,) array_like
        Natural frequencies, Hz (> 0).
    damping_ratio : float or (m,) array_like
    harmonic : (m,) int array_like
        Nodal diameters n.
    family : (m,) sequence of {"cos", "sin"}
        ``WheelModes.orientation``.
    contact_amplitude : (m, 3) array_like
        Section amplitudes (U_r, U_z, U_θ) at the contact node (``WheelModes.shapes[:, node]``).
    spin : float
        Ω, rad/s.

    Returns
    -------
    poles : (p,) complex ndarray
        rad/s; ``p_r ± i n_r Ω`` (one pole for n = 0).
    residues : (p, 3, 3) complex ndarray
        m/(N s), contact frame, in the :mod:`fe.greens` form.
    """
    spin = require_range("rotation.spin", spin, unit="rad/s")
    pole, r = _modal_pole(frequency_hz, damping_ratio)
    n = np.asarray(harmonic, dtype=int)
    alpha, beta = local_shape_coefficients(contact_amplitude, family)
    plus = r[:, None, None] * np.einsum("mi,mj->mij", alpha - 1j * beta, alpha) / 2
    minus = r[:, None, None] * np.einsum("mi,mj->mij", alpha + 1j * beta, alpha) / 2
    zero = n == 0
    poles = np.concatenate([pole[~zero] + 1j * n[~zero] * spin, pole[~zero] - 1j * n[~zero] * spin, pole[zero]])
    residues = np.concatenate([plus[~zero], minus[~zero],
                               r[zero, None, None] * np.einsum("mi,mj->mij", alpha[zero], alpha[zero])])
    return poles, residues


def moving_poles_residues_from_modes(modes, contact_node, damping_ratio, spin):
    """Path (b) from :class:`fe.wheel_modes.WheelModes` of the axisymmetric solver.

    Parameters
    ----------
    modes : WheelModes
        ``solver == "axisymmetric"``.
    contact_node : int
        Section node at the contact point.
    damping_ratio : float or (m,) array_like
    spin : float
        rad/s.

    Returns
    -------
    poles, residues
        See :func:`moving_poles_residues_axisymmetric`.
    """
    if modes.solver != "axisymmetric":
        raise InputError("wheel.fe.solver", "the exact moving-load path needs axisymmetric modes")
    return moving_poles_residues_axisymmetric(modes.frequency, damping_ratio, modes.nodal_diameters,
                                              modes.orientation, modes.shapes[:, contact_node, :], spin)


# --------------------------------------------------------------------------- path (a)


class RingInterpolant:
    """Local contact-frame mode shapes on the tread ring of a hex20 mesh, interpolated in angle.

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m.
    cells : (E, 20) int ndarray
        VTK hex20 order.
    shapes : (m, N, 3) ndarray
        Cartesian mode shapes, m/√kg.
    contact_node : int
        Node at the contact point (θ = 0).

    Attributes
    ----------
    theta : (K,) ndarray
        Ring node angles in [0, 2π), ascending, rad (the contact node first, θ = 0).
    values : (m, K, 3) ndarray
        Local-frame (x, y, z) = (u_θ, u_z, −u_r) shapes at the ring nodes.
    contact_shape : (m, 3) ndarray
        Shape at θ = 0 (the load point).

    Notes
    -----
    Interpolation: on each circumferential element edge (corner, mid-edge node, corner) the
    quadratic Lagrange polynomial in the angle, i.e. the hex20 interpolation along the edge
    when the edge parameter is linear in θ (true for meshes made by revolution).
    """

    def __init__(self, nodes, cells, shapes, contact_node):
        nodes = np.asarray(nodes, dtype=float)
        cells = np.asarray(cells)
        r = np.hypot(nodes[:, 0], nodes[:, 2])
        c = int(contact_node)
        on_ring = np.nonzero(np.isclose(r, r[c], rtol=0, atol=1e-9 * r[c])
                             & np.isclose(nodes[:, 1], nodes[c, 1], rtol=0, atol=1e-9 * r[c]))[0]
        _, _, theta, comp = cylindrical_components(nodes[on_ring], np.asarray(shapes)[:, on_ring, :])
        theta0 = np.arctan2(nodes[c, 0], -nodes[c, 2])
        theta = np.mod(theta - theta0, 2.0 * np.pi)
        theta[on_ring == c] = 0.0
        order = np.argsort(theta)
        corner_nodes = np.unique(cells[:, :8])
        is_corner = np.isin(on_ring[order], corner_nodes)
        if on_ring.size < 6 or on_ring.size % 2 or np.any(is_corner[0::2] != is_corner[0]) or np.any(
                is_corner[1::2] == is_corner[0]):
            raise InputError("mesh.hex_cells", "the tread ring must alternate corner and mid-edge nodes")
        self.theta = theta[order]
        loc = comp[:, order, :]
        self.values = np.stack([loc[..., 2], loc[..., 1], -loc[..., 0]], axis=-1)
        self.contact_shape = self.values[:, 0, :].copy()
        # Edge table: roll so that entry 0 is a corner, unwrap the angles, close the ring.
        shift = 0 if is_corner[0] else 1
        th = np.roll(self.theta, -shift)
        th[th < th[0]] += 2.0 * np.pi
        self._edge_theta = np.append(th, th[0] + 2.0 * np.pi)
        vals = np.roll(self.values, -shift, axis=1)
        self._edge_values = np.concatenate([vals, vals[:, :1]], axis=1)

    def __call__(self, angle):
        """Interpolated local shapes at angles (rad), shape (T,) -> (m, T, 3)."""
        th, vals = self._edge_theta, self._edge_values
        x = th[0] + np.mod(np.asarray(angle, dtype=float) - th[0], 2.0 * np.pi)
        n_edges = (th.size - 1) // 2
        e = np.clip(np.searchsorted(th[0:-1:2], x, side="right") - 1, 0, n_edges - 1)
        i0 = 2 * e
        t0, t1, t2 = th[i0], th[i0 + 1], th[i0 + 2]
        l0 = (x - t1) * (x - t2) / ((t0 - t1) * (t0 - t2))
        l1 = (x - t0) * (x - t2) / ((t1 - t0) * (t1 - t2))
        l2 = (x - t0) * (x - t1) / ((t2 - t0) * (t2 - t1))
        return (l0[None, :, None] * vals[:, i0] + l1[None, :, None] * vals[:, i0 + 1]
                + l2[None, :, None] * vals[:, i0 + 2])


def moving_green_interpolated(ring, frequency_hz, damping_ratio, spin, time):
    """Moving Green's function g̃(t) of path (a) at given times.

    Parameters
    ----------
    ring : RingInterpolant
    frequency_hz : (m,) array_like
        Hz.
    damping_ratio : float or (m,) array_like
    spin : float
        rad/s.
    time : (nt,) array_like
        s, ≥ 0.

    Returns
    -------
    (nt, 3, 3) ndarray
        m/(N s), local contact frame: ``g̃[t, i, j]`` displacement i at the current contact
        point per unit impulse j at the contact point of time 0.
    """
    pole, r = _modal_pole(frequency_hz, damping_ratio)
    t = np.asarray(time, dtype=float)
    h = 2.0 * np.real(r[None, :] * np.exp(pole[None, :] * t[:, None]))  # (nt, m)
    psi = ring(spin * t)  # (m, nt, 3)
    return np.einsum("tm,mti,mj->tij", h, psi, ring.contact_shape, optimize=True)


def moving_kernel_quadrature(ring, frequency_hz, damping_ratio, spin, time_step, n_samples, n_gauss=6,
                             chunk=2048):
    """Ramp-invariant kernel of path (a) by quadrature of g̃ against the hat function.

    ``k[m] = ∫ g̃(τ) Λ((τ − mΔt)/Δt) dτ`` with the hat ``Λ(s) = max(0, 1 − |s|)``, integrated
    with ``n_gauss`` Gauss–Legendre points on each step ``[jΔt, (j+1)Δt]``.

    Parameters
    ----------
    ring : RingInterpolant
    frequency_hz, damping_ratio
        As :func:`moving_green_interpolated`.
    spin : float
        rad/s.
    time_step : float
        s.
    n_samples : int
        Kernel length.
    n_gauss : int
        Points per step.
    chunk : int
        Steps per vectorised block.

    Returns
    -------
    (n_samples, 3, 3) ndarray
        m/N, same convention as :func:`fe.greens.ramp_invariant_kernel`.
    """
    dt = require_range("interaction.time_step", time_step, 0.0, None, low_open=True, unit="s")
    x, w = np.polynomial.legendre.leggauss(int(n_gauss))
    s = 0.5 * (x + 1.0)  # in [0, 1]
    w = 0.5 * w * dt
    kernel = np.zeros((n_samples, 3, 3))
    for j0 in range(0, n_samples, chunk):
        j = np.arange(j0, min(j0 + chunk, n_samples))  # step [jΔt, (j+1)Δt]
        tau = (j[:, None] + s[None, :]) * dt  # (nj, ng)
        g = moving_green_interpolated(ring, frequency_hz, damping_ratio, spin, tau.ravel()).reshape(
            j.size, s.size, 3, 3)
        kernel[j] += np.einsum("g,jgab->jab", w * (1.0 - s), g)  # falling half of hat j
        inside = j + 1 < n_samples
        kernel[j[inside] + 1] += np.einsum("g,jgab->jab", w * s, g[inside])  # rising half of hat j+1
    return kernel


def ring_fourier_coefficients(ring, q_max=None, oversample=16):
    """Circumferential Fourier coefficients of the interpolated ring shapes.

    Parameters
    ----------
    ring : RingInterpolant
    q_max : int, optional
        Highest harmonic returned (default: the number of ring nodes).
    oversample : int
        FFT samples per ring-node interval (the interpolant is sampled, so coefficients up to
        about ``oversample · K / 2`` are alias-free to the interpolant's smoothness).

    Returns
    -------
    q : (nq,) int ndarray
        Harmonics, ``|q| ≤ q_max``.
    coeff : (m, nq, 3) complex ndarray
        ``ψ̃_r(θ) = Σ_q coeff[r, q] e^{iqθ}`` (local contact frame, m/√kg).
    """
    k = ring.theta.size
    q_max = k if q_max is None else int(q_max)
    n_fft = max(int(oversample) * k, 2 * q_max + 2)
    angle = 2.0 * np.pi * np.arange(n_fft) / n_fft
    coeff = np.fft.fft(ring(angle), axis=1) / n_fft
    q = np.fft.fftfreq(n_fft, 1.0 / n_fft).astype(int)
    use = np.abs(q) <= q_max
    return q[use], coeff[:, use]


def moving_poles_residues_interpolated(ring, frequency_hz, damping_ratio, spin, q_max=None, oversample=16,
                                       rel_tol=1e-6):
    """Path (a) in pole-residue form from the Fourier series of the interpolated ring shapes.

    Parameters
    ----------
    ring : RingInterpolant
    frequency_hz : (m,) array_like
        Hz.
    damping_ratio : float or (m,) array_like
    spin : float
        rad/s.
    q_max : int, optional
        Highest circumferential harmonic kept (default: the number of ring nodes).
    oversample : int
        Samples of the interpolant per ring-node interval for the FFT.
    rel_tol : float
        Harmonics with ``|c_q| < rel_tol · max|c|`` (per mode) are dropped.

    Notes
    -----
    The interpolant has slope kinks at the element edges, so ``|c_q| ~ q⁻²`` and the truncated
    series converges slowly in the time domain near t = 0 (kernel error ~1e-3 at
    ``q_max`` = ring nodes); for time-domain use prefer :func:`moving_kernel_quadrature`,
    which is exact for the interpolant. The receptance near the peaks is insensitive to it.

    Returns
    -------
    poles : (p,) complex ndarray
        rad/s, ``p_r + iqΩ``.
    residues : (p, 3, 3) complex ndarray
        m/(N s).
    """
    spin = require_range("rotation.spin", spin, unit="rad/s")
    pole, r = _modal_pole(frequency_hz, damping_ratio)
    q, coeff = ring_fourier_coefficients(ring, q_max, oversample)
    size = np.linalg.norm(coeff, axis=2)
    keep = size >= rel_tol * size.max(axis=1, keepdims=True)
    mode, harm = np.nonzero(keep)
    if spin == 0.0:  # all harmonics share the pole p_r and sum to ψ̃(0) = φ(0)
        return pole, r[:, None, None] * np.einsum("mi,mj->mij", ring.contact_shape, ring.contact_shape)
    poles = pole[mode] + 1j * q[harm] * spin
    residues = r[mode, None, None] * np.einsum("pi,pj->pij", coeff[mode, harm], ring.contact_shape[mode])
    logger.debug("interpolated moving load: %d poles from %d modes", poles.size, pole.size)
    return poles, residues
