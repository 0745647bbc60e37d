"""Damping models of the track: hysteretic (constant loss factor, not causal) and causal
(generalised Zener / standard-linear-solid series with a nearly constant loss factor).

Every stiffness of the track (rail Young's modulus, pad and ballast stiffness) is the nominal
value times a complex, dimensionless factor ``e(omega)``:

``"hysteretic"``
    ``e = 1 + i eta sign(omega)``. Its real and imaginary parts are not a Hilbert pair, so
    the impulse response it implies is not causal (a precursor at t < 0).
``"viscous"`` (a spring with a dashpot in parallel, Kelvin-Voigt)
    ``e = 1 + i eta omega / omega_ref``: causal, storage stiffness nominal at every frequency,
    loss factor eta at ``f_ref`` only, proportional to frequency.
``"zener"``
    ``e(omega) = e_0 + sum_j a_j (i omega / omega_j) / (1 + i omega / omega_j)`` with
    relaxation frequencies ``omega_j`` log-uniform over (and a little beyond) the band
    ``[f_low, f_high]`` and weights ``e_0, a_j >= 0`` fitted by non-negative least squares
    to the constant-Q modulus (Kjartansson 1979)
    ``(omega / omega_ref)^(2 gamma) exp(i pi gamma) / cos(pi gamma)``,
    ``gamma = arctan(eta) / pi``, whose loss factor is exactly eta at every frequency.
    Each term is a spring in series with a dashpot (a Maxwell element) in parallel with the
    static spring ``e_0``: a passive, causal material whose loss factor is close to eta
    across the band and falls to 0 outside it. The storage part rises with frequency as
    Kramers-Kronig requires (about ``2 eta / pi`` per e-fold of frequency); the nominal
    stiffness is the storage stiffness at ``f_ref``: ``Re e(2 pi f_ref) = 1``.
"""

from __future__ import annotations

import dataclasses
import functools
import logging

import numpy as np
from scipy.optimize import nnls

logger = logging.getLogger(__name__)

__all__ = ["ZenerSeries", "zener_fit", "hysteretic_factor", "viscous_factor", "TrackDamping"]

#: relaxation frequencies per decade, and how far (factor) they extend beyond the band
TERMS_PER_DECADE = 3
BAND_EXTENSION = 3.0


@dataclasses.dataclass(frozen=True)
class ZenerSeries:
    """Normalised complex modulus of a generalised Zener (standard linear solid) series.

    Attributes
    ----------
    e0 : float
        Relaxed (static) modulus relative to the nominal one (-).
    weights : ndarray (J,)
        Relaxation strengths a_j (-), >= 0.
    omegas : ndarray (J,)
        Relaxation frequencies omega_j (rad/s).
    """

    e0: float
    weights: np.ndarray
    omegas: np.ndarray

    def __call__(self, omega):
        """Complex modulus factor e(omega) (-) at angular frequency ``omega`` (rad/s, any
        sign; e(-omega) = conj e(omega))."""
        s = 1j * np.asarray(omega, float)[..., None] / self.omegas
        return self.e0 + np.sum(self.weights * s / (1 + s), axis=-1)

    def loss_factor(self, omega):
        """Loss factor Im e / Re e (-) at ``omega`` (rad/s)."""
        e = self(omega)
        return e.imag / e.real

    @property
    def unrelaxed(self) -> float:
        """High-frequency limit e(inf) = e0 + sum a_j (-)."""
        return float(self.e0 + self.weights.sum())


