"""The ``[wheel.fe]`` and ``[wheel.rotation]`` study sections: the wheel's modal model and its rotation."""

from __future__ import annotations

from dataclasses import dataclass

from squealcore.schema import param, section

__all__ = ["WheelFEParams", "RotationParams", "SOLVERS", "HEX20_METHODS", "MOVING_LOAD_PATHS"]

SOLVERS = ("hex20", "axisymmetric")
HEX20_METHODS = ("cyclic", "full")
MOVING_LOAD_PATHS = ("harmonic", "interpolated")


@section("wheel.fe")
@dataclass(frozen=True)
class WheelFEParams:
    """Finite-element model of the wheel: solver, material, modes and modal damping."""

    solver: str = param("hex20", choices=SOLVERS,
                        doc="hex20: 3D 20-node elements, as in the paper; axisymmetric: fast.")
    hex20_method: str = param("cyclic", choices=HEX20_METHODS,
                              doc="cyclic: the 3D matrices solved by cyclic symmetry (exact, fast); full: all at once.")
    youngs_modulus: float = param(210e9, unit="Pa", low=0.0, high=1e13, low_open=True,
                                  doc="Young's modulus of the wheel steel.")
    poisson_ratio: float = param(0.3, low=-1.0, high=0.5, low_open=True, high_open=True,
                                 doc="Poisson's ratio of the wheel steel.")
    f_max: float = param(7000.0, unit="Hz", low=0.0, high=50e3, low_open=True,
                         doc="Modes up to this frequency are included.")
    damping_ratio: float = param(1e-4, low=0.0, high=1.0, high_open=True,
                                 doc="Modal damping ratio of the modes with more than low_order_max_n nodal diameters.")
    damping_ratio_low_order: float = param(1e-3, low=0.0, high=1.0, high_open=True,
                                           doc="Modal damping ratio of the modes with at most low_order_max_n "
                                               "nodal diameters.")
    low_order_max_n: int = param(1, low=0, high=100,
                                 doc="Largest number of nodal diameters of a low-order mode.")


@section("wheel.rotation")
@dataclass(frozen=True)
class RotationParams:
    """The rotating-wheel models written by wheel-greens (speed from ``[operating]``)."""

    gyroscopic: bool = param(True, doc="Eulerian model: Coriolis (gyroscopic) term 2 Omega V.")
    spin_softening: bool = param(True, doc="Eulerian model: convective term -Omega^2 A.")
    centrifugal_stiffening: bool = param(True, doc="Eulerian model: geometric stiffness of the centrifugal "
                                                   "prestress.")
    moving_load_path: str = param("harmonic", choices=MOVING_LOAD_PATHS,
                                  doc="harmonic: exact, by axisymmetric harmonics; interpolated: as the paper, "
                                      "on the 3D mesh.")
