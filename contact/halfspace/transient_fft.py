"""Transient and shift tangential problems on large contact areas: local sweeps plus one FFT product per two sweeps.

The exact Gauss-Seidel sweeps (:func:`~contact.halfspace.tangential_kernels.tangential_gauss_seidel`)
update the displacement of every contact element after every traction change, so a sweep costs
O(n_contact^2), and a transient step in partial slip needs some tens of them on issue 16's
44 x 36 grid (docs/benchmarks.md, *Contact solvers against CONTACT*). Here a sweep updates the displacement
only at the contact elements within ``reach`` grid lines of the changed one
(:func:`~contact.halfspace.tangential_kernels.tangential_sweep` with
:func:`~contact.halfspace.local_sweep_kernels.local_updates`, O(n_contact (2 reach + 1)^2)),
and after :data:`SWEEPS_PER_PRODUCT` such sweeps the displacement of all contact elements is
recomputed exactly by one FFT product (:class:`~contact.halfspace.fft_products.TangentialListProduct`
on the contact's bounding box of mx x my elements, :func:`box_spectra`, O(mx my log(mx my))).
Between products the sweeps solve the near coupling with the far coupling frozen (a block
iteration); Anderson mixing (without restarts, which stall these sweeps as in
steady.steady_sweeps_fft) accelerates the map from one product to the next. The whole loop,
products included, is one compiled call
(:func:`~contact.halfspace.local_sweep_kernels.local_sweeps_with_products`). A fixed point of these
sweeps is one of the exact sweeps; the caller finishes with exact sweeps, so the result passes
the very same stopping test as the exact solver.

The sweeps see the far coupling only through the last product, so the error's smooth part,
which the half-space operator couples over the whole contact, decays slowly, and the rounds
grow with the grid (a study on the linear model: ``benchmarks/contact_coarse.py``). On contact
lists of at least :data:`COARSE_MIN_CONTACT` elements each round therefore starts with a coarse
correction (:func:`~contact.halfspace.local_sweep_kernels.coarse_correction`): tractions constant on
blocks of about 1/64 of the contact (:func:`coarse_block_size`) cancel the sticking elements'
slip summed over each block (a Galerkin coarse matrix, built by
:func:`~contact.halfspace.local_sweep_kernels.coarse_level` once a contact list comes a second time in a
row), and the displacements gain the block means of the change's effect, which the coarse
matrix gives exactly; the round's product makes them exact. It costs no product of its own. At
88 x 72 (4144 in contact) a step takes 59 instead of 71 iterations and about 0.8 of the time
(0.46 at 176 x 144); from 44 x 36 to 88 x 72 the cost per step grows as n log n
(docs/benchmarks.md, "The coarse level in the solver").
"""

from __future__ import annotations

import numpy as np

from squealcore.errors import InputError

from contact.halfspace.anderson_kernels import anderson_history, continue_history
from contact.halfspace.bundles import SweepCompliance, TangentialProblem, Tractions
from contact.halfspace.fft_products import InfluenceSpectra, TangentialListProduct, influence_spectra
from contact.halfspace.influence import Kernels
from contact.halfspace.influence_kernels import flat_tangential
from contact.halfspace.local_sweep_kernels import coarse_level, local_sweeps_with_products, local_updates, no_coarse_level

__all__ = ["transient_sweeps_fft", "SWEEPS_PER_PRODUCT"]

SWEEPS_PER_PRODUCT = 2
"""Local sweeps between two FFT products: the fewest products and the quickest step of 1 / 2 / 3 on
the 44 x 36 transient from rest (docs/benchmarks.md, *Contact solvers against CONTACT*, *Two
local sweeps per product*)."""


COARSE_MIN_CONTACT = 1500
"""Contact lists of at least this many elements get a coarse level (:func:`coarse_block_size`):
where it starts to pay on issue 16's transient from rest (docs/benchmarks.md, *The coarse level
in the solver*)."""

