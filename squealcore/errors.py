"""Errors raised for bad user input.

Every check of user input raises :class:`InputError` naming the offending field and the
allowed range, so that the command line can print one clear line and exit with status 2.
"""

from __future__ import annotations


class InputError(ValueError):
    """Invalid user input.

    Parameters
    ----------
    field : str
        Dotted name of the offending input, e.g. ``"wheel.web_thickness"``.
    message : str
        What is wrong and what is allowed, e.g. ``"must be > 0 m (got -0.01)"``.
    """

    def __init__(self, field: str, message: str):
        self.field = field
        self.message = message
        super().__init__(f"{field}: {message}")


def require_range(field, value, low=None, high=None, *, low_open=False, high_open=False, unit=""):
    """Check that a real number lies in an interval and return it as float.

    Parameters
    ----------
    field : str
        Dotted field name used in the error message.
    value : object
        The value to check; must be a real number (bool is refused).
    low, high : float or None
        Bounds of the allowed interval; ``None`` means unbounded.
    low_open, high_open : bool
        Whether the corresponding bound is excluded.
    unit : str
        Unit shown in the message.

    Returns
    -------
    float
        ``value`` as a float.

    Raises
    ------
    InputError
        If ``value`` is not a real number or lies outside the interval.
    """
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise InputError(field, f"must be a number, got {value!r}")
    value = float(value)
    if value != value:  # NaN
        raise InputError(field, "must be a number, got NaN")
    lo = "(" if low_open else "["
    hi = ")" if high_open else "]"
    allowed = f"{lo}{'-inf' if low is None else low}, {'inf' if high is None else high}{hi}"
    if unit:
        allowed += f" {unit}"
    if low is not None and (value < low or (low_open and value == low)):
        raise InputError(field, f"must lie in {allowed}, got {value:g}")
    if high is not None and (value > high or (high_open and value == high)):
        raise InputError(field, f"must lie in {allowed}, got {value:g}")
    return value


def printable(value, limit=None):
    """``value`` as one line of text a terminal shows as it is: control characters escaped.

    Newlines, tabs, ESC, BEL and every other control or format character (Unicode categories Cc,
    Cf, Zl, Zp) become ``\\n``, ``\\t``, ``\\x1b``, ``\\u2028``, ..., so that text from a study
    file, a file name or a file's contents cannot forge a line or move the cursor. With ``limit``
    the text is cut to that many characters (``...`` appended).
    """
    import unicodedata  # lazy: small, but this module is imported at every start

    text = str(value)
    out = []
    for char in text:
        if char.isprintable() or char == " ":
            out.append(char)
        elif char in "\n\t\r":
            out.append({"\n": "\\n", "\t": "\\t", "\r": "\\r"}[char])
        elif unicodedata.category(char) in ("Cc", "Cf", "Zl", "Zp", "Cs", "Co", "Cn") or ord(char) < 0x20:
            out.append(f"\\x{ord(char):02x}" if ord(char) < 0x100 else f"\\u{ord(char):04x}")
        else:
            out.append(char)
    text = "".join(out)
    if limit is not None and len(text) > limit:
        text = text[:max(0, limit - 3)] + "..."
    return text


#: Largest input file read (bytes) unless a reader states its own limit: study files, profile and
#: outline files are a few kB.
MAX_INPUT_BYTES = 16 << 20


def check_input_file(field, path, max_bytes=MAX_INPUT_BYTES, what="file", show_path=True, missing_ok=False):
    """Refuse an input file that is not a regular file or is larger than ``max_bytes``.

    A FIFO would block the reader, a device such as ``/dev/zero`` never ends: both are refused
    before they are opened (``os.stat`` does not block).

    Returns
    -------
    int or None
        The file's size (bytes); None for a missing file with ``missing_ok``.

    Raises
    ------
    InputError
        Naming ``field`` and the path (escaped), for a missing file (unless ``missing_ok``), a
        folder, a FIFO, a device, a socket or a file that is too large.
    """
    import os
    import stat

    shown = printable(str(path), limit=300)

    def problem(text):  # "<path>: <text>", or "<text>" when the field is the path
        return InputError(field, f"{shown}: {text}" if show_path else text)

    try:
        info = os.stat(path)
    except FileNotFoundError:
        if missing_ok:  # the reader says so, in its own words
            return None
        raise problem("file not found") from None
    except OSError as exc:
        raise problem(f"cannot be read ({exc.strerror or exc.__class__.__name__})") from None
    if stat.S_ISDIR(info.st_mode):
        raise problem(f"is a directory, expected a {what}")
    if not stat.S_ISREG(info.st_mode):
        kind = ("a FIFO (named pipe)" if stat.S_ISFIFO(info.st_mode) else "a device" if stat.S_ISCHR(info.st_mode)
                or stat.S_ISBLK(info.st_mode) else "a socket" if stat.S_ISSOCK(info.st_mode) else "not a regular file")
        raise problem(f"is {kind}, expected a regular {what}")
    if info.st_size > max_bytes:
        raise problem(f"{info.st_size} bytes, more than the {max_bytes} bytes a {what} may have")
    return info.st_size
