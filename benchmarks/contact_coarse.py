"""Why the transient solver's iterations grow with the grid, and what a coarse correction would save.

A study for issue 16's "cost growing close to linearly": on the linear model of a transient step
(every contact element sticks: find the tangential tractions ``t`` on the contact set with
``A t = w``, ``A`` the half-space's tangential influence matrix on the set, ``w`` a smooth rigid
slip), it counts the Krylov iterations (scipy's GMRES without restarts, to a relative residual
of 1e-9) of three preconditioners over grids of 1, 4 and 16 times the elements:

* ``none``;
* ``local``: two forward Gauss-Seidel sweeps on the near coupling only (every element with the
  elements of its 3 x 3 neighbourhood, as :func:`contact.halfspace.local_sweep_kernels.local_updates`),
  started from zero: the linear part of one round of the solver's local sweeps
  (:mod:`contact.halfspace.transient_fft`), whose Anderson mixing is a Krylov method of the same
  kind;
* ``two-level``: a coarse correction first (piecewise-constant tractions on aggregates of
  ``agg`` x ``agg`` elements, the Galerkin coarse matrix ``P^T A P`` inverted), then the same two
  local sweeps on the remaining residual;

``two-level, block means of its effect``: the same, but the sweeps see the coarse correction's
effect as the block means of its displacements (given exactly by the coarse matrix, no extra
product): the solver's coarse level (:func:`contact.halfspace.local_sweep_kernels.coarse_correction`);
and, with the first aggregate size, ``two-level, near field only``: the same, but the sweeps see
the coarse correction's effect on the near coupling only (as they see their own updates until the
next product), which would spare the solver the correction's extra product; and ``coarse start``:
the local sweeps from the coarse solution instead of zero (the coarse correction once per
solution, not once per round).

The products with ``A`` are the project's FFT products
(:class:`~contact.halfspace.fft_products.TangentialListProduct`). The patch and grids are those
of issue 16's transient rows (a = 5, b = 4 mm, grids over 1.1 times the patch). Findings and their
use: docs/benchmarks.md, "A coarse correction for the local sweeps".

Run: ``python benchmarks/contact_coarse.py [--grids 22x18 44x36 88x72] [--aggregates 4 8]``.
"""

from __future__ import annotations

import argparse

import numpy as np
import scipy.sparse as sparse
import scipy.sparse.linalg as sparse_linalg


from contact.halfspace.fft_products import TangentialListProduct, spectra_from_kernels  # noqa: E402
from contact.halfspace.influence import rectangle_kernels  # noqa: E402

SEMI_AXES = (5e-3, 4e-3)  # issue 16's transient patch (m)
SHEAR_MODULUS, POISSON_RATIO = 82e9, 0.28
TOLERANCE = 1e-9


