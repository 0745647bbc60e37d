"""One declaration per parameter: the schema of study sections and contact case files.

A *section* is a frozen dataclass whose fields are declared with :func:`param`; the dataclass
is both the typed view the physics code uses and the schema of the TOML table it is read from.
Everything else is generated from these declarations:

- validation and error messages (:func:`build`: field name, allowed range or choices, unit),
- the defaults (:func:`defaults`; the complete default study is assembled from them),
- the documentation table (:func:`markdown_table`, used to write ``docs/parameters.md``).

Declaring a section::

    @section("operating")
    @dataclass(frozen=True)
    class OperatingParams:
        speed: float = param(13.9, unit="m/s", low=0.0, high=150.0, low_open=True,
                             doc="Train speed.")

        def cross_check(self, prefix):      # optional: checks between fields
            ...

    OperatingParams.from_mapping({"speed": 20.0})   # validated instance

A parameter shared by two sections (e.g. the friction coefficient of the study's ``[contact]``
and of a contact case file's ``[friction]``) is declared once as a :class:`Param` and turned into
a field in each section with :meth:`Param.field`.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import Any, Mapping

from .errors import InputError

__all__ = ["REQUIRED", "Param", "param", "section", "spec_of", "file_params", "build", "defaults",
           "markdown_table", "qualified"]


class _Required:
    """Marker of a parameter without a default (the user must give it)."""

    def __repr__(self):
        return "REQUIRED"


REQUIRED = _Required()

KINDS = ("number", "integer", "boolean", "string", "choice", "numbers", "file")


def qualified(prefix, key):
    """Dotted field name ``prefix.key`` (just ``key`` at the top level, ``prefix == ""``)."""
    return f"{prefix}.{key}" if prefix else key


def _infer_kind(default, choices):
    if choices:
        return "choice"
    if isinstance(default, bool):
        return "boolean"
    if isinstance(default, int):
        return "integer"
    if isinstance(default, float):
        return "number"
    if isinstance(default, str):
        return "string"
    if isinstance(default, (list, tuple)):
        return "numbers"
    raise TypeError(f"cannot infer the kind of a parameter with default {default!r}; give kind=")


@dataclasses.dataclass(frozen=True)
class Param:
    """Declaration of one parameter.

    Parameters
    ----------
    kind : str
        ``"number"`` (finite real), ``"integer"``, ``"boolean"``, ``"string"``, ``"choice"``
        (one of ``choices``), ``"numbers"`` (a list of ``length`` finite reals, each in the
        range) or ``"file"`` (a string naming a file whose *contents* the stage hash includes,
        unless it is ``""`` or one of ``choices``, the built-in names such as ``"S1002"``).
    default : object
        The default; :data:`REQUIRED` when the user must give the value; ``None`` when "not
        given" has a meaning of its own (explained in ``doc``).
    unit : str
        SI unit shown in messages and documentation (``""`` for dimensionless).
    low, high : float or None
        Bounds of numbers (None: unbounded); ``low_open`` / ``high_open`` exclude them.
    choices : tuple
        The allowed values of a ``"choice"``; for a ``"file"``, the built-in names that are no
        file.
    length : int
        Number of entries of a ``"numbers"`` list.
    doc : str
        One-sentence description for the documentation.
    """

    kind: str
    default: Any = REQUIRED
    unit: str = ""
    low: float | None = None
    high: float | None = None
    low_open: bool = False
    high_open: bool = False
    choices: tuple | Callable[[], tuple] = ()
    length: int = 0
    doc: str = ""

    @property
    def options(self) -> tuple:
        """The allowed values: ``choices``, or what it returns if it is a callable (a registry's
        names, read at each use, so that a model registered later is allowed)."""
        return tuple(self.choices()) if callable(self.choices) else self.choices

    def __post_init__(self):
        if self.kind not in KINDS:
            raise ValueError(f"unknown parameter kind {self.kind!r}")
        if self.default is not REQUIRED and self.default is not None:
            self.check("default", self.default)  # a declaration error, found at import

    @property
    def required(self) -> bool:
        """True if the parameter has no default."""
        return self.default is REQUIRED

    def interval(self) -> str:
        """The allowed interval of a number, e.g. ``"(0, 150] m/s"``."""
        lo = "(" if self.low_open or self.low is None else "["
        hi = ")" if self.high_open or self.high is None else "]"
        low = "-inf" if self.low is None else f"{self.low:g}"
        high = "inf" if self.high is None else f"{self.high:g}"
        return f"{lo}{low}, {high}{hi} {self.unit}".rstrip()

    def names_file(self, value) -> bool:
        """True if ``value`` of this parameter is the path of a file (a ``"file"`` parameter
        set to something else than ``""`` or one of its built-in names)."""
        return self.kind == "file" and isinstance(value, str) and value != "" and value not in self.options

    def allowed(self) -> str:
        """What the parameter accepts, in words (used in messages and in the documentation)."""
        if self.kind == "file":
            names = " | ".join(repr(c) for c in self.options)
            return "a file path" + (f" or one of {names}" if names else "")
        if self.kind == "boolean":
            return "true or false"
        if self.kind == "string":
            return "a string"
        if self.kind == "choice":
            return "one of " + " | ".join(repr(c) for c in self.options)
        if self.kind == "integer":
            return f"an integer in {self.interval()}"
        if self.kind == "numbers":
            return f"a list of {self.length} numbers in {self.interval()}"
        return f"a finite number in {self.interval()}"

    def _number(self, field, value, what="a number"):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise InputError(field, f"must be {what} in {self.interval()}, got {value!r}")
        if not math.isfinite(value):
            raise InputError(field, f"must be a finite number in {self.interval()}, got {value!r}")
        if self.low is not None and (value < self.low or (self.low_open and value == self.low)):
            raise InputError(field, f"must lie in {self.interval()}, got {value:g}")
        if self.high is not None and (value > self.high or (self.high_open and value == self.high)):
            raise InputError(field, f"must lie in {self.interval()}, got {value:g}")
        return value

    def check(self, field, value):
        """Return ``value`` checked and normalised (float, int, list of float).

        Parameters
        ----------
        field : str
            Dotted field name for the message.
        value : object
            The value read from TOML (or given in Python).

        Raises
        ------
        InputError
            Naming ``field`` and what is allowed (range with unit, or choices).
        """
        if self.kind == "boolean":
            if not isinstance(value, bool):
                raise InputError(field, f"must be true or false, got {value!r}")
            return value
        if self.kind in ("string", "file"):
            if not isinstance(value, str):
                raise InputError(field, f"must be {self.allowed() if self.kind == 'file' else 'a string'}, "
                                        f"got {value!r}")
            return value
        if self.kind == "choice":
            if isinstance(value, bool) or value not in self.options:
                raise InputError(field, f"must be {self.allowed()}, got {value!r}")
            return value
        if self.kind == "integer":
            if isinstance(value, bool) or not isinstance(value, int):
                raise InputError(field, f"must be {self.allowed()}, got {value!r}")
            return int(self._number(field, value))
        if self.kind == "numbers":
            if not isinstance(value, (list, tuple)) or len(value) != self.length:
                raise InputError(field, f"must be {self.allowed()}, got {value!r}")
            return [float(self._number(field, v)) for v in value]
        return float(self._number(field, value))

    def field(self, default=dataclasses.MISSING):
        """A :func:`dataclasses.field` carrying this declaration (optionally another default)."""
        spec = self if default is dataclasses.MISSING else dataclasses.replace(self, default=default)
        metadata = {"schema": spec}
        if spec.required:
            return dataclasses.field(metadata=metadata)
        if isinstance(spec.default, list):
            return dataclasses.field(default_factory=lambda: list(spec.default), metadata=metadata)
        return dataclasses.field(default=spec.default, metadata=metadata)


def param(default=REQUIRED, *, unit="", low=None, high=None, low_open=False, high_open=False,
          choices=(), kind=None, length=None, doc=""):
    """Declare one parameter of a section (a dataclass field with its schema as metadata).

    Parameters
    ----------
    default : object
        Default value; its type gives the kind (bool, int, float, str, list) unless ``kind`` or
        ``choices`` is given. :data:`REQUIRED`: no default. ``None``: "not given" (give ``kind``).
    unit, low, high, low_open, high_open, choices, doc
        See :class:`Param`.
    kind : str, optional
        Explicit kind (needed when ``default`` is None or REQUIRED).
    length : int, optional
        Number of entries of a list (default: the length of ``default``).

    Returns
    -------
    dataclasses.Field
    """
    if kind is None:
        kind = _infer_kind(default, choices)
    if length is None:
        length = len(default) if kind == "numbers" and isinstance(default, (list, tuple)) else 0
    if isinstance(default, tuple):
        default = list(default)
    return Param(kind, default, unit, low, high, low_open, high_open,
                 choices if callable(choices) else tuple(choices), length, doc).field()


def spec_of(cls) -> dict[str, Param]:
    """The parameter declarations of a section class, in declaration order."""
    return {f.name: f.metadata["schema"] for f in dataclasses.fields(cls) if "schema" in f.metadata}


def file_params(cls) -> dict[str, Param]:
    """The parameters of a section class that may name a file (kind ``"file"``)."""
    return {name: p for name, p in spec_of(cls).items() if p.kind == "file"}


def defaults(cls) -> dict[str, Any]:
    """The defaults of a section (parameters with a default other than None)."""
    return {name: (list(p.default) if isinstance(p.default, list) else p.default)
            for name, p in spec_of(cls).items() if not p.required and p.default is not None}


def build(cls, mapping: Mapping[str, Any] | None = None, prefix: str | None = None):
    """Validate a table against a section's schema and return the section instance.

    Parameters
    ----------
    cls : type
        A class decorated with :func:`section`.
    mapping : Mapping or None
        Key -> value (e.g. a parsed TOML table without its sub-tables); missing keys take the
        defaults.
    prefix : str, optional
        Dotted name of the table in messages (default: the section's name).

    Returns
    -------
    object
        ``cls(**values)`` after its ``cross_check(prefix)`` hook (if it has one).

    Raises
    ------
    InputError
        For unknown keys, missing required keys, values of the wrong type, non-finite or out of
        range, and failed cross-field checks.
    """
    prefix = cls.SECTION if prefix is None else prefix
    mapping = dict(mapping or {})
    spec = spec_of(cls)
    for key in mapping:
        if key not in spec:
            raise InputError(qualified(prefix, key), f"unknown key; must be one of: {', '.join(spec)}")
    values = {}
    for name, p in spec.items():
        field = qualified(prefix, name)
        if name in mapping:
            values[name] = p.check(field, mapping[name])
        elif p.required:
            raise InputError(field, f"missing; must be {p.allowed()}")
    instance = cls(**values)
    hook = getattr(instance, "cross_check", None)
    if hook is not None:
        hook(prefix)
    return instance


def section(name, doc=""):
    """Class decorator: mark a dataclass as the schema of the table ``name``.

    Adds ``SECTION`` (the dotted table name), ``SECTION_DOC`` and a ``from_mapping(mapping=None,
    prefix=name)`` class method (:func:`build`) unless the class defines its own.
    """

    def decorate(cls):
        if not dataclasses.is_dataclass(cls):
            raise TypeError(f"{cls.__name__}: @section goes above @dataclass")
        cls.SECTION = name
        cls.SECTION_DOC = doc or (cls.__doc__ or "").strip().splitlines()[0]
        if "from_mapping" not in cls.__dict__:
            cls.from_mapping = classmethod(build)
        return cls

    return decorate


def _format_value(value):
    if value is None:
        return "(not set)"
    if value is REQUIRED:
        return "(required)"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'`"{value}"`'
    if isinstance(value, list):
        return "`[" + ", ".join(f"{v:g}" for v in value) + "]`"
    if isinstance(value, float):
        return f"`{value!r}`"
    return f"`{value}`"


def _format_allowed(p):
    if p.kind == "choice":
        return " \\| ".join(f'`"{c}"`' for c in p.options)
    if p.kind in ("boolean", "string"):
        return p.kind
    if p.kind == "file":
        return " \\| ".join(["file path"] + [f'`"{c}"`' for c in p.options])
    text = p.interval()
    if p.unit:
        text = text[: -len(p.unit)].rstrip()
    if p.kind == "integer":
        return f"integer in {text}"
    if p.kind == "numbers":
        return f"{p.length} numbers, each in {text}"
    return text


def markdown_table(cls, prefix=None) -> str:
    """The documentation table of a section: key, default, unit, allowed values, description."""
    prefix = cls.SECTION if prefix is None else prefix
    lines = ["| key | default | unit | allowed | description |", "|---|---|---|---|---|"]
    for name, p in spec_of(cls).items():
        doc = p.doc.replace("|", "\\|").replace("\n", " ")
        lines.append(f"| `{qualified(prefix, name)}` | {_format_value(p.default)} | {p.unit or '-'} | "
                     f"{_format_allowed(p)} | {doc} |")
    return "\n".join(lines)
