"""Time per influence product of the half-space contact model: direct (dense) sums vs FFT.

For square grids (default 10 .. 150 elements a side, dx = dy = 0.5 mm, steel) it times, as the
median of repeated products:

* normal, whole grid: the compiled direct sum of the normal solver
  (``normal_kernels._influence_add`` over all elements, O(n^2) work, Toeplitz kernel in memory),
  a numpy dense matrix-vector product (explicit n x n matrix; only where it fits in
  ``--max-dense-mb``) and the FFT product (:func:`fft_products.normal_product`);
* tangential, whole grid: the compiled direct sum of the tangential solver
  (``rolling_kernels._tangential_displacement_at`` at every element), the numpy dense 2n x 2n block
  matvec (memory permitting) and :func:`fft_products.tangential_product`;
* normal, contact set only (the elements inside the inscribed ellipse, ~pi/4 of the grid, as
  a conjugate-gradient iteration sees them): direct sum over the set vs
  :func:`fft_products.normal_product_on`.

It prints the crossover grid (smallest size where the FFT wins) and the memory of each method.
Run: ``OMP_NUM_THREADS=1 python -m benchmarks.contact_fft [--sizes 20 40 ...]``.
"""

from __future__ import annotations

import argparse
import os
import time

import numba
import numpy as np


from contact.halfspace.bundles import FlatNormal, FlatTangential
from contact.halfspace.fft_products import (
    normal_product,
    normal_product_on,
    spectra_from_kernels,
    tangential_product,
)
from contact.halfspace.influence import rectangle_kernels
from contact.halfspace.normal_kernels import _influence_add
from contact.halfspace.rolling_kernels import _tangential_displacement_at

G, NU, H = 80.8e9, 0.3, 0.5e-3


@numba.njit(cache=True)
def _tangential_direct(operator, ix, iy, tx, ty, ux, uy):
    """Whole-grid tangential product by the solver's own per-element direct sum (``operator``: FlatTangential)."""
    sources = np.arange(ix.shape[0])
    for c in range(ix.shape[0]):
        ux[c], uy[c] = _tangential_displacement_at(operator, ix[c], iy[c], ix, iy, tx, ty, sources)


def _median_time(fn, budget=0.6, min_repeats=3, max_repeats=50):
    """Median wall time (s) of ``fn()`` over repeats filling about ``budget`` seconds (one warm-up)."""
    fn()
    times = []
    start = time.perf_counter()
    while len(times) < max_repeats and (len(times) < min_repeats or time.perf_counter() - start < budget):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def _dense(K, nx, ny):
    i, j = np.divmod(np.arange(nx * ny), ny)
    return K[i[:, None] - i[None, :] + nx - 1, j[:, None] - j[None, :] + ny - 1]


def _bench_grid(n, max_dense_bytes):
    nx = ny = n
    count = nx * ny
    k = rectangle_kernels(nx, ny, H, H, G, NU)
    t0 = time.perf_counter()
    spectra = spectra_from_kernels(k)
    setup = time.perf_counter() - t0
    rng = np.random.default_rng(n)
    p = rng.random((nx, ny))
    tx, ty = rng.standard_normal((2, nx, ny))
    row = {"n": n, "elements": count, "spectra_bytes": spectra.nbytes, "spectra_setup": setup,
           "toeplitz_bytes": 4 * k.K33.nbytes, "dense_normal_bytes": 8 * count ** 2,
           "dense_tangential_bytes": 8 * (2 * count) ** 2}

    # normal, whole grid
    f33 = k.K33.ravel()
    my = k.K33.shape[1]
    ix, iy = np.divmod(np.arange(count), ny)
    base = ix * my + iy
    offset = (nx - 1 - ix) * my + (ny - 1 - iy)
    everything = np.arange(count)
    flat_p = p.ravel().copy()
    out = np.zeros(count)
    flat_normal = FlatNormal(f33, base, offset)

    def direct_normal():
        out[:] = 0.0
        _influence_add(flat_normal, flat_p, everything, everything, out, 1.0)

    row["normal_direct"] = _median_time(direct_normal)
    ref = out.copy()
    row["normal_fft"] = _median_time(lambda: normal_product(spectra, p))
    row["normal_check"] = np.abs(normal_product(spectra, p).ravel() - ref).max() / np.abs(ref).max()
    row["normal_dense"] = None
    if row["dense_normal_bytes"] <= max_dense_bytes:
        A = _dense(k.K33, nx, ny)
        row["normal_dense"] = _median_time(lambda: A @ flat_p)
        del A

    # tangential, whole grid
    f11, f12, f22 = k.K11.ravel(), k.K12.ravel(), k.K22.ravel()
    ftx, fty = tx.ravel().copy(), ty.ravel().copy()
    ux, uy = np.zeros(count), np.zeros(count)
    flat_tangential = FlatTangential(f11, f12, f22, my, nx - 1, ny - 1)
    row["tangential_direct"] = _median_time(lambda: _tangential_direct(flat_tangential, ix, iy, ftx, fty, ux, uy))
    row["tangential_fft"] = _median_time(lambda: tangential_product(spectra, tx, ty))
    fx, fy = tangential_product(spectra, tx, ty)
    row["tangential_check"] = max(np.abs(fx.ravel() - ux).max() / np.abs(ux).max(),
                                  np.abs(fy.ravel() - uy).max() / np.abs(uy).max())
    row["tangential_dense"] = None
    if row["dense_tangential_bytes"] <= max_dense_bytes:
        B = np.block([[_dense(k.K11, nx, ny), _dense(k.K12, nx, ny)],
                      [_dense(k.K12, nx, ny), _dense(k.K22, nx, ny)]])
        t = np.concatenate((ftx, fty))
        row["tangential_dense"] = _median_time(lambda: B @ t)
        del B

    # normal, contact set = inscribed ellipse (what one CG iteration multiplies)
    c = (nx - 1) / 2
    inside = ((ix - c) / (nx / 2)) ** 2 + ((iy - (ny - 1) / 2) / (ny / 2)) ** 2 < 1.0
    contact = np.flatnonzero(inside)
    p_contact = flat_p[contact]

    def direct_contact():
        out[:] = 0.0
        _influence_add(flat_normal, flat_p, contact, contact, out, 1.0)

    row["contact_elements"] = contact.size
    row["contact_direct"] = _median_time(direct_contact)
    row["contact_fft"] = _median_time(lambda: normal_product_on(spectra, p_contact, contact))
    return row


