"""Study files shipped with the toolkit: ``paper.toml`` (the default study) and ``quick.toml``."""

from importlib import resources


def study_path(name):
    """Path of a shipped study file, e.g. ``study_path("paper.toml")``."""
    return resources.files(__name__) / name
