"""The per-contact outputs every method stores (rolling radius, contact angle, profile
coordinates, curvatures), from a contact's points, normal and indentation.

:class:`ContactResult` is declared here, next to the code that fills it: a new stored per-contact
quantity is an attribute here, its value in :func:`_side_records` (every method's contacts pass
through it) and its line in ``lutmpi/table/schema.py``; ``table/compute.py`` stores it by name."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numba import njit

from lutmpi.profiles.spline import ppoly_at

SIDE_SIGN = {"left": 1.0, "right": -1.0}
CURV_BASE = 2.5e-4  # m, half base of the transverse curvature estimate (_chord)


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
    k = len(rows)
    side, s = np.empty(k), np.empty(k)
    rp, nrm = np.empty((k, 3)), np.empty((k, 3))
    for i, r in enumerate(rows):
        side[i], rp[i], nrm[i], s[i] = r[0], r[2], r[3], r[5]
    geo = record_geometry(side, rp, s, nrm, *sd.record_args)
    out = []
    for (_, wp, rpi, n, C, si, kc), g in zip(rows, geo.tolist(), strict=True):
        C, kc = float(C), float(kc)
        out.append(ContactResult(
            wheel_point=np.asarray(wp, float),
            rail_point=np.asarray(rpi, float),
            normal=np.asarray(n, float),
            indentation=C,
            kc=kc,
            force=kc * C if math.isfinite(kc) else math.nan,
            rolling_radius=g[0],
            contact_angle=g[1],
            wheel_s=float(si),
            rail_v=g[2],
            wheel_curv_rolling=g[3],
            wheel_curv_transverse=g[4],
            rail_curv_transverse=g[5],
        ))
    return out


@njit(cache=True)
def _chord(x, lo_b, hi_b, h, c, xs, c1, x1):
    """Transverse curvature at ``x`` of a curve (spline ``c, xs``, slope ``c1, x1``) defined
    on ``[lo_b, hi_b]``, 1/m, positive where convex (a rail's crown, a wheel's flange tip): the
    change of the normal's angle over ``x ± h`` (clipped to the curve) over the chord, so that
    the joints of a profile made of arcs (UIC60: R300/R80/R13) give the mean of the two arcs
    instead of the ringing of a spline's second derivative."""
    lo = min(max(x - h, lo_b), hi_b)
    hi = min(max(x + h, lo_b), hi_b)
    a = np.arctan(ppoly_at(c1, x1, hi)) - np.arctan(ppoly_at(c1, x1, lo))
    span = np.hypot(hi - lo, ppoly_at(c, xs, hi) - ppoly_at(c, xs, lo))
    return -a / (span if span > 0 else np.inf)


@njit(cache=True)
def record_geometry(sgn, rp, s, nrm, wpp, r0, s_min, s_max, rpp, rail_geo, h):
    """The stored geometry of contacts (side signs ``sgn``; rail points ``rp`` (k, 3), m; wheel
    profile coordinates ``s``, m; the normals ``nrm`` (k, 3)): per contact, in this order, the
    :class:`ContactResult` attributes rolling radius, contact angle, rail profile coordinate,
    wheel rolling curvature (Meusnier: ``cos(slope) / r``), wheel and rail transverse
    curvatures (:func:`_chord`, the rail's at its point clipped to the rail), the rail profile
    coordinate ``v`` being the placed point mapped back through the rail's placement
    (:meth:`~lutmpi.geometry.track.PlacedRail.place`). ``wpp``, ``rpp``: ``(c, x, c1, x1)``
    of the wheel profile and the placed rail (their ``ppolys``); ``rail_geo``: ``(u_min,
    u_max, gauge, v_gp, w_top, inclination)`` (m, rad); ``h``: the curvature's half base
    (m)."""
    zc, zx, dc, dx = wpp
    rc, rx, rdc, rdx = rpp
    u_min, u_max, gauge, v_gp, w_top, incl = rail_geo
    cd, sd = np.cos(incl), np.sin(incl)
    out = np.empty((s.size, 6))
    for i in range(s.size):
        si = s[i]
        r = r0 + ppoly_at(zc, zx, si)
        d = ppoly_at(dc, dx, si)
        u = sgn[i] * rp[i, 1]
        out[i, 0] = r
        out[i, 1] = np.arctan2(-sgn[i] * nrm[i, 1], nrm[i, 2])
        out[i, 2] = (u - 0.5 * gauge + v_gp) * cd + (rp[i, 2] + w_top) * sd
        out[i, 3] = 1.0 / (r * np.sqrt(1.0 + d * d))
        out[i, 4] = _chord(si, s_min, s_max, h, zc, zx, dc, dx)
        out[i, 5] = _chord(min(max(u, u_min), u_max), u_min, u_max, h, rc, rx, rdc, rdx)
    return out
