"""``Table``: a complete lookup table in memory, and its jump-aware interpolation.

>>> from lutmpi.table import Table
>>> t = Table.open("t.h5")
>>> q = t.interp(y=[0.001, 0.002], yaw=0.0)          # every stored quantity, default method
>>> q["z_g"].shape, q["wheel_point"].shape            # ((2,), (2, 2, 2, 3))

Points whose solve did not converge (``status != 0``) are masked: their float values read as NaN in
:meth:`Table.get` and in :meth:`Table.interp` (see :mod:`lutmpi.table.interp` for how NaN spreads);
``raw=True`` / ``mask_failed=False`` give the stored values. Integer datasets (``status``,
``iterations``, ``n_contacts``) are not interpolated: the value at the nearest knot of the query's
side of any jump is returned.

Interpolation never crosses a located contact jump (``/<method>/jumps``, issue 11), uses per
quantity the interpolant chosen at build time (attribute ``interpolants``), and never clips: a
query outside the grid raises, or with ``outside="flag"`` reads NaN and is flagged.
"""

from __future__ import annotations

import json
import logging
import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lutmpi.equilibrium.result import CONVERGED, STATUS
from lutmpi.errors import MissingQuantityError, TableError
from lutmpi.table import interp as _interp
from lutmpi.table.schema import KNOTS_GROUP, LIMITS_GROUP, Y_AXIS, YAW_AXIS, D, J

log = logging.getLogger(__name__)


