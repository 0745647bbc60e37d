r"""Boundary-element reference for the radiation (bempp-cl, numba backend; optional dependency).

The exterior Neumann problem of the Helmholtz equation (time factor e^{-iωt}, the convention of
bempp-cl, whose Green's function is e^{ikr}/(4πr)) for a closed vibrating surface with normal
velocity v_n: ``∂p/∂n = i ω ρ v_n``. It is solved in the Burton–Miller form, free of the
interior (fictitious) resonances that spoil the plain direct formulation near the Dirichlet
eigenfrequencies of the interior (for a sphere first at ka = π):

``(½ I - K - η W) p = (-V + η (½ I + K')) ∂p/∂n``, ``η = i / k``,

with V, K, K', W the single-, double-, adjoint double-layer and hypersingular operators. The
pressure is piecewise linear (P1), the normal velocity piecewise constant (DP0). The radiated
power is ``W = ½ Re ∫ p v_n* dS`` and the radiation efficiency ``σ = W / (ρ c ½ ∫|v_n|² dS)``.

Why bempp-cl: a maintained open-source BEM library (MIT) with Helmholtz operators including the
hypersingular one (needed for Burton–Miller), a pure-Python install (numba backend; OpenCL not
needed) and numpy in and out. Its first use compiles the numba kernels (minutes on a loaded
2-core machine; cached afterwards).
"""

from __future__ import annotations

import logging
import time

import numpy as np
from scipy.special import spherical_jn, spherical_yn

from radiation.acoustics import AIR_DENSITY, SOUND_SPEED
from radiation.thin_disc import piston_normal_velocity, thin_disc_triangles
from squealcore.errors import InputError

logger = logging.getLogger(__name__)

try:  # optional dependency: `pip install curve-squeal[bem]`
    import bempp_cl.api as bempp
    from bempp_cl.api.operators.boundary import helmholtz, sparse
except ImportError:  # the fast model works without it; the BEM functions raise
    bempp = None


def available():
    """Whether bempp-cl can be imported."""
    return bempp is not None


def _require():
    if bempp is None:
        raise RuntimeError("the BEM reference needs bempp-cl: pip install bempp-cl (or curve-squeal[bem])")


def sphere_efficiency_exact(order, ka):
    """σ (-) of a sphere vibrating in the spherical harmonic of ``order`` (0 pulsating, 1 oscillating).

    ``σ_l = 1 / ((ka)² |h_l'(ka)|²)`` with h_l the spherical Hankel function (Junger & Feit 1986,
    §4): ``(ka)² / (1 + (ka)²)`` for l = 0, ``(ka)⁴ / (4 + (ka)⁴)`` for l = 1.
    """
    derivative = spherical_jn(order, ka, derivative=True) + 1j * spherical_yn(order, ka, derivative=True)
    return 1.0 / (ka**2 * np.abs(derivative) ** 2)


def grid_from_triangles(vertices, triangles):
    """A bempp grid from vertices (N, 3) m and triangles (T, 3) (outward-oriented)."""
    _require()
    return bempp.Grid(np.asarray(vertices, dtype=float).T.copy(), np.asarray(triangles, dtype=np.uint32).T.copy())


def radiated_power(grid, normal_velocity, frequency, rho=AIR_DENSITY, c=SOUND_SPEED, tol=1e-8, burton_miller=True):
    """Radiated power of a closed surface with a piecewise-constant normal velocity.

    Parameters
    ----------
    grid : bempp grid
        Closed surface, normals outward (into the air).
    normal_velocity : (T,) complex array_like
        Normal velocity amplitude per triangle, m/s.
    frequency : float
        Hz.
    rho, c : float
        Air density (kg/m³), speed of sound (m/s).
    tol : float
        GMRES tolerance.
    burton_miller : bool
        Couple the hypersingular equation with ``η = i/k`` (default). ``False`` solves the plain
        direct equation ``(½ I - K) p = -V ∂p/∂n``, valid only below the body's first interior
        Dirichlet eigenfrequency (a thin disc of thickness t: k ≥ π/t).

    Returns
    -------
    dict
        ``power`` (W), ``sigma`` (-), ``mean_square`` (``½ ∫|v_n|² dS``, m⁴/s²), ``seconds``,
        ``info`` (GMRES: 0 when converged), ``iterations`` (GMRES iterations).
    """
    _require()
    start = time.perf_counter()
    k = 2.0 * np.pi * frequency / c
    omega = 2.0 * np.pi * frequency
    p1 = bempp.function_space(grid, "P", 1)
    dp0 = bempp.function_space(grid, "DP", 0)
    identity_p = sparse.identity(p1, p1, p1)
    identity_g = sparse.identity(dp0, p1, p1)
    lhs = 0.5 * identity_p - helmholtz.double_layer(p1, p1, p1, k)
    rhs_op = -helmholtz.single_layer(dp0, p1, p1, k)
    if burton_miller:
        eta = 1j / k
        lhs = lhs - eta * helmholtz.hypersingular(p1, p1, p1, k)
        rhs_op = rhs_op + eta * (0.5 * identity_g + helmholtz.adjoint_double_layer(dp0, p1, p1, k))
    v = np.asarray(normal_velocity, dtype=complex)
    g = bempp.GridFunction(dp0, coefficients=1j * omega * rho * v)
    p, info, iterations = bempp.linalg.gmres(lhs, rhs_op * g, tol=tol, return_iteration_count=True)
    mass = sparse.identity(dp0, p1, p1).weak_form()  # (P1 test, DP0 trial): ∫ φ_i χ_j
    power = 0.5 * float(np.real(np.vdot(mass @ v, p.coefficients)))
    areas = grid.volumes
    mean_square = 0.5 * float(np.sum(np.abs(v) ** 2 * areas))
    sigma = power / (rho * c * mean_square)
    seconds = time.perf_counter() - start
    logger.info("BEM at %.0f Hz: %d triangles, sigma %.4g, %d GMRES iterations (%.1f s)", frequency,
                grid.number_of_elements, sigma, iterations, seconds)
    return {"power": power, "sigma": sigma, "mean_square": mean_square, "seconds": seconds, "info": info,
            "iterations": iterations}