COARSE_BLOCKS = 64
"""Blocks the coarse level aims at (:func:`coarse_block_size`): the smooth error it carries is
that of the contact area as a whole, so its size stays the same on every grid (the block sizes
tried: docs/benchmarks.md, *The coarse level in the solver*)."""


def coarse_block_size(contact_elements):
    """Grid lines a side of the coarse level's blocks for a contact list of ``contact_elements`` (0: none).

    ``round(sqrt(n / COARSE_BLOCKS))``, at least 2, for lists of at least
    :data:`COARSE_MIN_CONTACT` elements.
    """
    if contact_elements < COARSE_MIN_CONTACT:
        return 0
    return max(2, int(round(np.sqrt(contact_elements / COARSE_BLOCKS))))


def _coarse_level(kernels: Kernels, operator, cix, ciy, series, block):
    """The coarse level of this contact list (``block`` lines a side; 0: none), built when the list comes again.

    A new contact list is only remembered, and solved without a coarse level; from its second
    solution in a row on (a transient under a constant load keeps its list from step to step)
    the coarse level is built once and kept in the Kernels object's cache of operators with the
    list, block and series compliances it was built for. A list that changes at every solution
    never pays the build, which costs about as much as the coarse level saves in one solution
    (docs/benchmarks.md, *The coarse level in the solver*).
    """
    if block <= 0:
        return no_coarse_level()
    key = (int(block), float(series[0]), float(series[1]))
    kept = kernels._ops.get("coarse_level")
    if kept is not None and np.array_equal(kept[1], cix) and np.array_equal(kept[2], ciy):
        if kept[0] == key and kept[3] is not None:
            return kept[3]
        level = coarse_level(operator, cix, ciy, int(block), float(series[0]), float(series[1]))
        kernels._ops["coarse_level"] = (key, kept[1], kept[2], level)
        return level
    kernels._ops["coarse_level"] = (key, cix.copy(), ciy.copy(), None)
    return no_coarse_level()


def box_spectra(kernels: Kernels, mx, my) -> InfluenceSpectra:
    """The tangential FFT spectra of an ``mx`` x ``my`` box of elements of ``kernels``' grid.

    A product among elements of the box needs only the kernels' offsets up to the box's size,
    so its periodic embedding is about twice the box, not twice the grid (at 44 x 36 with the
    contact in a 40 x 32 box, 80 x 64 against 88 x 72 points). The spectra of the last box size
    asked for are kept in the Kernels object's cache of operators.
    """
    kept = kernels._ops.get("box_spectra")
    if kept is not None and kept[0] == (mx, my):
        return kept[1]
    ox, oy = kernels.nx - 1, kernels.ny - 1
    offsets = np.s_[ox - (mx - 1):ox + mx, oy - (my - 1):oy + my]
    spectra = influence_spectra(mx, my, kernels.K11[offsets], kernels.K12[offsets], kernels.K22[offsets])
    kernels._ops["box_spectra"] = ((mx, my), spectra)
    return spectra


def _mixing_memory(kernels: Kernels, depth, nc):
    """An empty Anderson memory for ``nc`` elements, reused from the last call on this grid if it has that size.

    A fresh memory (at 44 x 36 and depth 48, 48 rounds of 2 x 1036 tractions and displacements,
    about 2.4 MB) cost a noticeable part of a step, mostly the operating system's fresh pages
    (docs/benchmarks.md, *Contact solvers against CONTACT*); emptied
    (``anderson_kernels.continue_history`` without carrying) it is the same memory: the mixing reads only
    what it has written since.
    """
    kept = kernels._ops.get("local_mixing_memory")
    if kept is not None and kept[0] == (depth, nc):
        continue_history(kept[1], False)
        return kept[1]
    memory = anderson_history(depth, nc, nc)
    kernels._ops["local_mixing_memory"] = ((depth, nc), memory)
    return memory


