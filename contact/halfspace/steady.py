"""Steady rolling solved directly: Gauss-Seidel sweeps on the steady rolling operator (in the spirit of Vollebregt's SteadyGS).

Steady rolling in contact-fixed coordinates (rolling in +x, material enters at the leading
edge, large x): the slip over one element length dx of contact element i is the upwind
difference

    S_i = W_i + u_i - u_{i+1}              (m, i + 1 the element upstream along x)

of the tangential displacement difference u = A p, with W the rigid slip
``(xi - phi y, eta + phi x) dx`` (Kalker's steady-state formulation, S = W - dx du/dx).
Coulomb's law as in the transient problem: stick (S = 0) where |p| <= mu_s p_z, else
p = -mu_k p_z S/|S|.

The sweeps visit the contact elements line by line along the rolling direction (lines of
constant y), each line from the leading edge to the trailing edge, and solve each element's
2 x 2 local problem (stick: the slip vanishes; slip: the traction on the kinetic bound opposite
to the slip, friction_kernels._local_slip) exactly for its own traction with the upstream displacement
u_{i+1} held at its current value, which the sweep has just updated. The local compliance is
therefore the element's own coefficient A(0, 0), as in a transient step, rather than the
steady one A(0, 0) - A(+1, 0): this under-relaxes the update (by about half), and a fixed
point of the sweep satisfies the steady equations exactly whatever the local compliance. Both
choices were tried on the issue-16 cases (a = 8, b = 4 mm, 20 x 20 and 40 x 40, spin and no
spin, stick-dominated to full slip): with the steady compliance the sweeps diverge in
stick-dominated cases, and so they do in either case when the elements are visited in rows
of constant x; with A(0, 0) and lines along x, all converged with Anderson mixing of the last
sweeps (as tangential_kernels.tangential_gauss_seidel; the sweep counts: docs/benchmarks.md,
*Measurements behind the solvers' constants*). No convergence proof is known
to us; a sweep limit with a fallback in the caller guards it.

The displacement is kept at the contact elements and at their upstream neighbours (one extra
element per line at the leading edge) and updated after every traction change by direct
products over those points: memory grows like the number of elements, a sweep costs
O(n_contact^2). The sweeps hold these displacements on a box of lines of constant y (each line
from its first to its last point), so that an update is a contiguous loop per line over
transposed kernels (vectorised; the same result to the bit as the point-by-point update it
replaced; its time: docs/benchmarks.md, *Half-space screen and curve map*).
"""

from __future__ import annotations

from typing import NamedTuple

import numba
import numpy as np

from contact.halfspace.anderson_kernels import anderson_history, anderson_input, anderson_mix
from contact.friction_kernels import element_law

__all__ = ["SteadyPoints", "steady_points", "steady_gauss_seidel"]


class SteadyPoints(NamedTuple):
    """Where the steady sweeps keep the displacement.

    Attributes
    ----------
    ix, iy : (ne,) int64 ndarray
        Grid indices: the nc contact elements in sweep order, then the upstream neighbours
        (ix + 1, iy) that are not in contact.
    upstream : (nc,) int64 ndarray
        Position in (ix, iy) of each contact element's upstream neighbour.
    """

    ix: np.ndarray
    iy: np.ndarray
    upstream: np.ndarray


def steady_points(cix, ciy, nx, ny) -> SteadyPoints:
    """The :class:`SteadyPoints` of contact elements ``(cix, ciy)`` (int64, sweep order) on an nx x ny grid.

    An upstream neighbour may lie one line beyond the grid (ix = nx); the kernels must then
    cover that offset.
    """
    nc = cix.size
    lookup = -np.ones((nx + 1, ny), np.int64)
    lookup[cix, ciy] = np.arange(nc)
    ux, uy = cix + 1, ciy
    extra = lookup[ux, uy] < 0
    ex, ey = ux[extra], uy[extra]
    lookup[ex, ey] = nc + np.arange(ex.size)
    return SteadyPoints(np.concatenate([cix, ex]).astype(np.int64), np.concatenate([ciy, ey]).astype(np.int64),
                        lookup[ux, uy])


