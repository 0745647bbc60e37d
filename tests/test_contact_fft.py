"""FFT influence products against explicit summation and the Hertz closed form."""

import math

import numpy as np
import pytest

from contact.halfspace.fft_products import (
    TangentialListProduct,
    influence_spectra,
    kernel_spectrum,
    normal_product,
    normal_product_on,
    spectra_from_kernels,
    steady_tangential_product_on,
    tangential_product,
    tangential_product_on,
)
from contact.halfspace.influence import rectangle_kernels
from contact.halfspace.transient_fft import box_spectra
from squealcore.errors import InputError

G, NU = 80e9, 0.28
GRIDS = [(3, 3), (4, 4), (5, 8), (9, 4), (17, 12), (60, 40), (33, 47)]


def dense_sum(K, p):
    """u[i, j] = sum_kl K[i - k + nx - 1, j - l + ny - 1] p[k, l], one source element at a time."""
    nx, ny = p.shape
    u = np.zeros((nx, ny))
    for k in range(nx):
        for l in range(ny):
            u += p[k, l] * K[nx - 1 - k: 2 * nx - 1 - k, ny - 1 - l: 2 * ny - 1 - l]
    return u


def dense_matrix(K, nx, ny, rows, cols):
    """Explicit rows x cols block of the Toeplitz influence matrix (flat C-order element indices)."""
    ri, rj = np.divmod(np.asarray(rows), ny)
    ci, cj = np.divmod(np.asarray(cols), ny)
    return K[ri[:, None] - ci[None, :] + nx - 1, rj[:, None] - cj[None, :] + ny - 1]


def relative_error(u, ref):
    return np.abs(u - ref).max() / np.abs(ref).max()


# The FFT product differs from the direct sum by round-off only: O(eps log2(Lx Ly)) of the
# largest term, i.e. ~1e-14 for these grids; 1e-12 leaves room for cancellation in signed fields.
@pytest.mark.parametrize("nx,ny", GRIDS)
def test_normal_product_equals_explicit_sum(nx, ny):
    rng = np.random.default_rng(nx * 100 + ny)
    k = rectangle_kernels(nx, ny, 1e-3, 0.6e-3, G, NU)
    s = spectra_from_kernels(k, tangential=False)
    for p in (rng.random((nx, ny)), rng.standard_normal((nx, ny))):
        assert relative_error(normal_product(s, p), dense_sum(k.K33, p)) <= 1e-12


@pytest.mark.parametrize("nx,ny", GRIDS)
def test_tangential_product_equals_explicit_sum(nx, ny):
    rng = np.random.default_rng(nx * 100 + ny + 7)
    k = rectangle_kernels(nx, ny, 0.4e-3, 0.7e-3, G, NU)
    s = spectra_from_kernels(k, normal=False)
    px, py = rng.standard_normal((2, nx, ny))
    ux, uy = tangential_product(s, px, py)
    # the same K12 couples u_x to p_y and u_y to p_x (symmetric block, see influence.py)
    ref_x = dense_sum(k.K11, px) + dense_sum(k.K12, py)
    ref_y = dense_sum(k.K12, px) + dense_sum(k.K22, py)
    assert relative_error(ux, ref_x) <= 1e-12
    assert relative_error(uy, ref_y) <= 1e-12


def test_tangential_block_is_symmetric():
    # <q, A p> = <p, A q> for the 2x2 block operator: K12 even under (x, y) -> (-x, -y)
    rng = np.random.default_rng(3)
    nx, ny = 11, 6
    s = spectra_from_kernels(rectangle_kernels(nx, ny, 1e-3, 0.5e-3, G, NU), normal=False)
    p = rng.standard_normal((2, nx, ny))
    q = rng.standard_normal((2, nx, ny))
    ap = np.stack(tangential_product(s, *p))
    aq = np.stack(tangential_product(s, *q))
    assert np.vdot(q, ap) == pytest.approx(np.vdot(p, aq), rel=1e-12)


def test_spectra_of_halfspace_kernels_are_real():
    s = spectra_from_kernels(rectangle_kernels(9, 7, 1e-3, 0.8e-3, G, NU))
    assert all(x.dtype == np.float64 for x in (s.s11, s.s12, s.s22, s.s33))


def test_kernel_without_parity_keeps_complex_spectrum():
    # a general (non-even) kernel: the spectrum stays complex and the product stays exact
    rng = np.random.default_rng(5)
    nx, ny = 6, 9
    K = rng.standard_normal((2 * nx - 1, 2 * ny - 1))
    s = influence_spectra(nx, ny, K33=K)
    assert np.iscomplexobj(s.s33)
    p = rng.standard_normal((nx, ny))
    assert relative_error(normal_product(s, p), dense_sum(K, p)) <= 1e-12


