"""Kalker's creepage coefficients of the linear theory (Kalker 1990, Table E.3).

The table (package data ``data/kalker_creep_coefficients.csv``) gives C11, C22, C23 for
ratios a/b (a along rolling) and nu = 0, 0.25, 0.5. Interpolation: linear in the ratio of
the shorter to the longer semi-axis within each branch (a <= b uses a/b, a >= b uses b/a, as
in Kalker's table), and quadratic in nu for 1/C, Kalker's convention.
"""

from __future__ import annotations

import functools

import numpy as np

from squealcore.errors import require_range

from contact.tables import read_table

__all__ = ["load_table", "creep_coefficients"]


@functools.lru_cache(maxsize=1)
def load_table():
    """Return the table as a dict of arrays ``a_over_b, nu, C11, C22, C23``."""
    return read_table("kalker_creep_coefficients.csv")


def _branch(table, ratio):
    """Rows (ratio key g in (0, 1], C11, C22, C23) of the branch holding ``ratio`` = a/b."""
    ab = table["a_over_b"]
    if ratio <= 1.0:
        sel = ab <= 1.0 + 1e-9
        g = ab[sel]
    else:
        sel = ab >= 1.0 - 1e-9
        g = 1.0 / ab[sel]
    return g, table["nu"][sel], table["C11"][sel], table["C22"][sel], table["C23"][sel]


def creep_coefficients(a_over_b: float, nu: float) -> tuple[float, float, float]:
    """Kalker's C11, C22, C23 (-) for semi-axis ratio a/b (-) and Poisson ratio nu (-).

    Parameters
    ----------
    a_over_b : float
        Semi-axis ratio, in [0.1, 10].
    nu : float
        Poisson ratio, in [0, 0.5].

    Returns
    -------
    tuple of float
        (C11, C22, C23).
    """
    a_over_b = require_range("geometry.a_over_b", a_over_b, 0.1, 10.0)
    nu = require_range("material.poisson_ratio", nu, 0.0, 0.5)
    table = load_table()
    key = a_over_b if a_over_b <= 1.0 else 1.0 / a_over_b
    g, nus, c11, c22, c23 = _branch(table, a_over_b)
    nodes = (0.0, 0.25, 0.5)
    out = []
    for c in (c11, c22, c23):
        inv = []
        for n0 in nodes:
            m = np.isclose(nus, n0)
            order = np.argsort(g[m])
            inv.append(1.0 / np.interp(key, g[m][order], c[m][order]))
        # Lagrange quadratic through nu = 0, 0.25, 0.5 for 1/C
        l0 = (nu - 0.25) * (nu - 0.5) / ((0.0 - 0.25) * (0.0 - 0.5))
        l1 = (nu - 0.0) * (nu - 0.5) / ((0.25 - 0.0) * (0.25 - 0.5))
        l2 = (nu - 0.0) * (nu - 0.25) / ((0.5 - 0.0) * (0.5 - 0.25))
        out.append(1.0 / (l0 * inv[0] + l1 * inv[1] + l2 * inv[2]))
    return tuple(float(v) for v in out)
