"""Parametric wear of a profile: pure functions ``Profile -> Profile`` (issue 5 item 3).

Each returns a new :class:`Profile` with ``meta['wear']`` holding the parameters (appended to any
earlier wear), the name suffixed, and the same orientation. Zero wear returns the same points.
Parameters are in mm at this edge, as in ``[wear]`` of the config.

* :func:`flange_thinning` -- the flange face moves toward the flange back by ``thickness_mm`` at the
  Sd height (10 mm above the tape circle), tapering (C1 cosine) to zero at the flange tip and 2 mm
  above the tape circle: Sd falls by exactly ``thickness_mm``, Sh is unchanged.
* :func:`tread_hollowing` -- a C2 hollow ``depth * ((1 + cos(pi x)) / 2)^2``, ``x = (s - centre) /
  (width / 2)``, removed from the radius: the running band sinks, the field side of the hollow
  stays, a *false flange* -- two candidate contact zones on a flat rail.
* :func:`rail_vertical_wear` -- the crown is cut by an arc of radius ``crown_radius_mm`` (300 mm,
  the UIC60 crown) ``depth_mm`` below the old top; the head loses exactly ``depth_mm`` of height.
* :func:`rail_side_wear` -- the gauge side is cut by a straight worn face through the point
  ``depth_mm`` field-side of the gauge point (14 mm below the top), by default parallel to the face
  there: the gauge point moves by exactly ``depth_mm``.

Cuts use a smooth minimum (:data:`SOFT_MM` = 0.02 mm) so the spline sees no kink.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from lutmpi.errors import ProfileError
from lutmpi.profiles.model import Profile

SOFT_MM = 0.02
SD_HEIGHT_MM = 10.0
ROOT_HEIGHT_MM = 2.0


def _worn(p: Profile, y: np.ndarray, z: np.ndarray, what: str, params: dict[str, Any]) -> Profile:
    meta = dict(p.meta)
    meta["wear"] = list(meta.get("wear", [])) + [{"type": what, **params}]
    try:
        return p.with_points(y, z, name=f"{p.name}+{what}", meta=meta)
    except ProfileError as exc:
        raise ProfileError(f"{what} {params} does not leave a valid profile: {exc}",
                           path=p.source) from None


def _need(p: Profile, kind: str, what: str) -> None:
    if p.kind != kind:
        raise ProfileError(f"{what} applies to a {kind} profile, got a {p.kind}", path=p.source)


def _nonneg(value: float, name: str) -> float:
    if not (math.isfinite(value) and value >= 0):
        raise ProfileError(f"{name} must be a finite number >= 0, got {value!r}")
    return float(value)


def _softmin(a: np.ndarray, b: np.ndarray, eps: float) -> np.ndarray:
    m = np.minimum(a, b)
    return m - eps * np.log1p(np.exp(-np.abs(a - b) / eps))


def _cos_step(x: np.ndarray) -> np.ndarray:
    """0 for x <= 0, 1 for x >= 1, C1 cosine in between."""
    x = np.clip(x, 0.0, 1.0)
    return 0.5 * (1.0 - np.cos(np.pi * x))


def flange_thinning(wheel: Profile, thickness_mm: float) -> Profile:
    """Thin the flange: Sd decreases by ``thickness_mm`` (mm); see the module docstring."""
    _need(wheel, "wheel", "flange thinning")
    t = _nonneg(thickness_mm, "thickness_mm") * 1e-3
    y, z = wheel.y.copy(), wheel.z.copy()
    if t > 0:
        dr0 = float(wheel.z_at(0.0))
        tip = int(np.argmax(np.where(y < -0.020, z, -np.inf)))
        h = (z - dr0) * 1e3                                 # height above the tape circle, mm
        h_sd, h_tip = SD_HEIGHT_MM, (z[tip] - dr0) * 1e3
        w = np.where(h <= h_sd, _cos_step((h - ROOT_HEIGHT_MM) / (h_sd - ROOT_HEIGHT_MM)),
                     _cos_step((h_tip - h) / (h_tip - h_sd)))
        face = (np.arange(y.size) > tip) & (y < 0.0)

        def folds(tt: float) -> bool:
            return not bool(np.all(np.diff(np.where(face, y - tt * w, y)) > 0.0))

        if folds(t):
            # between the Sd height and the tip that stays, the face moves less the higher it
            # lies: a deep enough thinning folds the face over itself (z no longer a function
            # of y). The largest thinning that does not, by bisection
            lo, hi = 0.0, t
            for _ in range(40):
                mid = 0.5 * (lo + hi)
                lo, hi = (lo, mid) if folds(mid) else (mid, hi)
            raise ProfileError(
                f"[wear.wheel] flange_thinning_mm = {thickness_mm:g} folds the flange face of "
                f"{wheel.name} over itself (the thinning tapers to zero at the flange tip, "
                f"which stays): at most {math.floor(lo * 1e5) / 100:.2f} mm for this wheel",
                path=wheel.source)
        y = np.where(face, y - t * w, y)
    return _worn(wheel, y, z, "flange_thinning", {"thickness_mm": float(thickness_mm)})


def tread_hollowing(wheel: Profile, depth_mm: float, centre_mm: float = 0.0,
                    width_mm: float = 40.0) -> Profile:
    """Hollow the tread by ``depth_mm`` at ``centre_mm`` over ``width_mm`` (all mm)."""
    _need(wheel, "wheel", "tread hollowing")
    d = _nonneg(depth_mm, "depth_mm") * 1e-3
    if not width_mm > 0:
        raise ProfileError(f"width_mm must be > 0, got {width_mm!r}")
    x = (wheel.y - centre_mm * 1e-3) / (0.5 * width_mm * 1e-3)
    bump = np.where(np.abs(x) < 1.0, (0.5 * (1.0 + np.cos(np.pi * x))) ** 2, 0.0)
    z = wheel.z - d * bump
    return _worn(wheel, wheel.y.copy(), z, "tread_hollowing",
                 {"depth_mm": float(depth_mm), "centre_mm": float(centre_mm),
                  "width_mm": float(width_mm)})


def rail_vertical_wear(rail: Profile, depth_mm: float, crown_radius_mm: float = 300.0) -> Profile:
    """Lower the rail top by ``depth_mm`` (mm) with a worn crown of ``crown_radius_mm``."""
    _need(rail, "rail", "vertical wear")
    d = _nonneg(depth_mm, "depth_mm") * 1e-3
    z = rail.z.copy()
    if d > 0:
        top = int(np.argmax(z))
        cut = z[top] - d - (rail.y - rail.y[top]) ** 2 / (2.0 * crown_radius_mm * 1e-3)
        z = _softmin(z, cut, SOFT_MM * 1e-3)
        z[top] = rail.z[top] - d          # exact at the old top (the softmin is exp(-d/eps) off)
    return _worn(rail, rail.y.copy(), z, "rail_vertical_wear",
                 {"depth_mm": float(depth_mm), "crown_radius_mm": float(crown_radius_mm)})


def rail_side_wear(rail: Profile, depth_mm: float, angle_deg: float | None = None,
                   gauge_depth_mm: float = 14.0) -> Profile:
    """Remove ``depth_mm`` (mm, horizontal) of gauge face at the gauge depth.

    The worn face is a straight line through the point ``depth_mm`` field-side of the gauge point
    (``gauge_depth_mm`` below the top), at ``angle_deg`` from the vertical; None takes the face's
    own angle at the gauge point, so the wear is a parallel shift of the face there and zero depth
    touches nothing (a steeper or flatter face also cuts the gauge corner).
    """
    _need(rail, "rail", "side wear")
    d = _nonneg(depth_mm, "depth_mm") * 1e-3
    z = rail.z.copy()
    params: dict[str, Any] = {"depth_mm": float(depth_mm), "gauge_depth_mm": gauge_depth_mm}
    if d > 0:
        top = int(np.argmax(z))
        z14 = z[top] - gauge_depth_mm * 1e-3
        gauge = np.arange(z.size) <= top
        below = np.flatnonzero(gauge & (z <= z14))
        if below.size == 0:
            raise ProfileError(f"the gauge side does not reach {gauge_depth_mm} mm below the top",
                               path=rail.source)
        k = int(below[-1])                                   # first point below the gauge depth
        v_g = float(np.interp(z14, [z[k], z[k + 1]], [rail.y[k], rail.y[k + 1]]))
        if angle_deg is None:
            slope = abs(float(rail.slope(v_g)))
            angle_deg = math.degrees(math.atan2(1.0, max(slope, 1e-12)))
        if not 1.0 <= angle_deg <= 60.0:
            raise ProfileError(f"angle_deg must be within [1, 60] degrees, got {angle_deg!r}")
        line = z14 + (rail.y - v_g - d) / math.tan(math.radians(angle_deg))
        z = np.where(gauge, _softmin(z, line, SOFT_MM * 1e-3), z)
        params["angle_deg"] = float(angle_deg)
    return _worn(rail, rail.y.copy(), z, "rail_side_wear", params)
