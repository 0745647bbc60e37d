"""Classification of wheel modes: nodal diameters, nodal circles and family.

Both solvers are classified by the same rule, applied to the mode's *section amplitudes*
``(U_r, U_z, U_θ)`` of its dominant circumferential harmonic ``n`` (docs/conventions.md):

- the axisymmetric solver provides them directly;
- a 3D shape is first projected on circumferential harmonics ring by ring
  (:func:`harmonic_projection`): the nodes sharing one (r, z) position form a ring sampled at
  uniform angles, a discrete Fourier sum gives each harmonic's amplitude, and ``n`` is the
  harmonic with the largest mass-weighted energy.

Family: the component with the largest share of ``Σ r (U_c)²`` over the section: ``"axial"``
(u_z, out-of-plane), ``"radial"`` (u_r) or ``"circumferential"`` (u_θ; torsional for n = 0).
Nodal circles: sign changes of that component along the radius, after averaging it in radial
bins and ignoring bins below 10 % of the largest amplitude.
"""

from __future__ import annotations

import numpy as np

FAMILIES = ("radial", "axial", "circumferential")  # index = component of (U_r, U_z, U_theta)


def cylindrical_components(points, vectors):
    """Cylindrical components (u_r, u_z, u_θ) of Cartesian vectors at 3D points.

    Parameters
    ----------
    points : (N, 3) array_like
        Positions (X, Y, Z), m; the axle is the Y axis (docs/conventions.md).
    vectors : (..., N, 3) array_like
        Cartesian components.

    Returns
    -------
    r, z, theta : (N,) ndarray
        Radius (m), axial position (m), angle (rad, 0 at the bottom).
    components : (..., N, 3) ndarray
        (u_r, u_z, u_θ).
    """
    p = np.asarray(points, dtype=float)
    v = np.asarray(vectors, dtype=float)
    r = np.hypot(p[:, 0], p[:, 2])
    theta = np.arctan2(p[:, 0], -p[:, 2])
    s, c = np.sin(theta), np.cos(theta)
    ur = v[..., 0] * s - v[..., 2] * c
    ut = v[..., 0] * c + v[..., 2] * s
    return r, p[:, 1], theta, np.stack([ur, v[..., 1], ut], axis=-1)


def ring_index(r, z, tolerance=1e-7):
    """Group points by their (r, z) position.

    Returns
    -------
    ring : (N,) int ndarray
        Ring number of each point.
    ring_rz : (n_rings, 2) ndarray
        (r, z) of each ring, m.
    """
    key = np.round(np.column_stack([r, z]) / tolerance).astype(np.int64)
    unique, ring = np.unique(key, axis=0, return_inverse=True)
    return ring.ravel(), unique * tolerance


def harmonic_projection(points, shapes, n_max):
    """Project 3D mode shapes on circumferential harmonics, ring by ring.

    Parameters
    ----------
    points : (N, 3) array_like
        Node positions of a mesh of revolution, m.
    shapes : (m, N, 3) array_like
        Cartesian mode shapes.
    n_max : int
        Highest harmonic considered.

    Returns
    -------
    dominant : (m,) int ndarray
        Harmonic with the largest energy ``Σ_rings r |c_n|²``.
    section : (m, n_rings, 3) ndarray
        Real section amplitudes (U_r, U_z, U_θ) of the dominant harmonic, in the family-"cos"
        orientation of docs/conventions.md, turned to the phase that makes them real.
    ring_rz : (n_rings, 2) ndarray
        Ring positions (r, z), m.
    energy : (m, n_max + 1) ndarray
        Energy per harmonic (arbitrary scale).
    """
    r, z, theta, comp = cylindrical_components(points, shapes)
    ring, ring_rz = ring_index(r, z)
    n_rings = ring_rz.shape[0]
    count = np.bincount(ring, minlength=n_rings).astype(float)
    m = comp.shape[0]
    coeff = np.zeros((m, n_max + 1, n_rings, 3), dtype=complex)
    for n in range(n_max + 1):
        phase = np.exp(-1j * n * theta)
        for c in range(3):
            weighted = comp[:, :, c] * phase[None, :]
            for k in range(m):
                coeff[k, n, :, c] = (
                    np.bincount(ring, weighted[k].real, n_rings) + 1j * np.bincount(ring, weighted[k].imag, n_rings)
                ) / count
    weight = ring_rz[:, 0]
    energy = np.einsum("mnrc,r->mn", np.abs(coeff) ** 2, weight)
    dominant = np.argmax(energy, axis=1)
    section = np.zeros((m, n_rings, 3))
    for k in range(m):
        c = coeff[k, dominant[k]].copy()
        # family "cos": u_r, u_z ~ cos(n theta - a), u_theta ~ sin(n theta - a): multiplying the
        # theta coefficient by i puts all three on one phase.
        c[:, 2] *= 1j
        flat = c.ravel()
        # phase that maximises the real part's norm (principal direction in the complex plane)
        angle = 0.5 * np.angle(np.sum(flat * flat))
        section[k] = np.real(c * np.exp(-1j * angle))
    return dominant, section, ring_rz, energy


def classify_section_mode(section_rz, amplitudes, bin_width=None):
    """Family and number of nodal circles of a mode from its section amplitudes.

    Parameters
    ----------
    section_rz : (Ns, 2) array_like
        (r, z) of the section nodes (or rings), m.
    amplitudes : (Ns, 3) array_like
        (U_r, U_z, U_θ) at those nodes.
    bin_width : float, optional
        Radial bin width for counting sign changes, m; default: 1/40 of the radial extent.

    Returns
    -------
    family : str
        ``"radial"``, ``"axial"`` or ``"circumferential"``.
    nodal_circles : int
    fractions : (3,) ndarray
        Share of ``Σ r U_c²`` of each component (r, z, θ).
    """
    rz = np.asarray(section_rz, dtype=float)
    u = np.asarray(amplitudes, dtype=float)
    weights = rz[:, 0]
    share = np.einsum("n,nc->c", weights, u**2)
    fractions = share / share.sum() if share.sum() > 0 else np.full(3, 1 / 3)
    dominant = int(np.argmax(fractions))
    r = rz[:, 0]
    width = bin_width or (r.max() - r.min()) / 40.0
    bins = np.floor((r - r.min()) / width).astype(int)
    n_bins = bins.max() + 1
    total = np.bincount(bins, u[:, dominant] * weights, n_bins)
    norm = np.bincount(bins, weights, n_bins)
    profile = np.divide(total, norm, out=np.zeros(n_bins), where=norm > 0)
    significant = profile[np.abs(profile) >= 0.1 * np.abs(profile).max()]
    nodal_circles = int(np.count_nonzero(np.diff(np.sign(significant)) != 0))
    return FAMILIES[dominant], nodal_circles, fractions