def sphere_triangles(radius, refine):
    """Vertices and triangles of a sphere (bempp's regular sphere, ``refine`` levels)."""
    _require()
    grid = bempp.shapes.regular_sphere(refine)
    return grid.vertices.T * radius, grid.elements.T


def sphere_efficiency_bem(order, ka, refine=3, radius=1.0, c=SOUND_SPEED):
    """σ of a sphere vibrating as a spherical harmonic of ``order`` 0 or 1 (v_n = 1 or cos ϑ), BEM."""
    vertices, triangles = sphere_triangles(radius, refine)
    grid = grid_from_triangles(vertices, triangles)
    centres = vertices[triangles].mean(axis=1)
    normal_z = centres[:, 2] / np.linalg.norm(centres, axis=1)
    velocity = np.ones(len(triangles)) if order == 0 else normal_z
    return radiated_power(grid, velocity, ka * c / (2.0 * np.pi * radius), c=c)["sigma"]


def baffled_piston_efficiency_bem(ka, thickness_ratio=0.05, face_size_ratio=0.1, rim_size_ratio=0.05,
                                  grading_ratio=0.3, radius=1.0, c=SOUND_SPEED, burton_miller=False):
    """σ of a circular piston in an infinite rigid baffle, from the free-field BEM of a thin closed disc.

    The disc's two flat faces move outwards with the same speed and its rim is at rest; by symmetry
    about its mid-plane each half-space sees a baffled piston as the thickness goes to zero
    (radiation/thin_disc.py), so σ over the moving faces tends to ``1 - J₁(2ka)/(ka)``. The
    finite thickness leaves an error of first order in t/a (-0.7 … -2.5 % at t/a = 0.05 for
    ka = 0.5 … 3; see :func:`baffled_piston_efficiency_extrapolated` and docs/verification.md).

    Parameters
    ----------
    ka : float
        Wavenumber times disc radius (-), > 0.
    thickness_ratio : float
        t/a (-), in (0, 1).
    face_size_ratio : float
        Largest element size (at the centre) over a (-); must not exceed a sixth of the acoustic
        wavelength, ``2π/(6 ka)``.
    rim_size_ratio : float
        Element size at the rim over a (-), ≤ face_size_ratio.
    grading_ratio : float
        Distance from the rim, over a, over which the size grows to the face size (-).
    radius : float
        a, m.
    c : float
        Speed of sound, m/s.
    burton_miller : bool
        Formulation (:func:`radiated_power`). Default the plain direct one: the disc's interior
        has no Dirichlet eigenfrequency below ``k = π/t`` (ka = 63 at t/a = 0.05), so the
        Burton-Miller coupling is not needed, and its hypersingular operator makes each solve several
        times longer (docs/benchmarks.md, *Radiation*). It is also the more sensitive to a coarse
        mesh on a thin body: the coupling ``η = i/k`` turns the quadrature error of the nearly
        coincident faces into an error of the radiated (real) part that grows as ka falls (ka =
        0.5: +7 % with a centre size of 4t, 1804 triangles, against -1.9 % for the plain form;
        -0.6 % and -0.8 % with 2t, 2942 triangles).

    Returns
    -------
    dict
        That of :func:`radiated_power` plus ``triangles`` (count), ``ka`` and ``thickness_ratio``.
    """
    if not ka > 0.0:
        raise InputError("ka", f"must be > 0, got {ka}")
    if not 0.0 < face_size_ratio <= 2.0 * np.pi / (6.0 * ka):
        raise InputError("face_size_ratio", f"must lie in (0, λ/(6a) = {2.0 * np.pi / (6.0 * ka):.3g}] at ka = {ka}, "
                                            f"got {face_size_ratio}")
    vertices, triangles = thin_disc_triangles(radius, thickness_ratio * radius, face_size_ratio * radius,
                                              rim_size_ratio * radius, grading_ratio * radius)
    velocity = piston_normal_velocity(vertices, triangles)
    result = radiated_power(grid_from_triangles(vertices, triangles), velocity, ka * c / (2.0 * np.pi * radius), c=c,
                            burton_miller=burton_miller)
    return {**result, "triangles": len(triangles), "ka": ka, "thickness_ratio": thickness_ratio}


def baffled_piston_efficiency_extrapolated(ka, thickness_ratio=0.05, **options):
    """The thin-disc BEM at t/a and 2t/a, extrapolated linearly to zero thickness.

    The thickness error being of first order in t/a, ``σ₀ = 2 σ(t) - σ(2t)`` removes it and
    leaves the second-order remainder and the discretisation error.

    Parameters
    ----------
    ka : float
        Wavenumber times disc radius (-), > 0.
    thickness_ratio : float
        The thinner disc's t/a (-), in (0, 0.5).
    **options
        Passed to :func:`baffled_piston_efficiency_bem` (the same mesh sizes for both discs).

    Returns
    -------
    dict
        ``sigma`` (extrapolated, -), ``thin`` and ``thick`` (the two solves' dicts), ``seconds``.
    """
    thin = baffled_piston_efficiency_bem(ka, thickness_ratio, **options)
    thick = baffled_piston_efficiency_bem(ka, 2.0 * thickness_ratio, **options)
    return {"sigma": 2.0 * thin["sigma"] - thick["sigma"], "thin": thin, "thick": thick,
            "seconds": thin["seconds"] + thick["seconds"]}
