"""Test oracle: the vectorized numpy twin of the compiled contact methods of
:mod:`lutmpi.contact.methods` (same algorithm, written for reading; the tests compare the two).

Intersecting volume (eq. 2) and the three contact-point methods of §4.2.

Conventions: ``N_w`` is the wheel's outward unit normal (out of the wheel, into the rail);
``V_ij = P_j - P_i`` joins wheel node ``i`` to rail node ``j``. A wheel node is in the
intersecting volume when, paired with its nearest rail node, ``V_ij . N_j >= 0`` and
``V_ij . N_i <= 0`` (eq. 2); likewise a rail node with its nearest wheel node. The indentation
is reported positive: ``C = (P_w - P_r) . N_w >= 0``.

Methods (a registry, chosen by name):

``max_distance`` (eq. 3)
    over the wheel nodes of V_int, the pair (i, j(i)) with the largest ``V . N_i`` penetration.
``max_normal_distance`` (eqs. 4-5)
    over the wheel nodes of V_int, the distance along the wheel normal from ``P_i`` to the meshed
    rail surface (the rail nodes joined linearly across the profile); eq. (4) is the first step of
    this intersection, iterated here until the rail point lies on the rail facet.
``load_centre`` (eqs. 6-7)
    the centroids of the wheel nodes and of the rail nodes of V_int; ``C`` from eq. (7) with the
    wheel normal at the wheel centroid.

Double contact (§4.6): the wheel nodes of V_int are split into separate volumes wherever a whole
row of aligned nodes (a profile slice) inside their span is not in V_int.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lutmpi.contact.mesh import RailMesh, WheelMesh, Window
from lutmpi.contact.methods.base import MeshContact, MeshMethod


@dataclass
class WheelSearch:
    """Wheel nodes of a window at a pose, paired with their nearest rail nodes."""

    P: np.ndarray
    N: np.ndarray
    Pj: np.ndarray
    Nj: np.ndarray
    l: np.ndarray
    inside: np.ndarray
    k: np.ndarray


def search_wheel(win: Window, rmesh: RailMesh, centre: np.ndarray, R: np.ndarray) -> WheelSearch:
    """Eq. (2) for every wheel node of the window."""
    side = win.side
    P = centre + win.body_pts @ R.T
    N = win.body_nrm @ R.T
    u = side * P[:, 1]
    ln = rmesh.nearest_node(u, P[:, 2])
    Pj = np.empty_like(P)
    Pj[:, 0] = np.round(P[:, 0] / rmesh.h_x) * rmesh.h_x
    Pj[:, 1] = side * rmesh.u[ln]
    Pj[:, 2] = rmesh.z[ln]
    Nj = np.zeros_like(P)
    Nj[:, 1] = side * rmesh.nu[ln]
    Nj[:, 2] = rmesh.nz[ln]
    V = Pj - P
    inside = (np.einsum("ij,ij->i", V, Nj) >= 0.0) & (np.einsum("ij,ij->i", V, N) <= 0.0)
    return WheelSearch(P=P, N=N, Pj=Pj, Nj=Nj, l=ln, inside=inside, k=win.k)


def search_rail(
    win: Window, wmesh: WheelMesh, centre: np.ndarray, R: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Eq. (2) for every rail node of the window: (inside mask, nearest wheel slice)."""
    if win.rail_pts.shape[0] == 0:
        return np.zeros(0, dtype=bool), np.zeros(0, dtype=int)
    side = win.side
    c = (win.rail_pts - centre) @ R
    rho = np.hypot(c[:, 0], c[:, 2])
    k = wmesh.nearest_slice(side * c[:, 1], rho)
    m = np.round(np.arctan2(c[:, 0], -c[:, 2]) / wmesh.dphi).astype(int)
    bp, bn = wmesh.body_points(side, k, m)
    Pi = centre + bp @ R.T
    Ni = bn @ R.T
    V = win.rail_pts - Pi
    inside = (np.einsum("ij,ij->i", V, win.rail_nrm) >= 0.0) & (np.einsum("ij,ij->i", V, Ni) <= 0.0)
    return inside, k


