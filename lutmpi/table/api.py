"""``Table``: a complete lookup table in memory, and its interpolation.

>>> from lutmpi.table import Table
>>> t = Table.open("t.h5")
>>> q = t.interp(y=[0.001, 0.002], yaw=0.0)          # every stored quantity, default method
>>> q["z_g"].shape, q["wheel_point"].shape            # ((2,), (2, 2, 2, 3))

Points whose solve did not converge (``status != 0``) are masked: their float values read as NaN in
:meth:`Table.get` and in :meth:`Table.interp` (see :mod:`lutmpi.table.interp` for how NaN spreads);
``raw=True`` / ``mask_failed=False`` give the stored values. Integer datasets (``status``,
``iterations``, ``n_contacts``) are not interpolated: the value at the nearest node is returned.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lutmpi.equilibrium.result import CONVERGED, STATUS
from lutmpi.errors import TableError
from lutmpi.table import interp as _interp


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

    @classmethod
    def open(cls, path: str | os.PathLike[str], *, mask_failed: bool = True) -> Table:
        """Read a complete table (metadata and every array).

        Raises
        ------
        TableError
            Missing, incomplete, not a table, or written by a newer schema version.
        """
        from lutmpi.table.h5io import read_table

        raw = read_table(path)
        table = cls(str(path), raw["y"], raw["yaw"], raw["attrs"], raw["methods"], raw["meta"],
                    mask_failed)
        table._masked = {m: table._mask(d) for m, d in table.data.items()}
        return table

    def _mask(self, arrays: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        if not self.mask_failed or "status" not in arrays:
            return arrays
        bad = arrays["status"] != CONVERGED
        out = {}
        for name, arr in arrays.items():
            if arr.dtype.kind == "f" and bad.any():
                arr = arr.copy()
                arr[bad] = np.nan
            out[name] = arr
        return out

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
            raise TableError(f"{self.path}: no quantity {name!r} for method {method!r}; stored: "
                             f"{', '.join(source)}")
        return source[name]

    def units(self, name: str, method: str | None = None) -> str:
        return str(self.meta[self._method(method)][name].get("units", ""))

    def status_counts(self, method: str | None = None) -> dict[str, int]:
        """Number of points per status text."""
        codes, counts = np.unique(self.get("status", method, raw=True), return_counts=True)
        return {STATUS.get(int(c), str(c)).split(":")[0]: int(n) for c, n in zip(codes, counts,
                                                                                 strict=True)}

    def interp(self, y: Any, yaw: Any, method: str | None = None,
               quantities: Iterable[str] | None = None, *, outside: str = "clip",
               ) -> dict[str, np.ndarray]:
        """Bilinear interpolation of stored quantities at ``(y, yaw)``.

        Parameters
        ----------
        y, yaw : array_like
            Query points (broadcast together), m and rad.
        method : str, optional
            Contact method; default the first stored.
        quantities : iterable of str, optional
            Dataset names; default every stored one.
        outside : {"clip", "nan", "raise"}
            Queries outside the grid: clamp to the boundary (default), NaN, or ``ValueError``.

        Returns
        -------
        dict
            ``name -> array of shape broadcast(y, yaw).shape + suffix`` (float; integer datasets
            give the nearest node's value).
        """
        method = self._method(method)
        names = list(quantities) if quantities is not None else list(self.data[method])
        st = _interp.stencil(self.y, self.yaw, y, yaw, outside)
        out = {}
        for name in names:
            arr = self.get(name, method)
            if arr.dtype.kind == "f":
                out[name] = _interp.bilinear(arr, st)
            else:
                out[name] = _interp.nearest(arr, st, fill=-1)
        return out
