"""The per-contact outputs every method stores (rolling radius, contact angle, profile
coordinates, curvatures), from a contact's points, normal and indentation."""

from __future__ import annotations

import numpy as np

from lutmpi.equilibrium.result import ContactResult

SIDE_SIGN = {"left": 1.0, "right": -1.0}


def contact_record(
    sd,
    side: float,
    wheel_point: np.ndarray,
    rail_point: np.ndarray,
    normal: np.ndarray,
    C: float,
    s: float,
    kc: float,
) -> ContactResult:
    """One contact's stored record (track frame, SI); ``normal`` from the rail into the wheel,
    ``s`` the wheel profile coordinate, ``kc`` the contact's stiffness (NaN: rigid); ``sd``
    the :class:`~lutmpi.scene.SideScene` of the wheel."""
    wheel, rail = sd.wheel, sd.rail
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


def contact_records(scene, rows: list[tuple]) -> list[ContactResult]:
    """:func:`contact_record` for several contacts at once (one spline evaluation per quantity
    and side for all of them; the same numbers): ``rows`` of ``(side, wheel_point, rail_point,
    normal, C, s, kc)``; each side's own wheel and rail (``scene.side(name)``)."""
    out: list[ContactResult | None] = [None] * len(rows)
    for name, sign in SIDE_SIGN.items():
        idx = [i for i, r in enumerate(rows) if r[0] == sign]
        if idx:
            for i, rec in zip(idx, _side_records(scene.side(name), [rows[i] for i in idx]),
                              strict=True):
                out[i] = rec
    return out


def _side_records(sd, rows: list[tuple]) -> list[ContactResult]:
    wheel, rail = sd.wheel, sd.rail
    side = np.array([r[0] for r in rows])
    rp = np.array([r[2] for r in rows])
    s = np.array([float(r[5]) for r in rows])
    u_r = side * rp[:, 1]
    dr, rad = wheel.dr(s), wheel.radius(s)
    v = rail.profile_coordinate(u_r, rp[:, 2])
    cw = wheel.convex_curvature(s)
    cr = rail.convex_curvature(np.clip(u_r, rail.u_min, rail.u_max))
    out = []
    for i, (sg, wp, rpi, n, C, si, kc) in enumerate(rows):
        r, d = float(rad[i]), float(dr[i])
        out.append(ContactResult(
            wheel_point=np.asarray(wp, float),
            rail_point=np.asarray(rpi, float),
            normal=np.asarray(n, float),
            indentation=float(C),
            kc=float(kc),
            force=float(kc * C) if np.isfinite(kc) else float("nan"),
            rolling_radius=r,
            contact_angle=float(np.arctan2(-sg * n[1], n[2])),
            wheel_s=float(si),
            rail_v=float(v[i]),
            wheel_curv_rolling=1.0 / (r * np.sqrt(1.0 + d * d)),
            wheel_curv_transverse=float(cw[i]),
            rail_curv_transverse=float(cr[i]),
        ))
    return out
