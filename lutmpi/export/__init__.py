"""Export a lookup table to the formats other tools read: a registry, one module per format.

Each format module defines ``NAME``, ``DESCRIPTION`` and ``write(table, out, **options) -> list of
paths``; it is registered by one line in :data:`FORMATS`. Formats read the table through
:class:`lutmpi.table.Table` only, and take their columns and fields from
:mod:`lutmpi.table.schema` (via :mod:`lutmpi.reports.units`), never from a list of their own.

>>> from lutmpi.export import export
>>> export("t.h5", "csv", "t_yaw0.csv", yaw=0.0)
"""

from __future__ import annotations

import importlib
import os
from pathlib import Path
from types import ModuleType
from typing import Any

from lutmpi.errors import ConfigError

#: format name -> module (``lutmpi.export.<module>``)
FORMATS: dict[str, str] = {
    "csv": "lutmpi.export.csv_format",
    "mat": "lutmpi.export.mat_format",
    "kpf": "lutmpi.export.kpf_format",
}


def format_module(name: str) -> ModuleType:
    """The module of format ``name``; an unknown name raises and lists the valid ones."""
    if name not in FORMATS:
        raise ConfigError(f"unknown export format {name!r}; valid: {', '.join(FORMATS)}",
                          key="--format")
    return importlib.import_module(FORMATS[name])


def export(table: Any, fmt: str, out: str | os.PathLike[str], **options: Any) -> list[Path]:
    """Write ``table`` (a :class:`~lutmpi.table.Table` or a path) as ``fmt`` to ``out``.

    Returns
    -------
    list of pathlib.Path
        The files written.
    """
    from lutmpi.table import Table

    module = format_module(fmt)
    if not isinstance(table, Table):
        table = Table.open(table, mask_failed=False)
    return list(module.write(table, Path(out), **options))