class StickProblem:
    """The all-stick tangential problem on an elliptic contact set of an ``nx`` x ``ny`` grid."""

    def __init__(self, nx, ny):
        a, b = SEMI_AXES
        dx, dy = 2.2 * a / nx, 2.2 * b / ny
        self.kernels = rectangle_kernels(nx, ny, dx, dy, SHEAR_MODULUS, POISSON_RATIO)
        x = (np.arange(nx) + 0.5) * dx - 1.1 * a
        y = (np.arange(ny) + 0.5) * dy - 1.1 * b
        X, Y = np.meshgrid(x, y, indexing="ij")
        inside = (X / a) ** 2 + (Y / b) ** 2 < 1.0
        self.cells = np.argwhere(inside)  # (n, 2) grid indices, C order
        self.n = len(self.cells)
        self.product = TangentialListProduct(spectra_from_kernels(self.kernels, normal=False),
                                             np.flatnonzero(inside.ravel()))
        # a smooth rigid slip: creepage plus a linear variation (m)
        self.rigid_slip = np.concatenate([1e-6 * (1.0 + 0.3 * X[inside] / a), 1e-6 * (0.5 + Y[inside] / b)])
        self._near = self._near_coupling()

    def apply(self, tractions):
        """``A t``: displacement differences (m) on the contact set of tractions ``[t_x, t_y]`` (Pa)."""
        ux, uy = self.product(tractions[:self.n], tractions[self.n:])
        return np.concatenate([ux, uy])

    def _near_coupling(self):
        """Lower triangle and strict upper triangle of the near-coupling matrix, components interleaved."""
        k, n = self.kernels, self.n
        number = -np.ones((k.nx, k.ny), int)
        number[self.cells[:, 0], self.cells[:, 1]] = np.arange(n)
        rows, cols, values = [], [], []
        for di in (-1, 0, 1):
            for dj in (-1, 0, 1):
                i, j = self.cells[:, 0] + di, self.cells[:, 1] + dj
                ok = (i >= 0) & (i < k.nx) & (j >= 0) & (j < k.ny)
                source = np.arange(n)[ok]
                neighbour = number[i[ok], j[ok]]
                source, neighbour = source[neighbour >= 0], neighbour[neighbour >= 0]
                o = (k.nx - 1 + di, k.ny - 1 + dj)
                for (r, c), coefficient in (((0, 0), k.K11[o]), ((0, 1), k.K12[o]), ((1, 0), k.K12[o]),
                                            ((1, 1), k.K22[o])):
                    rows.append(2 * source + r)
                    cols.append(2 * neighbour + c)
                    values.append(np.full(source.size, coefficient))
        near = sparse.csr_matrix((np.concatenate(values), (np.concatenate(rows), np.concatenate(cols))),
                                 shape=(2 * n, 2 * n))
        return sparse.tril(near, format="csr"), sparse.triu(near, 1, format="csr")

    def near_apply(self, tractions):
        """The near coupling's product: ``A t`` with every element's sources cut to its 3 x 3 neighbourhood."""
        lower, upper = self._near
        t = np.empty_like(tractions)
        t[0::2], t[1::2] = tractions[:self.n], tractions[self.n:]
        u = lower @ t + upper @ t
        return np.concatenate([u[0::2], u[1::2]])

    def local_sweeps(self, residual):
        """Two forward Gauss-Seidel sweeps on the near coupling, from zero tractions."""
        lower, upper = self._near
        r = np.empty_like(residual)
        r[0::2], r[1::2] = residual[:self.n], residual[self.n:]
        t = sparse_linalg.spsolve_triangular(lower, r, lower=True)
        t = sparse_linalg.spsolve_triangular(lower, r - upper @ t, lower=True)
        return np.concatenate([t[0::2], t[1::2]])

    def coarse_correction(self, aggregate, block_means=False):
        """The map ``r -> P (P^T A P)^{-1} P^T r`` for piecewise-constant tractions on ``aggregate``-square blocks.

        With ``block_means``, also the map ``t -> P diag(1 / size) P^T A t`` for the corrections
        ``t = P c`` (``P^T A P c``, the coarse matrix's product, spread as block means): the
        effect of the correction that the solver's local sweeps see
        (:func:`contact.halfspace.local_sweep_kernels.coarse_correction`).
        """
        key = (self.cells[:, 0] // aggregate) * (self.kernels.ny + 1) + self.cells[:, 1] // aggregate
        _, group = np.unique(key, return_inverse=True)
        m = int(group.max()) + 1
        one = sparse.csr_matrix((np.ones(self.n), (np.arange(self.n), group)), shape=(self.n, m))
        prolong = sparse.block_diag([one, one], format="csr")
        a_p = np.column_stack([self.apply(prolong[:, j].toarray().ravel()) for j in range(2 * m)])
        coarse_matrix = prolong.T @ a_p
        coarse_inverse = np.linalg.inv(coarse_matrix)
        correction = lambda r: prolong @ (coarse_inverse @ (prolong.T @ r))  # noqa: E731
        if not block_means:
            return correction, 2 * m
        size = np.asarray(prolong.sum(axis=0)).ravel()

        def block_mean_effect(t):
            coefficients = (prolong.T @ t) / size  # t = P c: its block values
            return prolong @ ((coarse_matrix @ coefficients) / size)
        return correction, 2 * m, block_mean_effect


def gmres_iterations(problem, preconditioner=None, start=None):
    """GMRES iterations (no restart) to the relative residual :data:`TOLERANCE` (of the right-hand side),
    from ``start`` (default zero), and the residual reached."""
    size = 2 * problem.n
    operator = sparse_linalg.LinearOperator((size, size), matvec=problem.apply)
    m = None if preconditioner is None else sparse_linalg.LinearOperator((size, size), matvec=preconditioner)
    count = [0]

    def callback(_):
        count[0] += 1

    t, _ = sparse_linalg.gmres(operator, problem.rigid_slip, x0=start, M=m, rtol=TOLERANCE, restart=size,
                               maxiter=size, callback=callback, callback_type="pr_norm")
    residual = np.linalg.norm(problem.apply(t) - problem.rigid_slip) / np.linalg.norm(problem.rigid_slip)
    return count[0], residual


def two_level(problem, coarse, near_field_only=False, effect=None):
    """The coarse correction, then the local sweeps on what it leaves (of its effect, the near field's
    only with ``near_field_only``, the given ``effect`` else, default the exact product)."""
    product = problem.near_apply if near_field_only else (effect or problem.apply)

    def apply(r):
        t = coarse(r)
        return t + problem.local_sweeps(r - product(t))
    return apply


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--grids", nargs="+", default=["22x18", "44x36", "88x72"], help="grids NXxNY")
    parser.add_argument("--aggregates", nargs="+", type=int, default=[4, 8], help="coarse blocks (elements a side)")
    args = parser.parse_args(argv)
    print(f"GMRES iterations to a relative residual of {TOLERANCE:g}, all-stick problem on the elliptic contact "
          f"(a = {SEMI_AXES[0] * 1e3:g}, b = {SEMI_AXES[1] * 1e3:g} mm)")
    header = (["grid", "in contact", "none", "local"] + [f"two-level {g} x {g} (coarse unknowns)"
                                                        for g in args.aggregates]
              + [f"two-level {g} x {g}, block means of its effect (the solver's)" for g in args.aggregates]
              + [f"two-level {args.aggregates[0]} x {args.aggregates[0]}, near field only",
                 f"coarse start {args.aggregates[0]} x {args.aggregates[0]}, then local"])
    print("| " + " | ".join(header) + " |")
    print("|" + "---|" * len(header))
    for grid in args.grids:
        nx, ny = (int(v) for v in grid.lower().split("x"))
        problem = StickProblem(nx, ny)
        cells = [f"{nx} x {ny}", str(problem.n), str(gmres_iterations(problem)[0]),
                 str(gmres_iterations(problem, problem.local_sweeps)[0])]
        first = None
        for g in args.aggregates:
            coarse, unknowns = problem.coarse_correction(g)
            cells.append(f"{gmres_iterations(problem, two_level(problem, coarse))[0]} ({unknowns})")
            first = coarse if first is None else first
        for g in args.aggregates:
            coarse, _, effect = problem.coarse_correction(g, block_means=True)
            cells.append(str(gmres_iterations(problem, two_level(problem, coarse, effect=effect))[0]))
        cells.append(str(gmres_iterations(problem, two_level(problem, first, near_field_only=True))[0]))
        cells.append(str(gmres_iterations(problem, problem.local_sweeps, first(problem.rigid_slip))[0]))
        print("| " + " | ".join(cells) + " |", flush=True)


if __name__ == "__main__":
    main()
