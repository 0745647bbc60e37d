"""Waves of the supported rail: the quadratic eigenproblem in the wavenumber at each frequency.

Model: ``[K0 + kappa K1s + kappa^2 K2](1 + i eta) + Ks(omega) - omega^2 M] V = 0`` in the
real symmetric form of :mod:`waveguide.element` (physical ``U = T V``, ``T = diag(i, 1, 1)``
per node). Convention ``exp(i (omega t - kappa x))``: waves travelling or decaying towards
+x have ``Im kappa < 0`` (or, undamped and propagating, positive group velocity).

The matrices can be reduced to a Ritz basis of cross-section modes (undamped, at several
real wavenumbers, up to ``basis_frequency``) plus static load shapes, so that the
per-frequency eigenproblem is small; :class:`RailWaveguide` does both and the tests compare
the reduced and the full model.
"""

from __future__ import annotations

import dataclasses
import logging

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from waveguide.element import assemble
from waveguide.params import TrackParams
from waveguide.support import foot_support, patch_weights, section_weights

logger = logging.getLogger(__name__)

__all__ = ["Waves", "RailWaveguide", "dispersion", "LABELS", "full_kappa_solver"]

LABELS = ("longitudinal", "lateral", "vertical", "torsion", "section")


@dataclasses.dataclass(frozen=True)
class Waves:
    """Waves of one frequency that travel or decay towards +x.

    Attributes
    ----------
    omega : float
        Angular frequency (rad/s).
    kappa : ndarray (n,)
        Complex wavenumbers (rad/m), ``Im kappa <= 0``.
    q : ndarray (n, 3, 3)
        Wave amplitudes (m/N) of the load-point receptance: the response at distance x >= 0
        to a unit point force (in x) spread over the patch width is
        ``sum_n q[n] exp(-i kappa_n x)``.
    label : ndarray (n,) of int
        Dominant motion, index into :data:`LABELS`.
    """

    omega: float
    kappa: np.ndarray
    q: np.ndarray
    label: np.ndarray

    @property
    def decay_db_per_m(self):
        """Decay rate of each wave (dB/m): -20 log10(e) Im kappa."""
        return -20 * np.log10(np.e) * self.kappa.imag


