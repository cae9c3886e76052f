"""Sweep files → a list of run specs (pure: no MPI, no computation, same answer on every rank).

A sweep file::

    base = "paper_s1002_uic60_1in20.toml"    # a config file (relative to this file) ...
    # ... or the config inline:  [base.wheel] generator = "S1002"  [base.rail] ...

    [sweep]                                  # or several [[sweep]] blocks, members concatenated
    product = { "contact.method" = ["max_distance", "load_centre"], "mesh.spacing_mm" = [1.0, 0.5] }
    zip = { "wheel.profile" = ["a.whl", "b.whl"], "rail.profile" = ["a.ban", "b.ban"] }

``product`` is the Cartesian product of its lists; ``zip`` walks its lists together (equal lengths);
a block with both takes the product of the ``product`` lists with the zipped tuples. Keys are the
dotted keys of the config (``lutmpi.config.load.leaf_keys()``) plus the shorthand
``mesh.spacing_mm`` (all four mesh spacings). Bare dotted keys (``{contact.method = [...]}``)
mean the same as quoted ones.
Setting ``wheel.profile`` or ``wheel.generator`` replaces the base's wheel source (its profile,
generator and format); likewise for the rail. Relative profile paths in the sweep are relative to
the sweep file, those of a ``base`` file relative to that file.

Member IDs are ``<abbrev>-<value>`` joined by ``__`` in the order the keys appear, e.g.
``m-load_centre__h-0.25__w-MBench_S1002_v3``: filesystem-safe, and a function of the file alone.
"""

from __future__ import annotations

import copy
import dataclasses
import hashlib
import itertools
import json
import math
import os
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from lutmpi.config.load import config_from_dict, leaf_keys, read_toml
from lutmpi.config.model import Config
from lutmpi.errors import ConfigError

__all__ = ["RunSpec", "expand_sweep", "SWEEP_KEYS", "MAX_MEMBERS"]

MAX_MEMBERS = 100_000
MAX_ID_LENGTH = 200
SPACING_KEYS = ("mesh.wheel_lateral_mm", "mesh.wheel_circumferential_mm", "mesh.rail_lateral_mm",
                "mesh.rail_longitudinal_mm")
SHORTHANDS = {"mesh.spacing_mm": SPACING_KEYS}
SWEEP_KEYS = tuple(leaf_keys()) + tuple(SHORTHANDS)
# short ID prefixes; any other key uses its last component
_ABBREV = {
    "wheel.profile": "w", "wheel.generator": "w", "rail.profile": "r", "rail.generator": "r",
    "rail.inclination": "inc", "mesh.spacing_mm": "h", "mesh.wheel_lateral_mm": "hwl",
    "mesh.wheel_circumferential_mm": "hwc", "mesh.rail_lateral_mm": "hrl",
    "mesh.rail_longitudinal_mm": "hrx", "contact.method": "m",
    "contact.allowed_indentation_mm": "d", "grid.y_mm": "y", "grid.yaw_rad": "yaw",
    "wear.wheel.flange_thinning_mm": "ft", "wear.wheel.tread_hollowing_mm": "th",
    "wear.rail.vertical_mm": "rv", "wear.rail.side_mm": "rs",
}
_SOURCE_KEYS = {"profile", "generator", "format"}
_TOP_KEYS = ("base", "sweep", "name", "description")


@dataclasses.dataclass(frozen=True)
class RunSpec:
    """One sweep member.

    Attributes
    ----------
    id : str
        Stable, readable, filesystem-safe and unique within the sweep.
    params : dict
        Swept dotted key → value as written in the sweep file (in key order).
    config : Config
        The validated configuration of this member.
    """

    id: str
    params: dict[str, Any]
    config: Config


def _err(message: str, path: Path | None, key: str | None = None) -> ConfigError:
    return ConfigError(message, path=None if path is None else str(path), key=key)


# ------------------------------------------------------------------------------------ reading

def _absolutize_profiles(data: Mapping, base_dir: Path) -> dict:
    """Copy of a config mapping with relative wheel/rail profile paths made relative to base_dir.

    Only paths that exist there are rewritten; others are left for the loader's search (and error).
    """
    data = copy.deepcopy(dict(data))
    tables = []
    for section in ("wheel", "rail"):
        table = data.get(section)
        if isinstance(table, dict):
            tables.append(table)
            tables += [table[s] for s in ("left", "right") if isinstance(table.get(s), dict)]
    for table in tables:
        if isinstance(table.get("profile"), str):
            cand = base_dir / Path(table["profile"]).expanduser()
            try:
                if cand.is_file():
                    table["profile"] = str(cand.resolve())
            except (OSError, ValueError):
                pass   # the loader reports the invalid path
    return data


