r"""Rotating wheel: Eulerian modal-coordinate model (Fayos et al. 2007; Martínez-Casas et al. 2013).

Spin convention
---------------
The wheel rolls in +x of the contact frame (x = e_θ at θ = 0, docs/conventions.md), so the
material moves towards *decreasing* θ at the rate ``Ω = v / r0 > 0``: the material point that
carries the label θ_m sits at θ = θ_m − Ωt. Seen from the material, the contact point travels
towards increasing θ (θ_contact = θ_0 + Ωt, :mod:`fe.moving_load`). With the section point
(r, z, θ) at X = (r sin θ, z, −r cos θ), ``∂X/∂θ = (−Z, 0, X) = r e_θ``, so the rigid-body
velocity is ``v_0 = −Ω r e_θ`` and the derivative along the circumference acting on a field
with fixed Cartesian components is ``∂/∂θ = −Z ∂/∂X + X ∂/∂Z = r e_θ · ∇``.

Derivation
----------
Eulerian description: ``u(X, t)`` (fixed Cartesian components) is the elastic displacement of
the particle whose rigidly rotated reference position is the *fixed* point X. The particle is
at ``X + u`` and its velocity is the material derivative

.. math::  \dot x = v_0 + \partial_t u + (v_0\cdot\nabla) u = v_0 + \partial_t u - \Omega\,\partial_\theta u.

With ``u = Φ q`` (``Φ_k(X)`` the mass-normalised modes of the stationary wheel, ``Φ' = ∂Φ/∂θ``)
the kinetic energy ``T = ½∫ρ|ẋ|² dV`` is

.. math::  T = \tfrac12 \dot q^T \dot q - \Omega\,\dot q^T V q + \tfrac12\Omega^2 q^T A q
           + (\text{terms linear in } \dot q, q \text{ from } v_0) + \text{const},

``V_kl = ∫ρ Φ_k·Φ'_l dV`` and ``A_kl = ∫ρ Φ'_k·Φ'_l dV``. Integrating by parts around the
(periodic) circumference with an axisymmetric ρ gives ``V^T = −V`` (skew) and A symmetric
positive semi-definite. The term linear in q̇ has a constant coefficient and drops out of
Lagrange's equations; the term linear in q is the static centrifugal load
``Ω² ∫ρ r e_r·Φ_k dV``, a constant force (its static deflection is not part of the dynamic
response; its stress enters through K_σ). Lagrange's equations
``d/dt ∂T/∂q̇ − ∂T/∂q + ∂U/∂q + ∂R/∂q̇ = Φ_c^T f`` with
``∂T/∂q̇ = q̇ − ΩVq`` and ``∂T/∂q = −ΩV^T q̇ + Ω²Aq = ΩVq̇ + Ω²Aq`` give

.. math::  \ddot q + (D - 2\Omega V)\,\dot q + (\Lambda - \Omega^2 A + \Omega^2 K_\sigma)\,q
           = \Phi_c^T f,

i.e. **s = −1** in ``q̈ + (D + 2sΩV) q̇ + ...`` for our spin direction. ``Λ = diag(ω_r²)``,
``U = ½ q^T (Λ + Ω² K_σ) q`` with the geometric stiffness of the centrifugal prestress
(:mod:`fe.centrifugal`), ``K_σ,kl = ∫ σ⁰_ij ∂Φ_k/∂x_i · ∂Φ_l/∂x_j dV`` at Ω = 1 rad/s.

Damping: ``damping="fixed"`` (default, as in the papers' modal equation) uses ``D q̇`` with
``D = diag(2 ζ_r ω_r)``; ``damping="material"`` applies D to the material rate of the modal
coordinates, ``R = ½ (q̇ − ΩVq)^T D (q̇ − ΩVq)``, adding ``−Ω D V q`` to the stiffness (the
projection of ``∂_θ Φ q`` on the modes is ``V q``). The moving-load model of
:mod:`fe.moving_load` damps in the material frame, so it is the "material" variant that
coincides with it for purely axial modes.

Exact results used by the tests
-------------------------------
* A pair of purely axial modes (only u_Y ≠ 0) of harmonic n has ``Φ'_c = −n Φ_s``,
  ``Φ'_s = n Φ_c``, hence ``V_cs = n``, ``A = n² I`` on the pair and zero coupling to all
  other modes. With K_σ off and D = 0 the characteristic equation is ``(λ ∓ nΩ)² = ω_n²``:
  the fixed-frame frequencies are **exactly ω_n ± nΩ when V and A are both on**
  (with A off they are ``±nΩ + sqrt(ω_n² + n²Ω²)``).
* Reciprocity: with ``damping="fixed"``, ``Z(s, Ω)^T = Z(s, −Ω)`` (V skew, everything else
  symmetric), so ``H(Ω)^T = H(−Ω)``. H itself is not symmetric when the gyroscopic term is on
  and Ω ≠ 0; it is symmetric with V off.
* Thin ring, in-plane inextensional pair (``U_θ = −U_r/n``): ``V_cs = n − 2n/(n²+1)``, the
  fixed-frame split ``± n(n²−1)/(n²+1) Ω`` (Bryan's factor).

Mode sources
------------
:func:`modal_matrices_hex20` integrates V, A, K_σ over the 3D mesh with the hex20 shape
functions and 3×3×3 Gauss points. :func:`modal_matrices_axisymmetric` integrates over the
section with the quad8 Gauss points and exactly around the circumference by a uniform rule
with ``2n + 3`` angles (products of harmonics of order n are trigonometric polynomials of
degree ≤ 2n). Only modes of the same harmonic couple.

Units: Φ in m/√kg, so V (rad⁻¹), A (rad⁻²) and K_σ (per (rad/s)², at Ω = 1 rad/s) are
dimensionless modal matrices; ω in rad/s, poles rad/s, residues m/(N s).
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from fe import centrifugal, greens
from fe.quadrature import hex20_quadrature_chunks, section_quadrature
from squealcore.errors import InputError, require_range

logger = logging.getLogger(__name__)

_DAMPING_MODELS = ("fixed", "material")


def spin_rate(speed, rolling_radius):
    """Spin rate ``Ω = v / r0`` (rad/s) from the rolling speed ``v`` (m/s) and radius ``r0`` (m)."""
    v = require_range("rotation.speed", speed, 0.0, None, unit="m/s")
    r0 = require_range("wheel.rolling_radius", rolling_radius, 0.0, None, low_open=True, unit="m")
    return v / r0


@dataclass(frozen=True)
class RotationMatrices:
    """Modal matrices of a spinning wheel (dimensionless, mass-normalised modes).

    Attributes
    ----------
    gyroscopic : (m, m) ndarray
        ``V_kl = ∫ρ Φ_k·∂Φ_l/∂θ dV`` (1/rad), skew-symmetric.
    convective : (m, m) ndarray
        ``A_kl = ∫ρ ∂Φ_k/∂θ·∂Φ_l/∂θ dV`` (1/rad²), symmetric positive semi-definite.
    geometric : (m, m) ndarray or None
        ``K_σ`` of the centrifugal prestress at Ω = 1 rad/s (s²/rad² · 1/s² = dimensionless);
        None if not computed.
    skew_defect : float
        ``max|V + V^T| / max|V|`` of the raw integral before V was replaced by its skew part
        (hex20: the isoparametric mesh is not exactly a body of revolution; 0 for the
        axisymmetric path, whose V is skew to round-off).
    """

    gyroscopic: np.ndarray
    convective: np.ndarray
    geometric: np.ndarray | None
    skew_defect: float = 0.0


# --------------------------------------------------------------------------- fields of the modes


def theta_derivative_hex20(position, gradient):
    """``∂u/∂θ = −Z ∂u/∂X + X ∂u/∂Z`` from gradients (…, 3, 3) at points (e, G, 3)."""
    x = position[..., 0][None, ..., None]
    z = position[..., 2][None, ..., None]
    return -z * gradient[..., 0] + x * gradient[..., 2]


def _trig(n, family, theta):
    """Angular factors of (u_r, u_z, u_θ) and their θ-derivatives, each (k, T, 3)."""
    cos_f = np.array([f == "cos" for f in family])[:, None, None]
    c, s = np.cos(n * theta)[None, :, None], np.sin(n * theta)[None, :, None]
    ones = np.array([1.0, 1.0, 0.0])[None, None, :]
    # cos family: (c, c, s); sin family: (s, s, -c)
    f_cos = c * ones + s * (1 - ones)
    f_sin = s * ones - c * (1 - ones)
    d_cos = -n * s * ones + n * c * (1 - ones)
    d_sin = n * c * ones + n * s * (1 - ones)
    return np.where(cos_f, f_cos, f_sin), np.where(cos_f, d_cos, d_sin)


def axisymmetric_harmonic_fields(section_nodes, section_cells, amplitudes, n, family, theta, quad=None):
    """Cylindrical components of modes of one harmonic and their gradients at (Gauss point, angle).

    Parameters
    ----------
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    section_cells : (Es, 8) int ndarray
    amplitudes : (k, Ns, 3) ndarray
        Section amplitudes (U_r, U_z, U_θ) of k modes of harmonic n.
    n : int
    family : (k,) sequence of {"cos", "sin"}
    theta : (T,) ndarray
        Angles, rad.
    quad : tuple, optional
        Output of :func:`fe.quadrature.section_quadrature` (recomputed if None).

    Returns
    -------
    value : (k, E, G, T, 3) ndarray
        (u_r, u_z, u_θ).
    gradient : (k, E, G, T, 3, 3) ndarray
        ``gradient[..., c, j]``: physical gradient in the orthonormal basis (e_r, e_z, e_θ),
        directions j = (r, z, θ); u/m.
    w_rda : (E, G) ndarray
        m³ (multiply by the angular weight).
    """
    n_shape, dn_dx, radius, w_rda = quad if quad is not None else section_quadrature(section_nodes, section_cells)
    cells = np.asarray(section_cells)
    ue = np.asarray(amplitudes)[:, cells, :]  # (k, E, 8, 3)
    amp = np.einsum("ga,keac->kegc", n_shape, ue)
    d_amp = np.einsum("egaj,keac->kegcj", dn_dx, ue)  # (k, E, G, 3, 2)
    f, df = _trig(n, family, np.asarray(theta, dtype=float))  # (k, T, 3)
    fk = f[:, None, None, :, :]
    dfk = df[:, None, None, :, :]
    value = amp[:, :, :, None, :] * fk
    dtheta = amp[:, :, :, None, :] * dfk  # ∂u_c/∂θ of the components
    r = radius[None, :, :, None]
    grad = np.empty(value.shape + (3,))
    grad[..., 0] = d_amp[:, :, :, None, :, 0] * fk
    grad[..., 1] = d_amp[:, :, :, None, :, 1] * fk
    ur, ut = value[..., 0], value[..., 2]
    grad[..., 0, 2] = (dtheta[..., 0] - ut) / r
    grad[..., 1, 2] = dtheta[..., 1] / r
    grad[..., 2, 2] = (dtheta[..., 2] + ur) / r
    return value, grad, w_rda


# --------------------------------------------------------------------------- modal matrices


def modal_matrices_hex20(nodes, cells, shapes, *, prestress=None, chunk_size=64):
    """V, A and K_σ of 3D hex20 modes.

    Parameters
    ----------
    nodes : (N, 3) ndarray
        m.
    cells : (E, 20) int ndarray
    shapes : (m, N, 3) ndarray
        Mass-normalised Cartesian shapes, m/√kg (``WheelModes.shapes`` of the hex20 solver).
    prestress : (E, 27, 3, 3) ndarray, optional
        Cauchy stress at Ω = 1 rad/s at the Gauss points (Pa), from
        :func:`fe.centrifugal.prestress_hex20`; K_σ is None if omitted.
    chunk_size : int

    Returns
    -------
    RotationMatrices
        V and A **per unit density**: multiply by ρ (done by :func:`eulerian_model_hex20`).
    """
    nodes = np.asarray(nodes, dtype=float)
    cells = np.asarray(cells)
    shapes = np.asarray(shapes, dtype=float)
    m = shapes.shape[0]
    v = np.zeros((m, m))
    a = np.zeros((m, m))
    ks = np.zeros((m, m)) if prestress is not None else None
    for start, stop, w, pos, val, grad in hex20_quadrature_chunks(nodes, cells, shapes, chunk_size):
        dth = theta_derivative_hex20(pos, grad)  # (m, e, G, 3)
        wv = (val * w[None, :, :, None]).reshape(m, -1)
        v += wv @ dth.reshape(m, -1).T
        a += (dth * w[None, :, :, None]).reshape(m, -1) @ dth.reshape(m, -1).T
        if ks is not None:
            ks += centrifugal.geometric_stiffness(grad, prestress[start:stop], w)
    # ∫ρ ∂_θ(Φ_k·Φ_l) dV = ∮ ρ Φ_k·Φ_l (r e_θ)·n dS vanishes on a body of revolution; on the
    # isoparametric mesh it is a small geometric defect: keep the skew part (no work done by
    # the gyroscopic forces, exact reciprocity) and report the defect.
    scale = np.abs(v).max() if v.size else 0.0
    defect = float(np.abs(v + v.T).max() / scale) if scale > 0 else 0.0
    logger.info("hex20 modal matrices: %d modes, skew defect of V %.2e", m, defect)
    return RotationMatrices(0.5 * (v - v.T), 0.5 * (a + a.T), None if ks is None else 0.5 * (ks + ks.T), defect)


def modal_matrices_axisymmetric(section_nodes, section_cells, amplitudes, harmonic, family, *, prestress=None):
    """V, A and K_σ of axisymmetric harmonic modes (exact circumferential integration).

    Parameters
    ----------
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    section_cells : (Es, 8) int ndarray
    amplitudes : (m, Ns, 3) ndarray
        Mass-normalised section amplitudes (U_r, U_z, U_θ) (``WheelModes.shapes``), m/√kg.
    harmonic : (m,) int array_like
    family : (m,) sequence of {"cos", "sin"}
    prestress : (Es, 9, 3, 3) ndarray, optional
        Stress at Ω = 1 rad/s at the section Gauss points in the basis (e_r, e_z, e_θ) (Pa),
        from :func:`fe.centrifugal.prestress_axisymmetric`; K_σ is None if omitted.

    Returns
    -------
    RotationMatrices
        V and A **per unit density** (m³/kg · kg/m³): multiply by ρ (done by
        :func:`eulerian_model_axisymmetric`).
    """
    amplitudes = np.asarray(amplitudes, dtype=float)
    harmonic = np.asarray(harmonic, dtype=int)
    family = np.asarray(family, dtype=str)
    m = amplitudes.shape[0]
    quad = section_quadrature(section_nodes, section_cells)
    v = np.zeros((m, m))
    a = np.zeros((m, m))
    ks = np.zeros((m, m)) if prestress is not None else None
    for n in np.unique(harmonic):
        idx = np.nonzero(harmonic == n)[0]
        n_theta = 2 * int(n) + 3  # exact for trigonometric polynomials of degree <= 2n + 2
        theta = 2.0 * np.pi * np.arange(n_theta) / n_theta
        val, grad, w_rda = axisymmetric_harmonic_fields(section_nodes, section_cells, amplitudes[idx], int(n),
                                                        family[idx], theta, quad)
        k = idx.size
        w = (w_rda * (2.0 * np.pi / n_theta))[:, :, None]  # (E, G, 1) over angles
        dth = grad[..., 2] * quad[2][None, :, :, None, None]  # r e_θ·∇u = ∂u/∂θ (Cartesian)
        wv = (val * w[None, :, :, :, None]).reshape(k, -1)
        v[np.ix_(idx, idx)] = wv @ dth.reshape(k, -1).T
        a[np.ix_(idx, idx)] = (dth * w[None, :, :, :, None]).reshape(k, -1) @ dth.reshape(k, -1).T
        if ks is not None:
            e, g = w_rda.shape
            grad_flat = grad.transpose(0, 1, 3, 2, 4, 5).reshape(k, e * n_theta, g, 3, 3)
            stress = np.repeat(prestress, n_theta, axis=0)  # (E*T, G, 3, 3), element-major
            weight = np.repeat(w_rda * (2.0 * np.pi / n_theta), n_theta, axis=0)
            ks[np.ix_(idx, idx)] = centrifugal.geometric_stiffness(grad_flat, stress, weight)
    return RotationMatrices(v, a, ks)


# --------------------------------------------------------------------------- Eulerian model


@dataclass(frozen=True)
class EulerianModel:
    """Modal model of the spinning wheel observed at the fixed contact point.

    Attributes
    ----------
    frequency : (m,) ndarray
        Stationary natural frequencies, Hz.
    damping_ratio : (m,) ndarray
        Modal viscous damping ratios.
    contact_shape : (m, 3) ndarray
        Mass-normalised shapes at the contact point in the contact frame, m/√kg.
    matrices : RotationMatrices
    """

    frequency: np.ndarray
    damping_ratio: np.ndarray
    contact_shape: np.ndarray
    matrices: RotationMatrices

    def system(self, spin, *, gyroscopic=True, convective=True, centrifugal=True, damping="fixed"):
        """Modal damping and stiffness matrices at the spin rate ``spin`` (rad/s).

        Parameters
        ----------
        spin : float
            Ω, rad/s (the sign follows the module's convention; Ω < 0 reverses the spin).
        gyroscopic, convective, centrifugal : bool
            Switch the ``−2ΩV`` term, the ``−Ω²A`` term and the ``+Ω²K_σ`` term.
        damping : {"fixed", "material"}
            See the module docstring.

        Returns
        -------
        C : (m, m) ndarray
            1/s.
        K : (m, m) ndarray
            1/s².
        """
        spin = require_range("rotation.spin", spin, unit="rad/s")
        if damping not in _DAMPING_MODELS:
            raise InputError("rotation.damping", f"must be one of {_DAMPING_MODELS}, got {damping!r}")
        omega = 2.0 * np.pi * np.asarray(self.frequency, dtype=float)
        d = np.diag(2.0 * np.asarray(self.damping_ratio) * omega)
        mats = self.matrices
        c = d.copy()
        k = np.diag(omega**2)
        if gyroscopic:
            c = c - 2.0 * spin * mats.gyroscopic
        if convective:
            k = k - spin**2 * mats.convective
        if centrifugal:
            if mats.geometric is None:
                raise InputError("rotation.centrifugal", "K_sigma was not computed (pass a prestress)")
            k = k + spin**2 * mats.geometric
        if damping == "material":
            k = k - spin * d @ mats.gyroscopic
        return c, k

    def poles_residues(self, spin, **switches):
        """Poles and residues at the contact point, in the :mod:`fe.greens` form.

        ``H(s) = Σ_j R_j/(s − p_j) + conj(R_j)/(s − conj(p_j))``. From the state-space form
        ``ẋ = S x + B f``, ``x = (q, q̇)``, ``S = [[0, I], [−K, −C]]``, ``B = (0, P)``,
        ``u = (P^T, 0) x`` with ``P`` the contact shapes: ``S = X diag(λ) X⁻¹`` gives
        residues ``(C_out x_j)(X⁻¹ B)_j``. Of every complex-conjugate pair the member with
        ``Im λ > 0`` is kept; real eigenvalues (overdamped or divergent) keep half their residue.

        Parameters
        ----------
        spin : float
            rad/s.
        **switches
            See :meth:`system`.

        Returns
        -------
        poles : (p,) complex ndarray
            rad/s.
        residues : (p, 3, 3) complex ndarray
            m/(N s); not symmetric when Ω ≠ 0 and the gyroscopic term is on.
        """
        c, k = self.system(spin, **switches)
        m = c.shape[0]
        p = np.asarray(self.contact_shape, dtype=float)  # (m, 3)
        s = np.zeros((2 * m, 2 * m))
        s[:m, m:] = np.eye(m)
        s[m:, :m] = -k
        s[m:, m:] = -c
        lam, x = np.linalg.eig(s)
        b = np.zeros((2 * m, 3))
        b[m:] = p
        right = p.T @ x[:m]  # (3, 2m)
        left = np.linalg.solve(x, b)  # (2m, 3)
        keep = lam.imag > 0
        real = lam.imag == 0
        res = np.einsum("ij,jk->jik", right, left)
        poles = np.concatenate([lam[keep], lam[real]])
        residues = np.concatenate([res[keep], 0.5 * res[real]])
        if np.any(poles.real > 0):
            logger.warning("Eulerian model unstable at spin %g rad/s: max Re(p) = %g", spin, poles.real.max())
        order = np.argsort(np.abs(poles.imag))
        return poles[order], residues[order]

    def receptance(self, spin, frequency_hz, chunk=256, **switches):
        """Receptance by a direct solve of the modal equations, ``H = P^T Z(iω)⁻¹ P`` (m/N).

        Independent of the eigen-decomposition of :meth:`poles_residues` (used to check it).

        Parameters
        ----------
        spin : float
            rad/s.
        frequency_hz : (nf,) array_like
            Hz.
        chunk : int
            Frequencies per batched solve.
        **switches
            See :meth:`system`.

        Returns
        -------
        (nf, 3, 3) complex ndarray
            ``H[f, i, j]``: contact-frame displacement i per unit force j, ``exp(+iωt)``.
        """
        c, k = self.system(spin, **switches)
        p = np.asarray(self.contact_shape, dtype=float)
        w = 2.0 * np.pi * np.atleast_1d(np.asarray(frequency_hz, dtype=float))
        out = np.empty((w.size, 3, 3), dtype=complex)
        eye = np.eye(c.shape[0])
        for i in range(0, w.size, chunk):
            ww = w[i:i + chunk, None, None]
            z = -(ww**2) * eye + 1j * ww * c + k
            out[i:i + chunk] = p.T @ np.linalg.solve(z, np.broadcast_to(p, (ww.shape[0],) + p.shape))
        return out

    def eigenfrequencies(self, spin, **switches):
        """Fixed-frame damped natural frequencies ``Im(p)/2π`` (Hz), ascending by magnitude."""
        c, k = self.system(spin, **switches)
        m = c.shape[0]
        s = np.zeros((2 * m, 2 * m))
        s[:m, m:] = np.eye(m)
        s[m:, :m] = -k
        s[m:, m:] = -c
        lam = np.linalg.eigvals(s)
        return np.sort(np.abs(lam.imag[lam.imag >= 0])) / (2.0 * np.pi)


def _check_modes(modes, damping_ratio):
    zeta = np.broadcast_to(np.asarray(damping_ratio, dtype=float), np.shape(modes.frequency)).copy()
    if np.any((zeta < 0) | (zeta >= 1)):
        raise InputError("wheel.damping_ratio", "must lie in [0, 1)")
    return zeta


def eulerian_model_axisymmetric(modes, section_nodes, section_cells, clamped_nodes, youngs_modulus,
                                poisson_ratio, density, damping_ratio, *, centrifugal_stiffening=True):
    """Eulerian model from axisymmetric modes (:func:`fe.wheel_modes.solve_axisymmetric`).

    Parameters
    ----------
    modes : WheelModes
        ``solver == "axisymmetric"``.
    section_nodes : (Ns, 2) ndarray
        (r, z), m.
    section_cells : (Es, 8) int ndarray
    clamped_nodes : (c,) int ndarray
        Section nodes clamped for the centrifugal static solve (the hub bore).
    youngs_modulus, poisson_ratio, density : float
        Pa, -, kg/m³.
    damping_ratio : float or (m,) array_like
        Modal damping ratios.
    centrifugal_stiffening : bool
        Compute K_σ (a static solve); otherwise ``matrices.geometric`` is None.

    Returns
    -------
    EulerianModel
    """
    if modes.solver != "axisymmetric":
        raise InputError("wheel.fe.solver", "eulerian_model_axisymmetric needs axisymmetric modes")
    rho = require_range("wheel.fe.density", density, 0.0, None, low_open=True, unit="kg/m^3")
    stress = None
    if centrifugal_stiffening:
        stress = centrifugal.prestress_axisymmetric(section_nodes, section_cells, clamped_nodes, youngs_modulus,
                                                    poisson_ratio, density).stress
    mats = modal_matrices_axisymmetric(section_nodes, section_cells, modes.shapes, modes.nodal_diameters,
                                       modes.orientation, prestress=stress)
    mats = RotationMatrices(rho * mats.gyroscopic, rho * mats.convective, mats.geometric)
    return EulerianModel(np.asarray(modes.frequency), _check_modes(modes, damping_ratio),
                         np.asarray(modes.contact_shape), mats)


def eulerian_model_hex20(modes, nodes, cells, clamped_nodes, youngs_modulus, poisson_ratio, density,
                         damping_ratio, *, centrifugal_stiffening=True, n_sectors=None):
    """Eulerian model from 3D hex20 modes (:func:`fe.wheel_modes.solve_hex20`).

    Parameters
    ----------
    modes : WheelModes
        ``solver == "hex20"``.
    nodes : (N, 3) ndarray
        m.
    cells : (E, 20) int ndarray
    clamped_nodes : (c,) int ndarray
        Nodes clamped for the centrifugal static solve (the hub bore).
    youngs_modulus, poisson_ratio, density : float
        Pa, -, kg/m³.
    damping_ratio : float or (m,) array_like
    centrifugal_stiffening : bool
        Compute K_σ (a static 3D solve).
    n_sectors : int, optional
        Revolve steps of the mesh: the static solve by cyclic symmetry (fe/cyclic.py).

    Returns
    -------
    EulerianModel
    """
    if modes.solver != "hex20":
        raise InputError("wheel.fe.solver", "eulerian_model_hex20 needs hex20 modes")
    rho = require_range("wheel.fe.density", density, 0.0, None, low_open=True, unit="kg/m^3")
    stress = None
    if centrifugal_stiffening:
        stress = centrifugal.prestress_hex20(nodes, cells, clamped_nodes, youngs_modulus, poisson_ratio,
                                             density, n_sectors=n_sectors).stress
    mats = modal_matrices_hex20(nodes, cells, modes.shapes, prestress=stress)
    mats = RotationMatrices(rho * mats.gyroscopic, rho * mats.convective, mats.geometric, mats.skew_defect)
    return EulerianModel(np.asarray(modes.frequency), _check_modes(modes, damping_ratio),
                         np.asarray(modes.contact_shape), mats)


def stationary_poles_residues(model):
    """Poles/residues of the non-rotating wheel of ``model`` (:func:`fe.greens.modal_poles_residues`)."""
    return greens.modal_poles_residues(model.frequency, model.damping_ratio, model.contact_shape)
