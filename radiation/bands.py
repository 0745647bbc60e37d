"""One-third octave bands (IEC 61260-1, base 10) and the A-weighting of IEC 61672-1.

Spectra in this package are sampled on a frequency grid (per bin, power or mean square) and
summed into one-third octave bands here, so that every spectrum in the toolkit has the same band
edges.
"""

from __future__ import annotations

import numpy as np

BAND_INDEX_MIN = -17
"""Lowest band: 1000 Hz x 10^(-17/10) = 20 Hz."""
BAND_INDEX_MAX = 11
"""Highest band: 1000 Hz x 10^(11/10) = 12.6 kHz (nominal 12.5 kHz)."""


def third_octave_centres(index_min=BAND_INDEX_MIN, index_max=BAND_INDEX_MAX):
    """Exact mid-band frequencies ``1000 x 10^(k/10)`` Hz, k = index_min..index_max (IEC 61260-1)."""
    k = np.arange(index_min, index_max + 1)
    return 1000.0 * 10.0 ** (k / 10.0)


def third_octave_edges(centres):
    """Lower and upper band-edge frequencies ``f_m x 10^(∓1/20)`` (Hz), each shape of ``centres``."""
    centres = np.asarray(centres, dtype=float)
    return centres * 10.0 ** (-1.0 / 20.0), centres * 10.0 ** (1.0 / 20.0)


R10 = (1.0, 1.25, 1.6, 2.0, 2.5, 3.15, 4.0, 5.0, 6.3, 8.0)
"""Preferred numbers of the R10 series: the nominal mid-band frequencies (IEC 61260-1, Annex E)."""


def nominal_label(frequency):
    """The nominal name of the band of an exact mid-band frequency (``"12.5k"``, ``"630"``)."""
    k = round(10.0 * np.log10(frequency / 1000.0))
    nominal = R10[k % 10] * 10.0 ** (3 + k // 10)
    if nominal >= 1000:
        text = f"{nominal / 1000:g}k"
    else:
        text = f"{nominal:g}"
    return text


def band_sum(frequency, values, centres):
    """Sum per-bin values (power or mean square) into bands.

    Parameters
    ----------
    frequency : (nf,) array_like
        Bin frequencies, Hz.
    values : (..., nf) array_like
        Per-bin quantities that add (W, Pa², (m/s)²).
    centres : (nb,) array_like
        Band mid-frequencies, Hz.

    Returns
    -------
    (..., nb) ndarray
        Sums over the bins inside each band ``[lower, upper)``.
    """
    frequency = np.asarray(frequency, dtype=float)
    values = np.asarray(values, dtype=float)
    lower, upper = third_octave_edges(centres)
    out = np.zeros(values.shape[:-1] + (len(lower),))
    for b, (lo, hi) in enumerate(zip(lower, upper)):
        inside = (frequency >= lo) & (frequency < hi)
        out[..., b] = values[..., inside].sum(axis=-1)
    return out


def a_weighting_db(frequency):
    """A-weighting A(f) in dB (IEC 61672-1:2013, eq. E.6 with the constant A_1000 = 2.00 dB).

    ``R_A(f) = f_4² f⁴ / ((f² + f_1²) sqrt((f² + f_2²)(f² + f_3²)) (f² + f_4²))`` with
    f_1 = 20.598997, f_2 = 107.65265, f_3 = 737.86223, f_4 = 12194.217 Hz, and
    ``A(f) = 20 log10 R_A(f) + 2.00`` dB.
    """
    f2 = np.asarray(frequency, dtype=float) ** 2
    f1, f2c, f3, f4 = 20.598997, 107.65265, 737.86223, 12194.217
    with np.errstate(divide="ignore"):
        ra = f4**2 * f2**2 / ((f2 + f1**2) * np.sqrt((f2 + f2c**2) * (f2 + f3**2)) * (f2 + f4**2))
        return 20.0 * np.log10(ra) + 2.00


def level_db(value, reference):
    """``10 log10(value / reference)`` for powers or mean squares (-inf for zero)."""
    with np.errstate(divide="ignore"):
        return 10.0 * np.log10(np.asarray(value, dtype=float) / reference)
