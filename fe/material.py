"""Linear elastic material laws.

Voigt order used throughout ``fe/``: (xx, yy, zz, yz, xz, xy), with engineering shear strains
(gamma_yz = 2 eps_yz, ...), so that the strain energy density is ``0.5 * eps @ D @ eps``.
"""

from __future__ import annotations

import numpy as np

from squealcore.errors import require_range


def isotropic_elasticity(youngs_modulus, poisson_ratio, prefix=""):
    """Elasticity matrix of a linear isotropic solid (3D, Voigt notation).

    Parameters
    ----------
    youngs_modulus : float
        Young's modulus E in Pa; must be > 0.
    poisson_ratio : float
        Poisson's ratio nu (dimensionless); must lie in (-1, 0.5).
    prefix : str, optional
        Prefix of the field names in error messages, e.g. ``"wheel.fe."`` gives
        ``"wheel.fe.youngs_modulus"``.

    Returns
    -------
    ndarray, shape (6, 6)
        Matrix D in Pa with ``sigma = D @ eps`` in Voigt order (xx, yy, zz, yz, xz, xy),
        engineering shear strains.

    Raises
    ------
    squealcore.errors.InputError
        If E <= 0 or nu is outside (-1, 0.5).
    """
    e = require_range(prefix + "youngs_modulus", youngs_modulus, 0.0, None, low_open=True, unit="Pa")
    nu = require_range(prefix + "poisson_ratio", poisson_ratio, -1.0, 0.5, low_open=True, high_open=True)
    lam = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu))
    mu = e / (2.0 * (1.0 + nu))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[np.arange(3), np.arange(3)] = lam + 2.0 * mu
    d[np.arange(3, 6), np.arange(3, 6)] = mu
    return d
