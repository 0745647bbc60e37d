"""Rolling contact models: Kalker-type non-steady half-space (``halfspace``) and point contact (``point``).

Modules: ``params`` (material, friction), ``hertz`` (Hertz formulas), ``influence``
(half-space influence coefficients, FFT products), ``normal`` / ``tangential`` (grid
solvers), ``kernels`` (numba inner loops, compiled lazily), ``halfspace`` / ``point`` (the
two models), ``model`` (common interface: ``create_model``, ``ContactResult``), ``kalker``
(creep coefficient table), ``config`` / ``cli`` / ``output`` / ``plots`` (stand-alone command).
"""
