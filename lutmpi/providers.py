"""Contact providers for the dynamics from the command line's inputs: a table file or a config for
the online solve, and the wheelset data each carries (the layer above ``dynamics/``, which never
reads a file or a config itself). Used by ``simulate`` and ``critical-speed``."""

from __future__ import annotations

import argparse
import json
import logging
from collections.abc import Callable
from pathlib import Path
from typing import Any

log = logging.getLogger(__name__)

#: the config sections (dotted-key prefixes) that describe the wheelset, its track and the data
#: the dynamics takes from a table (load, E, nu); the grid, the mesh, the contact method and the
#: solver settings only say how a table was computed
PAIR_KEYS = ("wheel.", "rail.", "track.", "wheelset.", "wear.", "material.",
             "equilibrium.vertical_load_N")


def make_provider(config: str | Path, table: str | Path | None = None, online: bool = False,
                  method: str | None = None) -> tuple[Any, Any, str]:
    """``(provider, params, description)``: the table's contact (``table``, its ``method``
    group, default its first) with the wheelset data its build wrote, or with ``online`` a pose
    solve of ``config``'s scene at every call (``method``, default the config's).

    With a table, ``config`` is validated and compared with the config the table was built from:
    a different wheelset, track, wear, material or load is logged as a warning naming each key
    (the run uses the table's). With ``online``, a ``table`` is not read, and a warning says so.

    Raises
    ------
    ConfigError
        No ``table`` without ``online``; a ``method`` that is no contact method (on-line).
    """
    from lutmpi.config.load import load_config
    from lutmpi.dynamics.contact_provider import OnlineProvider, TableProvider
    from lutmpi.dynamics.wheelset import WheelsetParams
    from lutmpi.errors import ConfigError

    cfg = load_config(config)
    if online:
        from lutmpi.contact.methods import METHOD_NAMES
        from lutmpi.scene import Scene

        if table:
            log.warning("--online: the contact comes from pose solves of %s's pair; the table "
                        "%s is not read (leave out --table, or --online to use it)", config,
                        table)
        if method is not None and method not in METHOD_NAMES:
            raise ConfigError(f"--method: expected one of {', '.join(METHOD_NAMES)}, got "
                              f"{method!r}")
        method = method or cfg.contact.method
        params = WheelsetParams.from_config(cfg)
        return OnlineProvider(Scene.from_config(cfg), method), params, f"online:{method}"
    if not table:
        raise ConfigError("--table is required unless --online is given")
    from lutmpi.table import Table

    opened = Table.open(table)
    method = method or opened.methods[0]
    provider = TableProvider(opened, method)
    diffs = pair_differences(cfg, opened)
    if diffs:
        log.warning("%s describes another wheelset than the one %s was built from (%s); the run "
                    "uses the table's pair and its E, nu, r0 and load, not the config's. Give "
                    "the table's own config, or build a table from this one", config, table,
                    "; ".join(diffs))
    return provider, params_from_table(opened), f"table:{table}:{method}"


def pair_differences(config: Any, table: Any) -> list[str]:
    """What differs between ``config`` and the config ``table`` was built from, in the keys of
    :data:`PAIR_KEYS`: ``"key: <config's> (config), <table's> (table)"``, profile files compared
    by content (SHA-256, :func:`lutmpi.table.provenance.input_record`), not by path.

    Parameters
    ----------
    config : lutmpi.config.model.Config
        The resolved config given with the table.
    table : lutmpi.table.Table
    """
    import tomllib

    from lutmpi.config.load import config_from_dict
    from lutmpi.table.provenance import input_record

    given = input_record(config)["config"]
    stored = json.loads(table.attrs.get("inputs") or "{}").get("config")
    if not stored:               # a table made before inputs were recorded: its stored config
        stored = input_record(config_from_dict(tomllib.loads(table.config_toml)))["config"]
    out = []
    # a key only one record has is a setting one lutmpi version knows and the other not
    for key in sorted(set(given) & set(stored)):
        if not key.startswith(PAIR_KEYS):
            continue
        mine, theirs = given.get(key), stored.get(key)
        if mine != theirs:
            out.append(f"{key}: {_short(mine)} (config), {_short(theirs)} (table)")
    return out


def _short(value: Any) -> str:
    """A config value for a message: a file by the first 12 digits of its hash."""
    text = str(value)
    return f"file sha256 {text[12:24]}" if text.startswith("file sha256 ") else repr(value)


def duration_type(dt_out: float) -> Callable[[str], float]:
    """An argparse type of ``--duration`` (``simulate``, ``critical-speed``): a run length in s,
    a finite number > 0 whose output samples (one every ``dt_out`` s) fit in
    :data:`lutmpi.dynamics.simulate.MAX_OUTPUT_SAMPLES`; else a usage error."""
    from lutmpi.argtypes import positive

    def check(text: str) -> float:
        from lutmpi.dynamics.simulate import MAX_OUTPUT_SAMPLES

        v = positive(text)
        longest = (MAX_OUTPUT_SAMPLES - 1) * dt_out
        if v > longest:
            raise argparse.ArgumentTypeError(
                f"expected at most {longest:g} s (a run keeps {MAX_OUTPUT_SAMPLES} output "
                f"samples, one every {dt_out:g} s), got {text!r}")
        return v

    return check


def params_from_table(table: Any) -> Any:
    """Wheelset data (E, nu, r0, vertical load) from the attributes the table's build wrote
    (:data:`lutmpi.table.schema.DYNAMICS_ATTRIBUTES`); the rest is Table 2 of the paper."""
    from lutmpi.dynamics.wheelset import WheelsetParams

    return WheelsetParams(young=float(table.attribute("young_modulus")),
                          poisson=float(table.attribute("poisson_ratio")),
                          r0=float(table.attribute("nominal_radius")),
                          vertical_load=float(table.attribute("vertical_load")))
