"""The one module that reads and writes table files (HDF5), collectively with MPI or serially.

Writing strategy
----------------
* All ranks create every dataset of :mod:`lutmpi.table.schema` with its global shape (contiguous
  layout, fill value = "not computed"), attach the ``/y`` and ``/yaw`` dimension scales and set the
  same attributes: HDF5 metadata operations are collective.
* Each rank owns a block of grid rows (:func:`lutmpi.parallel.partition.block_range`) and writes it
  with **one collective low-level write per dataset**; a rank owning no rows still makes the call,
  with an empty selection (h5py's high-level ``__setitem__`` may skip the call, hence ``dset.id``).
* One rank -> a plain serial file, no ``mpio`` driver.
* The build writes ``<out>.partial`` (fixed name, so ``--resume`` can find it), with a per-point
  ``/done`` mask. During compute each rank checkpoints its own points with *independent* writes of
  raw data only (no rank waits for another; the metadata, written when the file was created, never
  changes, so a killed job leaves a readable file). At the end every rank writes its row block
  collectively; ``/done`` is removed, ``complete`` set last, and rank 0 renames the file.
"""

from __future__ import annotations

import json
import os
import shutil
import uuid
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from h5py import h5fd, h5p, h5s

from lutmpi.errors import TableError
from lutmpi.table.grid import Grid
from lutmpi.table.schema import FIELDS, SCHEMA_VERSION, Field, dataset_attributes

DONE = "done"
# bytes per point per method of a full table, plus slack; used for the free-space check
_BYTES_PER_POINT = 8 * 200


def partial_path(out: str | os.PathLike[str]) -> Path:
    """The fixed name of an unfinished build of ``out``: ``<out>.partial``."""
    out = Path(out)
    return out.with_name(out.name + ".partial")


def estimate_bytes(n_points: int, n_methods: int) -> int:
    """Generous size estimate of a table file, bytes."""
    return n_points * max(n_methods, 1) * _BYTES_PER_POINT + (1 << 20)


def preflight(out: Path, *, force: bool, resume: bool, need_bytes: int) -> bool:
    """Decide, before any compute, whether the build may go ahead (run on rank 0 only).

    Returns
    -------
    bool
        True when an existing partial file is to be resumed.

    Raises
    ------
    TableError
        Output exists without ``force``; a partial build exists without ``resume``/``force``;
        the directory is missing, not a directory, not writable, or short of space.
    """
    partial = partial_path(out)
    if out.exists() and not force:
        raise TableError(f"{out} exists; pass --force to overwrite it")
    if partial.exists() and not (resume or force):
        raise TableError(f"an unfinished build {partial} exists; pass --resume to continue it "
                         "or --force to start over")
    _check_directory(out.parent if str(out.parent) else Path("."), need_bytes)
    return bool(resume and partial.exists())


def _check_directory(directory: Path, need_bytes: int) -> None:
    if not directory.is_dir():
        raise TableError(f"output directory {directory} does not exist or is not a directory")
    probe = directory / f".lutmpi-probe-{uuid.uuid4().hex}"
    try:
        with open(probe, "wb") as fh:
            fh.write(b"\0" * 4096)
            fh.flush()
            os.fsync(fh.fileno())
    except OSError as exc:
        raise TableError(f"output directory {directory} is not writable: {exc}") from exc
    finally:
        probe.unlink(missing_ok=True)
    free = shutil.disk_usage(directory).free
    if free < need_bytes:
        raise TableError(f"output directory {directory} has {free / 1e6:.1f} MB free, the table "
                         f"needs about {need_bytes / 1e6:.1f} MB")


def _open(path: Path, mode: str, comm: Any) -> h5py.File:
    if comm is not None and comm.size > 1:
        return h5py.File(path, mode, driver="mpio", comm=comm)
    return h5py.File(path, mode)


def _dxpl(parallel: bool) -> Any:
    dxpl = h5p.create(h5p.DATASET_XFER)
    if parallel:
        dxpl.set_dxpl_mpio(h5fd.MPIO_COLLECTIVE)
    return dxpl


def write_rows(dset: h5py.Dataset, start: int, block: np.ndarray, dxpl: Any) -> None:
    """Write rows ``start:start+len(block)`` of ``dset`` (collective when ``dxpl`` says so).

    An empty ``block`` still makes the H5Dwrite call, with empty selections.
    """
    fspace = dset.id.get_space()
    if len(block):
        arr = np.ascontiguousarray(block, dtype=dset.dtype)
        fspace.select_hyperslab((start,) + (0,) * (arr.ndim - 1), arr.shape)
        mspace = h5s.create_simple(arr.shape)
    else:
        arr = np.zeros(1, dtype=dset.dtype)
        fspace.select_none()
        mspace = h5s.create_simple((1,))
        mspace.select_none()
    dset.id.write(mspace, fspace, arr, dxpl=dxpl)


