"""The one module that reads and writes table files (HDF5), collectively with MPI or serially.

Writing strategy (used by :class:`lutmpi.parallel.writer.TableWriter`)
----------------------------------------------------------------------
* Two strategies behind one interface: :class:`SerialH5` (one rank, a plain file) and
  :class:`MpioH5` (N ranks, ``driver="mpio"``, collective transfers).
* All ranks create every dataset of :mod:`lutmpi.table.schema` with its global shape (contiguous
  layout, storage allocated and filled with "not computed" at creation, so a full disk shows up
  before any compute, not in the final write), attach the ``/y`` and ``/yaw`` dimension scales and
  set every root attribute, the run ones with placeholders of their final size: HDF5 metadata
  operations are collective, and finishing only rewrites them in place.
* Each rank owns a block of grid rows (:func:`lutmpi.parallel.partition.block_range`) and writes it
  with **one collective low-level write per dataset**; a rank owning no rows still makes the call,
  with an empty selection (h5py's high-level ``__setitem__`` may skip the call, hence ``dset.id``).
* Computed points are not checkpointed into this file: they go to the journal
  (:mod:`lutmpi.table.journal`) the moment they are computed.
"""

from __future__ import annotations

import json
import os
import tomllib
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import h5py
import numpy as np
from h5py import h5d, h5fd, h5p, h5s

from lutmpi.errors import TableError
from lutmpi.table.grid import Grid
from lutmpi.table.schema import (
    AXES,
    FIELDS,
    SCHEMA_VERSION,
    Y_AXIS,
    YAW_AXIS,
    D,
    Field,
    dataset_attributes,
)

# bytes per point per method of a full table, plus slack; used for the free-space check
_BYTES_PER_POINT = 8 * 200


def partial_path(out: str | os.PathLike[str]) -> Path:
    """The fixed name of an unfinished build of ``out``: ``<out>.partial``."""
    out = Path(out)
    return out.with_name(out.name + ".partial")


def estimate_bytes(n_points: int, n_methods: int) -> int:
    """Generous size estimate of a table file, bytes."""
    return n_points * max(n_methods, 1) * _BYTES_PER_POINT + (1 << 20)


class SerialH5:
    """One rank: a plain HDF5 file, independent transfers."""

    parallel = False

    def open(self, path: Path, mode: str) -> h5py.File:
        return h5py.File(path, mode)

    def xfer(self) -> Any:
        return h5p.create(h5p.DATASET_XFER)


class MpioH5(SerialH5):
    """N ranks: one file opened with the ``mpio`` driver, collective transfers."""

    parallel = True

    def __init__(self, comm: Any):
        self.comm = comm

    def open(self, path: Path, mode: str) -> h5py.File:
        return h5py.File(path, mode, driver="mpio", comm=self.comm)

    def xfer(self) -> Any:
        dxpl = h5p.create(h5p.DATASET_XFER)
        dxpl.set_dxpl_mpio(h5fd.MPIO_COLLECTIVE)
        return dxpl


def strategy(comm: Any) -> SerialH5:
    """The strategy for ``comm``: collective for more than one rank, serial otherwise."""
    return MpioH5(comm) if comm is not None and comm.size > 1 else SerialH5()


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


