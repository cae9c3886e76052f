"""``--solver module:function``: a test or research solver in place of the production one
(``build`` and ``sweep``)."""

from __future__ import annotations

import importlib
from typing import Any


def load_solver_hook(spec: str) -> tuple[Any, Any]:
    """``"module:function"`` -> ``(solver, make_scene or None)``."""
    from lutmpi.errors import ConfigError

    module_name, sep, func_name = spec.partition(":")
    try:
        module = importlib.import_module(module_name) if sep else None
        return getattr(module, func_name), getattr(module, "make_scene", None)
    except (ImportError, AttributeError) as exc:
        raise ConfigError(f"--solver expects an importable module:function, got {spec!r} "
                          f"({exc})") from exc
