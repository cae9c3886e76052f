"""``max_normal_distance`` (eqs. 4-5): over the wheel nodes of each volume of V_int, the
distance along the wheel normal from ``P_i`` to the meshed rail surface (the rail nodes joined
linearly across the profile); eq. (4) is the first step of this intersection, iterated until
the rail point lies on the rail facet."""

from __future__ import annotations

import numpy as np
from numba import njit

from lutmpi.contact.kernels import (
    empty_contacts,
    packed,
    search_wheel_nodes,
    set_profile_coordinates,
)
from lutmpi.contact.methods.base import MeshMethod


@njit(cache=True)
def normal_to_rail(p, n, side, ru, rz, t0):
    """Eq. (4), iterated: distance ``t`` along ``-n`` from ``p`` to the piecewise-linear rail
    profile (Newton on the facet, 4 steps from ``t0``), and the rail point ``p - t n``."""
    u0, z0 = side * p[1], p[2]
    nu, nz = side * n[1], n[2]
    t = t0
    m = ru.size
    for _ in range(4):
        u = u0 - t * nu
        i = np.searchsorted(ru, u) - 1
        i = min(max(i, 0), m - 2)
        sl = (rz[i + 1] - rz[i]) / (ru[i + 1] - ru[i])
        zr = rz[i] + sl * (u - ru[i])
        f = (z0 - t * nz) - zr
        df = -nz + sl * nu
        if abs(df) > 1e-12:
            t = t - f / df
    rp = np.empty(3)
    for a in range(3):
        rp[a] = p[a] - t * n[a]
    return t, rp


@njit(cache=True)
def contacts(win, wheel, rail, pose):
    """Eqs. (4)-(5) on every volume of one wheel's window (see :class:`MeshMethod`)."""
    ws = search_wheel_nodes(win, rail, pose)
    out = empty_contacts(ws)
    P, N, Pj = ws.P, ws.N, ws.Pj
    for i in range(ws.vol.size):
        g = ws.vol[i]
        if g < 0:
            continue
        c = (P[i, 0] - Pj[i, 0]) * N[i, 0] + (P[i, 1] - Pj[i, 1]) * N[i, 1] \
            + (P[i, 2] - Pj[i, 2]) * N[i, 2]
        c, rp = normal_to_rail(P[i], N[i], win.side, rail.u, rail.z, c)  # eq. (4)
        if c > out.C[g]:  # eq. (5): the largest normal distance
            out.C[g] = c
            out.wheel_point[g] = P[i]
            out.rail_point[g] = rp
            out.n_wheel[g] = N[i]
    set_profile_coordinates(out, win.side, pose, wheel)
    return packed(out)


METHOD = MeshMethod("max_normal_distance",
                    "largest distance along the wheel normal to the rail mesh, eqs. (4)-(5)",
                    kernel=contacts)
