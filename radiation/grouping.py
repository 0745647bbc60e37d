"""Grouping of radiation results by operating point: the three wheel models of one case."""

from __future__ import annotations

import re

MODEL_ORDER = ("stationary", "moving_load", "eulerian")
"""Wheel models in the order the report and figures show them (the reference first)."""


def case_key(case_id):
    """A case id without its wheel model and hash, to pair the three models of one operating point."""
    label = case_id.rsplit("-", 1)[0]
    return re.sub(r"_?wheel_model=(stationary|moving_load|eulerian)", "", label) or "base"