def create_partial(path: Path, comm: Any, grid: Grid, methods: Sequence[str],
                   fields: Sequence[Field], attrs: dict[str, Any]) -> None:
    """Create the partial file with every dataset at its global shape (collective)."""
    with _open(path, "w", comm) as f:
        for key, value in attrs.items():
            f.attrs[key] = value
        f.attrs["complete"] = False
        for name, values, units, desc in (("y", grid.y, "m", "lateral shift y_g of the wheelset"),
                                          ("yaw", grid.yaw, "rad", "yaw angle theta_z")):
            d = f.create_dataset(name, shape=values.shape, dtype="f8")
            d.attrs["units"], d.attrs["description"] = units, desc
            write_rows(d, 0, values if _rank(comm) == 0 else values[:0], _dxpl(_par(comm)))
            d.make_scale(name)
        done = f.create_dataset(DONE, shape=grid.shape, dtype="u1", fillvalue=0)
        done.attrs["description"] = "1 where the point is computed (removed when complete)"
        for method in methods:
            g = f.create_group(method)
            g.attrs["method"] = method
            for fld in fields:
                d = g.create_dataset(fld.name, shape=grid.shape + fld.suffix, dtype=fld.dtype,
                                     fillvalue=fld.fill)
                for key, value in dataset_attributes(fld).items():
                    d.attrs[key] = value
                d.dims[0].attach_scale(f["y"])
                d.dims[1].attach_scale(f["yaw"])


def _rank(comm: Any) -> int:
    return 0 if comm is None else comm.rank


def _par(comm: Any) -> bool:
    return comm is not None and comm.size > 1


def open_rw(path: Path, comm: Any) -> h5py.File:
    """Open a partial file for the build (collective with several ranks)."""
    return _open(path, "r+", comm)


def write_points(f: h5py.File, grid: Grid, points: np.ndarray,
                 records: dict[str, dict[str, np.ndarray]]) -> None:
    """Checkpoint: write computed points and their ``/done`` flags, *independently* (no other
    rank takes part). Only raw data of datasets allocated at creation is written, so the file's
    metadata never changes and a killed job leaves it readable."""
    iy, iyaw = grid.ij(np.asarray(points))
    for method in sorted(records):
        group = f[method]
        for name in sorted(records[method]):
            dset, values = group[name], records[method][name]
            for i in range(len(points)):
                dset[iy[i], iyaw[i]] = values[i]
    for i in range(len(points)):
        f[DONE][iy[i], iyaw[i]] = 1


def write_blocks(f: h5py.File, comm: Any, row_start: int,
                 blocks: dict[str, dict[str, np.ndarray]], done_rows: np.ndarray) -> None:
    """Write this rank's row block of every dataset and of ``/done`` (collective)."""
    dxpl = _dxpl(_par(comm))
    for method in sorted(blocks):
        for name in sorted(blocks[method]):
            write_rows(f[method][name], row_start, blocks[method][name], dxpl)
    write_rows(f[DONE], row_start, done_rows, dxpl)


def check_partial(path: Path, methods: Sequence[str], fields: Sequence[Field],
                  config_toml: str) -> np.ndarray:
    """Check an unfinished build can be resumed by this build; return its ``/done`` mask.

    Raises
    ------
    TableError
        The file is unreadable or was made from another configuration / method / quantity set.
    """
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise TableError(f"cannot read the unfinished build {path} ({exc}); pass --force to start "
                         "over") from exc
    with f:
        if f.attrs.get("config_toml") != config_toml:
            raise TableError(f"{path} was started from a different configuration; pass --force "
                             "to start over")
        stored = {m: set(f[m]) for m in f if isinstance(f[m], h5py.Group)}
        wanted = {m: {fld.name for fld in fields} for m in methods}
        if stored != wanted or DONE not in f:
            raise TableError(f"{path} holds methods/quantities {sorted(stored)} that differ from "
                             f"this build's {sorted(wanted)}; pass --force to start over")
        return f[DONE][...].astype(bool)


def read_rows(path: Path, row_start: int, row_count: int, methods: Sequence[str],
              fields: Sequence[Field]) -> dict[str, dict[str, np.ndarray]]:
    """This rank's row block of every dataset of a partial file (serial read, every rank)."""
    rows = slice(row_start, row_start + row_count)
    with h5py.File(path, "r") as f:
        return {m: {fld.name: f[m][fld.name][rows] for fld in fields} for m in methods}


def finalize(f: h5py.File, attrs: dict[str, Any]) -> None:
    """Drop ``/done``, set the run attributes and, last, ``complete = True``, then close
    (collective)."""
    del f[DONE]
    for key, value in attrs.items():
        f.attrs[key] = value
    f.attrs["complete"] = True
    f.close()