@numba.njit(cache=True)
def _steady_sweep(k11, k12, k22, ox, oy, x0, first, stop, cix, ciy, wx, wy, gs, gk, px, py, bx, by, dxx, dyy, skip,
                  status):
    """One Gauss-Seidel sweep of the steady problem; returns the largest traction change (Pa).

    The displacement is held on a box of lines (:func:`steady_gauss_seidel`): ``bx[iy, ix - x0]``
    (and ``by``), whose line iy is kept from ``first[iy]`` to ``stop[iy]`` (exclusive, offsets
    from x0), covering the evaluation points of that line. The kernels are transposed,
    ``k11[ky, kx]`` the coefficient at offset ``(kx - ox, ky - oy)``, so that one traction's
    update of a line is a contiguous (vectorised) loop; each displacement receives the same
    updates in the same order as a point-by-point update would.
    """
    nc = px.shape[0]
    ny = first.shape[0]
    change = 0.0
    for c in range(nc):
        r = cix[c] - x0
        j = ciy[c]
        sx = wx[c] + bx[j, r] - bx[j, r + 1]
        sy = wy[c] + by[j, r] - by[j, r + 1]
        qx, qy, sliding = element_law(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c])
        status[c] = 2 if sliding else 1
        if sliding:
            gs[c] = gk[c]
        dpx = qx - px[c]
        dpy = qy - py[c]
        if abs(dpx) > skip or abs(dpy) > skip:
            px[c] = qx
            py[c] = qy
            off = ox - r
            for line in range(ny):
                a = first[line]
                b = stop[line]
                if a >= b:
                    continue
                row = oy + line - j
                c11 = k11[row, off + a:off + b]
                c12 = k12[row, off + a:off + b]
                c22 = k22[row, off + a:off + b]
                ux = bx[line, a:b]
                uy = by[line, a:b]
                for t in range(b - a):
                    q = c12[t]
                    ux[t] += c11[t] * dpx + q * dpy
                    uy[t] += q * dpx + c22[t] * dpy
            m = max(abs(dpx), abs(dpy))
            if m > change:
                change = m
    return change