def create_partial(path: Path, io: SerialH5, rank: int, grid: Grid, methods: Sequence[str],
                   fields: Sequence[Field], attrs: dict[str, Any]) -> None:
    """Create the partial file with every dataset at its global shape, storage allocated and
    filled, and every root attribute at its final size (collective with :class:`MpioH5`)."""
    with io.open(path, "w") as f:
        for key, value in attrs.items():
            f.attrs[key] = value
        f.attrs["complete"] = False
        for name, values, units, desc in (
                (Y_AXIS, grid.y, "m", "lateral shift y_g of the wheelset"),
                (YAW_AXIS, grid.yaw, "rad", "yaw angle theta_z")):
            d = f.create_dataset(name, shape=values.shape, dtype="f8")
            d.attrs["units"], d.attrs["description"] = units, desc
            write_rows(d, 0, values if rank == 0 else values[:0], io.xfer())
            d.make_scale(name)
        for method in methods:
            g = f.create_group(method)
            g.attrs["method"] = method
            for fld in fields:
                dcpl = h5p.create(h5p.DATASET_CREATE)
                dcpl.set_alloc_time(h5d.ALLOC_TIME_EARLY)
                d = g.create_dataset(fld.name, shape=grid.shape + fld.suffix, dtype=fld.dtype,
                                     fillvalue=fld.fill, dcpl=dcpl, fill_time="alloc")
                for key, value in dataset_attributes(fld).items():
                    d.attrs[key] = value
                d.dims[0].attach_scale(f[Y_AXIS])
                d.dims[1].attach_scale(f[YAW_AXIS])


def write_blocks(f: h5py.File, io: SerialH5, row_start: int,
                 blocks: dict[str, dict[str, np.ndarray]]) -> None:
    """Write this rank's row block of every dataset (collective with :class:`MpioH5`)."""
    dxpl = io.xfer()
    for method in sorted(blocks):
        for name in sorted(blocks[method]):
            write_rows(f[method][name], row_start, blocks[method][name], dxpl)


def finalize(f: h5py.File, attrs: dict[str, Any]) -> None:
    """Rewrite the run attributes in place and, last, set ``complete = True``; close."""
    for key, value in attrs.items():
        f.attrs.modify(key, value)
    f.attrs.modify("complete", True)
    f.close()


def read_attrs(path: str | os.PathLike[str]) -> dict[str, Any]:
    """The root attributes of an HDF5 file (any state, complete or not) as plain values.

    Raises
    ------
    TableError
        Missing or unreadable file.
    """
    try:
        with h5py.File(path, "r") as f:
            return {k: _plain(v) for k, v in f.attrs.items()}
    except OSError as exc:
        raise _open_error(path, exc) from exc


def _open_error(path: str | os.PathLike[str], exc: OSError) -> TableError:
    """The error for a file h5py cannot open: a file another process holds (HDF5's lock: a
    build still writing it), and a file system without locks, are told apart from a file that
    is not HDF5 at all."""
    msg = str(exc)
    if "unable to lock file" in msg and ("errno = 11" in msg or "temporarily unavailable" in msg):
        what = ("a build's unfinished output" if str(path).endswith(".partial")
                else "open for writing")
        return TableError(f"{path}: {what}, locked by another process (a build still running?): "
                          f"wait for it to end, or read a copy of the file ({exc})")
    if "unable to lock file" in msg:
        return TableError(f"{path}: HDF5 cannot lock files on this file system ({exc}); set "
                          "HDF5_USE_FILE_LOCKING=FALSE to read it without a lock")
    return TableError(f"{path}: not a readable HDF5 file ({exc})")


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
        raise _open_error(path, exc) from exc
    try:
        with f:
            return _read_open_table(f, path)
    except TableError:
        raise
    except (KeyError, ValueError, TypeError, OSError, RuntimeError) as exc:
        # a damaged or doctored file: name the file and what is missing or wrong
        raise TableError(f"{path}: damaged table ({type(exc).__name__}: {exc})") from exc


