"""Hooks named ``"module:function"``: the stage table and the model registries name the code they
run this way, so that it is imported at first use (a model's or a stage's module may compile
numba kernels or pull in a physics package that a listing of names should not pay for)."""

from __future__ import annotations

import importlib
from collections.abc import Callable

__all__ = ["resolve_hook"]


def resolve_hook(hook: str | Callable) -> Callable:
    """``hook`` itself if it is callable, else the attribute ``name`` of the module ``module`` that
    the string ``"module:name"`` names (imported now)."""
    if callable(hook):
        return hook
    module, _, name = hook.partition(":")
    return getattr(importlib.import_module(module), name)