def mask_failed(arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Float arrays with NaN where ``status`` is not converged (same leading shape)."""
    if D.status not in arrays:
        return arrays
    bad = arrays[D.status] != CONVERGED
    out = {}
    for name, arr in arrays.items():
        if arr.dtype.kind == "f" and bad.any():
            arr = arr.copy()
            arr[bad] = np.nan
        out[name] = arr
    return out


#: the extra keys of :meth:`Table.interp` with ``info=True``
INFO_KEYS = ("out_of_range", "jump_side", "jump_distance")


@dataclass(eq=False)
class Table:
    """A lookup table read into memory.

    Attributes
    ----------
    path : str
    y : ndarray, shape (ny,)
        Lateral shifts, m.
    yaw : ndarray, shape (nyaw,)
        Yaw angles, rad.
    attrs : dict
        Root attributes (``config_toml``, ``lutmpi_version``, ``schema_version``, ...).
    data : dict
        ``method -> dataset name -> array (ny, nyaw, *suffix)`` as stored.
    meta : dict
        ``method -> dataset name -> attributes`` (``units``, ``description``, ...).
    mask_failed : bool
        Whether non-converged points read as NaN.
    """

    path: str
    y: np.ndarray
    yaw: np.ndarray
    attrs: dict[str, Any]
    data: dict[str, dict[str, np.ndarray]]
    meta: dict[str, dict[str, dict[str, Any]]]
    mask_failed: bool = True
    _masked: dict[str, dict[str, np.ndarray]] = field(default_factory=dict, repr=False)
    _built: Any = field(default=None, repr=False)   # built_config's checked result
    jumps: dict[str, dict[str, Any]] = field(default_factory=dict, repr=False)
    _interp: dict[tuple[Any, ...], _interp.Interpolator] = field(default_factory=dict,
                                                                 repr=False)

    @classmethod
    def open(cls, path: str | os.PathLike[str], *, mask_failed: bool = True) -> Table:
        """Read a complete table (metadata and every array).

        Raises
        ------
        TableError
            Missing, incomplete, not a table, or written by a newer schema version.
        """
        from lutmpi.table.h5io import read_jumps, read_table

        raw = read_table(path)
        table = cls(str(path), raw[Y_AXIS], raw[YAW_AXIS], raw["attrs"], raw["methods"],
                    raw["meta"], mask_failed)
        table._masked = {m: table._mask(d) for m, d in table.data.items()}
        table.jumps = read_jumps(path)
        return table

    def _mask(self, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        return mask_failed(arrays) if self.mask_failed else arrays

    def interpolator(self, method: str | None = None, *, jump_aware: bool = True,
                     quantities: Iterable[str] | None = None) -> _interp.Interpolator:
        """The compiled-ready interpolator of one method (built once, cached).

        ``jump_aware=False`` gives the plain interpolation (linear in y and yaw over the grid
        nodes, blending across jumps): the baseline the table-error report compares with.
        ``quantities`` restricts it to some datasets (``status`` is always kept): a smaller
        value vector, a faster lookup (the dynamics' provider).
        """
        method = self._method(method)
        names = None if quantities is None else tuple(
            n for n in self.data[method] if n in set(quantities) | {D.status})
        key = (method, jump_aware, names)
        if key not in self._interp:
            arrays = self._masked[method]
            if names is not None:
                arrays = {n: arrays[n] for n in names}
            stored = self.jumps.get(method) if jump_aware else None
            if stored is None:
                if jump_aware and self.y.size > 1:
                    log.warning("%s: %s holds no located contact jumps (built with "
                                "output.jumps = false, or before jumps were located): between "
                                "grid points it is interpolated across any contact jump",
                                self.path, method)
                ip = _interp.build(self.y, self.yaw, arrays)
            else:
                limits = self._mask(stored[LIMITS_GROUP])
                modes = json.loads(stored["attrs"].get("interpolants", "{}"))
                ip = _interp.build(self.y, self.yaw, arrays, stored["arrays"], limits,
                                   stored["arrays"].get(J.knot_y),
                                   self._mask(stored.get(KNOTS_GROUP, {})), modes)
            self._interp[key] = ip
        return self._interp[key]

    def jump_positions(self, method: str | None = None) -> np.ndarray:
        """Located jumps ``(nyaw, K)``, m (NaN padded); ``(nyaw, 0)`` when none are stored."""
        stored = self.jumps.get(self._method(method))
        if stored is None:
            return np.zeros((self.yaw.size, 0))
        return np.asarray(stored["arrays"][J.jump_y], float)

    def attribute(self, name: str) -> Any:
        """A root attribute the dynamics needs (:data:`lutmpi.table.schema.DYNAMICS_ATTRIBUTES`).

        Raises
        ------
        TableError
            The table predates it (rebuild the table).
        """
        if name not in self.attrs:
            raise TableError(f"{self.path}: no attribute {name!r}; the table was built by an "
                             f"older lutmpi ({self.attrs.get('lutmpi_version', '?')}): rebuild it")
        return self.attrs[name]

    @property
    def methods(self) -> list[str]:
        """Contact methods stored, in build order."""
        return list(json.loads(self.attrs["methods"]))

    @property
    def quantities(self) -> list[str]:
        """Dataset names stored for every method."""
        return list(self.data[self.methods[0]])

    @property
    def shape(self) -> tuple[int, int]:
        return (self.y.size, self.yaw.size)

    @property
    def config_toml(self) -> str:
        return str(self.attrs["config_toml"])

    def built_config(self) -> Any:
        """The :class:`~lutmpi.config.model.Config` the table was built from (its stored,
        resolved TOML), for what reads the profiles again (KPF export, report's profile plots
        and direct solves).

        Raises
        ------
        TableError
            An input file (a profile) whose content differs from what the table recorded at
            build time (its SHA-256 in the ``inputs`` attribute), or that cannot be read: its
            profile is not the table's any more, and what is made from it would describe
            another pair.
        """
        if self._built is not None:   # checked once per opened table (report: several uses)
            return self._built
        import tomllib

        from lutmpi.config.load import config_from_dict
        from lutmpi.table.provenance import file_sha256, input_files

        cfg = config_from_dict(tomllib.loads(self.config_toml))
        stored = json.loads(self.attrs.get("inputs") or "{}").get("files", {})
        changed = []
        for key, path in input_files(cfg).items():
            want = stored.get(key, {}).get("sha256")
            if want is None:     # a table made before inputs were recorded: nothing to compare
                continue
            got = file_sha256(path)
            if got != want:
                changed.append(f"[{key}] {path}: "
                               + (got if got.startswith("unreadable") else
                                  f"content differs (sha256 {want[:12]} at build time, "
                                  f"{got[:12]} now)"))
        if changed:
            raise TableError(f"{self.path} was built from profile files that have changed since "
                             "(what is made from them now would not be the table's pair): "
                             + "; ".join(changed) + ". Restore the files, or rebuild the table")
        self._built = cfg
        return cfg

    def _method(self, method: str | None) -> str:
        method = method or self.methods[0]
        if method not in self.data:
            raise TableError(f"{self.path}: no method {method!r}; "
                             f"stored: {', '.join(self.methods)}")
        return method

    def get(self, name: str, method: str | None = None, *, raw: bool = False) -> np.ndarray:
        """The grid array of one dataset, ``(ny, nyaw, *suffix)`` (masked unless ``raw``)."""
        method = self._method(method)
        source = self.data[method] if raw else self._masked[method]
        if name not in source:
            raise MissingQuantityError(f"{self.path}: no quantity {name!r} for method "
                                       f"{method!r}; stored: {', '.join(source)}")
        return source[name]

    def units(self, name: str, method: str | None = None) -> str:
        return str(self.meta[self._method(method)][name].get("units", ""))

    def status_counts(self, method: str | None = None) -> dict[str, int]:
        """Number of points per status text."""
        codes, counts = np.unique(self.get(D.status, method, raw=True), return_counts=True)
        return {STATUS.get(int(c), str(c)).split(":")[0]: int(n) for c, n in zip(codes, counts,
                                                                                 strict=True)}

    def interp(self, y: Any, yaw: Any, method: str | None = None,
               quantities: Iterable[str] | None = None, *, outside: str = "raise",
               info: bool = False, jump_aware: bool = True) -> dict[str, np.ndarray]:
        """Interpolate stored quantities at ``(y, yaw)``, never across a located jump.

        Parameters
        ----------
        y, yaw : array_like
            Query points (broadcast together), m and rad.
        method : str, optional
            Contact method; default the first stored.
        quantities : iterable of str, optional
            Dataset names; default every stored one.
        outside : {"raise", "flag"}
            A query outside the grid raises ``ValueError`` naming it (default), or with
            ``"flag"`` reads NaN (-1 for integers) and is marked in ``out_of_range``.
        info : bool
            Add :data:`INFO_KEYS`: ``out_of_range`` (bool), ``jump_side`` (int: the number of
            jumps below the query at its yaw, so two queries on the same side of every jump have
            the same value; a query exactly at a jump is on its upper side) and
            ``jump_distance`` (m, signed distance to the nearest jump, NaN when none).
        jump_aware : bool
            False: plain linear interpolation over the grid nodes (the baseline).

        Returns
        -------
        dict
            ``name -> array of shape broadcast(y, yaw).shape + suffix`` (float; integer datasets
            keep their dtype), plus ``out_of_range`` with ``outside="flag"`` and
            :data:`INFO_KEYS` with ``info``.
        """
        if outside not in ("raise", "flag"):
            raise ValueError(f"outside must be 'raise' or 'flag', got {outside!r} (a table "
                             "never clips a query to its edge)")
        method = self._method(method)
        names = list(quantities) if quantities is not None else list(self.data[method])
        for name in names:
            self.get(name, method)
        ys, yaws = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(yaw, dtype=float))
        ip = self.interpolator(method, jump_aware=jump_aware)
        value, _, _, flags, piece, dist = ip.evaluate(ys.ravel(), yaws.ravel())
        out_of_range = (flags & _interp.OUT_OF_RANGE) != 0
        if outside == "raise" and out_of_range.any():
            k = int(np.flatnonzero(out_of_range)[0])
            raise ValueError(
                f"{self.path}: query (y={ys.ravel()[k]:.6g} m, yaw={yaws.ravel()[k]:.6g} rad) "
                f"outside the table grid y in [{self.y[0]:.6g}, {self.y[-1]:.6g}] m, yaw in "
                f"[{self.yaw[0]:.6g}, {self.yaw[-1]:.6g}] rad")
        dtypes = {n: self.data[method][n].dtype for n in names}
        out = {n: v.reshape(ys.shape + v.shape[1:])
               for n, v in ip.layout.unpack(value, names, dtypes).items()}
        if outside == "flag" or info:
            out["out_of_range"] = out_of_range.reshape(ys.shape)
        if info:
            out["jump_side"] = piece.reshape(ys.shape)
            out["jump_distance"] = dist.reshape(ys.shape)
        return out
