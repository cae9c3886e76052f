"""Vectorized bilinear interpolation over the (y, yaw) grid of a table. Pure: numpy only.

NaN policy: a grid node whose value is NaN (a missing contact, or a point whose solve did not
converge once :class:`lutmpi.table.api.Table` has masked it) makes every query whose bilinear
stencil gives that node a *non-zero* weight NaN. A query exactly on a good node, or on the edge
between two good nodes, is not affected by a NaN neighbour of weight zero.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

OUTSIDE = ("clip", "nan", "raise")


@dataclass(frozen=True)
class Stencil:
    """Cell corners and weights of a batch of queries (shape ``q`` = broadcast query shape)."""

    i0: np.ndarray      # (q,) lower y index
    j0: np.ndarray      # (q,) lower yaw index
    wy: np.ndarray      # (q,) weight of the upper y node, in [0, 1]
    wa: np.ndarray      # (q,) weight of the upper yaw node, in [0, 1]
    outside: np.ndarray  # (q,) bool, query outside the grid
    shape: tuple[int, ...]


def _locate(axis: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    if axis.size == 1:
        return np.zeros(x.shape, dtype=np.intp), np.zeros(x.shape)
    i = np.clip(np.searchsorted(axis, x, side="right") - 1, 0, axis.size - 2)
    w = (x - axis[i]) / (axis[i + 1] - axis[i])
    return i, np.clip(w, 0.0, 1.0)


def stencil(y_axis: np.ndarray, yaw_axis: np.ndarray, y: np.ndarray | float,
            yaw: np.ndarray | float, outside: str = "clip") -> Stencil:
    """Locate queries on the grid.

    Parameters
    ----------
    y_axis, yaw_axis : ndarray
        Increasing grid axes, m and rad.
    y, yaw : array_like
        Query points, broadcast together, m and rad.
    outside : {"clip", "nan", "raise"}
        Queries outside the grid: clamp to the boundary, give NaN, or raise ``ValueError``.
    """
    if outside not in OUTSIDE:
        raise ValueError(f"outside must be one of {OUTSIDE}, got {outside!r}")
    y, yaw = np.broadcast_arrays(np.asarray(y, dtype=float), np.asarray(yaw, dtype=float))
    shape = y.shape
    y, yaw = y.ravel(), yaw.ravel()
    out = ((y < y_axis[0]) | (y > y_axis[-1]) | (yaw < yaw_axis[0]) | (yaw > yaw_axis[-1])
           | np.isnan(y) | np.isnan(yaw))
    if outside == "raise" and out.any():
        bad = np.flatnonzero(out)[0]
        raise ValueError(f"query (y={y[bad]:.6g} m, yaw={yaw[bad]:.6g} rad) outside the table grid "
                         f"y in [{y_axis[0]:.6g}, {y_axis[-1]:.6g}] m, yaw in "
                         f"[{yaw_axis[0]:.6g}, {yaw_axis[-1]:.6g}] rad")
    i0, wy = _locate(y_axis, y)
    j0, wa = _locate(yaw_axis, yaw)
    return Stencil(i0, j0, wy, wa, out if outside == "nan" else np.zeros_like(out), shape)


def bilinear(values: np.ndarray, st: Stencil) -> np.ndarray:
    """Interpolate ``values`` of shape ``(ny, nyaw, *suffix)`` at the stencil's queries.

    Returns
    -------
    ndarray, shape ``q_shape + suffix``, float
    """
    ny, na = values.shape[:2]
    suffix = values.shape[2:]
    extra = (slice(None),) + (None,) * len(suffix)
    i1 = np.minimum(st.i0 + 1, ny - 1)
    j1 = np.minimum(st.j0 + 1, na - 1)
    acc = np.zeros((st.i0.size,) + suffix)
    for ii, jj, w in ((st.i0, st.j0, (1 - st.wy) * (1 - st.wa)), (i1, st.j0, st.wy * (1 - st.wa)),
                      (st.i0, j1, (1 - st.wy) * st.wa), (i1, j1, st.wy * st.wa)):
        corner = values[ii, jj].astype(float)
        # a zero-weight corner must not spread its NaN (0 * NaN = NaN)
        acc += np.where(w[extra] > 0, w[extra] * corner, 0.0)
    acc[st.outside] = np.nan
    return acc.reshape(st.shape + suffix)


def nearest(values: np.ndarray, st: Stencil, fill: float | int = 0) -> np.ndarray:
    """Value at the nearest grid node (for codes and counts); ``fill`` outside with ``"nan"``."""
    ny, na = values.shape[:2]
    i = np.minimum(st.i0 + (st.wy >= 0.5), ny - 1)
    j = np.minimum(st.j0 + (st.wa >= 0.5), na - 1)
    out = values[i, j].copy()
    out[st.outside] = fill
    return out.reshape(st.shape + values.shape[2:])