def _read_base(doc: Mapping, path: Path | None, base_dir: Path) -> dict:
    if "base" not in doc:
        raise _err("missing 'base' (a config file name or inline [base.wheel], [base.rail], ...)",
                   path, "base")
    base = doc["base"]
    if isinstance(base, str):
        base_path = base_dir / Path(base).expanduser()
        return _absolutize_profiles(read_toml(base_path), base_path.parent)
    if isinstance(base, Mapping):
        return copy.deepcopy(dict(base))
    raise _err(f"expected a config file name or a table, got {type(base).__name__}", path, "base")


def _flatten(table: Mapping, prefix: str = "") -> dict[str, Any]:
    """``{"contact": {"method": [..]}}`` (bare dotted TOML keys) → ``{"contact.method": [..]}``."""
    out: dict[str, Any] = {}
    for key, value in table.items():
        dotted = f"{prefix}{key}"
        if isinstance(value, Mapping):
            out.update(_flatten(value, dotted + "."))
        else:
            out[dotted] = value
    return out


def _axis_lists(block: Mapping, kind: str, path: Path | None, where: str) -> dict[str, list]:
    table = block.get(kind, {})
    if not isinstance(table, Mapping):
        raise _err(f"expected a table of key = [values], got {type(table).__name__}", path,
                   f"{where}.{kind}")
    lists = _flatten(table)
    for key, values in lists.items():
        if key not in SWEEP_KEYS:
            raise _err("unknown sweep key; valid keys: " + ", ".join(SWEEP_KEYS), path,
                       f"{where}.{kind}.{key}")
        if not isinstance(values, list):
            raise _err(f"expected a list of values, got {type(values).__name__}", path,
                       f"{where}.{kind}.{key}")
        if not values:
            raise _err("empty list: the sweep would have no members", path, f"{where}.{kind}.{key}")
    return lists


def _check_block(block: Any, path: Path | None, where: str) -> tuple[dict, dict]:
    if not isinstance(block, Mapping):
        raise _err(f"expected a table, got {type(block).__name__}", path, where)
    for key in block:
        if key not in ("product", "zip"):
            raise _err("unknown key; valid keys: product, zip", path, f"{where}.{key}")
    product = _axis_lists(block, "product", path, where)
    zipped = _axis_lists(block, "zip", path, where)
    if not product and not zipped:
        raise _err("empty sweep: give product = {key = [values]} and/or zip = {...}", path, where)
    lengths = {len(v) for v in zipped.values()}
    if len(lengths) > 1:
        sizes = ", ".join(f"{k}: {len(v)}" for k, v in zipped.items())
        raise _err(f"zip lists must have equal lengths, got {sizes}", path, f"{where}.zip")
    keys = list(product) + list(zipped)
    for key in set(product) & set(zipped):
        raise _err("key given in both product and zip", path, f"{where}.{key}")
    _check_overlaps(keys, path, where)
    return product, zipped


def _check_overlaps(keys: list[str], path: Path | None, where: str) -> None:
    """Two keys that set the same config value in one member conflict."""
    for short, targets in SHORTHANDS.items():
        for key in keys:
            if short in keys and key in targets:
                raise _err(f"conflicts with {short} (which sets {', '.join(targets)})", path,
                           f"{where}.{key}")
    for side in ("wheel", "rail"):
        if f"{side}.profile" in keys and f"{side}.generator" in keys:
            raise _err(f"{side}.profile and {side}.generator both swept: a member has one source",
                       path, f"{where}.{side}.generator")


def _block_members(product: dict, zipped: dict) -> list[dict[str, Any]]:
    axes = [[((key, v),) for v in values] for key, values in product.items()]
    if zipped:
        n = len(next(iter(zipped.values())))
        axes.append([tuple((key, values[i]) for key, values in zipped.items()) for i in range(n)])
    return [dict(pair for group in combo for pair in group) for combo in itertools.product(*axes)]


# ---------------------------------------------------------------------------------- members

def _set(data: dict, dotted: str, value: Any, path: Path | None) -> None:
    *parents, leaf = dotted.split(".")
    table = data
    for n, name in enumerate(parents):
        table = table.setdefault(name, {})
        if not isinstance(table, dict):
            where = ".".join(parents[: n + 1])
            raise _err(f"expected a table in the base config, got {type(table).__name__}", path,
                       f"base.{where}")
    table[leaf] = copy.deepcopy(value)


def _member_dict(base: dict, params: dict[str, Any], path: Path | None) -> dict:
    data = copy.deepcopy(base)
    for key, value in params.items():
        section, _, leaf = key.partition(".")
        if section in ("wheel", "rail") and leaf in ("profile", "generator"):
            table = data.get(section)
            if isinstance(table, dict):   # the swept source replaces the base's source
                for name in _SOURCE_KEYS - ({"format"} if f"{section}.format" in params else set()):
                    table.pop(name, None)
        for target in SHORTHANDS.get(key, (key,)):
            _set(data, target, value, path)
    return data