def _read_open_table(f: h5py.File, path: Path) -> dict[str, Any]:
    attrs = {k: _plain(v) for k, v in f.attrs.items()}
    version = attrs.get("schema_version")
    if version is None:
        raise TableError(f"{path}: not a lutmpi table (no schema_version attribute)")
    if int(version) > SCHEMA_VERSION:
        raise TableError(f"{path}: schema version {version} is newer than this lutmpi "
                         f"understands ({SCHEMA_VERSION}); upgrade lutmpi to read it")
    if not attrs.get("complete", False):
        raise TableError(f"{path}: the table is incomplete (its build did not finish)"
                         + _journal_note(path))
    for key in ("methods", "config_toml"):
        if key not in attrs:
            raise TableError(f"{path}: damaged table: root attribute {key!r} is missing")
    try:
        tomllib.loads(str(attrs["config_toml"]))
    except tomllib.TOMLDecodeError as exc:
        raise TableError(f"{path}: damaged table: root attribute 'config_toml' is not valid TOML "
                         f"({exc})") from exc
    try:
        names = json.loads(attrs["methods"])
    except (TypeError, ValueError) as exc:
        raise TableError(f"{path}: damaged table: root attribute 'methods' is not a JSON list "
                         f"({exc})") from exc
    if not isinstance(names, list) or not names or not all(isinstance(n, str) for n in names):
        raise TableError(f"{path}: damaged table: root attribute 'methods' = {names!r} is not "
                         "a non-empty list of names")
    y, yaw = (_dataset(f, path, k, 1) for k in AXES)
    methods, meta = {}, {}
    for name in names:
        if not isinstance(f.get(name), h5py.Group):
            raise TableError(f"{path}: damaged table: group /{name} (method {name}) is missing")
        g = f[name]
        if D.status not in g:
            raise TableError(f"{path}: damaged table: dataset /{name}/{D.status} is missing")
        order = [fld.name for fld in FIELDS if fld.name in g]
        methods[name] = {}
        for k in order:
            arr = _dataset(g, path, k, None)
            if arr.shape[:2] != (y.size, yaw.size):
                raise TableError(f"{path}: damaged table: /{name}/{k} has shape {arr.shape}, "
                                 f"expected ({y.size}, {yaw.size}, ...) from /y and /yaw")
            methods[name][k] = arr
        meta[name] = {k: {a: _plain(v) for a, v in g[k].attrs.items()
                          if a not in ("DIMENSION_LIST",)} for k in order}
    return {"attrs": attrs, Y_AXIS: y, YAW_AXIS: yaw, "methods": methods, "meta": meta}


def _journal_note(path: Path) -> str:
    """``"; N of M points are journaled ... --resume"`` for the partial file of a build."""
    from lutmpi.table import journal

    if not path.name.endswith(".partial"):
        return ""
    out = path.with_name(path.name.removesuffix(".partial"))
    try:
        header = journal.read_header(journal.journal_dir(out))
        done = journal.done_points(journal.journal_dir(out))
    except (TableError, OSError, KeyError, ValueError):
        return ""
    total = int(np.prod(header.shape))
    return (f"; {done.size} of {total} points are journaled in {journal.journal_dir(out).name}/: "
            f"`lutmpi build CONFIG -o {out} --resume` continues it")


def _dataset(group: h5py.Group, path: Path, name: str, ndim: int | None) -> np.ndarray:
    obj = group.get(name)
    where = f"{group.name.rstrip('/')}/{name}"
    if not isinstance(obj, h5py.Dataset):
        raise TableError(f"{path}: damaged table: dataset {where} is missing")
    arr = obj[...]
    if ndim is not None and (arr.ndim != ndim or arr.size == 0):
        raise TableError(f"{path}: damaged table: {where} has shape {arr.shape}, expected a "
                         "non-empty vector")
    return arr


def _plain(value: Any) -> Any:
    if isinstance(value, bytes):
        return value.decode()
    if isinstance(value, np.generic):
        return value.item()
    return value


# -- contact jumps (issue 11): /<method>/jumps, written after the grid is complete ------------
def write_jumps(f: h5py.File, io: SerialH5, rank: int, method: str, arrays: dict[str, np.ndarray],
                limits: dict[str, np.ndarray], knot_y: np.ndarray, knots: dict[str, np.ndarray],
                attrs: dict[str, Any]) -> None:
    """Create ``/<method>/jumps`` (collective with :class:`MpioH5`: every rank holds the same
    arrays) and write it from rank 0 (the other ranks take part with empty selections)."""
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
    dxpl = io.xfer()
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
            write_rows(d, 0, arr if rank == 0 else arr[:0], dxpl)


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
