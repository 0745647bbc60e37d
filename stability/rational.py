r"""Rational (pole-residue) model of a sampled 3×3 receptance by vector fitting.

The rail enters the closed-loop stability analysis (:mod:`stability.screen`) as a
state-space model; it is known only as sampled frequency responses (the wave sum or the
wavenumber integral of :mod:`waveguide`). This module fits

.. math::

    H(s) \approx \sum_{k=1}^{m} \left[\frac{R_k}{s - p_k} + \frac{\bar R_k}{s - \bar p_k}\right] + D
    \; (+\, s E),

the form of :func:`fe.greens.receptance` plus a direct term D (3×3, m/N) and optionally a
proportional term E, with one pole set for all nine components, by **vector fitting** with
relaxed pole identification (B. Gustavsen and A. Semlyen, "Rational approximation of frequency
domain responses by vector fitting", IEEE Trans. Power Delivery 14(3), 1999, 1052-1061;
B. Gustavsen, "Improving the pole relocating properties of vector fitting", IEEE Trans. Power
Delivery 21(3), 2006, 1587-1592), written here from the published algorithm:

1. start from complex pole pairs ``a = -α + iβ`` spread log-uniformly over the band, α = β/100;
2. pole identification: with the scaling function ``σ(s) = Σ c̃_n / (s - a_n) + d̃``, solve the
   linear least-squares problem ``Σ c_kn / (s - a_n) + d_k (+ s e_k) - σ(s) H_k(s) ≈ 0`` for all
   components k at once (a QR of every component's block leaves only the rows of the common
   unknowns c̃, d̃), with the relaxation constraint ``Re Σ_s σ(s) = N_s`` instead of d̃ = 1;
3. the new poles are the zeros of σ, the eigenvalues of ``Λ - b c̃ᵀ / d̃`` (real realisation);
   unstable ones are flipped into the left half plane (Re p → -Re p);
4. after the last iteration, poles far above the band (|p| > :data:`OUT_OF_BAND` 2π f_max) are
   dropped (they make D a negative compliance, see :func:`vector_fit`), and the residues, D
   (and E) follow from one linear least-squares problem per component with the poles fixed.

Every residue pair is complex conjugate by construction (real basis functions
``1/(s-a) + 1/(s-ā)`` and ``i/(s-a) - i/(s-ā)``), so the impulse response is real. A real pole
``p`` with real residue ``r`` is stored as pole ``p`` with residue ``r / 2`` (its "pair" is
itself). The samples are weighted by the inverse magnitude of each component (a relative
fit), floored at ``floor`` times the largest magnitude of all components.

Passivity: a receptance H (displacement per force, ``exp(+iωt)``) is passive when the power
``Re(F^H iωH F)`` is never negative, i.e. the mobility ``Y = iωH`` has ``Y + Y^H`` positive
semi-definite at every ω; :func:`passivity_violations` checks that on a grid.

scikit-rf's ``VectorFitting`` (skrf 2.x) implements the same algorithm, but for
:class:`skrf.Network` objects (S, Y or Z parameters of microwave networks) with passivity
defined for scattering parameters; wrapping a mechanical receptance into a network and adding a
dependency (and its own dependencies) for one linear least-squares loop was judged not worth
it, so the algorithm is implemented here.

The rail's continuous-time moving receptance that the fit takes as data is
:func:`rail_moving_receptance`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from squealcore.errors import InputError, require_range
from waveguide.response import receptance_along, wavenumber_integral

logger = logging.getLogger(__name__)

__all__ = ["RationalModel", "vector_fit", "evaluate", "passivity_violations", "rail_moving_receptance",
           "fit_rail"]


@dataclass(frozen=True)
class RationalModel:
    """Pole-residue model of a 3×3 receptance.

    Attributes
    ----------
    poles : (m,) complex ndarray
        rad/s, ``Re <= 0``, one of each conjugate pair (``Im >= 0``).
    residues : (m, 3, 3) complex ndarray
        m/(N s); the conjugate pole carries the conjugate residue.
    direct : (3, 3) ndarray
        D, m/N.
    proportional : (3, 3) ndarray
        E, m s/N (zero unless fitted).
    band : (2,) tuple of float or None
        The fitted band, Hz (None: valid at all frequencies, e.g. the rigid rail or a modal
        model). Outside it the model is an extrapolation.
    """

    poles: np.ndarray
    residues: np.ndarray
    direct: np.ndarray
    proportional: np.ndarray
    band: tuple | None = None

    @classmethod
    def rigid(cls):
        """The rigid rail: no poles, D = E = 0."""
        return cls(np.zeros(0, complex), np.zeros((0, 3, 3), complex), np.zeros((3, 3)), np.zeros((3, 3)))


def evaluate(model: RationalModel, frequency_hz):
    """Receptance (nf, 3, 3) complex, m/N, of ``model`` at ``frequency_hz`` (Hz)."""
    f = np.asarray(frequency_hz, dtype=float)
    s = 2j * np.pi * f[:, None]
    p = model.poles[None, :]
    a = 1.0 / (s - p)
    b = 1.0 / (s - np.conj(p))
    out = np.einsum("fm,mij->fij", a, model.residues) + np.einsum("fm,mij->fij", b, np.conj(model.residues))
    return out + model.direct[None] + s[:, :, None] * model.proportional[None]


#: poles with |p| above this multiple of the band's top (2π f_max) are dropped after the fit
OUT_OF_BAND = 3.0


def _starting_poles(f_min, f_max, n_pairs):
    beta = 2 * np.pi * np.geomspace(f_min, f_max, n_pairs)
    return -beta / 100.0 + 1j * beta


def _split(poles):
    """Poles as (real poles, upper complex poles): Im of a pair's member below 1e-9 |p| is real."""
    poles = np.asarray(poles, complex)
    real = np.abs(poles.imag) <= 1e-9 * np.abs(poles)
    return poles[real].real, poles[~real & (poles.imag > 0)]


