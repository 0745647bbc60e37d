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
