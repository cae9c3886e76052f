"""What a table was computed from, by content: a hash of every input file and of the config.

A table (and an unfinished build) records :func:`input_record` in its root attribute ``inputs``
(JSON). Resume and sweep reruns compare these hashes, never paths: the same profile bytes at
another path are the same input, a changed file is a different one (named by its config key).

The config hash is taken over every resolved key with each file path replaced by the SHA-256 of the
file's bytes (so moving a config or its profiles changes nothing, editing either does).
No MPI, no HDF5.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from pathlib import Path
from typing import Any

#: read files in pieces of this size when hashing, bytes
_CHUNK = 1 << 20


def file_sha256(path: str | Path) -> str:
    """SHA-256 of a file's bytes, hex; ``"unreadable: <reason>"`` when it cannot be read."""
    digest = hashlib.sha256()
    try:
        with open(path, "rb") as fh:
            while chunk := fh.read(_CHUNK):
                digest.update(chunk)
    except OSError as exc:
        return f"unreadable: {exc.strerror or exc}"
    return digest.hexdigest()


def _flatten(obj: Any, prefix: str, keys: dict[str, Any], files: dict[str, dict[str, str]]) -> None:
    for fld in dataclasses.fields(obj):
        if not prefix and fld.name == "path":      # where the config file sits is no input
            continue
        value, key = getattr(obj, fld.name), f"{prefix}{fld.name}"
        if dataclasses.is_dataclass(value):
            _flatten(value, key + ".", keys, files)
        elif isinstance(value, Path):
            sha = file_sha256(value)
            files[key] = {"path": str(value), "sha256": sha}
            keys[key] = f"file sha256 {sha}"
        elif isinstance(value, tuple):
            keys[key] = list(value)
        else:
            keys[key] = value


def input_files(config: Any) -> dict[str, Path]:
    """Every file a resolved config reads (dotted key -> path): its profiles and the like, not
    the config file itself. Commands refuse to write over any of them."""
    out: dict[str, Path] = {}

    def walk(obj: Any, prefix: str) -> None:
        for fld in dataclasses.fields(obj):
            if not prefix and fld.name == "path":
                continue
            value, key = getattr(obj, fld.name), f"{prefix}{fld.name}"
            if dataclasses.is_dataclass(value):
                walk(value, key + ".")
            elif isinstance(value, Path):
                out[key] = value

    walk(config, "")
    return out


def input_record(config: Any) -> dict[str, Any]:
    """The inputs of a build, by content.

    Parameters
    ----------
    config : Config
        A resolved configuration (any frozen dataclass tree whose file inputs are ``Path`` fields).

    Returns
    -------
    dict
        ``sha256`` (one hash over everything), ``files`` (dotted key -> ``path``, ``sha256``) and
        ``config`` (dotted key -> value, file paths replaced by their content hash).
    """
    keys: dict[str, Any] = {}
    files: dict[str, dict[str, str]] = {}
    _flatten(config, "", keys, files)
    canonical = json.dumps(keys, sort_keys=True, default=str, separators=(",", ":"))
    return {"sha256": hashlib.sha256(canonical.encode()).hexdigest(), "files": files,
            "config": keys}


def differences(stored: dict[str, Any] | None, current: dict[str, Any]) -> list[str]:
    """Human-readable differences between two :func:`input_record` values (empty: same inputs).

    A changed file is named by its key and path; a changed setting by its key, old and new value.
    """
    if not stored or "sha256" not in stored:
        return ["it records no input hashes (made by an older lutmpi)"]
    if stored["sha256"] == current["sha256"]:
        return []
    out = []
    old_files, new_files = stored.get("files", {}), current["files"]
    for key in sorted(set(old_files) | set(new_files)):
        old, new = old_files.get(key, {}), new_files.get(key, {})
        if old.get("sha256") != new.get("sha256"):
            out.append(f"{key} {new.get('path', '(none)')}: content differs (sha256 "
                       f"{str(old.get('sha256', 'none'))[:12]} then, "
                       f"{str(new.get('sha256', 'none'))[:12]} now)")
    old_keys, new_keys = stored.get("config", {}), current["config"]
    for key in sorted(set(old_keys) | set(new_keys)):
        if key in new_files or key in old_files:
            continue
        if old_keys.get(key) != new_keys.get(key):
            out.append(f"{key} = {old_keys.get(key)!r} then, {new_keys.get(key)!r} now")
    return out or ["the inputs' hash differs"]
