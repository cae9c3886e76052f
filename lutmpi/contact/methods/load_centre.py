"""``load_centre`` (eqs. 6-7, the paper's preferred method): the centroids of the wheel nodes
and of the rail nodes of each volume of V_int; ``C`` from eq. (7) with the wheel normal at the
wheel centroid.

A rail node is in V_int by eq. (2) paired with its nearest wheel node; it belongs to the first
volume whose slices (one either side) hold its nearest wheel slice."""

from __future__ import annotations

import numpy as np
from numba import njit

from lutmpi.contact.kernels import (
    K_NEAR,
    empty_contacts,
    grid_angle,
    nearest_from,
    packed,
    search_wheel_nodes,
    wheel_normal,
)
from lutmpi.contact.methods.base import MeshMethod

#: m: the bound of :func:`_rail_centroid_sums`' early test must exceed this to drop a rail
#: node; V.N_i is then at least this over sqrt(1 + dr^2) (above 1e-12 m for the slopes the
#: test is taken at), far above its rounding (~1e-16 m on coordinates of ~1 m)
REJECT_M = 1e-9
#: the largest wheel profile slope |dr| for which that test is taken (a steeper slice is
#: tested in full)
REJECT_SLOPE = 1e3


@njit(cache=True)
def _rail_centroid_sums(out, ws, win, wheel, pose):
    """Eq. (2) for every rail node of the window; the sums of the V_int rail nodes per volume
    into ``out.rail_point`` and their counts into ``out.n_rail_nodes``."""
    side, centre, R = win.side, pose.centre, pose.R
    rail_pts, rail_nrm = win.rail_pts, win.rail_nrm
    ws_, wr, wdr, d = wheel.s, wheel.r, wheel.dr, wheel.d
    # the slices a volume takes rail nodes from, and the profile coordinates outside which a
    # node's nearest slice (within K_NEAR of its sorted position) cannot be one of them
    klo, khi = ws.kmin[0] - 1, ws.kmax[0] + 1
    for h in range(1, ws.nvol):
        klo, khi = min(klo, ws.kmin[h] - 1), max(khi, ws.kmax[h] + 1)
    n = ws_.size
    x_lo = ws_[klo - K_NEAR - 1] if klo - K_NEAR - 1 >= 0 else -np.inf
    x_hi = ws_[khi + K_NEAR] if khi + K_NEAR < n else np.inf
    # eq. (2)'s wheel-side test bounded before the node's grid angle is sought (issue 14): with
    # the rail node at wheel-frame (c0, c1, c2) = rho (sin a, ., -cos a), its nearest slice k
    # and the grid angle m dphi nearest a (|a - m dphi| <= dphi / 2), V.N_i times
    # sqrt(1 + dr^2) is rho cos(a - m dphi) - r - dr (x - s) >= rho cos(dphi / 2) - r - dr (x - s):
    # where that is above REJECT_M the node lies outside the wheel and fails eq. (2) whatever its
    # angle (the same nodes are kept; on the Manchester table's windows 28 % of the rail nodes
    # stop here, 44 % of those whose angle was sought before)
    cos_half = np.cos(0.5 * wheel.dphi)
    pos = 0
    for j in range(rail_pts.shape[0]):
        q0 = rail_pts[j, 0] - centre[0]
        q1 = rail_pts[j, 1] - centre[1]
        q2 = rail_pts[j, 2] - centre[2]
        c1 = R[0, 1] * q0 + R[1, 1] * q1 + R[2, 1] * q2
        x = side * c1 - d
        if x <= x_lo or x > x_hi:
            continue  # its nearest slice lies outside every volume's (the same as below)
        c0 = R[0, 0] * q0 + R[1, 0] * q1 + R[2, 0] * q2
        c2 = R[0, 2] * q0 + R[1, 2] * q1 + R[2, 2] * q2
        rho = np.sqrt(c0 * c0 + c2 * c2)
        k, pos = nearest_from(x, rho, ws_, wr, K_NEAR, pos)
        g = -1
        for h in range(ws.nvol):
            if ws.kmin[h] - 1 <= k <= ws.kmax[h] + 1:
                g = h
                break
        if g < 0:
            continue
        r, dr = wr[k], wdr[k]
        if rho * cos_half - r - dr * (x - ws_[k]) > REJECT_M and abs(dr) < REJECT_SLOPE:
            continue  # outside the wheel by more than rounding: not in V_int (above)
        _, sp, cp = grid_angle(c0, c2, wheel)   # the node's angle, its sine and cosine
        b0, b1, b2 = r * sp, side * (d + ws_[k]), -r * cp
        inv = 1.0 / np.sqrt(1.0 + dr * dr)
        n0, n1, n2 = sp * inv, -side * dr * inv, -cp * inv
        vn = 0.0
        vm = 0.0
        for a in range(3):
            pa = centre[a] + R[a, 0] * b0 + R[a, 1] * b1 + R[a, 2] * b2
            na = R[a, 0] * n0 + R[a, 1] * n1 + R[a, 2] * n2
            va = rail_pts[j, a] - pa
            vn += va * rail_nrm[j, a]
            vm += va * na
        if vn >= 0.0 and vm <= 0.0:  # eq. (2), rail side
            out.n_rail_nodes[g] += 1
            for a in range(3):
                out.rail_point[g, a] += rail_pts[j, a]


@njit(cache=True)
def contacts(win, wheel, rail, pose):
    """Eqs. (6)-(7) on every volume of one wheel's window (see :class:`MeshMethod`)."""
    ws = search_wheel_nodes(win, rail, pose)
    out = empty_contacts(ws)
    if ws.nvol == 0:
        return packed(out)
    WP, RP = out.wheel_point, out.rail_point
    for i in range(ws.vol.size):
        g = ws.vol[i]
        if g >= 0:
            for a in range(3):
                WP[g, a] += ws.P[i, a]
    _rail_centroid_sums(out, ws, win, wheel, pose)
    for g in range(ws.nvol):
        for a in range(3):  # eq. (6): centroid of the wheel nodes
            WP[g, a] /= ws.n_nodes[g]
        if out.n_rail_nodes[g] > 0:
            for a in range(3):  # eq. (6): centroid of the rail nodes
                RP[g, a] /= out.n_rail_nodes[g]
        else:  # no rail node inside yet: the wheel nodes' nearest rail nodes
            cnt = 0
            for i in range(ws.vol.size):
                if ws.vol[i] == g:
                    cnt += 1
                    for a in range(3):
                        RP[g, a] += ws.Pj[i, a]
            for a in range(3):
                RP[g, a] /= cnt
        nwv, s = wheel_normal(WP[g], win.side, pose, wheel)
        out.n_wheel[g] = nwv
        out.s[g] = s
        # eq. (7): indentation along the wheel normal at the wheel centroid
        out.C[g] = (
            (WP[g, 0] - RP[g, 0]) * nwv[0]
            + (WP[g, 1] - RP[g, 1]) * nwv[1]
            + (WP[g, 2] - RP[g, 2]) * nwv[2]
        )
    return packed(out)


METHOD = MeshMethod("load_centre", "centroids of the intersecting volume, eqs. (6)-(7)",
                    kernel=contacts, indentation_rate=0.5, rail_nodes=True, centroid=True)