class RailWaveguide:
    """Waveguide FE model of a rail on a continuous two-layer support.

    Parameters
    ----------
    mesh : mesh.rail_mesh.RailMesh
    track : TrackParams
    basis_frequency : float or None
        Build a reduced Ritz basis valid up to this frequency (Hz); ``None`` keeps the full
        model (dense, for small meshes and tests).
    load : {"patch", "section"}
        ``"patch"``: force and response on the head-top patch at
        ``track.contact_lateral_position`` (the default, contact receptance);
        ``"section"``: body-force-like load and area-averaged response (beam theory's w).
    """

    #: Ritz basis: modes up to basis_mode_factor * basis_frequency at basis_n_kappa
    #: wavenumbers, plus static load shapes at basis_n_static wavenumbers
    basis_mode_factor = 1.5
    basis_max_modes = 60
    basis_n_kappa = 5
    basis_n_static = 6

    def __init__(self, mesh, track: TrackParams, basis_frequency: float | None = None,
                 load: str = "patch"):
        self.mesh = mesh
        self.track = track
        mats = assemble(mesh, track.youngs_modulus, track.poisson_ratio)
        self.n_full = mats.M.shape[0]
        if load == "patch":
            p = patch_weights(mesh, track.contact_lateral_position, track.load_patch_width)
        elif load == "section":
            p = section_weights(mesh)
        else:
            raise ValueError(f"load must be 'patch' or 'section', got {load!r}")
        sup = foot_support(mesh) if track.supported else None
        if basis_frequency is None:
            basis = None
        else:
            basis = self._ritz_basis(mats, sup, p, basis_frequency)
        self.basis = basis

        def red(a):
            a = a.toarray() if sp.issparse(a) else np.asarray(a)
            if basis is None:
                return a
            return basis.T @ a @ basis if a.ndim == 2 else basis.T @ a

        self.K0, self.K1, self.K2, self.M = (red(a) for a in (mats.K0, mats.K1s, mats.K2, mats.M))
        self.P = p if basis is None else basis.T @ p
        if sup is not None:
            self.sup = ([red(a) for a in sup.mb], [red(c) for c in sup.c], sup.width)
        else:
            self.sup = None
        n = self.K0.shape[0]
        eta = track.loss_factor
        # precomputations for the companion form: K2^-1 K0, K2^-1 K1, K2^-1 M, ...
        cho = sla.cho_factor(self.K2)
        self._k2inv = lambda a: sla.cho_solve(cho, a)
        self._a0 = self._k2inv(self.K0)
        self._a1 = self._k2inv(self.K1)
        self._am = self._k2inv(self.M) / (1 + 1j * eta)
        if self.sup is not None:
            self._as = [self._k2inv(a) / (1 + 1j * eta) for a in self.sup[0]]
            self._ac = [self._k2inv(c) / (1 + 1j * eta) for c in self.sup[1]]
        self.n = n
        logger.info("rail waveguide: %d DOF (full %d)", n, self.n_full)

    # ------------------------------------------------------------------ basis
    def _ritz_basis(self, mats, sup, p, fmax):
        t = self.track
        cs = np.sqrt(t.shear_modulus / self.mesh.density)
        kmax = 2.0 * 2 * np.pi * fmax / cs
        ks = np.linspace(0.0, kmax, self.basis_n_kappa)
        k_static = mats.K0.copy()
        if sup is not None:  # the pads (not the ballast) keep the free-body modes away from 0
            for (kp, _), mb in zip(t.support_layers(), sup.mb):
                k_static = k_static + (kp / sup.width) * mb
        wmax2 = (2 * np.pi * self.basis_mode_factor * fmax) ** 2
        shift = -(2 * np.pi * 50.0) ** 2
        vecs = []
        for kap in ks:
            kk = (k_static + kap * mats.K1s + kap**2 * mats.K2).tocsc()
            n_ev = min(self.basis_max_modes, kk.shape[0] - 2)
            w2, v = spla.eigsh(kk, k=n_ev, M=mats.M, sigma=shift, which="LM")
            keep = w2 < wmax2
            if keep.all():
                logger.warning("Ritz basis: all %d modes at kappa=%.1f below the basis frequency", n_ev, kap)
            vecs.append(v[:, keep])
        # static shapes of the load at wavenumbers up to beyond the patch cut-off 2 pi / L:
        # they carry the local (near-field) deformation under the patch
        k_cut = 2 * np.pi / max(t.load_patch_length, 1e-3)
        for kap in np.r_[0.0, np.geomspace(3.0, 2 * k_cut, self.basis_n_static - 1)]:
            kk = (k_static + kap * mats.K1s + kap**2 * mats.K2 + 1e-6 * abs(shift) * mats.M).tocsc()
            vecs.append(spla.splu(kk).solve(np.asarray(p)))
        v = np.hstack(vecs)
        # mirror symmetry in x (S = diag(-1, 1, 1) per node maps kappa to -kappa): split
        # every vector into its axial and cross-sectional parts so that the basis is
        # S-invariant and the reduced model keeps D(-kappa) = S D(kappa) S
        is_x = (np.arange(v.shape[0]) % 3) == 0
        v = np.hstack([v * is_x[:, None], v * ~is_x[:, None]])
        v = v[:, np.linalg.norm(v, axis=0) > 0]
        # M-orthonormalise and drop dependent vectors
        m = mats.M
        v = v / np.sqrt(np.einsum("ij,ij->j", v, m @ v))  # unit M-norm: modes and static shapes alike
        g = v.T @ (m @ v)
        lam, u = np.linalg.eigh(g)
        keep = lam > lam.max() * 1e-10
        basis = v @ (u[:, keep] / np.sqrt(lam[keep]))
        logger.info("Ritz basis: %d vectors from %d candidates (up to %.0f Hz, kappa <= %.1f rad/m)",
                    basis.shape[1], v.shape[1], fmax, kmax)
        return basis

    # ----------------------------------------------------------------- support
    def support_stiffness(self, omega):
        """Support stiffness matrix (reduced coordinates) at ``omega`` (rad/s), N/m per m."""
        if self.sup is None:
            return np.zeros((self.n, self.n))
        mb, c, _ = self.sup
        out = np.zeros((self.n, self.n), complex)
        for (a, g), mbi, ci in zip(self._support_coeffs(omega), mb, c):
            out += a * mbi - g * np.outer(ci, ci)
        return out

    def _support_coeffs(self, omega):
        t = self.track
        sgn = -1.0 if omega < 0 else 1.0  # hysteretic damping: E (1 + i eta sign(omega))
        out = []
        for kp0, kb0 in t.support_layers():
            kp = kp0 * (1 + 1j * sgn * t.pad_loss_factor)
            kb = kb0 * (1 + 1j * sgn * t.ballast_loss_factor) - omega**2 * t.sleeper_mass
            b = self.sup[2]
            out.append((kp / b, kp**2 / (kp + kb) / b**2))
        return out

    # ------------------------------------------------------------------- waves
    def dynamic_matrix(self, kappa, omega):
        """D(kappa, omega) in the symmetric form (reduced coordinates); negative omega uses
        the conjugate loss factors (hysteretic damping, E (1 + i eta sign(omega)))."""
        eta = self.track.loss_factor * (-1.0 if omega < 0 else 1.0)
        return ((self.K0 + kappa * self.K1 + kappa**2 * self.K2) * (1 + 1j * eta)
                + self.support_stiffness(omega) - omega**2 * self.M)

    def receptance_kappa(self, kappa, omega):
        """Wavenumber-domain receptance (3, 3) at real ``kappa`` (rad/m) and ``omega`` (rad/s)
        by a direct solve: a second method for checking the wave sum."""
        pr = self.P.astype(complex)
        pf = pr.copy()
        pr[:, 0] *= 1j
        pf[:, 0] *= -1j
        return pr.T @ np.linalg.solve(self.dynamic_matrix(kappa, omega), pf)

    def waves(self, omega: float) -> Waves:
        """Waves travelling/decaying towards +x at ``omega`` (rad/s), with their receptance
        amplitudes at the load patch.

        Parameters
        ----------
        omega : float
            Angular frequency (rad/s), > 0 for the free rail.

        Returns
        -------
        Waves
        """
        n = self.n
        eta = self.track.loss_factor
        a0 = self._a0 - omega**2 * self._am
        if self.sup is not None:
            for (a, g), asi, aci, ci in zip(self._support_coeffs(omega), self._as, self._ac,
                                            self.sup[1]):
                a0 = a0 + a * asi - g * np.outer(aci, ci)
        comp = np.zeros((2 * n, 2 * n), dtype=complex)
        comp[:n, n:] = np.eye(n)
        comp[n:, :n] = -a0
        comp[n:, n:] = -self._a1
        lam, vec = np.linalg.eig(comp)
        phi = vec[:n]
        tol = 1e-7 * np.maximum(np.abs(lam), 1e-3)
        prop = np.abs(lam.imag) <= tol
        # d_n = phi^T (K1 + 2 kappa K2)(1 + i eta) phi
        k1phi = self.K1 @ phi
        k2phi = self.K2 @ phi
        d = np.einsum("in,in->n", phi, k1phi + 2 * lam[None, :] * k2phi) * (1 + 1j * eta)
        sel = lam.imag < -tol
        if np.any(prop):
            # group velocity sign: d omega / d kappa = d / (2 omega phi^T M phi) (free rail)
            mm = np.einsum("in,in->n", phi, self.M @ phi)
            cg = (d / (2 * omega * mm)).real
            sel |= prop & (cg > 0)
        if sel.sum() != n:
            logger.warning("omega=%.4g: %d waves selected, expected %d", omega, sel.sum(), n)
        lam, phi, d = lam[sel], phi[:, sel], d[sel]
        pr = self.P.astype(complex).copy()
        pf = self.P.astype(complex).copy()
        # x column: response weights times i, force weights times -i (U = T V)
        pr[:, 0] *= 1j
        pf[:, 0] *= -1j
        a = pr.T @ phi  # (3, n)
        b = phi.T @ pf  # (n, 3)
        q = -1j * np.einsum("in,nj->nij", a, b) / d[:, None, None]
        return Waves(omega=float(omega), kappa=lam, q=q, label=self._labels(phi))

    def _labels(self, phi):
        """Dominant motion of each wave from the kinetic-energy shares of the section
        displacements (longitudinal, lateral, vertical, rotation about x)."""
        full = phi if self.basis is None else self.basis @ phi
        nodes = self.mesh.nodes
        ux, uy, uz = full[0::3], full[1::3], full[2::3]
        # rigid-body fits: translations and rotation about the shear-free centroid (area average)
        yc, zc = nodes.mean(axis=0)
        y, z = nodes[:, 0] - yc, nodes[:, 1] - zc
        rot = (np.einsum("i,in->n", y, uz) - np.einsum("i,in->n", z, uy)) / np.sum(y**2 + z**2)
        e_tot = np.sum(np.abs(ux) ** 2 + np.abs(uy) ** 2 + np.abs(uz) ** 2, axis=0)
        e_x = np.sum(np.abs(ux) ** 2, axis=0)
        e_y = np.abs(uy.mean(axis=0)) ** 2 * len(y)
        e_z = np.abs(uz.mean(axis=0)) ** 2 * len(y)
        e_r = np.abs(rot) ** 2 * np.sum(y**2 + z**2)
        shares = np.stack([e_x, e_y, e_z, e_r], 0) / e_tot
        lab = np.argmax(shares, axis=0)
        lab[shares.max(axis=0) < 0.5] = 4
        return lab


