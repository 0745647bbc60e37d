"""What compiled libraries print goes to the log, not the terminal.

Some libraries write to the process's standard output from compiled code, past Python and past
their own logging switches (gmsh's embedded Netgen optimiser prints ``WARNING:
shrinks.length==shrinks_max=28`` although ``General.Terminal`` is 0). :func:`stdout_to_log`
points file descriptor 1 at a temporary file while such a library runs and logs what it wrote
(INFO: shown with ``--verbose``), so the terminal shows only what the command prints itself.
"""

from __future__ import annotations

import contextlib
import ctypes
import logging
import os
import sys
import tempfile

#: Most bytes of a library's output kept for the log per block.
MAX_LOGGED_BYTES = 1 << 16


def _flush_c_stdio():
    """Flush the C library's output buffers (``fflush(NULL)``; C++ streams write through them)."""
    try:
        ctypes.CDLL(None).fflush(None)
    except (OSError, AttributeError, TypeError):  # no C library to ask (not POSIX)
        pass


@contextlib.contextmanager
def stdout_to_log(logger, source, level=logging.INFO):
    """While the block runs, what is written on file descriptor 1 goes to ``logger`` (one record per
    line, prefixed with ``source``) instead of the terminal. Does nothing where file descriptor 1
    cannot be redirected."""
    try:
        sys.stdout.flush()
    except (OSError, ValueError, AttributeError):
        pass
    try:
        capture = tempfile.TemporaryFile()
        saved = os.dup(1)
    except OSError:
        yield
        return
    try:
        os.dup2(capture.fileno(), 1)
    except OSError:
        os.close(saved)
        capture.close()
        yield
        return
    try:
        yield
    finally:
        _flush_c_stdio()
        os.dup2(saved, 1)
        os.close(saved)
        try:
            capture.seek(0)
            text = capture.read(MAX_LOGGED_BYTES).decode("utf-8", "replace")
        except OSError:
            text = ""
        capture.close()
        for line in text.splitlines():
            if line.strip():
                logger.log(level, "%s: %s", source, line.strip())


#: Format of the log records on stderr (the command line's and its case worker's alike).
LOG_FORMAT = "%(levelname)s %(name)s: %(message)s"


def route_library_warnings(verbose: bool) -> None:
    """Send Python warnings (numba's performance and deprecation warnings, scipy's ``LinAlgWarning``,
    numpy's floating-point ``RuntimeWarning``) to the log instead of printing them: they become
    records of the logger ``py.warnings``, shown only with ``verbose`` (the project's own code
    reports through ``logging``, never through :mod:`warnings`)."""
    logging.captureWarnings(True)
    logging.getLogger("py.warnings").setLevel(logging.INFO if verbose else logging.ERROR)


def configure_worker_logging(level: int) -> None:
    """Logging of a worker process the command line starts (its cases run there): records at
    ``level`` and above on stderr in :data:`LOG_FORMAT`, library warnings routed as by
    :func:`route_library_warnings` (shown when ``level`` is INFO or lower, i.e. ``--verbose``)."""
    handler = logging.StreamHandler(sys.stderr)
    handler.setFormatter(logging.Formatter(LOG_FORMAT))
    logging.basicConfig(level=level, handlers=[handler], force=True)
    route_library_warnings(level <= logging.INFO)