def _basis(s, real_poles, pair_poles):
    """Real basis (Ns, N) for the given poles: 1/(s-a) per real pole; per pair
    1/(s-a) + 1/(s-ā) and i/(s-a) - i/(s-ā)."""
    cols = [1.0 / (s - a) for a in real_poles]
    for a in pair_poles:
        u, w = 1.0 / (s - a), 1.0 / (s - np.conj(a))
        cols += [u + w, 1j * u - 1j * w]
    return np.array(cols).T if cols else np.zeros((s.size, 0), complex)


def _ri(a):
    """Stack real and imaginary parts row-wise."""
    return np.concatenate([a.real, a.imag], axis=0)


def _relocate(s, data, weight, real_poles, pair_poles, proportional):
    """One relaxed pole identification; returns the new (real, pair) poles."""
    ns, nc = data.shape
    phi = _basis(s, real_poles, pair_poles)
    n = phi.shape[1]
    extra = [np.ones(ns)] + ([s] if proportional else [])
    own = np.column_stack([phi] + extra)  # (Ns, n_own): c_k, d_k (, e_k)
    n_own = own.shape[1]
    sig = np.column_stack([phi, np.ones(ns)])  # σ unknowns c̃, d̃
    blocks, rhs = [], []
    for k in range(nc):
        w = weight[:, k]
        a = _ri(np.column_stack([w[:, None] * own, -(w * data[:, k])[:, None] * sig]))
        scale = np.linalg.norm(a, axis=0)
        scale[scale == 0] = 1.0
        r = np.linalg.qr(a / scale, mode="r")
        blocks.append(r[n_own:, n_own:] * scale[n_own:])  # back to unscaled unknowns
        rhs.append(np.zeros(r.shape[0] - n_own))
    # relaxation: Re Σ_s σ(s) = Ns, weighted like an average equation of the data
    total = np.sqrt(sum(np.sum(np.abs(weight[:, k] * data[:, k]) ** 2) for k in range(nc)))
    row = np.concatenate([np.sum(phi.real, axis=0), [ns]]) * total / ns
    blocks.append(row[None, :])
    rhs.append(np.array([total]))
    m = np.vstack(blocks)
    colscale = np.linalg.norm(m, axis=0)
    colscale[colscale == 0] = 1.0
    x = np.linalg.lstsq(m / colscale, np.concatenate(rhs), rcond=None)[0] / colscale
    c, d = x[:n], x[n]
    if abs(d) < 1e-8:
        d = np.copysign(1e-8, d if d != 0 else 1.0)
    # real realisation of σ's poles: Λ, b, c̃
    lam = np.zeros((n, n))
    b = np.zeros(n)
    i = 0
    for a in real_poles:
        lam[i, i], b[i] = a, 1.0
        i += 1
    for a in pair_poles:
        lam[i:i + 2, i:i + 2] = [[a.real, a.imag], [-a.imag, a.real]]
        b[i] = 2.0
        i += 2
    zeros = scipy.linalg.eigvals(lam - np.outer(b, c) / d)
    zeros = np.where(zeros.real > 0, -zeros.real + 1j * zeros.imag, zeros)  # flip unstable poles
    return _split(zeros)