def dispersion(waveguide: RailWaveguide, frequencies):
    """Wavenumbers of the +x waves over a frequency grid.

    Parameters
    ----------
    waveguide : RailWaveguide
    frequencies : array_like (nf,)
        Hz, > 0.

    Returns
    -------
    dict
        ``frequency`` (nf,) Hz; ``wavenumber`` (nf, n) complex rad/m sorted by decay
        (|Im kappa| ascending); ``decay`` (nf, n) dB/m; ``label`` (nf, n) int (see LABELS).
    """
    f = np.asarray(frequencies, float)
    out_k, out_l = [], []
    for fi in f:
        w = waveguide.waves(2 * np.pi * fi)
        order = np.argsort(np.abs(w.kappa.imag))
        out_k.append(w.kappa[order])
        out_l.append(w.label[order])
    nmin = min(len(k) for k in out_k)
    k = np.array([kk[:nmin] for kk in out_k])
    lab = np.array([ll[:nmin] for ll in out_l])
    return {"frequency": f, "wavenumber": k, "decay": -20 * np.log10(np.e) * k.imag, "label": lab}


def full_kappa_solver(mesh, track: TrackParams, omega: float, load: str = "patch"):
    """Sparse solver of the *unreduced* model in the wavenumber domain, for checks.

    Returns
    -------
    callable
        ``solve(kappa) -> (3, 3)`` complex: the patch-averaged displacement (contact frame)
        due to a unit force per unit wavenumber spread over the patch width (m/N m).
    """
    mats = assemble(mesh, track.youngs_modulus, track.poisson_ratio)
    eta = track.loss_factor
    p = patch_weights(mesh, track.contact_lateral_position, track.load_patch_width) \
        if load == "patch" else section_weights(mesh)
    base = -omega**2 * mats.M.astype(complex)
    if track.supported:
        sup = foot_support(mesh)
        for (kp0, kb0), mb, c in zip(track.support_layers(), sup.mb, sup.c):
            kp = kp0 * (1 + 1j * track.pad_loss_factor)
            kb = kb0 * (1 + 1j * track.ballast_loss_factor) - omega**2 * track.sleeper_mass
            cs = sp.csr_matrix(c[:, None])
            base = base + kp / sup.width * mb - kp**2 / (kp + kb) / sup.width**2 * (cs @ cs.T)
    pr = p.astype(complex)
    pf = p.astype(complex)
    pr[:, 0] *= 1j
    pf[:, 0] *= -1j

    def solve(kappa):
        d = (mats.K0 + kappa * mats.K1s + kappa**2 * mats.K2) * (1 + 1j * eta) + base
        return pr.T @ spla.splu(d.tocsc()).solve(pf)

    return solve
