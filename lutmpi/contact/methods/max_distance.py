"""``max_distance`` (eq. 3): over the wheel nodes of each volume of V_int, the pair
(i, j(i)) with the largest penetration ``C = (P_i - P_j) . N_i``."""

from __future__ import annotations

from numba import njit

from lutmpi.contact.kernels import (
    empty_contacts,
    packed,
    search_wheel_nodes,
    set_profile_coordinates,
)
from lutmpi.contact.methods.base import MeshMethod


@njit(cache=True)
def contacts(win, wheel, rail, pose):
    """Eq. (3) on every volume of one wheel's window (see :class:`MeshMethod`)."""
    ws = search_wheel_nodes(win, rail, pose)
    out = empty_contacts(ws)
    P, N, Pj = ws.P, ws.N, ws.Pj
    for i in range(ws.vol.size):
        g = ws.vol[i]
        if g < 0:
            continue
        # eq. (3): penetration of node i along its own normal
        c = (P[i, 0] - Pj[i, 0]) * N[i, 0] + (P[i, 1] - Pj[i, 1]) * N[i, 1] \
            + (P[i, 2] - Pj[i, 2]) * N[i, 2]
        if c > out.C[g]:
            out.C[g] = c
            out.wheel_point[g] = P[i]
            out.rail_point[g] = Pj[i]
            out.n_wheel[g] = N[i]
    set_profile_coordinates(out, win.side, pose, wheel)
    return packed(out)


METHOD = MeshMethod("max_distance", "largest wheel-node penetration, eq. (3)", kernel=contacts)
