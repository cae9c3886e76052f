"""Contact providers for the dynamics from the command line's inputs: a table file or a config for
the online solve, and the wheelset data each carries (the layer above ``dynamics/``, which never
reads a file or a config itself). Used by ``simulate`` and ``critical-speed``."""

from __future__ import annotations

from pathlib import Path
from typing import Any


def make_provider(config: str | Path, table: str | Path | None = None, online: bool = False,
                  method: str | None = None) -> tuple[Any, Any, str]:
    """``(provider, params, description)``: the table's contact (``table``, its ``method``
    group, default its first) with the wheelset data its build wrote, or with ``online`` a pose
    solve of ``config``'s scene at every call (``method``, default the config's)."""
    from lutmpi.config.load import load_config
    from lutmpi.dynamics.contact_provider import OnlineProvider, TableProvider
    from lutmpi.dynamics.wheelset import WheelsetParams
    from lutmpi.errors import ConfigError

    cfg = load_config(config)
    if online:
        from lutmpi.scene import Scene

        method = method or cfg.contact.method
        params = WheelsetParams.from_config(cfg)
        return OnlineProvider(Scene.from_config(cfg), method), params, f"online:{method}"
    if not table:
        raise ConfigError("--table is required unless --online is given")
    from lutmpi.table import Table

    opened = Table.open(table)
    method = method or opened.methods[0]
    return TableProvider(opened, method), params_from_table(opened), f"table:{table}:{method}"


def params_from_table(table: Any) -> Any:
    """Wheelset data (E, nu, r0, vertical load) from the attributes the table's build wrote
    (:data:`lutmpi.table.schema.DYNAMICS_ATTRIBUTES`); the rest is Table 2 of the paper."""
    from lutmpi.dynamics.wheelset import WheelsetParams

    return WheelsetParams(young=float(table.attribute("young_modulus")),
                          poisson=float(table.attribute("poisson_ratio")),
                          r0=float(table.attribute("nominal_radius")),
                          vertical_load=float(table.attribute("vertical_load")))