def split_volumes(k_inside: np.ndarray) -> list[np.ndarray]:
    """Group the V_int wheel nodes (by slice index) into separate volumes (§4.6)."""
    if k_inside.size == 0:
        return []
    ks = np.unique(k_inside)
    breaks = np.nonzero(np.diff(ks) > 1)[0]
    bounds = np.split(ks, breaks + 1)
    return [np.nonzero((k_inside >= b[0]) & (k_inside <= b[-1]))[0] for b in bounds]


def wheel_normal_at(
    point: np.ndarray, side: float, wmesh: WheelMesh, centre: np.ndarray, R: np.ndarray
) -> tuple[np.ndarray, float]:
    """Outward wheel normal (track frame) at the wheel-surface location of ``point``, and the
    profile coordinate ``s`` of that location (slope from the mesh's 10 µm table, as in the
    compiled kernel)."""
    c = (point - centre) @ R
    s = side * c[1] - wmesh.wheel.d
    s = float(np.clip(s, wmesh.wheel.s_min, wmesh.wheel.s_max))
    phi = np.arctan2(c[0], -c[2])
    dr = float(np.interp(s, wmesh.tab_s, wmesh.tab_dr))
    inv = 1.0 / np.sqrt(1.0 + dr * dr)
    nb = np.array([np.sin(phi) * inv, -side * dr * inv, -np.cos(phi) * inv])
    return R @ nb, s


def _pair_contact(
    ws: WheelSearch,
    idx: np.ndarray,
    i: int,
    C: float,
    rail_point: np.ndarray,
    side: float,
    wmesh: WheelMesh,
    centre: np.ndarray,
    R: np.ndarray,
) -> MeshContact:
    _, s = wheel_normal_at(ws.P[i], side, wmesh, centre, R)
    return MeshContact(
        wheel_point=ws.P[i].copy(),
        rail_point=rail_point,
        n_wheel=ws.N[i].copy(),
        indentation=float(C),
        s=s,
        u_rail=float(side * rail_point[1]),
        n_wheel_nodes=int(idx.size),
        n_rail_nodes=0,
    )


def max_distance(ws: WheelSearch, idx: np.ndarray, ctx: dict) -> MeshContact:
    """Eq. (3): the wheel node of the volume with the largest indentation ``(P_i - P_j) . N_i``."""
    C = np.einsum("ij,ij->i", ws.P[idx] - ws.Pj[idx], ws.N[idx])
    a = int(np.argmax(C))
    i = idx[a]
    return _pair_contact(
        ws, idx, i, C[a], ws.Pj[i].copy(), ctx["side"], ctx["wmesh"], ctx["centre"], ctx["R"]
    )


def _normal_line_to_rail(
    P: np.ndarray, N: np.ndarray, side: float, rmesh: RailMesh, t0: np.ndarray, iters: int = 4
) -> np.ndarray:
    """Distance ``t`` along ``-N`` from ``P`` to the piecewise-linear rail profile (vectorized)."""
    u0, z0 = side * P[:, 1], P[:, 2]
    nu, nz = side * N[:, 1], N[:, 2]
    t = t0.copy()
    for _ in range(iters):
        u = u0 - t * nu
        i = np.clip(np.searchsorted(rmesh.u, u) - 1, 0, rmesh.u.size - 2)
        sl = (rmesh.z[i + 1] - rmesh.z[i]) / (rmesh.u[i + 1] - rmesh.u[i])
        zr = rmesh.z[i] + sl * (u - rmesh.u[i])
        f = (z0 - t * nz) - zr
        df = -nz + sl * nu
        t = t - f / np.where(np.abs(df) > 1e-12, df, -1.0)
    return t


def max_normal_distance(ws: WheelSearch, idx: np.ndarray, ctx: dict) -> MeshContact:
    """Eqs. (4)-(5): the wheel node with the largest distance along its normal to the rail mesh."""
    side, rmesh = ctx["side"], ctx["rmesh"]
    P, N = ws.P[idx], ws.N[idx]
    t0 = np.einsum("ij,ij->i", P - ws.Pj[idx], N)
    t = _normal_line_to_rail(P, N, side, rmesh, t0)
    a = int(np.argmax(t))
    i = idx[a]
    rail_point = ws.P[i] - t[a] * ws.N[i]  # eq. (4): on the wheel normal through P_w
    return _pair_contact(ws, idx, i, t[a], rail_point, side, ctx["wmesh"], ctx["centre"], ctx["R"])