def read_table(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read a complete table into memory (serial h5py).

    Returns
    -------
    dict
        ``attrs`` (root attributes), ``y``, ``yaw``, ``methods`` (name -> field -> array) and
        ``meta`` (method -> field -> dataset attributes).

    Raises
    ------
    TableError
        Missing file, not a table, incomplete, or a newer schema version.
    """
    path = Path(path)
    if not path.is_file():
        raise TableError(f"{path}: no such table file")
    try:
        f = h5py.File(path, "r")
    except OSError as exc:
        raise TableError(f"{path}: not a readable HDF5 file ({exc})") from exc
    with f:
        attrs = {k: _plain(v) for k, v in f.attrs.items()}
        version = attrs.get("schema_version")
        if version is None:
            raise TableError(f"{path}: not a lutmpi table (no schema_version attribute)")
        if int(version) > SCHEMA_VERSION:
            raise TableError(f"{path}: schema version {version} is newer than this lutmpi "
                             f"understands ({SCHEMA_VERSION}); upgrade lutmpi to read it")
        if not attrs.get("complete", False):
            raise TableError(f"{path}: the table is incomplete (its build did not finish)")
        methods, meta = {}, {}
        for name in json.loads(attrs["methods"]):
            g = f[name]
            order = [fld.name for fld in FIELDS if fld.name in g]
            methods[name] = {k: g[k][...] for k in order}
            meta[name] = {k: {a: _plain(v) for a, v in g[k].attrs.items()
                              if a not in ("DIMENSION_LIST",)} for k in g}
        return {"attrs": attrs, "y": f["y"][...], "yaw": f["yaw"][...], "methods": methods,
                "meta": meta}


def _plain(value: Any) -> Any:
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.generic):
        return value.item()
    return value


# -- contact jumps (issue 11): /<method>/jumps, written after the grid is complete ------------
def write_jumps(f: h5py.File, comm: Any, method: str, arrays: dict[str, np.ndarray],
                limits: dict[str, np.ndarray], knot_y: np.ndarray, knots: dict[str, np.ndarray],
                attrs: dict[str, Any]) -> None:
    """Create ``/<method>/jumps`` (collective: every rank holds the same arrays) and write it from
    rank 0 (the other ranks take part with empty selections)."""
    from lutmpi.table.schema import (
        FIELDS_BY_NAME,
        JUMP_FIELDS_BY_NAME,
        JUMPS_GROUP,
        KNOT_FIELD,
        KNOTS_GROUP,
        LIMITS_GROUP,
        jump_attributes,
    )

    if JUMPS_GROUP in f[method]:        # a resumed build whose jumps were already written
        del f[method][JUMPS_GROUP]
    g = f[method].create_group(JUMPS_GROUP)
    for key, value in attrs.items():
        g.attrs[key] = value
    dxpl = _dxpl(_par(comm))
    items = [(g, name, arr, jump_attributes(JUMP_FIELDS_BY_NAME[name]))
             for name, arr in arrays.items()]
    lg = g.create_group(LIMITS_GROUP)
    items += [(lg, name, arr, jump_attributes(FIELDS_BY_NAME[name], limit=True))
              for name, arr in limits.items()]
    items.append((g, KNOT_FIELD.name, knot_y, jump_attributes(KNOT_FIELD)))
    kg = g.create_group(KNOTS_GROUP)
    items += [(kg, name, arr, jump_attributes(FIELDS_BY_NAME[name]))
              for name, arr in knots.items()]
    for group, name, arr, meta in items:
        d = group.create_dataset(name, shape=arr.shape, dtype=arr.dtype)
        for key, value in meta.items():
            d.attrs[key] = value
        if arr.size:
            write_rows(d, 0, arr if _rank(comm) == 0 else arr[:0], dxpl)


def write_root_attributes(f: h5py.File, attrs: dict[str, Any]) -> None:
    """Set root attributes (collective: every rank passes the same values)."""
    for key, value in attrs.items():
        f.attrs[key] = value


def read_jumps(path: str | os.PathLike[str]) -> dict[str, dict[str, Any]]:
    """``method -> {"arrays", "limits", "attrs"}`` of the jumps stored in a table (methods
    without a jumps group are absent: a table built before jumps were stored)."""
    from lutmpi.table.schema import JUMPS_GROUP, KNOTS_GROUP, LIMITS_GROUP

    out: dict[str, dict[str, Any]] = {}
    with h5py.File(path, "r") as f:
        for method in json.loads(_plain(f.attrs["methods"])):
            if JUMPS_GROUP not in f[method]:
                continue
            g = f[method][JUMPS_GROUP]
            out[method] = {
                "arrays": {k: g[k][...] for k in g if isinstance(g[k], h5py.Dataset)},
                "limits": {k: v[...] for k, v in g[LIMITS_GROUP].items()},
                "knots": {k: v[...] for k, v in g[KNOTS_GROUP].items()},
                "attrs": {k: _plain(v) for k, v in g.attrs.items()}}
    return out