def transient_sweeps_fft(kernels: Kernels, problem: TangentialProblem, tractions: Tractions, series, tol, max_sweeps,
                         depth, reach=1, sweeps_per_product=None, stop_in_full_slip=False, coarse_block=None):
    """Local Gauss-Seidel sweeps with an exact FFT product after every few, Anderson-accelerated.

    Parameters
    ----------
    kernels : Kernels
        Influence kernels of the grid.
    problem : TangentialProblem
        Contact elements in sweep order (leading edge first), rigid slip (m), previous
        displacement (m) and traction bounds (Pa); the static bound is lowered to the kinetic
        one in place where an element slides (as in the exact sweeps).
    tractions : Tractions
        Tractions (Pa), initial guess in, result out (updated in place), and their displacement
        differences (m) at the contact elements (read only; the result's are returned).
    series : (float, float)
        Series compliances times the element area, m/Pa (as for the exact sweeps).
    tol : float
        Stop when the largest traction change of a sweep is below tol (Pa).
    max_sweeps : int
        Sweep limit.
    depth : int
        Sweeps remembered by the Anderson mixing (0: plain sweeps).
    reach : int
        Grid lines on each side, along x and y, whose displacement a traction change updates
        within a sweep.
    sweeps_per_product : int, optional
        Local sweeps between two products (default :data:`SWEEPS_PER_PRODUCT`).
    stop_in_full_slip : bool
        Return after the first product if every element slides (the exact sweeps converge in a
        few there).
    coarse_block : int, optional
        Grid lines a side of the coarse level's blocks (0: no coarse level); default
        :func:`coarse_block_size` of the contact list.

    Returns
    -------
    sweeps : int
        Local sweeps done.
    change : float
        Largest traction change (Pa) of the first sweep of the last round of sweeps, the one that
        started from the exact displacements of the product before it.
    ux, uy : (nc,) ndarray
        Displacement differences (m) of the result at the contact elements (exact product).
    status : (nc,) int8 ndarray
        1 stick, 2 slip after the last sweep.
    """
    nx, ny = kernels.nx, kernels.ny
    cix, ciy = problem.ix, problem.iy
    nc = cix.size
    per_product = SWEEPS_PER_PRODUCT if sweeps_per_product is None else int(sweeps_per_product)
    if per_product < 1:
        raise InputError("sweeps_per_product", f"must be an integer >= 1, got {sweeps_per_product!r}")
    if int(reach) < 0:
        raise InputError("reach", f"must be an integer >= 0, got {reach!r}")
    block = coarse_block_size(nc) if coarse_block is None else int(coarse_block)
    if block < 0:
        raise InputError("coarse_block", f"must be an integer >= 0, got {coarse_block!r}")
    operator = flat_tangential(kernels.bundle())
    series_x, series_y = series
    ox, oy = nx - 1, ny - 1
    compliance = SweepCompliance(float(kernels.K11[ox, oy]) + series_x, float(kernels.K22[ox, oy]) + series_y,
                                 series_x, series_y)
    # exact, at the contact: the product among the elements of the contact's bounding box
    x0, y0 = cix.min(), ciy.min()
    mx, my = int(cix.max() - x0 + 1), int(ciy.max() - y0 + 1)
    product = TangentialListProduct(box_spectra(kernels, mx, my), (cix - x0) * my + (ciy - y0))
    ux, uy = tractions.ux.copy(), tractions.uy.copy()
    sweeps, change, status = local_sweeps_with_products(
        operator, problem, cix * operator.row + ciy, Tractions(tractions.px, tractions.py, ux, uy), compliance,
        product.plan, local_updates(operator, cix, ciy, nx, ny, int(reach)), float(tol), int(max_sweeps),
        int(per_product), _mixing_memory(kernels, depth, nc), int(depth), bool(stop_in_full_slip),
        _coarse_level(kernels, operator, cix, ciy, series, block))
    return sweeps, change, ux, uy, status
