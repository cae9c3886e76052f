"""The per-contact outputs every method stores (rolling radius, contact angle, profile
coordinates, curvatures), from a contact's points, normal and indentation.

:class:`ContactResult` is declared here, next to the code that fills it: a new stored per-contact
quantity is an attribute here, its value in :func:`_side_records` (every method's contacts pass
through it) and its line in ``lutmpi/table/schema.py``; ``table/compute.py`` stores it by name."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

SIDE_SIGN = {"left": 1.0, "right": -1.0}


@dataclass
class ContactResult:
    """One contact on one wheel (SI, track frame)."""

    wheel_point: np.ndarray      # (3,) m, contact point on the wheel
    rail_point: np.ndarray       # (3,) m, contact point on the rail
    normal: np.ndarray           # (3,) unit, rail outward normal (from rail into wheel)
    indentation: float           # m, C_max of this contact (>= 0)
    kc: float = float("nan")     # N/m, contact stiffness used for this contact
    force: float = 0.0           # N, normal force magnitude kc * indentation
    rolling_radius: float = float("nan")   # m, distance of wheel_point from the axle axis
    contact_angle: float = float("nan")    # rad, normal's angle from vertical; > 0 toward flange
    wheel_s: float = float("nan")          # m, profile coordinate on the wheel (see Profile)
    rail_v: float = float("nan")           # m, profile coordinate on the rail (see Profile)
    wheel_curv_rolling: float = float("nan")    # 1/m, principal curvature, rolling direction
    wheel_curv_transverse: float = float("nan")  # 1/m, wheel profile curvature (convex > 0)
    rail_curv_transverse: float = float("nan")   # 1/m, rail profile curvature (convex > 0)


def contact_records(scene, rows: list[tuple]) -> list[ContactResult]:
    """The stored record of several contacts (one spline evaluation per quantity and side for
    all of them): ``rows`` of ``(side, wheel_point, rail_point,
    normal, C, s, kc)``; each side's own wheel and rail (``scene.side(name)``; a scene whose
    sides share one wheel and one rail evaluates them for all rows at once)."""
    left, right = scene.side("left"), scene.side("right")
    if rows and left.wheel is right.wheel and left.rail is right.rail:
        return _side_records(left, rows)  # one wheel and rail, mirrored: one call for all
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
    rad, dr, cw = wheel.contact_geometry(s)
    v = rail.profile_coordinate(u_r, rp[:, 2])
    cr = rail.convex_curvature(np.minimum(np.maximum(u_r, rail.u_min), rail.u_max))
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
