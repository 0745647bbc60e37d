"""Numeric tables shipped with the contact package (``data/*.csv``)."""

from __future__ import annotations

from importlib import resources

import numpy as np

__all__ = ["read_table"]


def read_table(filename: str) -> dict:
    """Read ``data/<filename>``: comment lines (``#``) skipped, a header row, then numbers.

    Returns
    -------
    dict of str -> ndarray
        One column per header name.
    """
    text = resources.files(__package__).joinpath("data", filename).read_text()
    lines = [ln for ln in text.splitlines() if ln.strip() and not ln.startswith("#")]
    header = [name.strip() for name in lines[0].split(",")]
    data = np.array([[float(v) for v in ln.split(",")] for ln in lines[1:]])
    return {name: data[:, i] for i, name in enumerate(header)}