def _id_value(key: str, value: Any) -> str:
    if isinstance(value, bool):
        text = "true" if value else "false"
    elif isinstance(value, float) and math.isfinite(value):
        text = format(value, "g")
    elif isinstance(value, (int, float)):
        text = str(value)
    elif isinstance(value, list):
        text = "_".join(_id_value(key, v) for v in value)
    elif key.endswith(".profile") and isinstance(value, str):
        text = Path(value).stem
    elif key == "rail.inclination" and isinstance(value, str):
        text = value.replace(":", "in")
    else:
        text = str(value)
    return re.sub(r"[^A-Za-z0-9._+-]", "_", text)


def _abbrev(key: str) -> str:
    """The short name of a swept key in member IDs; a side's own key names its side
    (``wear.wheel.left.flange_thinning_mm`` -> ``ftL``, ``wheel.right.profile`` -> ``wR``), so
    the left and right members of one sweep never share a name."""
    parts = key.split(".")
    sides = [p for p in parts if p in ("left", "right")]
    plain = ".".join(p for p in parts if p not in ("left", "right"))
    short = _ABBREV.get(plain, plain.rsplit(".", 1)[-1])
    return short + "".join(side[0].upper() for side in sides)


def _member_id(params: dict[str, Any]) -> str:
    parts = [f"{_abbrev(k)}-{_id_value(k, v)}" for k, v in params.items()]
    text = "__".join(parts).lstrip(".")
    if len(text) > MAX_ID_LENGTH:
        text = text[: MAX_ID_LENGTH - 9] + "~" + _digest(params)
    return text


def _digest(params: dict[str, Any]) -> str:
    blob = json.dumps(params, sort_keys=True, default=str).encode()
    return hashlib.sha1(blob).hexdigest()[:8]


def _unique_ids(members: list[dict[str, Any]], path: Path | None) -> list[str]:
    """IDs; colliding ones (e.g. two files with one stem) get a digest of their parameters."""
    ids = [_member_id(p) for p in members]
    counts: dict[str, int] = {}
    for i in ids:
        counts[i] = counts.get(i, 0) + 1
    ids = [i if counts[i] == 1 else f"{i}~{_digest(p)}" for i, p in zip(ids, members, strict=True)]
    seen: dict[str, dict] = {}
    for i, p in zip(ids, members, strict=True):
        if i in seen:
            raise _err(f"the same member is listed twice: {p!r}", path, "sweep")
        seen[i] = p
    return ids


def _build_member(base: dict, params: dict, member_id: str, path: Path | None,
                  base_dir: Path) -> Config:
    try:
        return config_from_dict(_member_dict(base, params, path), path=path, base_dir=base_dir)
    except ConfigError as exc:
        detail = str(exc)
        if path is not None and detail.startswith(f"{path}: "):
            detail = detail[len(f"{path}: "):]
        raise ConfigError(f"sweep member {member_id} {params!r}: {detail}",
                          path=None if path is None else str(path), key=exc.key) from None


def expand_sweep(source: str | os.PathLike | Mapping,
                 base_dir: str | os.PathLike | None = None) -> list[RunSpec]:
    """Expand a sweep file (or its parsed mapping) into validated run specs.

    Parameters
    ----------
    source : path-like or Mapping
        The sweep TOML file, or the mapping ``tomllib`` would return for it.
    base_dir : path-like, optional
        Directory for relative paths (``base`` file, profiles); default: the sweep file's
        directory, or the current directory for a mapping.

    Returns
    -------
    list of RunSpec
        In file order: blocks in order, and within a block the product with the first key
        varying slowest and the zipped tuples last. Identical on every call and every rank.

    Raises
    ------
    ConfigError
        Unknown or conflicting keys, unequal zip lengths, an empty product, a duplicate member,
        or a member whose configuration is invalid (the message names its parameters).
    """
    if isinstance(source, Mapping):
        path, doc = None, source
        root = Path(base_dir) if base_dir is not None else Path.cwd()
    else:
        path = Path(source).absolute()
        doc = read_toml(path)
        root = Path(base_dir) if base_dir is not None else path.parent
    for key in doc:
        if key not in _TOP_KEYS:
            raise _err("unknown top-level key; valid keys: " + ", ".join(_TOP_KEYS), path, str(key))
    for key in ("name", "description"):
        if key in doc and not isinstance(doc[key], str):
            raise _err(f"expected a string, got {type(doc[key]).__name__}", path, key)
    base = _read_base(doc, path, root)
    blocks = doc.get("sweep")
    if isinstance(blocks, Mapping):
        blocks = [blocks]
    if not isinstance(blocks, list) or not blocks:
        raise _err("expected a [sweep] table or [[sweep]] blocks", path, "sweep")
    members: list[dict[str, Any]] = []
    for n, block in enumerate(blocks):
        where = "sweep" if len(blocks) == 1 else f"sweep[{n}]"
        members.extend(_block_members(*_check_block(block, path, where)))
        if len(members) > MAX_MEMBERS:
            raise _err(f"more than {MAX_MEMBERS} members", path, where)
    ids = _unique_ids(members, path)
    return [RunSpec(i, p, _build_member(base, p, i, path, root))
            for i, p in zip(ids, members, strict=True)]