@numba.njit(cache=True)
def steady_gauss_seidel(K11, K12, K22, ix, iy, up, wx, wy, gs, gk, px, py, ux, uy, dxx, dyy, tol, max_sweeps, depth):
    """Gauss-Seidel sweeps, Anderson-accelerated, for the steady rolling tractions.

    The displacements of the evaluation points are held, during the sweeps, on a box of lines
    of constant y (:func:`_steady_sweep`: per line, from its first to its last evaluation point),
    so that a traction change updates them by contiguous loops over transposed kernels; the
    Anderson mixing mixes the box (its extra points are never read). The arithmetic per
    evaluation point is that of a point-by-point update: the result is the same to the bit
    (tests/test_contact_rolling.py).

    Parameters
    ----------
    K11, K12, K22 : (2 mx - 1, 2 ny - 1) ndarray
        Tangential influence kernels (m/Pa) of a grid of mx >= (largest ix) + 1 lines.
    ix, iy : (ne,) int64 ndarray
        Grid indices of the evaluation points: the nc contact elements in sweep order (leading
        edge first, line by line), then the extra upstream points.
    up : (nc,) int64 ndarray
        Evaluation point upstream (ix + 1, iy) of each contact element (it is found in the box
        by its grid indices).
    wx, wy : (nc,) ndarray
        Rigid slip over dx, m.
    gs, gk : (nc,) ndarray
        Static and kinetic traction bounds, Pa (``gs`` lowered to ``gk`` in place where an
        element slides).
    px, py : (nc,) ndarray
        Tractions (Pa), initial guess in, solution out.
    ux, uy : (ne,) ndarray
        Displacement differences of the tractions at the evaluation points (m), consistent with
        ``px, py`` on entry; updated in place.
    dxx, dyy : float
        Local compliances of the element updates, m/Pa (the kernels' zero-lag coefficients).
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps : int
        Limit of sweeps.
    depth : int
        Sweeps remembered by the Anderson mixing (0: plain sweeps).

    Returns
    -------
    sweeps : int
    change : float
        Largest traction change of the last sweep, Pa.
    status : (nc,) int8 ndarray
        1 stick, 2 slip.
    """
    nc = px.shape[0]
    ne = ux.shape[0]
    ox = (K11.shape[0] + 1) // 2 - 1
    oy = (K11.shape[1] + 1) // 2 - 1
    ny = oy + 1
    k11 = np.ascontiguousarray(K11.T)
    k12 = np.ascontiguousarray(K12.T)
    k22 = np.ascontiguousarray(K22.T)
    x0 = ix.min()
    width = ix.max() - x0 + 1
    first = np.full(ny, width, np.int64)
    stop = np.zeros(ny, np.int64)
    for t in range(ne):
        r = ix[t] - x0
        first[iy[t]] = min(first[iy[t]], r)
        stop[iy[t]] = max(stop[iy[t]], r + 1)
    box_x = np.zeros(ny * width)
    box_y = np.zeros(ny * width)
    bx = box_x.reshape(ny, width)
    by = box_y.reshape(ny, width)
    for t in range(ne):
        bx[iy[t], ix[t] - x0] = ux[t]
        by[iy[t], ix[t] - x0] = uy[t]
    cix = ix[:nc]
    ciy = iy[:nc]
    status = np.ones(nc, np.int8)
    skip = 1e-3 * tol
    history = anderson_history(depth, nc, ny * width)
    change = 0.0
    sweeps = 0
    for sweep in range(max_sweeps):
        anderson_input(history, px, py)
        change = _steady_sweep(k11, k12, k22, ox, oy, x0, first, stop, cix, ciy, wx, wy, gs, gk, px, py, bx, by,
                               dxx, dyy, skip, status)
        sweeps = sweep + 1
        if change <= tol:
            break
        if depth == 0:
            continue
        anderson_mix(history, change, px, py, box_x, box_y)
    for t in range(ne):
        ux[t] = bx[iy[t], ix[t] - x0]
        uy[t] = by[iy[t], ix[t] - x0]
    return sweeps, change, status


@numba.njit(cache=True)
def _steady_sweep_local(coef, shift, flat, up, line_ptr, line_points, line_of, reach, wx, wy, gs, gk, px, py, ux, uy,
                        dxx, dyy, status):
    """One sweep like :func:`_steady_sweep` whose displacement updates reach only nearby lines.

    After a traction change at contact element c the displacement is updated at the evaluation
    points of the lines within ``reach`` of c's line (``line_points[line_ptr[l]:line_ptr[l + 1]]``
    for line l; ``line_of[c]`` is c's line), the rest being left to an exact FFT product after
    the sweep. Returns the largest traction change (Pa).
    """
    nc = px.shape[0]
    nlines = line_ptr.shape[0] - 1
    change = 0.0
    for c in range(nc):
        j = up[c]
        sx = wx[c] + ux[c] - ux[j]
        sy = wy[c] + uy[c] - uy[j]
        qx, qy, sliding = element_law(sx, sy, px[c], py[c], dxx, dyy, gs[c], gk[c])
        status[c] = 2 if sliding else 1
        if sliding:
            gs[c] = gk[c]
        dpx = qx - px[c]
        dpy = qy - py[c]
        if dpx != 0.0 or dpy != 0.0:
            px[c] = qx
            py[c] = qy
            off = np.uint64(shift - flat[c])
            lc = line_of[c]
            for line in range(max(lc - reach, 0), min(lc + reach + 1, nlines)):
                for q in range(line_ptr[line], line_ptr[line + 1]):
                    t = line_points[q]
                    k = np.uint64(flat[t]) + off
                    k12 = coef[k, 1]
                    ux[t] += coef[k, 0] * dpx + k12 * dpy
                    uy[t] += k12 * dpx + coef[k, 2] * dpy
            m = max(abs(dpx), abs(dpy))
            if m > change:
                change = m
    return change