def _residues(s, data, weight, real_poles, pair_poles, proportional):
    """Residues (real, pair), D and E of every component with the poles fixed."""
    ns, nc = data.shape
    phi = _basis(s, real_poles, pair_poles)
    own = np.column_stack([phi, np.ones(ns)] + ([s] if proportional else []))
    n = phi.shape[1]
    x = np.empty((own.shape[1], nc))
    for k in range(nc):
        w = weight[:, k]
        a = _ri(w[:, None] * own)
        scale = np.linalg.norm(a, axis=0)
        scale[scale == 0] = 1.0
        x[:, k] = np.linalg.lstsq(a / scale, _ri(w * data[:, k]), rcond=None)[0] / scale
    nr = len(real_poles)
    res_real = x[:nr]
    pairs = x[nr:n]
    res_pair = pairs[0::2] + 1j * pairs[1::2]
    return res_real, res_pair, x[n], (x[n + 1] if proportional else np.zeros(nc))


def vector_fit(frequency_hz, receptance, n_pairs=20, n_iterations=15, proportional=False,
               floor=1e-4, symmetric=False):
    """Fit a :class:`RationalModel` to a sampled 3×3 receptance.

    Parameters
    ----------
    frequency_hz : (nf,) array_like
        Sample frequencies, Hz, > 0 (e.g. log-spaced over the band).
    receptance : (nf, 3, 3) complex array_like
        m/N, ``exp(+iωt)`` convention.
    n_pairs : int
        Number of complex pole pairs of the starting set (the model order is 2 n_pairs), >= 1.
    n_iterations : int
        Pole relocations, >= 1.
    proportional : bool
        Fit a proportional term E too (default: D only).
    floor : float
        Weights are ``1 / max(|H_ij|, floor max|H|)`` (relative fit of every component above the
        floor), -.
    symmetric : bool
        Fit the symmetric part ``(H + Hᵀ)/2`` (6 components) and mirror it (reciprocal data).

    Returns
    -------
    RationalModel
    """
    f = np.asarray(frequency_hz, dtype=float)
    h = np.asarray(receptance, dtype=complex)
    if f.ndim != 1 or f.size < 4 or np.any(f <= 0) or h.shape != (f.size, 3, 3):
        raise InputError("frequency_hz", "need >= 4 frequencies > 0 Hz and a receptance of shape (nf, 3, 3)")
    n_pairs = int(require_range("n_pairs", n_pairs, 1, 500))
    n_iterations = int(require_range("n_iterations", n_iterations, 1, 1000))
    if symmetric:
        h = 0.5 * (h + np.swapaxes(h, 1, 2))
        comps = [(i, j) for i in range(3) for j in range(i, 3)]
    else:
        comps = [(i, j) for i in range(3) for j in range(3)]
    data = np.column_stack([h[:, i, j] for i, j in comps])
    mag = np.abs(data)
    weight = 1.0 / np.maximum(mag, floor * mag.max())
    s = 2j * np.pi * f
    real_poles, pair_poles = np.zeros(0), _starting_poles(f.min(), f.max(), n_pairs)
    for _ in range(n_iterations):
        real_poles, pair_poles = _relocate(s, data, weight, real_poles, pair_poles, proportional)
    # poles far above the band model the data's trend across it, and with them D is often a
    # large negative compliance that the pole cancels in the band: out of the band (a real pole
    # at 1e7 1/s, D_zz = -4.7e-9 m/N for the quick study's rail) the model is then a negative
    # spring, which the closed loop turns into a spurious real instability. They are dropped
    # and D takes their in-band part (R/(s - p) ≈ -R/p for |s| << |p|).
    top = OUT_OF_BAND * 2 * np.pi * f.max()
    dropped = int(np.sum(np.abs(real_poles) > top) + 2 * np.sum(np.abs(pair_poles) > top))
    real_poles, pair_poles = real_poles[np.abs(real_poles) <= top], pair_poles[np.abs(pair_poles) <= top]
    rr, rp, d, e = _residues(s, data, weight, real_poles, pair_poles, proportional)
    poles = np.concatenate([real_poles.astype(complex), pair_poles])
    residues = np.zeros((poles.size, 3, 3), complex)
    direct = np.zeros((3, 3))
    prop = np.zeros((3, 3))
    for k, (i, j) in enumerate(comps):
        vals = np.concatenate([rr[:, k] / 2.0, rp[:, k]])
        for a, b in {(i, j), (j, i)} if symmetric else {(i, j)}:
            residues[:, a, b] = vals
            direct[a, b] = d[k]
            prop[a, b] = e[k]
    model = RationalModel(poles, residues, direct, prop, (float(f.min()), float(f.max())))
    err = np.abs(evaluate(model, f) - h)
    rel = np.max(err / np.maximum(np.abs(h), floor * np.abs(h).max()))
    logger.info("vector fit: %d poles (%d real, %d above the band dropped), %d iterations, largest "
                "weighted error %.2e", 2 * pair_poles.size + real_poles.size, real_poles.size, dropped,
                n_iterations, rel)
    return model