def _ms(t):
    return "        -" if t is None else f"{t * 1e3:9.3f}"


def _mb(b):
    return f"{b / 2 ** 20:9.1f}"


def _crossover(rows, slow, fft):
    """Smallest grid from which on the FFT product beats ``slow`` at every larger size timed."""
    timed = [r for r in rows if r[slow] is not None]
    found = None
    for r in reversed(timed):
        if r[fft] >= r[slow]:
            break
        found = r
    if found is None:
        return "none in the sizes timed"
    first = " (the smallest size timed)" if found is timed[0] else ""
    return f"{found['n']} x {found['n']} ({found['elements']} elements){first}"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[10, 15, 20, 30, 40, 60, 80, 100, 150],
                        help="grid elements per side (square grids)")
    parser.add_argument("--max-dense-mb", type=float, default=512.0,
                        help="largest explicit dense matrix to build (MiB)")
    args = parser.parse_args(argv)
    print(f"threads: OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}, FFT: numpy.fft, one thread, "
          f"numba threads={numba.get_num_threads()}, cpus={os.cpu_count()}")
    rows = []
    for n in args.sizes:
        rows.append(_bench_grid(n, args.max_dense_mb * 2 ** 20))
        r = rows[-1]
        print(f"{n} x {n} done (FFT vs direct: normal {r['normal_check']:.1e}, "
              f"tangential {r['tangential_check']:.1e} relative)", flush=True)
    print("\nTime per product (ms, median); direct = the solvers' compiled sums, dense = numpy matvec")
    print("  grid  elements | normal: direct    dense      FFT | tangential: direct    dense      FFT "
          "| contact set: elements  direct      FFT")
    for r in rows:
        print(f"{r['n']:4d}^2 {r['elements']:9d} |     {_ms(r['normal_direct'])}{_ms(r['normal_dense'])}"
              f"{_ms(r['normal_fft'])} |        {_ms(r['tangential_direct'])}{_ms(r['tangential_dense'])}"
              f"{_ms(r['tangential_fft'])} |   {r['contact_elements']:9d}{_ms(r['contact_direct'])}"
              f"{_ms(r['contact_fft'])}")
    print("\nMemory (MiB): dense matrices vs the Toeplitz kernels (K11, K12, K22, K33) and the FFT spectra")
    print("  grid | dense normal  dense tang. | Toeplitz kernels | spectra (setup ms)")
    for r in rows:
        print(f"{r['n']:4d}^2 | {_mb(r['dense_normal_bytes'])}    {_mb(r['dense_tangential_bytes'])} | "
              f"      {_mb(r['toeplitz_bytes'])} | {_mb(r['spectra_bytes'])} ({r['spectra_setup'] * 1e3:.1f})")
    print("\nCrossover (smallest grid where the FFT product is faster than the compiled direct sum):")
    print(f"  normal, whole grid:      {_crossover(rows, 'normal_direct', 'normal_fft')}")
    print(f"  tangential, whole grid:  {_crossover(rows, 'tangential_direct', 'tangential_fft')}")
    print(f"  normal, contact set:     {_crossover(rows, 'contact_direct', 'contact_fft')}")
    print("Crossover against the numpy dense matvec (where built; needs the n^2 matrix):")
    print(f"  normal, whole grid:      {_crossover(rows, 'normal_dense', 'normal_fft')}")
    print(f"  tangential, whole grid:  {_crossover(rows, 'tangential_dense', 'tangential_fft')}")


if __name__ == "__main__":
    main()
