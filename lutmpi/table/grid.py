"""The (y_g, yaw) grid of a table: axes in SI units and the flat point index (row-major, y first).

Pure: no MPI, no HDF5.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from lutmpi.errors import ConfigError


def _axis(spec: tuple[float, float, int], scale: float, key: str) -> np.ndarray:
    start, stop, count = spec
    if int(count) != count or count < 1:
        raise ConfigError(f"grid count must be an integer >= 1, got {count!r}", key=key)
    if count > 1 and not stop > start:
        raise ConfigError(f"grid needs start < stop when count > 1, got {start} .. {stop}", key=key)
    return np.linspace(start, stop, int(count)) * scale


@dataclass(frozen=True, eq=False)
class Grid:
    """Grid of imposed poses.

    Attributes
    ----------
    y : ndarray, shape (ny,)
        Lateral shifts y_g, m, strictly increasing.
    yaw : ndarray, shape (nyaw,)
        Yaw angles theta_z, rad, strictly increasing.
    """

    y: np.ndarray
    yaw: np.ndarray

    @classmethod
    def from_config(cls, grid: Any) -> Grid:
        """Build the grid from ``[grid]`` (:class:`lutmpi.config.model.GridConfig`: ``y_mm`` in
        mm, ``yaw_rad`` in rad; not imported here, the table core stays below the config)."""
        return cls(_axis(grid.y_mm, 1e-3, "grid.y_mm"), _axis(grid.yaw_rad, 1.0, "grid.yaw_rad"))

    @property
    def shape(self) -> tuple[int, int]:
        """``(ny, nyaw)``."""
        return (self.y.size, self.yaw.size)

    @property
    def n_points(self) -> int:
        return self.y.size * self.yaw.size

    def ij(self, k: int | np.ndarray) -> tuple:
        """Flat index -> ``(iy, iyaw)``."""
        return divmod(k, self.yaw.size)

    def flat(self, iy: int | np.ndarray, iyaw: int | np.ndarray) -> int | np.ndarray:
        """``(iy, iyaw)`` -> flat index."""
        return iy * self.yaw.size + iyaw

    def pose(self, k: int) -> tuple[float, float]:
        """Flat index -> ``(y, yaw)`` in m and rad."""
        iy, iyaw = self.ij(k)
        return float(self.y[iy]), float(self.yaw[iyaw])

    def describe(self, k: int) -> str:
        """Human-readable grid point, for log and error messages."""
        iy, iyaw = self.ij(k)
        return (f"grid point #{k} (iy={iy}, iyaw={iyaw}: y={self.y[iy] * 1e3:.6g} mm, "
                f"yaw={self.yaw[iyaw]:.6g} rad)")
