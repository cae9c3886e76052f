"""The reference method's pose result: the rigid locus solution itself (no mesh, no k_c, stored
as NaN, indentation 0)."""

from __future__ import annotations

import numpy as np
from numba import njit

from lutmpi.contact.records import SIDE_SIGN, contact_records
from lutmpi.equilibrium.result import CONVERGED, STATUS, PoseResult
from lutmpi.profiles.spline import ppoly_at


def rigid_result(scene, rigid, name: str) -> PoseResult:
    """The :class:`PoseResult` of the rigid two-point contact ``rigid`` (a successful
    :class:`~lutmpi.contact.locus.RigidSolution`) for method ``name``."""
    res = PoseResult(
        y=rigid.y, yaw=rigid.yaw, method=name, x_g=0.0, z_g=rigid.z_g,
        roll=rigid.roll, pitch=0.0, success=True, status=CONVERGED,
        message=STATUS[CONVERGED], nit=rigid.nit, indentation=0.0,
    )
    rows, names = [], []
    for side_name, side in SIDE_SIGN.items():
        cs = rigid.contacts[side_name]
        if not cs:
            continue
        k = len(cs)
        u, x = np.empty(k), np.empty(k)
        for i, c in enumerate(cs):
            u[i], x[i] = c.u, c.point[0]
        rp, n = _rail_points(side, u, x, *scene.side(side_name).rail_point_args)
        for i, c in enumerate(cs):
            rows.append((side, c.point, rp[i], n[i], max(-c.gap, 0.0), c.s, np.nan))
            names.append(side_name)
    for side_name, rec in zip(names, contact_records(scene, rows), strict=True):
        res.contacts[side_name].append(rec)
    return res


@njit(cache=True)
def _rail_points(side, u, x, rpp, u_min, u_max):
    """The rail point under each rigid contact (track frame: ``x``, lateral ``side * u`` with
    ``u`` clipped to the rail's data, the rail's height there) and the rail's outward unit
    normal ``(0, -side * slope, 1) / hypot(1, slope)``; ``rpp``: the placed rail's ``ppolys``.
    Returns ``(points (k, 3), normals (k, 3))``, m."""
    c, xs, c1, x1 = rpp
    rp, n = np.empty((u.size, 3)), np.empty((u.size, 3))
    for i in range(u.size):
        ui = min(max(u[i], u_min), u_max)
        sl = ppoly_at(c1, x1, ui)
        den = np.hypot(1.0, sl)
        n[i, 0], n[i, 1], n[i, 2] = 0.0 / den, side * -sl / den, 1.0 / den
        rp[i, 0], rp[i, 1], rp[i, 2] = x[i], side * ui, ppoly_at(c, xs, ui)
    return rp, n