def passivity_violations(model: RationalModel, frequency_hz, tolerance=1e-9):
    """Frequencies where the model is not passive.

    The mobility ``Y = iωH`` must have ``Y + Y^H`` positive semi-definite (the power taken by
    the structure is never negative). Violations are the grid points where its smallest
    eigenvalue is below ``-tolerance`` times the largest eigenvalue magnitude of the grid.

    Parameters
    ----------
    model : RationalModel
    frequency_hz : (nf,) array_like
        Dense grid, Hz.
    tolerance : float
        Relative tolerance, -.

    Returns
    -------
    dict
        ``frequency`` (nv,) Hz of the violations, ``min_eigenvalue`` (nv,) m/(N s) there, and
        ``relative`` (nv,): that eigenvalue over the largest magnitude on the grid.
    """
    f = np.asarray(frequency_hz, dtype=float)
    y = 2j * np.pi * f[:, None, None] * evaluate(model, f)
    eig = np.linalg.eigvalsh(y + np.conj(np.swapaxes(y, 1, 2)))
    scale = np.abs(eig).max()
    low = eig[:, 0]
    bad = low < -tolerance * scale
    return {"frequency": f[bad], "min_eigenvalue": low[bad], "relative": low[bad] / scale}


def rail_moving_receptance(waveguide, speed, frequency_hz):
    """Continuous-time moving receptance of the rail at the contact (no discrete-time aliases).

    ``G~(Ω) = 1/(2π) ∫ Ĥ(κ, Ω + κv) sinc(κL/2) dκ``: the displacement under the load that moves
    with it at speed v, per unit harmonic force of frequency Ω seen by the contact (Nordborg's
    moving Green's function in the frequency domain; the reference of
    tests/test_waveguide_greens.py). At v = 0 it is the point receptance H(0, Ω) of the wave sum
    (:func:`waveguide.response.receptance_along`), one eigenproblem per frequency; for v > 0 the
    wavenumber integral (:func:`waveguide.response.wavenumber_integral`) with panels refined
    around the lightly damped waves, a few thousand cross-section solves per frequency.

    Parameters
    ----------
    waveguide : waveguide.waves.RailWaveguide
    speed : float
        v, m/s, in [0, 200].
    frequency_hz : (nf,) array_like
        Ω / 2π, Hz, > 0.

    Returns
    -------
    (nf, 3, 3) complex ndarray
        m/N, contact frame (x along the rail, y lateral, z up).
    """
    speed = require_range("operating.speed", speed, 0.0, 200.0, unit="m/s")
    f = np.atleast_1d(np.asarray(frequency_hz, dtype=float))
    if np.any(f <= 0):
        raise InputError("frequency_hz", "frequencies must be > 0 Hz")
    if speed == 0.0:
        return receptance_along(waveguide, f, [0.0])[0]
    length = waveguide.track.load_patch_length
    out = np.empty((f.size, 3, 3), complex)
    for i, fi in enumerate(f):
        omega = 2 * np.pi * fi
        bps = [(abs(k.real), max(4 * abs(k.imag), 0.02)) for k in waveguide.waves(omega).kappa
               if abs(k.imag) < 0.3 * abs(k.real) + 1]

        def solve(kappa, omega=omega):
            return waveguide.receptance_kappa_many(kappa, omega + kappa * speed)

        out[i] = wavenumber_integral(solve, [0.0], length, 2e4, bps, n_per_panel=6, panel_width=1.0,
                                     vectorized=True)[0].reshape(3, 3)
    return out


def fit_rail(waveguide, speed, f_min=20.0, f_max=8000.0, n_frequencies=240, n_pairs=24, n_iterations=15,
             symmetric=None):
    """Rational model of the rail's moving receptance over [f_min, f_max].

    Parameters
    ----------
    waveguide : waveguide.waves.RailWaveguide
    speed : float
        m/s.
    f_min, f_max : float
        Band, Hz, 0 < f_min < f_max.
    n_frequencies : int
        Log-spaced samples of the band.
    n_pairs, n_iterations : int
        See :func:`vector_fit`.
    symmetric : bool, optional
        Fit the symmetric part; default: when the data are symmetric to 1e-6 of their peak.

    Returns
    -------
    model : RationalModel
    frequency : (nf,) ndarray
        The samples, Hz.
    receptance : (nf, 3, 3) complex ndarray
        The data, m/N.
    """
    f_min = require_range("f_min", f_min, 0.0, None, low_open=True, unit="Hz")
    f_max = require_range("f_max", f_max, f_min, None, low_open=True, unit="Hz")
    f = np.geomspace(f_min, f_max, int(n_frequencies))
    h = rail_moving_receptance(waveguide, speed, f)
    if symmetric is None:
        symmetric = bool(np.abs(h - np.swapaxes(h, 1, 2)).max() <= 1e-6 * np.abs(h).max())
    model = vector_fit(f, h, n_pairs=n_pairs, n_iterations=n_iterations, symmetric=symmetric)
    return model, f, h