def load_centre(ws: WheelSearch, idx: np.ndarray, ctx: dict) -> MeshContact:
    """Eqs. (6)-(7): centroids of the wheel and rail nodes of the volume."""
    side, wmesh, centre, R = ctx["side"], ctx["wmesh"], ctx["centre"], ctx["R"]
    Pw = ws.P[idx].mean(axis=0)
    rail_in = ctx["rail_inside"]
    sel = rail_in & (ctx["rail_volume"] == ctx["volume"])
    if np.any(sel):
        Pr = ctx["rail_pts"][sel].mean(axis=0)
        n_r = int(sel.sum())
    else:  # no rail node inside yet (very small volume): the wheel nodes' nearest rail nodes
        Pr = ws.Pj[idx].mean(axis=0)
        n_r = 0
    Nw, s = wheel_normal_at(Pw, side, wmesh, centre, R)
    C = float(np.dot(Pw - Pr, Nw))  # eq. (7)
    return MeshContact(
        wheel_point=Pw,
        rail_point=Pr,
        n_wheel=Nw,
        indentation=C,
        s=s,
        u_rail=float(side * Pr[1]),
        n_wheel_nodes=int(idx.size),
        n_rail_nodes=n_r,
    )


METHODS: dict[str, Callable[[WheelSearch, np.ndarray, dict], MeshContact]] = {
    "max_distance": max_distance,
    "max_normal_distance": max_normal_distance,
    "load_centre": load_centre,
}
NEEDS_RAIL_NODES = {"load_centre"}


def get_method(name: str) -> Callable[[WheelSearch, np.ndarray, dict], MeshContact]:
    """The contact-point method registered under ``name``."""
    try:
        return METHODS[name]
    except KeyError:
        raise ValueError(f"unknown contact method {name!r}; valid: {sorted(METHODS)}") from None


def wheel_contacts(
    method: str,
    win: Window,
    wmesh: WheelMesh,
    rmesh: RailMesh,
    centre: np.ndarray,
    R: np.ndarray,
    max_contacts: int = 2,
) -> list[MeshContact]:
    """All contacts of one wheel at the pose (``centre``, ``R``), largest indentation first."""
    fn = get_method(method)
    ws = search_wheel(win, rmesh, centre, R)
    inside_idx = np.nonzero(ws.inside)[0]
    if inside_idx.size == 0:
        return []
    ctx = {"side": win.side, "wmesh": wmesh, "rmesh": rmesh, "centre": centre, "R": R}
    vols = split_volumes(ws.k[inside_idx])
    if method in NEEDS_RAIL_NODES:
        rin, rk = search_rail(win, wmesh, centre, R)
        # each rail node belongs to the first volume whose slices (one either side) hold its
        # nearest wheel slice
        rvol = np.full(rk.shape, -1)
        for g in range(len(vols) - 1, -1, -1):
            kv = ws.k[inside_idx[vols[g]]]
            rvol[(rk >= kv.min() - 1) & (rk <= kv.max() + 1)] = g
        ctx.update(rail_inside=rin, rail_volume=rvol, rail_pts=win.rail_pts)
    out = []
    for g, v in enumerate(vols):
        ctx["volume"] = g
        out.append(fn(ws, inside_idx[v], ctx))
    out = [c for c in out if c.indentation > 0.0]
    out.sort(key=lambda c: -c.indentation)
    return out[:max_contacts]


class NumpyMethod(MeshMethod):
    """A registered mesh method with its contact stage replaced by the numpy twin (the oracle of
    whole pose solves)."""

    def contacts(self, win, wmesh, rmesh, centre, R, max_contacts=2):
        return wheel_contacts(self.name, win, wmesh, rmesh, centre, R, max_contacts)


def numpy_twin(method: MeshMethod) -> NumpyMethod:
    """``method`` with the numpy contact stage."""
    return NumpyMethod(method.name, method.description, kernel=method.kernel,
                       indentation_rate=method.indentation_rate, rail_nodes=method.rail_nodes)
