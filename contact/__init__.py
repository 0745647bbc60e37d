"""Rolling contact: the models, their shared theory, and the stand-alone contact command.

One folder per model, each registering itself once in :mod:`contact.registry` (like meshio's
format registry): ``halfspace/`` (Kalker-type non-steady half-space, the paper's model) and
``point/`` (Hertz spring and transient strips). Shared by the models: ``model`` (the common
interface: ``ContactModel``, ``ContactResult``, ``CompiledPath``), ``params`` (material,
friction, the study's ``[contact]`` section), ``hertz`` (Hertz formulas), ``kalker`` (creep
coefficient table), ``friction_kernels`` and ``kernels_linalg`` (compiled helpers), ``factory``
(``create_model``). The stand-alone command: ``config`` (case files), ``cli``, ``output``,
``plots``, ``lean_start``, ``examples/``.

A new model is a new folder whose ``__init__.py`` calls :func:`contact.registry.register`, and
one import line below.
"""

from contact import registry  # noqa: F401  (first: the model folders register into it)
from contact import halfspace, point  # noqa: F401  (each registers itself)
