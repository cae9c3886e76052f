"""The per-contact outputs every method stores (rolling radius, contact angle, profile
coordinates, curvatures), from a contact's points, normal and indentation."""

from __future__ import annotations

import numpy as np

from lutmpi.equilibrium.result import ContactResult

SIDE_SIGN = {"left": 1.0, "right": -1.0}


def contact_record(
    scene,
    side: float,
    wheel_point: np.ndarray,
    rail_point: np.ndarray,
    normal: np.ndarray,
    C: float,
    s: float,
    kc: float,
) -> ContactResult:
    """One contact's stored record (track frame, SI); ``normal`` from the rail into the wheel,
    ``s`` the wheel profile coordinate, ``kc`` the contact's stiffness (NaN: rigid)."""
    wheel, rail = scene.wheel, scene.rail
    u_r = side * rail_point[1]
    dr = float(wheel.dr(s))
    r = float(wheel.radius(s))
    return ContactResult(
        wheel_point=np.asarray(wheel_point, float),
        rail_point=np.asarray(rail_point, float),
        normal=np.asarray(normal, float),
        indentation=float(C),
        kc=float(kc),
        force=float(kc * C) if np.isfinite(kc) else float("nan"),
        rolling_radius=r,
        contact_angle=float(np.arctan2(-side * normal[1], normal[2])),
        wheel_s=float(s),
        rail_v=float(rail.profile_coordinate(u_r, rail_point[2])),
        wheel_curv_rolling=1.0 / (r * np.sqrt(1.0 + dr * dr)),
        wheel_curv_transverse=float(wheel.convex_curvature(s)),
        rail_curv_transverse=float(rail.convex_curvature(np.clip(u_r, rail.u_min, rail.u_max))),
    )