@pytest.mark.parametrize("nx,ny", [(8, 5), (23, 30)])
def test_products_on_subsets_equal_explicit_blocks(nx, ny):
    rng = np.random.default_rng(11)
    k = rectangle_kernels(nx, ny, 1e-3, 0.6e-3, G, NU)
    s = spectra_from_kernels(k)
    n = nx * ny
    sources = rng.choice(n, size=n // 3, replace=False)
    targets = rng.choice(n, size=n // 2, replace=False)
    p, tx, ty = rng.standard_normal((3, sources.size))
    u = normal_product_on(s, p, sources, targets)
    assert relative_error(u, dense_matrix(k.K33, nx, ny, targets, sources) @ p) <= 1e-12
    ux, uy = tangential_product_on(s, tx, ty, sources)  # targets default to the sources
    a11, a12, a22 = (dense_matrix(K, nx, ny, sources, sources) for K in (k.K11, k.K12, k.K22))
    assert relative_error(ux, a11 @ tx + a12 @ ty) <= 1e-12
    assert relative_error(uy, a12 @ tx + a22 @ ty) <= 1e-12


@pytest.mark.parametrize("parity", [True, False])
def test_kept_list_product_equals_explicit_blocks_on_every_call(parity):
    """The product object of the local sweeps (buffers kept between calls) against the dense blocks, three calls.

    The whole product runs compiled (influence_kernels.list_product, numpy.fft through rocket-fft).
    Without the half-space parity (random kernels) the spectra are complex and the compiled
    pointwise product takes its complex path. A stale buffer (e.g. a padding written by an
    earlier call) would show in the second and third calls.
    """
    rng = np.random.default_rng(12)
    nx, ny = 19, 14
    if parity:
        k = rectangle_kernels(nx, ny, 1e-3, 0.6e-3, G, NU)
        K11, K12, K22 = k.K11, k.K12, k.K22
    else:
        K11, K12, K22 = rng.standard_normal((3, 2 * nx - 1, 2 * ny - 1))
    s = influence_spectra(nx, ny, K11, K12, K22)
    assert np.iscomplexobj(s.s11) != parity
    n = nx * ny
    sources = rng.choice(n, size=n // 3, replace=False)
    targets = rng.choice(n, size=n // 2, replace=False)
    product = TangentialListProduct(s, sources, targets)
    a11, a12, a22 = (dense_matrix(K, nx, ny, targets, sources) for K in (K11, K12, K22))
    for _ in range(3):
        tx, ty = rng.standard_normal((2, sources.size))
        ux, uy = product(tx, ty)
        assert relative_error(ux, a11 @ tx + a12 @ ty) <= 1e-12
        assert relative_error(uy, a12 @ tx + a22 @ ty) <= 1e-12


def test_product_on_the_contact_box_equals_the_grid_product():
    """The local sweeps' product among the elements of the contact's bounding box (spectra of the box only).

    transient_fft.box_spectra cuts the kernels to the box's offsets and embeds them in about
    twice the box instead of twice the grid; against the dense blocks of the grid's own kernels
    (1e-12), for an elliptic contact away from the grid's corner, in the sweeps' flat indexing of
    the box. A wrong cut of the offsets (e.g. off by one) or a wrong flat index of the box fails
    by far more.
    """
    rng = np.random.default_rng(21)
    nx, ny = 23, 17
    k = rectangle_kernels(nx, ny, 0.5e-3, 0.4e-3, G, NU)
    ix, iy = np.divmod(np.arange(nx * ny), ny)
    inside = ((ix - 12.3) / 8.2) ** 2 + ((iy - 9.1) / 5.6) ** 2 < 1
    cix, ciy = ix[inside], iy[inside]
    x0, y0 = cix.min(), ciy.min()
    mx, my = cix.max() - x0 + 1, ciy.max() - y0 + 1
    assert (mx, my) < (nx, ny) and x0 > 0 and y0 > 0
    spectra = box_spectra(k, mx, my)
    assert spectra.shape[0] < 2 * nx - 1 and spectra.shape[1] < 2 * ny - 1
    assert box_spectra(k, mx, my) is spectra  # kept for the next solution of the same box
    product = TangentialListProduct(spectra, (cix - x0) * my + (ciy - y0))
    flat = np.flatnonzero(inside)
    a11, a12, a22 = (dense_matrix(K, nx, ny, flat, flat) for K in (k.K11, k.K12, k.K22))
    tx, ty = rng.standard_normal((2, flat.size))
    ux, uy = product(tx, ty)
    assert relative_error(ux, a11 @ tx + a12 @ ty) <= 1e-12
    assert relative_error(uy, a12 @ tx + a22 @ ty) <= 1e-12


def test_steady_rolling_rows_equal_explicit_upwind_difference():
    # B = (I - S) A: row i of B is row i of A minus row (ix + 1, iy) of A, i.e. flat index i + ny
    rng = np.random.default_rng(13)
    nx, ny = 14, 9
    k = rectangle_kernels(nx, ny, 0.5e-3, 0.5e-3, G, NU)
    s = spectra_from_kernels(k, normal=False)
    ix, iy = np.divmod(np.arange(nx * ny), ny)
    sources = np.flatnonzero(((ix - 6) / 5.5) ** 2 + ((iy - 4) / 4.2) ** 2 < 1)  # ellipse, off the leading row
    tx, ty = rng.standard_normal((2, sources.size))
    bx, by = steady_tangential_product_on(s, tx, ty, sources)
    a11, a12, a22 = (dense_matrix(K, nx, ny, sources, sources) - dense_matrix(K, nx, ny, sources + ny, sources)
                     for K in (k.K11, k.K12, k.K22))
    assert relative_error(bx, a11 @ tx + a12 @ ty) <= 1e-12
    assert relative_error(by, a12 @ tx + a22 @ ty) <= 1e-12
    with pytest.raises(InputError, match="downstream"):
        steady_tangential_product_on(s, tx, ty, sources, targets=[(nx - 1) * ny])


@pytest.mark.parametrize("per_radius,aspect", [(10, 1.0), (20, 0.7)])
def test_hertz_pressure_gives_hertz_displacement(per_radius, aspect):
    # Hertz circular contact, radius a: p = p0 sqrt(1 - r^2/a^2) gives inside r < a, for two
    # identical bodies (twice Johnson 1985 eq. 3.41a, (1 - nu^2)/E = (1 - nu)/(2G))
    #   u_z = (1 - nu)/G * pi p0/(4a) * (2a^2 - r^2).
    # Discretisation error of piecewise-constant pressure collocated at element centres: the
    # ~2 pi a/h elements cut by the edge carry a pressure error ~ p0 sqrt(h/a) on an area h^2,
    # seen at distance ~ a through 1/(pi G r): relative error <~ (h/a)^(3/2) (observed
    # 0.11-0.17 (h/a)^(3/2) for a/h = 10 .. 80); the smooth interior adds O((h/a)^2).
    a, p0 = 1e-3, 1e9
    dx = a / per_radius
    dy = aspect * dx
    nx, ny = math.ceil(2.4 * a / dx), math.ceil(2.4 * a / dy)
    x = (np.arange(nx) - (nx - 1) / 2) * dx
    y = (np.arange(ny) - (ny - 1) / 2) * dy
    X, Y = np.meshgrid(x, y, indexing="ij")
    r2 = X ** 2 + Y ** 2
    p = p0 * np.sqrt(np.clip(1 - r2 / a ** 2, 0.0, None))
    s = spectra_from_kernels(rectangle_kernels(nx, ny, dx, dy, G, NU), tangential=False)
    u = normal_product(s, p)
    ref = (1 - NU) / G * math.pi * p0 / (4 * a) * (2 * a * a - r2)
    inside = r2 < a * a
    h = max(dx, dy)
    assert np.abs(u - ref)[inside].max() <= (h / a) ** 1.5 * ref.max()


@pytest.mark.parametrize("nx,ny", [(3, 3), (20, 20), (61, 41), (100, 37), (150, 150)])
def test_spectra_memory_grows_like_the_grid(nx, ny):
    # four real spectra of size Lx (Ly/2 + 1) with L ~ 2n: ~8 nx ny doubles, never (nx ny)^2
    s = spectra_from_kernels(rectangle_kernels(nx, ny, 1e-3, 1e-3, G, NU))
    assert s.nbytes < 64 * nx * ny * 8


def test_bad_input_is_refused():
    k = rectangle_kernels(4, 3, 1e-3, 1e-3, G, NU)
    s = spectra_from_kernels(k, tangential=False)
    with pytest.raises(InputError, match="pressure"):
        normal_product(s, np.zeros((3, 4)))
    with pytest.raises(InputError, match="tangential"):
        tangential_product(s, np.zeros((4, 3)), np.zeros((4, 3)))
    with pytest.raises(InputError, match="kernel"):
        kernel_spectrum(np.zeros((5, 5)), 4, 3)
    with pytest.raises(InputError, match="K11, K12, K22"):
        influence_spectra(4, 3, K11=k.K11)
    with pytest.raises(InputError, match="sources"):
        normal_product_on(s, [1.0], [12])
    with pytest.raises(InputError, match="grid.nx"):
        influence_spectra(0, 3, K33=np.zeros((1, 5)))


@pytest.mark.parametrize("nx, ny", [(30, 30), (41, 26)])
def test_normal_solution_by_fft_products_equals_the_direct_one(monkeypatch, nx, ny):
    """The prescribed-force normal problem on a large grid (compiled, FFT products) against the direct-product solver.

    Both run the same constrained conjugate gradients to tolerance 1e-10, one with FFT products
    on the doubled grid (normal_kernels.normal_cg_fft), the other with direct sums over the candidate
    elements (normal_kernels.normal_conjugate_gradient, forced by raising the FFT threshold). The two
    take the same iterations and differ by the products' round-off only (measured: pressures
    6e-14 / 1e-13 of the peak, approach 1e-15); asserted with a margin of 1000, 1e-10 of the
    peak: a step that differs between the two would show far above round-off.
    """
    from contact.halfspace import normal
    from contact.hertz import hertz_from_semi_axes
    from contact.params import Material

    a, b, force = 5e-3, 3.5e-3, 40e3
    hz = hertz_from_semi_axes(a, b, force, Material(G, NU).contact_modulus)
    x = (np.arange(nx) - (nx - 1) / 2) * (2.4 * a / nx)
    y = (np.arange(ny) - (ny - 1) / 2) * (2.4 * b / ny)
    X, Y = np.meshgrid(x, y, indexing="ij")
    k = rectangle_kernels(nx, ny, x[1] - x[0], y[1] - y[0], G, NU)
    gap = hz.A * X ** 2 + hz.B * Y ** 2 + 1e-7 * X / a  # a slight tilt: no symmetry to lean on
    assert gap.size >= normal.FFT_MIN_ELEMENTS
    by_fft = normal.solve_normal(k, gap, normal_force=force)
    monkeypatch.setattr(normal, "FFT_MIN_ELEMENTS", 10 ** 9)
    direct = normal.solve_normal(k, gap, normal_force=force)
    assert np.array_equal(by_fft.pressure > 0, direct.pressure > 0)
    assert np.abs(by_fft.pressure - direct.pressure).max() <= 1e-10 * direct.pressure.max()
    assert by_fft.normal_force == pytest.approx(force, rel=1e-12)
    assert by_fft.approach == pytest.approx(direct.approach, rel=1e-12)
    assert np.abs(by_fft.displacement - direct.displacement).max() <= 1e-10 * np.abs(direct.displacement).max()


def test_normal_fft_solver_leaves_a_solved_active_set_with_overlaps(monkeypatch):
    """A start whose active set is already solved, with overlapping elements outside it, must not stall.

    On a symmetric 8 x 8 gap the start is the 2 x 2 centre (equal gaps): the deformed gap is
    constant over it, so the step is zero, and re-entering the overlapping elements with the
    step length (p = -tau r) re-enters none: the FFT iteration used to repeat that step until
    its limit. Like the direct solver it now re-enters them with the pressure that closes each
    one's own gap. Both solvers then agree to round-off (1e-10 of the peak, as above).
    """
    from contact.halfspace import normal
    from contact.halfspace.model import Grid
    from contact.hertz import hertz_from_semi_axes
    from contact.params import Material

    a, b, force = 8e-3, 4e-3, 50e3
    hz = hertz_from_semi_axes(a, b, force, Material(G, NU).contact_modulus)
    grid = Grid.covering(a, b, nx=8, ny=8)
    X, Y = np.meshgrid(grid.x, grid.y, indexing="ij")
    gap = hz.A * X ** 2 + hz.B * Y ** 2
    k = rectangle_kernels(8, 8, grid.dx, grid.dy, G, NU)
    monkeypatch.setattr(normal, "FFT_MIN_ELEMENTS", 1)
    by_fft = normal.solve_normal(k, gap, normal_force=force)
    monkeypatch.setattr(normal, "FFT_MIN_ELEMENTS", 10 ** 9)
    direct = normal.solve_normal(k, gap, normal_force=force)
    assert (by_fft.pressure > 0).sum() > 4
    assert np.array_equal(by_fft.pressure > 0, direct.pressure > 0)
    assert np.abs(by_fft.pressure - direct.pressure).max() <= 1e-10 * direct.pressure.max()