@functools.lru_cache(maxsize=64)
def zener_fit(eta: float, f_low: float, f_high: float, f_ref: float) -> ZenerSeries:
    """Zener series with loss factor close to ``eta`` over ``[f_low, f_high]`` (Hz) and unit
    storage modulus at ``f_ref`` (Hz).

    Parameters
    ----------
    eta : float
        Target loss factor (-), >= 0.
    f_low, f_high : float
        Band of (nearly) constant loss factor (Hz), 0 < f_low < f_high.
    f_ref : float
        Frequency (Hz) at which the storage modulus equals the nominal one.

    Returns
    -------
    ZenerSeries
    """
    if eta == 0:
        return ZenerSeries(1.0, np.zeros(0), np.ones(0))
    lo, hi = f_low / BAND_EXTENSION, f_high * BAND_EXTENSION
    n_terms = int(np.ceil(TERMS_PER_DECADE * np.log10(hi / lo))) + 1
    omegas = 2 * np.pi * np.geomspace(lo, hi, n_terms)
    w = 2 * np.pi * np.geomspace(f_low, f_high, int(20 * np.log10(f_high / f_low)) + 2)
    gamma = np.arctan(eta) / np.pi
    target = (w / (2 * np.pi * f_ref)) ** (2 * gamma) * np.exp(1j * np.pi * gamma) / np.cos(np.pi * gamma)
    s = 1j * w[:, None] / omegas[None, :]
    basis = np.hstack([np.ones((len(w), 1)), s / (1 + s)]) / np.abs(target)[:, None]
    rhs = target / np.abs(target)
    x, _ = nnls(np.vstack([basis.real, basis.imag]), np.r_[rhs.real, rhs.imag])
    series = ZenerSeries(float(x[0]), x[1:], omegas)
    scale = series(2 * np.pi * f_ref).real  # exact normalisation at f_ref
    series = ZenerSeries(series.e0 / scale, series.weights / scale, omegas)
    err = np.abs(series.loss_factor(w) / eta - 1).max()
    logger.debug("Zener fit eta=%.3g over %.3g-%.3g Hz: %d terms, max loss-factor error %.2g",
                 eta, f_low, f_high, n_terms, err)
    return series


def hysteretic_factor(eta: float, omega):
    """Hysteretic factor 1 + i eta sign(omega) (-), with sign(0) = +1."""
    return 1 + 1j * eta * np.where(np.asarray(omega, float) < 0, -1.0, 1.0)


def viscous_factor(eta: float, omega, f_ref: float):
    """Kelvin-Voigt factor 1 + i eta omega / (2 pi f_ref) (-)."""
    return 1 + 1j * eta * np.asarray(omega, float) / (2 * np.pi * f_ref)


#: layer -> kind of factor, per track damping model
LAYER_MODELS = {
    "causal": {"rail": "zener", "pad": "zener", "ballast": "viscous"},
    "zener": {"rail": "zener", "pad": "zener", "ballast": "zener"},
    "hysteretic": {"rail": "hysteretic", "pad": "hysteretic", "ballast": "hysteretic"},
}


class TrackDamping:
    """Complex stiffness factors of rail, pad and ballast for a :class:`TrackParams`.

    ``damping_model = "causal"``: Zener series for rail and pad, viscous ballast;
    ``"zener"``: Zener series for all; ``"hysteretic"``: hysteretic for all.

    Parameters
    ----------
    track : waveguide.params.TrackParams
        Uses ``damping_model``, ``loss_factor``, ``pad_loss_factor``,
        ``ballast_loss_factor`` and the ``damping_*_frequency`` fields.
    """

    def __init__(self, track):
        self.model = track.damping_model
        self.kinds = LAYER_MODELS[self.model]
        self.reference_frequency = track.damping_reference_frequency
        self._eta = {"rail": track.loss_factor, "pad": track.pad_loss_factor,
                     "ballast": track.ballast_loss_factor}
        band = (track.damping_low_frequency, track.damping_high_frequency,
                track.damping_reference_frequency)
        self._series = {k: zener_fit(float(eta), *band) for k, eta in self._eta.items()
                        if self.kinds[k] == "zener"}

    @property
    def causal(self) -> bool:
        """True unless a layer is hysteretic."""
        return "hysteretic" not in self.kinds.values()

    def factor(self, which: str, omega):
        """Complex factor (-) of ``which`` in {"rail", "pad", "ballast"} at ``omega``
        (rad/s, scalar or array)."""
        kind = self.kinds[which]
        if kind == "hysteretic":
            return hysteretic_factor(self._eta[which], omega)
        if kind == "viscous":
            return viscous_factor(self._eta[which], omega, self.reference_frequency)
        return self._series[which](omega)
