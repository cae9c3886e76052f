"""Standard measures of a profile in its own frame (no track placement).

Wheels (EN 15313 flange dimensions, as MiniProf reports them in ``Sd Sh qR``):

* **Sh**, flange height: flange tip above the tape circle, ``dr_tip - dr(0)``;
* **Sd**, flange thickness: lateral distance from the flange back (``s = -70 mm``, the inner face,
  70 mm from the tape circle) to the flange face where it is 10 mm above the tape circle
  (``dr = dr(0) + 10 mm``);
* **qR**, flange slope: lateral distance between that Sd point and the flange-face point 2 mm below
  the flange tip.

S1002 new: Sh = 28, Sd = 32.5, qR = 10.8 mm (nominal values; the generator gives them within
0.1 mm, see tests).

Rails: **head width** at the gauge depth (14 mm below the top), and the **gauge point**: on the
gauge side of the top, the point nearest the track centre (smallest ``v``) within 14 mm below the
top. For a canted profile these are measured in the data's own (canted) frame; the track geometry
applies inclination first and measures there.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lutmpi.errors import ProfileError
from lutmpi.profiles.model import Profile

FLANGE_BACK_S_M = -0.070
SD_HEIGHT_M = 0.010
QR_DROP_M = 0.002
GAUGE_DEPTH_M = 0.014


def _dense(p: Profile, step: float = 1e-5) -> tuple[np.ndarray, np.ndarray]:
    y = np.arange(p.y_min, p.y_max, step)
    return y, p.z_at(y)


def _crossing(y: np.ndarray, z: np.ndarray, start: int, level: float, step: int) -> float | None:
    """First ``y`` where ``z`` falls to ``level`` walking from ``start`` by ``step``; linear."""
    i = start
    while 0 <= i + step < y.size:
        j = i + step
        if z[j] <= level < z[i] or z[j] < level <= z[i]:
            t = (z[i] - level) / (z[i] - z[j])
            return float(y[i] + t * (y[j] - y[i]))
        i = j
    return None


@dataclass(frozen=True)
class WheelMeasures:
    """Flange dimensions (m) and the flange tip position."""

    flange_height: float
    flange_thickness: float | None
    flange_slope_qr: float | None
    tip_s: float
    dr_at_tape: float


def wheel_measures(p: Profile) -> WheelMeasures:
    """Sh, Sd, qR of a wheel (module docstring), m."""
    if p.kind != "wheel":
        raise ProfileError("flange measures need a wheel profile", path=p.source)
    if not p.y_min <= 0.0 <= p.y_max:
        raise ProfileError("the profile does not reach the tape circle s = 0", path=p.source)
    y, z = _dense(p)
    flange = y < -0.020
    tip = int(np.argmax(np.where(flange, z, -np.inf)))
    dr0 = float(p.z_at(0.0))
    s_sd = _crossing(y, z, tip, dr0 + SD_HEIGHT_M, +1)
    s_q = _crossing(y, z, tip, float(z[tip]) - QR_DROP_M, +1)
    sd = None if s_sd is None else s_sd - FLANGE_BACK_S_M
    qr = None if (s_sd is None or s_q is None) else s_sd - s_q
    return WheelMeasures(float(z[tip]) - dr0, sd, qr, float(y[tip]), dr0)


@dataclass(frozen=True)
class RailMeasures:
    """Head measures (m) in the profile's own frame."""

    top_v: float
    top_z: float
    head_width: float | None
    gauge_point: tuple[float, float]
    gauge_point_at_depth: bool


def rail_measures(p: Profile, depth: float = GAUGE_DEPTH_M) -> RailMeasures:
    """Head width and gauge point ``depth`` (m) below the top; see the module docstring."""
    if p.kind != "rail":
        raise ProfileError("head measures need a rail profile", path=p.source)
    y, z = _dense(p)
    top = int(np.argmax(z))
    level = float(z[top]) - depth
    left = _crossing(y, z, top, level, -1)
    right = _crossing(y, z, top, level, +1)
    width = None if (left is None or right is None) else right - left
    if left is not None:
        gp = (left, level)
    else:                                # the gauge side ends above the gauge depth
        gp = (float(y[0]), float(z[0]))
    return RailMeasures(float(y[top]), float(z[top]), width, gp, left is not None)
