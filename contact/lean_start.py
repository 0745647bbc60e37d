"""A lean start for the contact command: rocket-fft and numba set up without scipy modules they import for nothing.

A small contact problem takes about half a second end to end, nearly all of it start-up: numpy,
numba, and what numba sets up before it can load the first cached kernel (docs/benchmarks.md,
start-up). Two scipy imports in there serve nothing the contact command runs:

* **scipy.fft**: the compiled kernels (:mod:`contact.halfspace.influence_kernels`) call ``numpy.fft``
  inside numba code through rocket-fft, a maintained numba extension (BSD-3) on DUCC0, the C++
  library of scipy.fft. Importing rocket-fft also imports ``scipy.fft`` whenever scipy is
  installed (with scipy.special and scipy's array-API layer), to register overloads of
  ``scipy.fft`` that no kernel of this project calls; numba imports rocket-fft itself, through
  its extension entry point, on the first call of any compiled function.
* **scipy.linalg**: while numba sets up its typing and lowering registries (on the first call of
  any compiled function) it imports ``scipy.linalg.cython_blas`` to learn whether a BLAS exists,
  and with it the whole of ``scipy.linalg``. numba's own linear algebra (``np.dot``,
  ``np.linalg.solve``, ...) finds BLAS and LAPACK again when such a function is compiled or first
  runs, whatever that answer was; the answer is kept only for ``np.correlate`` and
  ``np.convolve``, which then sum in a loop instead of calling BLAS (no kernel of this project
  uses them).

Together a third of numba's start-up floor (docs/benchmarks.md, *Start-up*, *Lean start*;
``python -m benchmarks.startup``). :func:`lean_start` does both set-ups first, each with its scipy module
masked in ``sys.modules`` for that moment only (``import scipy.fft`` then fails, and rocket-fft and
numba skip it). The contact command calls it before importing its solvers
(``pipeline._contact_command``); anything else keeps the usual imports. Afterwards every scipy
module imports as usual.
"""

from __future__ import annotations

import contextlib
import importlib
import logging
import sys
import threading

__all__ = ["lean_start", "import_rocket_fft_without_scipy_fft", "set_up_numba_without_scipy_linalg"]

log = logging.getLogger(__name__)


def _can_mask(*names) -> bool:
    """Whether modules ``names`` can be masked: none imported yet, and no other Python thread running
    (it could import one of them while it is masked)."""
    return threading.active_count() == 1 and not any(name in sys.modules for name in names)


@contextlib.contextmanager
def _masked(name):
    """``import name`` raises ImportError inside the block (``None`` in ``sys.modules``); as before after it."""
    sys.modules[name] = None
    try:
        yield
    finally:
        if name in sys.modules and sys.modules[name] is None:
            del sys.modules[name]


def import_rocket_fft_without_scipy_fft() -> bool:
    """Import rocket-fft registering its ``numpy.fft`` overloads only (not those of ``scipy.fft``).

    Nothing is done when rocket-fft or ``scipy.fft`` is already imported, or when another Python
    thread runs.

    Returns
    -------
    bool
        True if rocket-fft was imported here without ``scipy.fft``.
    """
    if not _can_mask("rocket_fft", "scipy.fft"):
        return False
    with _masked("scipy.fft"):
        importlib.import_module("rocket_fft")
    return True


def set_up_numba_without_scipy_linalg() -> bool:
    """Set up numba's typing and lowering registries (CPU target) without importing ``scipy.linalg``.

    Nothing is done when ``scipy.linalg`` is already imported (numba's registries may then be set
    up with it already), when another Python thread runs, or when numba's CPU target does not
    offer the set-up this calls (``numba.core.registry.cpu_target.target_context.refresh``, numba's
    internals, tested with numba 0.68): numba then sets itself up as usual on the first compiled call.

    Returns
    -------
    bool
        True if the registries were set up here without ``scipy.linalg``.
    """
    if not _can_mask("scipy.linalg"):
        return False
    try:
        from numba.core.registry import cpu_target
        refresh = cpu_target.target_context.refresh  # what the first compiled call runs
    except (ImportError, AttributeError) as exc:  # another numba's internals: the usual start
        log.debug("lean start: numba's registries not set up here (%s)", exc)
        return False
    with _masked("scipy.linalg"):
        refresh()
    return True


def lean_start() -> bool:
    """Both set-ups of this module, rocket-fft's first; True if both were done here."""
    without_fft = import_rocket_fft_without_scipy_fft()
    without_linalg = set_up_numba_without_scipy_linalg()
    log.debug("lean start: rocket-fft without scipy.fft %s, numba without scipy.linalg %s",
              without_fft, without_linalg)
    return without_fft and without_linalg
