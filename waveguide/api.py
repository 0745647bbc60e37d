"""Entry points for the pipeline stages ``rail-mesh`` and ``rail-greens``.

All functions take the section mesh (:class:`mesh.rail_mesh.RailMesh`) and the ``[track]``
parameters (:class:`waveguide.params.TrackParams`) and build the reduced waveguide model
internally (or accept a prebuilt ``waveguide`` to reuse it).
"""

from __future__ import annotations

import logging

import numpy as np

from waveguide import greens, response, waves
from waveguide.params import TrackParams

logger = logging.getLogger(__name__)

__all__ = ["build_waveguide", "dispersion", "receptance_along", "moving_kernel", "rail_greens"]


def build_waveguide(section_mesh, track: TrackParams, max_frequency: float | None = None):
    """Reduced waveguide model valid up to ``max_frequency`` (Hz, default
    ``track.max_frequency``); the Ritz basis is built up to 1.25 times that."""
    fmax = track.max_frequency if max_frequency is None else max_frequency
    return waves.RailWaveguide(section_mesh, track, basis_frequency=1.25 * fmax)


def dispersion(section_mesh, track: TrackParams, frequencies, waveguide=None):
    """Wavenumbers (rad/m), decay rates (dB/m) and labels of the +x waves.

    Returns the dict of :func:`waveguide.waves.dispersion`: ``frequency`` (nf,) Hz,
    ``wavenumber`` (nf, n) complex, ``decay`` (nf, n) dB/m, ``label`` (nf, n) int.
    """
    f = np.asarray(frequencies, float)
    wg = waveguide or build_waveguide(section_mesh, track, max(f.max(), 100.0))
    return waves.dispersion(wg, f)


def receptance_along(section_mesh, track: TrackParams, frequencies, distances, waveguide=None):
    """Receptance H (n_x, nf, 3, 3) complex m/N at distances x >= 0 (m) from the load, contact
    frame, at ``frequencies`` (Hz, > 0)."""
    f = np.asarray(frequencies, float)
    wg = waveguide or build_waveguide(section_mesh, track, max(f.max(), 100.0))
    return response.receptance_along(wg, f, distances)


def moving_kernel(section_mesh, track: TrackParams, speed: float, time_step: float,
                  waveguide=None, **kwargs):
    """Moving Green's kernel, see :func:`waveguide.greens.moving_kernel` for the returned
    dict (``kernel`` (nt, 3, 3) m/N, ``frequency`` Hz, ``moving_receptance`` (nf, 3, 3) m/N,
    ``static_compliance`` (3, 3) m/N, ...)."""
    wg = waveguide or build_waveguide(section_mesh, track, min(track.max_frequency, 1.0 / time_step))
    return greens.moving_kernel(wg, speed, time_step, **kwargs)


def rail_greens(section_mesh, track: TrackParams, speed: float, time_step: float,
                frequencies=None, distances=None, moving=True):
    """Everything ``rail_greens.h5`` holds, from one waveguide model.

    Parameters
    ----------
    section_mesh : mesh.rail_mesh.RailMesh
    track : TrackParams
    speed : float
        Train speed (m/s).
    time_step : float
        s.
    frequencies : array_like, optional
        Receptance/dispersion grid (Hz); default 200 log-spaced points 20 Hz - max frequency.
    distances : array_like, optional
        m; default 0, 0.1, ..., 3 m... (31 points).
    moving : bool
        Compute the moving kernel (else ``moving`` is None: the caller computes it elsewhere,
        e.g. at another contact position with :func:`moving_kernel`).

    Returns
    -------
    dict
        ``frequency`` (nf,) Hz, ``distance`` (n_x,) m, ``receptance`` (n_x, nf, 3, 3) m/N,
        ``wavenumbers`` (nf, n) rad/m, ``decay`` (nf, n) dB/m, ``wave_label`` (nf, n),
        ``moving`` (dict of :func:`waveguide.greens.moving_kernel`, or None).
    """
    fmax = min(track.max_frequency, 1.0 / time_step)
    wg = build_waveguide(section_mesh, track, fmax)
    f = np.geomspace(20.0, fmax, 200) if frequencies is None else np.asarray(frequencies, float)
    x = np.linspace(0.0, 3.0, 31) if distances is None else np.asarray(distances, float)
    wave_list = [wg.waves(2 * np.pi * fi) for fi in f]
    disp = waves.dispersion(wg, f, wave_list)
    rec = response.receptance_along(wg, f, x, wave_list)
    mov = greens.moving_kernel(wg, speed, time_step) if moving else None
    return {"frequency": f, "distance": x, "receptance": rec, "wavenumbers": disp["wavenumber"],
            "decay": disp["decay"], "wave_label": disp["label"], "moving": mov}
