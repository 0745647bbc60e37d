"""Grouping of radiation results by operating point: the three wheel models of one case."""

from __future__ import annotations

import re

from interaction.params import WHEEL_MODELS

MODEL_ORDER = WHEEL_MODELS
"""Wheel models in the order the report and figures show them: the interaction's order, the
stationary reference first."""


def case_key(case_id):
    """A case id without its wheel model and hash, to pair the three models of one operating point."""
    label = case_id.rsplit("-", 1)[0]
    return re.sub(r"_?wheel_model=(" + "|".join(WHEEL_MODELS) + ")", "", label) or "base"