def steady_sweeps_fft(kernels, points: SteadyPoints, wx, wy, gs, gk, px, py, tol, max_sweeps, depth, reach=1):
    """Steady Gauss-Seidel sweeps with local displacement updates and an exact FFT product per sweep.

    For large contact areas: within a sweep a traction change updates the displacement only on
    the lines within ``reach`` of its own (:func:`_steady_sweep_local`; the strong upstream
    coupling lies on the element's own line), and after the sweep the displacement at every
    evaluation point is recomputed exactly by FFT (``kernels.tangential_displacement``). A sweep
    then costs O(n_contact (reach + 1) nx + nx ny log(nx ny)) instead of O(n_contact^2). The
    deferred coupling across lines makes the plain sweeps diverge in stick-dominated cases;
    Anderson mixing of the last ``depth`` sweeps makes them converge (a restart of the history
    when a sweep's change grows, as in the transient solver, stalls them: it was tried); they take
    more sweeps than the exact updates, each much cheaper (docs/benchmarks.md, *Measurements
    behind the solvers' constants*).
    The caller falls back to :func:`steady_gauss_seidel` if they do not converge.

    Parameters
    ----------
    kernels : Kernels
        Influence kernels of the grid.
    points : SteadyPoints
        Evaluation points; the first nc are the contact elements in sweep order.
    wx, wy, gs, gk, px, py : (nc,) ndarray
        As for :func:`steady_gauss_seidel` (px, py and gs updated in place).
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps, depth : int
        Sweep limit; sweeps remembered by the Anderson mixing.
    reach : int
        Lines on each side updated within a sweep.

    Returns
    -------
    sweeps : int
    change : float
        Largest traction change of the last sweep, Pa.
    status : (nc,) int8 ndarray
        1 stick, 2 slip.
    """
    nx, ny = kernels.nx, kernels.ny
    nc = px.shape[0]
    cix, ciy = points.ix[:nc], points.iy[:nc]
    line_points = np.argsort(points.iy, kind="stable").astype(np.int64)
    line_ptr = np.concatenate([[0], np.cumsum(np.bincount(points.iy, minlength=ny))]).astype(np.int64)
    ox, oy = nx - 1, ny - 1
    my = 2 * ny - 1
    coef = np.zeros((kernels.K11.size, 4))
    coef[:, 0] = kernels.K11.ravel()
    coef[:, 1] = kernels.K12.ravel()
    coef[:, 2] = kernels.K22.ravel()
    flat = points.ix * my + points.iy
    dxx, dyy = float(kernels.K11[ox, oy]), float(kernels.K22[ox, oy])
    status = np.ones(nc, np.int8)
    field = np.zeros((nx, ny, 2))

    def displacement():
        field[cix, ciy, 0] = px
        field[cix, ciy, 1] = py
        u = kernels.tangential_displacement(field)
        return np.ascontiguousarray(u[points.ix, points.iy, 0]), np.ascontiguousarray(u[points.ix, points.iy, 1])

    ux, uy = displacement()
    # the transient solver's Anderson mixing, without restarts; the displacements it mixes too
    # are recomputed exactly after every sweep anyway
    history = anderson_history(depth, nc, ux.size)
    change = np.inf
    sweeps = 0
    for sweeps in range(1, max_sweeps + 1):
        anderson_input(history, px, py)
        change = _steady_sweep_local(coef, ox * my + oy, flat, points.upstream, line_ptr, line_points, ciy, reach,
                                     wx, wy, gs, gk, px, py, ux, uy, dxx, dyy, status)
        if change <= tol:
            break
        if depth > 0:
            anderson_mix(history, change, px, py, ux, uy, False)
        ux, uy = displacement()
    return sweeps, change, status
