"""Grouping of radiation results by operating point: the wheel models of one case (in the registry's order,
:mod:`interaction.wheel_models`, the reference first)."""

from __future__ import annotations

import re

from interaction.wheel_models import wheel_model_names


def case_key(case_id):
    """A case id without its wheel model and hash, to pair the three models of one operating point."""
    label = case_id.rsplit("-", 1)[0]
    return re.sub(r"_?wheel_model=(" + "|".join(map(re.escape, wheel_model_names())) + ")", "", label) or "base"
