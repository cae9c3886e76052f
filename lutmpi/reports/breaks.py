"""Where a curve of the table against y must not be joined: contact jumps and status changes.

A contact that moves across the profile between two neighbouring grid poses (tread -> flange), a
contact that appears or disappears, or a change of solve status is a discontinuity of the table's
functions; a line drawn through it would show a value that exists nowhere. :func:`break_mask`
marks the intervals ``[y_i, y_i+1]`` to leave open: the jumps the table stores (when it has them:
``Table.jump_positions``, issue 11) and, in any case, those detected here from the data.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from lutmpi.table.schema import D

#: a contact point moving more than this along the wheel profile between neighbouring poses, m
JUMP_THRESHOLD = 3e-3


def detect(wheel_s: np.ndarray, n_contacts: np.ndarray | None = None,
           status: np.ndarray | None = None, threshold: float = JUMP_THRESHOLD) -> np.ndarray:
    """Intervals ``i -> i+1`` (bool, shape ``(n-1,)``) across which a 1-D function jumps.

    Parameters
    ----------
    wheel_s : ndarray, shape (n, 2, 2)
        Wheel-profile coordinate of each contact (side, slot), m, NaN where none.
    n_contacts : ndarray, shape (n, 2), optional
    status : ndarray, shape (n,), optional
    threshold : float
        Largest move of a contact point between neighbours that is still continuous, m.
    """
    s = np.asarray(wheel_s, float)[:, :, 0]
    move = np.abs(np.diff(s, axis=0))
    out = np.any(move > threshold, axis=1)
    if n_contacts is not None:
        out |= np.any(np.diff(np.asarray(n_contacts), axis=0) != 0, axis=1)
    if status is not None:
        out |= np.diff(np.asarray(status)) != 0
    return out


def stored(table: Any, method: str | None, j: int, y: np.ndarray) -> np.ndarray:
    """Intervals containing a jump the table stores at yaw index ``j`` (none if it stores none)."""
    positions = getattr(table, "jump_positions", None)
    out = np.zeros(max(y.size - 1, 0), bool)
    if positions is None:
        return out
    jy = np.asarray(positions(method))
    if jy.ndim != 2 or jy.shape[1] == 0:
        return out
    for p in jy[j][np.isfinite(jy[j])]:
        k = int(np.searchsorted(y, p)) - 1
        if 0 <= k < out.size:
            out[k] = True
    return out


def break_mask(table: Any, method: str | None, j: int) -> np.ndarray:
    """Intervals of the y grid at yaw index ``j`` not to join: stored jumps or detected ones."""
    get = lambda name: table.get(name, method, raw=True)[:, j]  # noqa: E731
    y = np.asarray(table.y)
    names = set(table.quantities)
    mask = stored(table, method, j, y)
    if D.wheel_s in names:
        mask |= detect(get(D.wheel_s), get(D.n_contacts) if D.n_contacts in names else None,
                       get(D.status))
    else:
        mask |= np.diff(get(D.status)) != 0
    return mask


def broken(x: np.ndarray, v: np.ndarray, mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``(x, v)`` with a NaN inserted in every interval of ``mask``, so a plotted line breaks there
    (the values on both sides stay: a jump is shown as a jump, not as a slope)."""
    x = np.asarray(x, float)
    v = np.asarray(v, float)
    idx = np.flatnonzero(mask) + 1
    xs = np.insert(x, idx, 0.5 * (x[idx - 1] + x[idx]))
    vs = np.insert(v, idx, np.nan, axis=0)
    return xs, vs
