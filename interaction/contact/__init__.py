"""Rolling contact models: Kalker-type non-steady half-space (``halfspace``) and point contact (``point``).

Modules: ``params`` (material, friction), ``hertz`` (Hertz formulas), ``influence``
(half-space influence coefficients, FFT products), ``normal`` / ``tangential`` (grid
solvers), ``bundles`` (typed named tuples that the compiled kernels take), ``kernels`` (numba
inner loops, compiled lazily), ``halfspace`` / ``point`` (the two models), ``model`` (common
interface: ``ContactModel``, ``ContactResult``, ``CompiledPath``), ``factory``
(``create_model``), ``kalker`` (creep coefficient table), ``config`` / ``cli`` / ``output`` /
``plots`` (stand-alone command).
"""
