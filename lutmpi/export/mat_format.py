"""``mat``: the whole table for MATLAB / ``scipy.io.loadmat`` (MAT-file level 5).

Variables: ``y`` (m), ``yaw`` (rad); one struct per contact method (``load_centre``, ...) with every
dataset the table holds, stored values unchanged (SI, the schema's shapes ``(ny, nyaw, side, slot,
xyz)``, integer codes as integers, not-converged points as stored: use ``status``); ``units`` and
``description`` structs (method -> dataset -> text); ``status_codes`` (a cell of ``"code: text"``);
``attrs`` (the root attributes as text, ``config_toml`` included). Datasets the table adds beyond
the schema (e.g. stored jump curves) are written the same way, so the file holds every dataset of
the HDF5 file; a test reads it back with ``scipy.io.loadmat`` and compares each one to the HDF5.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np

from lutmpi.equilibrium.result import STATUS
from lutmpi.errors import TableError
from lutmpi.table.schema import JUMPS_GROUP

NAME = "mat"
DESCRIPTION = "the whole table (grid, every dataset, units, status codes) for MATLAB / scipy"
_MAX_NAME = 63   # MATLAB's limit on variable and field names


def _check_name(name: str) -> str:
    if not name.isidentifier() or len(name) > _MAX_NAME:
        raise TableError(f"{name!r} cannot be a MATLAB variable or field name")
    return name


def content(table: Any) -> dict[str, Any]:
    """The dictionary ``scipy.io.savemat`` writes."""
    out: dict[str, Any] = {"y": np.asarray(table.y), "yaw": np.asarray(table.yaw)}
    units: dict[str, Any] = {}
    desc: dict[str, Any] = {}
    for method in table.methods:
        group = table.data[method]
        out[_check_name(method)] = {_check_name(k): np.asarray(v) for k, v in group.items()}
        stored_jumps = _jumps(table, method)
        if stored_jumps:
            out[method][JUMPS_GROUP] = stored_jumps
        meta = table.meta[method]
        units[method] = {k: str(meta.get(k, {}).get("units", "")) for k in group}
        desc[method] = {k: str(meta.get(k, {}).get("description", "")) for k in group}
    out["units"] = units
    out["description"] = desc
    out["status_codes"] = np.array([f"{k}: {v}" for k, v in STATUS.items()], dtype=object)
    out["attrs"] = {_check_name(k): (v if isinstance(v, str) else json.dumps(v, default=str))
                    for k, v in table.attrs.items()}
    return out


def _jumps(table: Any, method: str) -> dict[str, Any]:
    """The located contact jumps of ``method`` as the HDF5 group ``/<method>/jumps`` holds them:
    its datasets, and its sub-groups (one-sided limits, knots) as structs (empty: none stored).

    ``Table.jumps[method]`` (issue 11) is ``{"arrays": {...}, "<sub-group>": {...}, "attrs": ...}``.
    """
    stored = (getattr(table, "jumps", None) or {}).get(method)
    if not stored:
        return {}
    node: dict[str, Any] = {_check_name(k): np.asarray(v)
                            for k, v in stored.get("arrays", {}).items()}
    for key, sub in stored.items():
        if key not in ("arrays", "attrs") and isinstance(sub, dict):
            node[_check_name(key)] = {_check_name(k): np.asarray(v) for k, v in sub.items()}
    return node


def output_path(table_path: str | Path, out: Path) -> Path:
    """The file written for ``out``: ``.mat`` added when missing; a directory gets
    ``<table stem>.mat``."""
    if out.is_dir():
        return out / f"{Path(table_path).stem}.mat"
    return out if out.suffix == ".mat" else out.with_name(out.name + ".mat")


def write(table: Any, out: Path, **_: Any) -> list[Path]:
    """Write :func:`output_path` of ``out``."""
    import scipy.io

    out = output_path(table.path, out)
    scipy.io.savemat(out, content(table), do_compression=True, oned_as="column",
                     long_field_names=True)
    return [out]
