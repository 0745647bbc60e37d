"""Typed bundles of the half-space model's compiled path (numba-compatible named tuples).

A bundle groups the arrays and scalars that a compiled contact kernel needs under names, so
that a kernel takes a handful of bundles instead of dozens of positional arguments, and the
Python model and the compiled time loop hand the same values to the same law. Bundles are
plain :class:`typing.NamedTuple` classes of arrays, numbers and other bundles: numba passes
them into ``@njit`` functions (as ``types.NamedTuple``, fields read by name) and its on-disk
cache keys on them like on any other argument type. Their arrays may be written in place by
the kernels (the state bundles); the scalars are fixed for a run.

* :class:`HalfspaceInputs` = :class:`Influence` + :class:`GridGeometry` +
  gap + :class:`FrictionCoefficients` + :class:`SolverSettings` + :class:`NormalTable`; the
  per-pass inputs :class:`RollingInputs`; the carried contact states :class:`ElementStates`;
* inside the solvers: :class:`TangentialProblem` and :class:`Tractions` (a tangential solution),
  :class:`NormalProblem` (a normal solution), and the flat views of the influence coefficients
  that the direct products index, :class:`FlatTangential`, :class:`FlatNormal`, the dense
  rows of the coefficients between the elements of one contact list, :class:`DenseTangential`
  (kept in a :class:`DenseCache` while the list stays the same), with the diagonal compliances
  of a Gauss-Seidel sweep, :class:`SweepCompliance`, and the memory of the Anderson mixing of
  the sweeps, :class:`AndersonHistory` (carried from one solution to the next in the time loop's
  :class:`ElementStates`); the FFT product of the tangential tractions of one list of elements,
  with its kept buffer, :class:`ListProduct`.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from contact.friction_law import CONSTANT_LAW, FrictionLaw

__all__ = ["Influence", "GridGeometry", "FrictionCoefficients", "SolverSettings", "NormalTable",
           "HalfspaceInputs", "RollingInputs", "ElementStates", "TangentialProblem", "Tractions",
           "NormalProblem", "FlatTangential", "DenseTangential", "DenseCache", "dense_cache", "DENSE_MAX_CONTACT",
           "UpstreamRows", "upstream_rows_storage", "UPSTREAM_MAX_ROWS", "TRACTION_HISTORY",
           "FlatNormal", "SweepCompliance", "AndersonHistory", "ListProduct", "CoarseLevel",
           "element_states", "no_spectra",
           "GAUSS_SEIDEL", "COMMITTED"]

GAUSS_SEIDEL = 0
"""``SolverSettings.tangential_solver``: element-by-element Gauss-Seidel sweeps with Anderson
mixing and direct products of the influence coefficients over the contact elements (the only
solver implemented). Other codes are reserved for solvers on FFT products (see
:class:`Influence`)."""

COMMITTED = 0
"""Slot of :class:`ElementStates` that holds the committed state of the last step."""


class Influence(NamedTuple):
    """Influence coefficients of the half-space grid.

    Attributes
    ----------
    K11, K12, K22, K33 : (2 nx - 1, 2 ny - 1) ndarray
        Toeplitz kernels, m/Pa: ``K[i + nx - 1, j + ny - 1]`` is the displacement difference at
        element (k + i, l + j) due to unit traction on element (k, l)
        (:class:`~contact.halfspace.influence.Kernels`). The compiled solvers form direct
        products with them over the elements in contact.
    spectra : (4, 2 nx, ny + 1) complex ndarray
        Real-FFT spectra (``numpy.fft.rfft2``) of K11, K12, K22, K33 wrapped on the grid doubled
        in each direction (2 nx x 2 ny, the layout of
        :class:`~contact.halfspace.influence.ToeplitzOperator`), for solvers that form the
        products by FFT on large contact areas; shape (0, 0, 0) when not computed
        (:func:`no_spectra`). No compiled solver reads them yet.
    """

    K11: np.ndarray
    K12: np.ndarray
    K22: np.ndarray
    K33: np.ndarray
    spectra: np.ndarray


def no_spectra() -> np.ndarray:
    """The empty ``Influence.spectra`` of a bundle without FFT spectra."""
    return np.zeros((0, 0, 0), np.complex128)


class GridGeometry(NamedTuple):
    """The half-space grid (contact/halfspace/model.py ``Grid``) as numbers.

    Attributes
    ----------
    nx, ny : int
        Elements along x (rolling) and y (lateral).
    x, y : (nx,), (ny,) ndarray
        Element centres, m.
    dx, dy : float
        Element sizes, m; ``dx`` is also the rolled distance of one transient step.
    area : float
        Element area dx dy, m².
    """

    nx: int
    ny: int
    x: np.ndarray
    y: np.ndarray
    dx: float
    dy: float
    area: float


class FrictionCoefficients(NamedTuple):
    """Friction of the half-space model.

    Attributes
    ----------
    static, kinetic : float
        Static (stick bound) and kinetic (slip traction) coefficients (-).
    law : FrictionLaw
        The kinetic coefficient's factor ``φ`` of the element's slip over a time step
        (contact/friction_law.py; rate per metre of slip); :data:`~contact.friction_law.CONSTANT_LAW`
        for Coulomb friction.
    """

    static: float
    kinetic: float
    law: FrictionLaw = CONSTANT_LAW


class SolverSettings(NamedTuple):
    """Settings of the half-space contact solvers.

    Attributes
    ----------
    tol : float
        Relative tolerance of the normal and tangential solutions (-).
    max_sweeps : int
        Sweep limit of one tangential solution.
    anderson_depth : int
        Sweeps remembered by the Anderson mixing of the Gauss-Seidel sweeps (0: plain sweeps).
    tangential_solver : int
        Choice of the tangential (and steady) solver: :data:`GAUSS_SEIDEL` (direct products);
        further codes are reserved for solvers on the FFT spectra of :class:`Influence`.
    """

    tol: float
    max_sweeps: int
    anderson_depth: int
    tangential_solver: int


class NormalTable(NamedTuple):
    """Normal solutions of the contact alone at ascending approaches (the warm starts of a step).

    Attributes
    ----------
    approach : (m,) ndarray
        m.
    force : (m,) ndarray
        N.
    pressure : (m, nx ny) ndarray
        Pa, flat in C order.
    displacement : (m, nx ny) ndarray
        Normal displacement difference, m, flat in C order.
    """

    approach: np.ndarray
    force: np.ndarray
    pressure: np.ndarray
    displacement: np.ndarray


class HalfspaceInputs(NamedTuple):
    """Everything fixed of the half-space model that a compiled transient step needs.

    Attributes
    ----------
    influence : Influence
    grid : GridGeometry
    gap : (nx ny,) ndarray
        Undeformed gap at the element centres, m, flat in C order.
    friction : FrictionCoefficients
    solver : SolverSettings
    table : NormalTable
    """

    influence: Influence
    grid: GridGeometry
    gap: np.ndarray
    friction: FrictionCoefficients
    solver: SolverSettings
    table: NormalTable


class RollingInputs(NamedTuple):
    """Inputs of one transient rolling solution (one coupling pass of a time step).

    Attributes
    ----------
    approach : float
        Approach of contact and series springs together, m.
    creepage : (3,) ndarray
        xi, eta (-), spin phi (1/m) at the normal force ``force_reference``.
    creepage_per_force : (2,) ndarray
        Change of xi and eta per newton of normal force (1/N): the creepages are
        ``creepage[:2] + creepage_per_force * (Fz - force_reference)`` with Fz from this
        solution's normal problem.
    force_reference : float
        N.
    series : (3,) ndarray
        Compliances of springs in series with the contact, m/N.
    use_table : bool
        Warm-start the normal problem from the :class:`NormalTable` (the first pass of a step)
        instead of the warm-start slot; it changes the iteration count only.
    """

    approach: float
    creepage: np.ndarray
    creepage_per_force: np.ndarray
    force_reference: float
    series: np.ndarray
    use_table: bool


class TangentialProblem(NamedTuple):
    """The contact elements of one tangential problem, in sweep order (leading edge first).

    Attributes
    ----------
    ix, iy : (nc,) int64 ndarray
        Grid indices of the contact elements.
    slip_x, slip_y : (nc,) ndarray
        Rigid slip over the step, m.
    previous_x, previous_y : (nc,) ndarray
        Previous displacement u' of the same particle, m.
    static_bound, kinetic_bound : (nc,) ndarray
        Traction bounds mu_s p_z and mu_k p_z, Pa; with Coulomb friction the solver lowers
        ``static_bound`` to ``kinetic_bound`` in place where an element slides.
    law : FrictionLaw
        The sliding bound is ``kinetic_bound`` times ``φ`` of the element's slip over the step
        (contact/friction_law.py, rate per metre of slip; ``CONSTANT_LAW``: Coulomb friction).
    """

    ix: np.ndarray
    iy: np.ndarray
    slip_x: np.ndarray
    slip_y: np.ndarray
    previous_x: np.ndarray
    previous_y: np.ndarray
    static_bound: np.ndarray
    kinetic_bound: np.ndarray
    law: FrictionLaw


class Tractions(NamedTuple):
    """Tangential tractions of the contact elements with their displacements (in and out of a solver).

    Attributes
    ----------
    px, py : (nc,) ndarray
        Tractions on the wheel, Pa.
    ux, uy : (nc,) ndarray
        Tangential displacement differences of the elements, consistent with the tractions, m.
    """

    px: np.ndarray
    py: np.ndarray
    ux: np.ndarray
    uy: np.ndarray


class NormalProblem(NamedTuple):
    """One normal contact problem on the half-space grid (the inputs of the constrained conjugate gradients).

    Attributes
    ----------
    gap : (nx ny,) ndarray
        Undeformed gap, m, flat in C order.
    pressure : (nx ny,) ndarray
        Pressure, Pa: initial guess in, solution out (written in place).
    force_mode : bool
        Prescribed normal force ``target`` (N), else prescribed approach ``target`` (m).
    target : float
        N or m (see ``force_mode``).
    series : float
        Compliance of springs in series with the contact times the element area, m/Pa, added to
        every influence coefficient (approach mode only; 0 for the contact alone).
    area : float
        Element area, m².
    tol : float
        Relative tolerance of the pressure change and the gap residual (-).
    max_iter : int
        Iteration limit.
    warm : bool
        ``pressure`` is a warm start (see
        :func:`~contact.halfspace.normal_kernels.normal_conjugate_gradient`).
    """

    gap: np.ndarray
    pressure: np.ndarray
    force_mode: bool
    target: float
    series: float
    area: float
    tol: float
    max_iter: int
    warm: bool


class FlatTangential(NamedTuple):
    """The tangential influence coefficients flattened for direct products over contact elements.

    The coefficient between a traction on element (k, l) and the displacement difference at
    element (i, j) is ``f[(i - k + ox) * row + (j - l + oy)]``.

    Attributes
    ----------
    f11, f12, f22 : (row (2 nx - 1),) ndarray
        K11, K12, K22 of :class:`Influence` raveled in C order, m/Pa.
    row : int
        Row length of the kernels, 2 ny - 1.
    ox, oy : int
        Offsets of the zero lag, nx - 1 and ny - 1.
    """

    f11: np.ndarray
    f12: np.ndarray
    f22: np.ndarray
    row: int
    ox: int
    oy: int


class DenseTangential(NamedTuple):
    """The tangential influence coefficients between the elements of one contact list, row by row.

    The coefficient between a traction on list element c and the displacement difference at
    list element t is ``m[c * count + t]``: a Gauss-Seidel update of element c then reads three
    contiguous rows (it vectorises without gathers: faster than the indexed products of
    :class:`FlatTangential` up to :data:`DENSE_MAX_CONTACT` elements, docs/benchmarks.md, *The
    half-space time loop*, *Dense influence rows*). Built by
    :func:`~contact.halfspace.influence_kernels.dense_tangential` from the flat view; the same
    coefficients, so a sweep gives the same numbers bit for bit.

    Attributes
    ----------
    m11, m12, m22 : (capacity,) ndarray
        The rows, m/Pa; ``capacity >= count**2`` (empty: not used).
    count : int
        Elements of the list.
    """

    m11: np.ndarray
    m12: np.ndarray
    m22: np.ndarray
    count: int


DENSE_MAX_CONTACT = 600
"""Contact lists of at most this many elements get their tangential influence coefficients as
dense rows (:class:`DenseTangential`, 3 n² doubles: 8.6 MB at 600) for the exact sweeps; longer
lists keep the indexed products of :class:`FlatTangential` (and, from
``tangential.TRANSIENT_FFT_MIN_CONTACT``, the FFT-product sweeps)."""


class DenseCache(NamedTuple):
    """Storage of the :class:`DenseTangential` rows of a contact list, kept while the list stays the same.

    Attributes
    ----------
    m11, m12, m22 : (capacity²,) ndarray
        The rows (m/Pa) of the list ``ix[:count[0]]``, ``iy[:count[0]]``.
    ix, iy : (capacity,) int64 ndarray
        Grid indices of the list the rows belong to.
    count : (1,) int64 ndarray
        Length of that list; -1 before the first build.
    """

    m11: np.ndarray
    m12: np.ndarray
    m22: np.ndarray
    ix: np.ndarray
    iy: np.ndarray
    count: np.ndarray


def dense_cache(n) -> DenseCache:
    """Row storage for contact lists of up to ``min(n, DENSE_MAX_CONTACT)`` elements."""
    capacity = min(int(n), DENSE_MAX_CONTACT)
    return DenseCache(np.empty(capacity**2), np.empty(capacity**2), np.empty(capacity**2),
                      np.zeros(capacity, np.int64), np.zeros(capacity, np.int64), -np.ones(1, np.int64))


UPSTREAM_MAX_ROWS = 64
"""Most elements of a contact list whose upstream neighbour is outside the list (the leading edge,
one per grid line along y, and the downstream sides of holes) that get rows in :class:`UpstreamRows`;
a list with more keeps the indexed sums."""


class UpstreamRows(NamedTuple):
    """The tangential influence coefficients from a contact list to the elements just upstream of it.

    In the time loop's transient step the particle at list element (ix, iy) was at (ix + 1, iy)
    one step earlier; where that element was outside the contact, its displacement difference is
    summed from the last step's tractions over the whole list. While the list stays the same these
    sums read rows of coefficients built once (contiguous inner products instead of gathers from
    the kernels). Kept with the :class:`DenseCache` of the same list.

    Attributes
    ----------
    position : (capacity,) int64 ndarray
        For list position c, the row of its upstream element (ix + 1, iy), or -1 when that element
        is in the list.
    m11, m12, m22 : (UPSTREAM_MAX_ROWS capacity,) ndarray
        The rows, m/Pa: row r, source c at ``[r * count + c]`` (count the list's length).
    count : (1,) int64 ndarray
        Rows built; -1: none (not built for the cache's list, or more than :data:`UPSTREAM_MAX_ROWS`).
    """

    position: np.ndarray
    m11: np.ndarray
    m12: np.ndarray
    m22: np.ndarray
    count: np.ndarray


def upstream_rows_storage(n) -> UpstreamRows:
    """Storage of :class:`UpstreamRows` for the lists of a :func:`dense_cache` of ``n`` grid elements."""
    capacity = min(int(n), DENSE_MAX_CONTACT)
    size = UPSTREAM_MAX_ROWS * capacity
    return UpstreamRows(-np.ones(capacity, np.int64), np.empty(size), np.empty(size), np.empty(size),
                        -np.ones(1, np.int64))


class FlatNormal(NamedTuple):
    """The normal influence matrix of the whole grid as an index into the raveled kernel K33.

    ``A[i, j] = f33[base[i] + offset[j]]`` for flat (C order) element indices i, j.

    Attributes
    ----------
    f33 : ((2 nx - 1) (2 ny - 1),) ndarray
        K33 of :class:`Influence` raveled in C order, m/Pa.
    base, offset : (nx ny,) int64 ndarray
        Index parts of the row and of the column element.
    """

    f33: np.ndarray
    base: np.ndarray
    offset: np.ndarray


class SweepCompliance(NamedTuple):
    """Compliances that a Gauss-Seidel sweep of the tangential problem applies to every element.

    Attributes
    ----------
    dxx, dyy : float
        Own compliance of an element (the kernels' zero-lag coefficient plus the series term), m/Pa.
    series_x, series_y : float
        Compliances of springs in series with the contact times the element area, m/Pa.
    """

    dxx: float
    dyy: float
    series_x: float
    series_y: float


class LocalUpdates(NamedTuple):
    """Which contact elements a traction change updates within a local sweep, and by how much.

    Built once per contact list (``local_sweep_kernels.local_updates``) for the sweeps with local updates
    (contact/halfspace/transient_fft.py): a change at list position ``c`` updates the
    displacement at the positions ``neighbours[c, q]`` (``-1``: no contact element there) by the
    influence coefficients of offset ``q``, which are the same for every element (the kernels
    are translation invariant). Empty arrays (``tangential_kernels.no_local_updates``) mean the exact
    sweep: every contact element is updated.

    Attributes
    ----------
    neighbours : (nc, q) int64 ndarray
        List positions of the elements within ``reach`` grid lines along x and y, offsets in
        row-major order (x outer, y inner), ``q = (2 reach + 1)^2``.
    stencil : (3, q) ndarray
        The coefficients of those offsets: rows 11, 12, 22 of the tangential kernels (m/Pa).
    """

    neighbours: np.ndarray
    stencil: np.ndarray


class CoarseLevel(NamedTuple):
    """A coarse level of the local sweeps: piecewise-constant tractions on blocks of contact elements.

    Built for a contact list (``local_sweep_kernels.coarse_level``) for the sweeps with local updates
    (contact/halfspace/transient_fft.py, ``local_sweep_kernels.coarse_correction``). Empty arrays
    (``local_sweep_kernels.no_coarse_level``) mean no coarse level.

    Attributes
    ----------
    group : (nc,) int64 ndarray
        The block of each contact element (list order).
    size : (m,) ndarray
        Contact elements in each block.
    inverse : (2 m, 2 m) ndarray
        The inverse (Pa/m) of the blocks' Galerkin coarse matrix ``P^T (A + S) P``
        (``local_sweep_kernels.coarse_matrix``; x blocks first, then y).
    """

    group: np.ndarray
    size: np.ndarray
    inverse: np.ndarray


class ListProduct(NamedTuple):
    """The tangential FFT product from one fixed list of grid elements to another (``influence_kernels.list_product``).

    The tractions are written into ``padded`` at ``sources`` (the same positions on every call,
    so the rest stays zero), transformed along y over the grid's nx rows, then along x with zero
    padding to ``lx``, multiplied by the spectra, transformed back along x and, over the nx rows
    of the grid only, along y; the displacements are read at ``targets``.

    Attributes
    ----------
    padded : (2, nx, ly) ndarray
        Kept buffer of the two traction components on the grid's rows, zero-padded along y, Pa.
    sources, targets : (n,) int64 ndarray
        Flat positions ``ix * ly + iy`` in a layer of ``padded`` of the source and target elements.
    s11, s12, s22 : (lx, ly // 2 + 1) ndarray
        Spectra of the influence kernels on the (lx, ly) periodic embedding (real for the
        half-space's kernels, complex otherwise), m/Pa.
    nx : int
        Grid elements along x.
    lx, ly : int
        Size of the periodic embedding.
    """

    padded: np.ndarray
    sources: np.ndarray
    targets: np.ndarray
    s11: np.ndarray
    s12: np.ndarray
    s22: np.ndarray
    nx: int
    lx: int
    ly: int


class AndersonHistory(NamedTuple):
    """Memory of the type-II Anderson mixing of Gauss-Seidel sweeps (``anderson_kernels.anderson_mix``).

    The mixed unknowns are the n tractions of each direction, stacked (x then y, 2 n); the
    displacements (m points per direction, stacked, 2 m) are affine in them and mixed with the
    same coefficients. Ring buffers of ``slots`` rows hold the differences of consecutive sweeps.

    Attributes
    ----------
    dg, df : (slots, 2 n) ndarray
        Differences of the sweeps' outputs (Pa) and of their residuals (output - input, Pa).
    du : (slots, 2 m) ndarray
        Differences of the displacements after the sweeps, m.
    gram : (slots, slots) ndarray
        Inner products of the rows of ``df``, Pa^2.
    x, f_now, g_prev, f_prev : (2 n) ndarray
        Input of the current sweep, its residual, the last sweep's output and residual, Pa.
    u_prev : (2 m) ndarray
        Displacements after the last sweep, m.
    counters : (4,) int64 ndarray
        Differences stored, ring position of the newest, whether a last sweep is stored (0/1),
        whether the differences are carried to the next solution of the same contact list (0/1,
        ``anderson_kernels.continue_history``).
    last_change : (1,) ndarray
        Largest traction change of the last sweep (Pa), inf at the start.
    """

    dg: np.ndarray
    df: np.ndarray
    du: np.ndarray
    gram: np.ndarray
    x: np.ndarray
    f_now: np.ndarray
    g_prev: np.ndarray
    f_prev: np.ndarray
    u_prev: np.ndarray
    counters: np.ndarray
    last_change: np.ndarray


class ElementStates(NamedTuple):
    """Contact states of the compiled half-space loop, as lists of the elements in contact.

    Three slots (first index): :data:`COMMITTED` (0) the committed state of the last step, 1
    and 2 the passes of the current step (alternating warm start and result). Per slot: the
    ``count`` elements in contact (grid indices ``ix``, ``iy``, in sweep order, leading edge
    first), their tractions ``tx``, ``ty`` (Pa), tangential displacement differences ``ux``,
    ``uy`` (m) and stick/slip ``status`` (1 stick, 2 slip); ``lookup`` (nx ny) maps a flat grid
    index to its position in the list or -1; the pressure (nx ny, Pa) and its normal
    displacement ``normal_u`` (m), known where the undeformed gap is below ``threshold`` (m).

    Attributes
    ----------
    pressure, normal_u : (3, nx ny) ndarray
    threshold : (3,) ndarray
    count : (3,) int64 ndarray
    ix, iy, lookup : (3, nx ny) int64 ndarray
    tx, ty, ux, uy : (3, nx ny) ndarray
    status : (3, nx ny) int8 ndarray
    rows : DenseCache
        The dense influence rows of the last contact list the tangential solver saw.
    mixing : AndersonHistory
        The Anderson mixing's memory of the tangential sweeps, carried from one solution to the
        next while the contact list stays the same (sized for the whole grid).
    upstream : UpstreamRows
        The coefficients from the list of ``rows`` to its upstream neighbours outside it.
    history : (TRACTION_HISTORY, 2 nx ny) ndarray
        Committed tangential tractions (Pa; x over the grid, then y; zero out of contact) of the
        last :data:`TRACTION_HISTORY` steps, step s in row ``s % TRACTION_HISTORY``: the time loop
        predicts the first pass's starting tractions from them.
    prediction : (3,) int64 ndarray
        The time loop's decision whether to predict the starting tractions (x, y) in the window of
        steps that starts at ``prediction[0]`` (-1: none yet).
    """

    pressure: np.ndarray
    normal_u: np.ndarray
    threshold: np.ndarray
    count: np.ndarray
    ix: np.ndarray
    iy: np.ndarray
    tx: np.ndarray
    ty: np.ndarray
    ux: np.ndarray
    uy: np.ndarray
    status: np.ndarray
    lookup: np.ndarray
    rows: DenseCache
    mixing: AndersonHistory
    upstream: UpstreamRows
    history: np.ndarray
    prediction: np.ndarray


TRACTION_HISTORY = 32
"""Committed tangential traction fields that :class:`ElementStates` keeps (a ring by step number;
at least the force predictor's order plus two)."""


def element_states(n, pressure, mixing) -> ElementStates:
    """Element states of an ``n``-element grid whose committed state is the traction-free ``pressure`` (Pa).

    ``mixing`` is an empty Anderson memory for ``n`` elements
    (``anderson_kernels.carried_anderson_history(depth, n, n)``).
    """
    states = ElementStates(np.zeros((3, n)), np.zeros((3, n)), np.zeros(3), np.zeros(3, np.int64),
                           np.zeros((3, n), np.int64), np.zeros((3, n), np.int64), np.zeros((3, n)),
                           np.zeros((3, n)), np.zeros((3, n)), np.zeros((3, n)), np.zeros((3, n), np.int8),
                           -np.ones((3, n), np.int64), dense_cache(n), mixing,
                           upstream_rows_storage(n), np.zeros((TRACTION_HISTORY, 2 * n)),
                           np.array([-1, 0, 0], np.int64))
    states.pressure[COMMITTED] = np.asarray(pressure, dtype=float).ravel()
    return states
