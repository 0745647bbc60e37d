"""Waves of the supported rail: the quadratic eigenproblem in the wavenumber at each frequency.

Model: ``[K0 + kappa K1s + kappa^2 K2] e_r(omega) + Ks(omega) - omega^2 M] V = 0`` in the
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

from waveguide.damping import TrackDamping
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

    The dynamic stiffness is ``D(kappa, omega) = e_r(omega) (K0 + kappa K1 + kappa^2 K2)
    + Ks(omega) - omega^2 M`` with the complex modulus factor ``e_r`` of the rail and the
    support stiffness ``Ks`` from the pad and ballast factors (:mod:`waveguide.damping`).

    The coordinates are ordered axial first (``n_x`` coordinates carrying u_x only), then
    cross-sectional (u_y, u_z). K0, K2, M and Ks are block diagonal in this split and K1
    couples the blocks only (mirror symmetry of the rail in x), so the waves come in pairs
    +-kappa. With ``V_x = kappa Y`` the quadratic eigenproblem becomes the linear one
    ``(P + kappa^2 Q) [Y; V_t] = 0``, ``P = [[A_xx, K1_xt], [0, A_tt]]``,
    ``Q = [[K2_xx, 0], [K1_tx, K2_tt]]``, ``A = K0 + (Ks - omega^2 M) / e_r``: one
    n x n eigenproblem per frequency instead of the 2n x 2n companion form, with Q constant.

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
    basis_mode_factor = 1.0
    basis_max_modes = 60
    basis_n_kappa = 5
    basis_n_static = 6

    def __init__(self, mesh, track: TrackParams, basis_frequency: float | None = None,
                 load: str = "patch"):
        self.mesh = mesh
        self.track = track
        self.damping = TrackDamping(track)
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
            basis, n_x = _axial_first(self.n_full)
        else:
            basis, n_x = self._ritz_basis(mats, sup, p, basis_frequency)
        self.basis = basis
        self.n_x = n_x
        n = basis.shape[1]
        axial = np.arange(n) < n_x
        same = axial[:, None] == axial[None, :]

        def red(a, keep=None):
            a = a.toarray() if sp.issparse(a) else np.asarray(a)
            r = basis.T @ a @ basis if a.ndim == 2 else basis.T @ a
            if keep is not None:  # zero the blocks that vanish by symmetry (round-off only)
                r = np.where(keep, r, 0.0)
            return r

        self.K0, self.K2, self.M = (red(a, same) for a in (mats.K0, mats.K2, mats.M))
        self.K1 = red(mats.K1s, ~same)
        self.P = basis.T @ p
        if sup is not None:
            self.sup = ([red(a, same) for a in sup.mb], [red(c) for c in sup.c], sup.width)
        else:
            self.sup = None
        # constant parts of Q^-1 P(omega) (see the class docstring)
        q = np.where(same, self.K2, 0.0)
        q[n_x:, :n_x] = self.K1[n_x:, :n_x]
        p0 = self.K0.copy()
        p0[:n_x, n_x:] = self.K1[:n_x, n_x:]
        lu = sla.lu_factor(q)
        self._qinv = lambda a: sla.lu_solve(lu, a)
        self._c0 = self._qinv(p0)
        self._cm = self._qinv(self.M)
        if self.sup is not None:
            self._cs = [self._qinv(a) for a in self.sup[0]]
            self._cc = [self._qinv(c) for c in self.sup[1]]
        self.n = n
        logger.info("rail waveguide: %d DOF (%d axial; full %d), damping %s", n, n_x, self.n_full,
                    track.damping_model)

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
            # fixed start vector: the basis (and the results) are reproducible run to run
            w2, v = spla.eigsh(kk, k=n_ev, M=mats.M, sigma=shift, which="LM",
                               v0=np.ones(kk.shape[0]))
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
        # every vector into its axial and cross-sectional parts and orthonormalise the two
        # sets separately, so that the basis is S-invariant, the reduced model keeps
        # D(-kappa) = S D(kappa) S and the axial coordinates come first
        is_x = (np.arange(v.shape[0]) % 3) == 0
        m = mats.M

        def orthonormal(w):
            w = w[:, np.linalg.norm(w, axis=0) > 0]
            w = w / np.sqrt(np.einsum("ij,ij->j", w, m @ w))  # unit M-norm
            lam, u = np.linalg.eigh(w.T @ (m @ w))
            keep = lam > lam.max() * 1e-10  # drop dependent vectors
            return w @ (u[:, keep] / np.sqrt(lam[keep]))

        bx, bt = orthonormal(v * is_x[:, None]), orthonormal(v * ~is_x[:, None])
        basis = np.hstack([bx, bt])
        logger.info("Ritz basis: %d vectors (%d axial) from %d candidates (up to %.0f Hz, "
                    "kappa <= %.1f rad/m)", basis.shape[1], bx.shape[1], 2 * v.shape[1], fmax, kmax)
        return basis, bx.shape[1]

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
        """Per direction (x, y, z): (kp / b, kp^2 / (kp + kb - omega^2 ms) / b^2)."""
        t = self.track
        fp = complex(self.damping.factor("pad", omega))
        fb = complex(self.damping.factor("ballast", omega))
        out = []
        for kp0, kb0 in t.support_layers():
            kp = kp0 * fp
            kb = kb0 * fb - omega**2 * t.sleeper_mass
            b = self.sup[2]
            out.append((kp / b, kp**2 / (kp + kb) / b**2))
        return out

    # ------------------------------------------------------------------- waves
    def rail_factor(self, omega):
        """Complex modulus factor of the rail steel at ``omega`` (rad/s) (-)."""
        return complex(self.damping.factor("rail", omega))

    def dynamic_matrix(self, kappa, omega):
        """D(kappa, omega) in the symmetric form (reduced coordinates)."""
        return ((self.K0 + kappa * self.K1 + kappa**2 * self.K2) * self.rail_factor(omega)
                + self.support_stiffness(omega) - omega**2 * self.M)

    def receptance_kappa(self, kappa, omega):
        """Wavenumber-domain receptance (3, 3) at real ``kappa`` (rad/m) and ``omega`` (rad/s)
        by a direct solve: a second method for checking the wave sum."""
        pr = self.P.astype(complex)
        pf = pr.copy()
        pr[:, 0] *= 1j
        pf[:, 0] *= -1j
        return pr.T @ np.linalg.solve(self.dynamic_matrix(kappa, omega), pf)

    def receptance_kappa_many(self, kappa, omega, chunk=16):
        """:meth:`receptance_kappa` at many points at once: ``kappa`` (nk,) rad/m real and
        ``omega`` (nk,) or scalar rad/s; returns (nk, 3, 3). The same dynamic stiffness
        ``D(kappa, omega)`` assembled and solved in small batches (for wavenumber
        integrations)."""
        kappa = np.atleast_1d(np.asarray(kappa, float))
        omega = np.broadcast_to(np.asarray(omega, float), kappa.shape)
        pr = self.P.astype(complex)
        pf = pr.copy()
        pr[:, 0] *= 1j
        pf[:, 0] *= -1j
        nk, n = len(kappa), self.n
        # per-point scalars: rail factor, and per support direction a, g (see _support_coeffs)
        er = np.broadcast_to(np.asarray(self.damping.factor("rail", omega), complex), (nk,))
        sup = []
        if self.sup is not None:
            t = self.track
            mb, c, b = self.sup
            fp = np.asarray(self.damping.factor("pad", omega), complex)
            fb = np.asarray(self.damping.factor("ballast", omega), complex)
            for (kp0, kb0), mbi, ci in zip(t.support_layers(), mb, c):
                kp = kp0 * fp
                kb = kb0 * fb - omega**2 * t.sleeper_mass
                sup.append((kp / b, kp**2 / (kp + kb) / b**2, mbi, np.outer(ci, ci)))
        out = np.empty((nk, 3, 3), complex)
        d = np.empty((chunk, n, n), complex)
        for lo in range(0, nk, chunk):
            sl = slice(lo, min(lo + chunk, nk))
            m = sl.stop - sl.start
            k, w = kappa[sl, None, None], omega[sl, None, None]
            dd = d[:m]
            dd[:] = self.K0
            dd += k * self.K1
            dd += k**2 * self.K2
            dd *= er[sl, None, None]
            dd -= w**2 * self.M
            for a, g, mbi, cc in sup:
                dd += a[sl, None, None] * mbi
                dd -= g[sl, None, None] * cc
            x = np.linalg.solve(dd, np.broadcast_to(pf, (m,) + pf.shape))
            out[sl] = np.einsum("ia,kib->kab", pr, x)
        return out

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
        n, n_x = self.n, self.n_x
        er = self.rail_factor(omega)
        c = -omega**2 * self._cm
        if self.sup is not None:
            for (a, g), csi, cci, ci in zip(self._support_coeffs(omega), self._cs, self._cc,
                                            self.sup[1]):
                c = c + a * csi - g * np.outer(cci, ci)
        c = self._c0 + c / er
        lam, z = sla.eig(c, check_finite=False, overwrite_a=True)
        kappa = np.sqrt(-lam)  # (P + kappa^2 Q) z = 0
        kappa = np.where(kappa.imag > 0, -kappa, kappa)  # decaying towards +x
        phi = z.copy()
        phi[:n_x] *= kappa[None, :]  # V_x = kappa Y
        # d_n = phi^T dD/dkappa phi = e_r phi^T (K1 + 2 kappa K2) phi
        d = np.einsum("in,in->n", phi, self.K1 @ phi + 2 * kappa[None, :] * (self.K2 @ phi)) * er
        tol = 1e-7 * np.maximum(np.abs(kappa), 1e-3)
        prop = np.abs(kappa.imag) <= tol
        if np.any(prop):
            # undamped propagating wave: the one with positive group velocity
            # d omega / d kappa = d / (2 omega phi^T M phi) goes to +x; kappa -> -kappa maps
            # phi to S phi and d to -d
            mm = np.einsum("in,in->n", phi, self.M @ phi)
            flip = prop & ((d / (2 * omega * mm)).real < 0)
            kappa = np.where(flip, -kappa, kappa)
            phi[:n_x] *= np.where(flip, -1.0, 1.0)[None, :]
            d = np.where(flip, -d, d)
        pr = self.P.astype(complex).copy()
        pf = self.P.astype(complex).copy()
        # x column: response weights times i, force weights times -i (U = T V)
        pr[:, 0] *= 1j
        pf[:, 0] *= -1j
        a = pr.T @ phi  # (3, n)
        b = phi.T @ pf  # (n, 3)
        q = -1j * np.einsum("in,nj->nij", a, b) / d[:, None, None]
        return Waves(omega=float(omega), kappa=kappa, q=q, label=self._labels(phi))

    def _labels(self, phi):
        """Dominant motion of each wave from the kinetic-energy shares of the section
        displacements (longitudinal, lateral, vertical, rotation about x)."""
        if not hasattr(self, "_label_ops"):
            self._label_ops = self._label_operators()
        g_tot, g_x, r = self._label_ops
        e_tot = np.einsum("in,in->n", phi.conj(), g_tot @ phi).real
        e_x = np.einsum("in,in->n", phi.conj(), g_x @ phi).real
        e_yzr = np.abs(r @ phi) ** 2  # (3, n): lateral, vertical, rotation
        shares = np.vstack([e_x[None], e_yzr]) / e_tot
        lab = np.argmax(shares, axis=0)
        lab[shares.max(axis=0) < 0.5] = 4
        return lab

    def _label_operators(self):
        """Reduced operators of :meth:`_labels`: sum |u|^2, sum |u_x|^2 (quadratic forms) and
        the rigid-body fits (lateral, vertical translation; rotation about the area centre of
        the nodes), scaled so that |r phi|^2 is the share of sum |u|^2 they carry."""
        b = self.basis
        bx, by, bz = b[0::3], b[1::3], b[2::3]
        nodes = self.mesh.nodes
        n_nodes = len(nodes)
        yc, zc = nodes.mean(axis=0)
        y, z = nodes[:, 0] - yc, nodes[:, 1] - zc
        ip = np.sum(y**2 + z**2)
        r = np.vstack([by.sum(axis=0) / np.sqrt(n_nodes), bz.sum(axis=0) / np.sqrt(n_nodes),
                       (y @ bz - z @ by) / np.sqrt(ip)])
        return b.T @ b, bx.T @ bx, r


def _axial_first(n_dof):
    """Permutation basis (n_dof, n_dof) putting the axial DOF (``dof % 3 == 0``) first."""
    order = np.r_[np.arange(0, n_dof, 3), np.flatnonzero(np.arange(n_dof) % 3)]
    basis = np.zeros((n_dof, n_dof))
    basis[order, np.arange(n_dof)] = 1.0
    return basis, n_dof // 3


def dispersion(waveguide: RailWaveguide, frequencies, wave_list=None):
    """Wavenumbers of the +x waves over a frequency grid.

    Parameters
    ----------
    waveguide : RailWaveguide
    frequencies : array_like (nf,)
        Hz, > 0.
    wave_list : list of Waves, optional
        The waves at ``frequencies`` if already computed.

    Returns
    -------
    dict
        ``frequency`` (nf,) Hz; ``wavenumber`` (nf, n) complex rad/m sorted by decay
        (|Im kappa| ascending); ``decay`` (nf, n) dB/m; ``label`` (nf, n) int (see LABELS).
    """
    f = np.asarray(frequencies, float)
    out_k, out_l = [], []
    if wave_list is None:
        wave_list = [waveguide.waves(2 * np.pi * fi) for fi in f]
    for w in wave_list:
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
    damping = TrackDamping(track)
    er = complex(damping.factor("rail", omega))
    p = patch_weights(mesh, track.contact_lateral_position, track.load_patch_width) \
        if load == "patch" else section_weights(mesh)
    base = -omega**2 * mats.M.astype(complex)
    if track.supported:
        sup = foot_support(mesh)
        fp = complex(damping.factor("pad", omega))
        fb = complex(damping.factor("ballast", omega))
        for (kp0, kb0), mb, c in zip(track.support_layers(), sup.mb, sup.c):
            kp = kp0 * fp
            kb = kb0 * fb - omega**2 * track.sleeper_mass
            cs = sp.csr_matrix(c[:, None])
            base = base + kp / sup.width * mb - kp**2 / (kp + kb) / sup.width**2 * (cs @ cs.T)
    pr = p.astype(complex)
    pf = p.astype(complex)
    pr[:, 0] *= 1j
    pf[:, 0] *= -1j

    def solve(kappa):
        d = (mats.K0 + kappa * mats.K1s + kappa**2 * mats.K2) * er + base
        return pr.T @ spla.splu(d.tocsc()).solve(pf)

    return solve
