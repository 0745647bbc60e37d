"""Rolling contact models: Kalker-type non-steady half-space (``halfspace``) and point contact (``point``).

Modules: ``params`` (material, friction), ``hertz`` (Hertz formulas), ``influence``
(half-space influence coefficients, FFT products), ``normal`` / ``tangential`` (grid
solvers), ``bundles`` (typed named tuples that the compiled kernels take), the numba inner
loops by job, compiled lazily (``normal_kernels``, ``tangential_kernels``, ``friction_kernels``,
``anderson_kernels``, ``local_sweep_kernels``, ``influence_kernels``, ``rolling_kernels``,
``kernels_linalg``; ``point_kernels`` for the point model), ``halfspace`` / ``point`` (the two
models), ``model`` (common interface: ``ContactModel``, ``ContactResult``, ``CompiledPath``),
``factory`` (``create_model``), ``kalker`` (creep coefficient table), ``config`` / ``cli`` /
``output`` / ``plots`` (stand-alone command).
"""
