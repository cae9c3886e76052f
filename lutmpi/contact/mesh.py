"""Surface meshes of the wheel (surface of revolution) and the rail (extrusion), and the contact
window ("mesh only where contact can happen").

Both meshes are *implicit global grids*. Wheel nodes sit at arc length ``k * h_w`` along the wheel
profile (``k = 0`` on the tape circle) and at angles ``m * dphi`` (``dphi = h_c / r0``). Rail
nodes sit at arc length ``l * h_r`` along the placed rail profile (``l = 0`` at the top of rail)
and at ``x = j * h_x`` along the track. A window is a set of integer indices of that grid, so a
windowed mesh is an exact subset of the full mesh, and both give the same result whenever the
window holds every node of the intersecting volume.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from lutmpi.contact.kernels import (
    Pose,
    RailArrays,
    WheelArrays,
    WindowArrays,
    angle_bounds,
    angle_table,
    locus_at_slices,
    locus_window,
    window_nodes,
)
from lutmpi.errors import GeometryError
from lutmpi.geometry.track import PlacedRail, WheelGeometry

#: the most wheel nodes a contact window may hold (~100 bytes each with the rail nodes facing them)
MAX_WINDOW_NODES = 20_000_000


def _arc_grid(x: np.ndarray, z: np.ndarray, x_anchor: float, h: float) -> np.ndarray:
    """Abscissae of nodes spaced ``h`` in arc length along the curve ``(x, z)`` (dense samples),
    anchored so that a node falls on ``x_anchor``."""
    lam = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(z)))])
    lam0 = np.interp(x_anchor, x, lam)
    k_lo = int(np.ceil((lam[0] - lam0) / h))
    k_hi = int(np.floor((lam[-1] - lam0) / h))
    ks = np.arange(k_lo, k_hi + 1)
    return np.interp(lam0 + ks * h, lam, x)


@dataclass(frozen=True, eq=False)
class WheelMesh:
    """Wheel grid: slices (profile nodes) with radius and profile slope; circumferential step."""

    wheel: WheelGeometry
    h_lat: float
    h_circ: float
    s: np.ndarray  # (nk,) profile coordinate of each slice, m
    r: np.ndarray  # (nk,) radius, m
    dr: np.ndarray  # (nk,) d r / d s
    dphi: float  # rad
    tab_s: np.ndarray  # dense table of s (10 µm) ...
    tab_dr: np.ndarray  # ... and d r / d s, for the wheel normal off the nodes (both kernels)

    @classmethod
    def build(cls, wheel: WheelGeometry, h_lat: float, h_circ: float) -> WheelMesh:
        xs = np.linspace(wheel.s_min, wheel.s_max, 20000)
        s = _arc_grid(xs, wheel.profile.z_at(xs), 0.0, h_lat)
        tab_s = np.linspace(wheel.s_min, wheel.s_max, int((wheel.s_max - wheel.s_min) / 1e-5) + 2)
        return cls(
            wheel=wheel,
            h_lat=h_lat,
            h_circ=h_circ,
            s=s,
            r=wheel.radius(s),
            dr=wheel.dr(s),
            dphi=h_circ / wheel.r0,
            tab_s=tab_s,
            tab_dr=wheel.dr(tab_s),
        )

    @cached_property
    def arrays(self) -> WheelArrays:
        """The grid as the compiled kernels take it."""
        w = self.wheel
        return WheelArrays(self.s, self.r, self.dr, float(w.d), float(self.dphi), self.tab_s,
                           self.tab_dr, float(w.s_min), float(w.s_max), *self.angles,
                           angle_bounds(float(self.dphi), self._half_turn))

    @property
    def _half_turn(self) -> int:
        """Angle steps in half a turn (rounded up): the extent of the angle tables."""
        return int(np.ceil(np.pi / self.dphi))

    @cached_property
    def angles(self) -> tuple[np.ndarray, np.ndarray]:
        """``sin`` and ``cos`` of the grid's angles over half a turn either way
        (:func:`~lutmpi.contact.kernels.angle_table`): a window's nodes look them up."""
        return angle_table(float(self.dphi), self._half_turn)

    def body_points(
        self, side: float, k: np.ndarray, m: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray]:
        """Wheelset-frame node positions and outward unit normals for slice ``k``, angle ``m``."""
        phi = m * self.dphi
        r, s, dr = self.r[k], self.s[k], self.dr[k]
        sp, cp = np.sin(phi), np.cos(phi)
        pts = np.empty((k.size, 3))
        pts[:, 0] = r * sp
        pts[:, 1] = side * (self.wheel.d + s)
        pts[:, 2] = -r * cp
        inv = 1.0 / np.sqrt(1.0 + dr * dr)
        nrm = np.empty((k.size, 3))
        nrm[:, 0] = sp * inv
        nrm[:, 1] = -side * dr * inv
        nrm[:, 2] = -cp * inv
        return pts, nrm

    def nearest_slice(self, uw: np.ndarray, rho: np.ndarray, K: int = 3) -> np.ndarray:
        """Index of the slice nearest to the point (``uw``, ``rho``) of the profile plane, where
        ``uw = d + s`` is the side-local lateral coordinate in the wheelset frame."""
        s = uw - self.wheel.d
        i0 = np.searchsorted(self.s, s)
        cand = np.clip(i0[:, None] + np.arange(-K, K + 1)[None, :], 0, self.s.size - 1)
        d2 = (self.s[cand] - s[:, None]) ** 2 + (self.r[cand] - rho[:, None]) ** 2
        return cand[np.arange(s.size), np.argmin(d2, axis=1)]


@dataclass(frozen=True, eq=False)
class RailMesh:
    """Rail grid: profile nodes (u, z) with unit normals in the (u, z) plane; longitudinal step."""

    rail: PlacedRail
    h_lat: float
    h_x: float
    u: np.ndarray  # (nl,) side-local lateral coordinate, m
    z: np.ndarray  # (nl,) height, m
    nu: np.ndarray  # (nl,) u-component of the outward normal
    nz: np.ndarray  # (nl,) z-component of the outward normal

    @classmethod
    def build(cls, rail: PlacedRail, h_lat: float, h_x: float) -> RailMesh:
        us = np.linspace(rail.u_min, rail.u_max, 20000)
        u_top = float(us[np.argmax(rail.height(us))])
        u = _arc_grid(us, rail.height(us), u_top, h_lat)
        z = rail.height(u)
        sl = rail.slope(u)
        inv = 1.0 / np.sqrt(1.0 + sl * sl)
        return cls(rail=rail, h_lat=h_lat, h_x=h_x, u=u, z=z, nu=-sl * inv, nz=inv)

    @cached_property
    def arrays(self) -> RailArrays:
        """The grid as the compiled kernels take it."""
        u0, du, tab_z = self.rail.height_table
        return RailArrays(self.u, self.z, self.nu, self.nz, float(self.h_x), u0, du, tab_z,
                          float(self.rail.u_min), float(self.rail.u_max))

    def nearest_node(self, u: np.ndarray, z: np.ndarray, K: int = 3) -> np.ndarray:
        """Index of the profile node nearest to (u, z)."""
        i0 = np.searchsorted(self.u, u)
        cand = np.clip(i0[:, None] + np.arange(-K, K + 1)[None, :], 0, self.u.size - 1)
        d2 = (self.u[cand] - u[:, None]) ** 2 + (self.z[cand] - z[:, None]) ** 2
        return cand[np.arange(u.size), np.argmin(d2, axis=1)]


@dataclass
class Window:
    """The part of both meshes where contact can happen for one wheel at one pose.

    Wheel nodes are given by (slice ``k``, angle ``m``) with their wheelset-frame positions and
    normals; rail nodes by their track-frame positions and normals.
    """

    side: float
    k: np.ndarray
    m: np.ndarray
    body_pts: np.ndarray
    body_nrm: np.ndarray
    rail_pts: np.ndarray  # (n, 3) track frame
    rail_nrm: np.ndarray  # (n, 3) track frame

    @cached_property
    def arrays(self) -> WindowArrays:
        """The window as the compiled kernels take it."""
        return WindowArrays(float(self.side), self.k, self.body_pts, self.body_nrm,
                            self.rail_pts, self.rail_nrm)


def build_window(
    side: float,
    wmesh: WheelMesh,
    rmesh: RailMesh,
    centre: np.ndarray,
    R: np.ndarray,
    locus: tuple[np.ndarray, np.ndarray, np.ndarray],
    depth: float,
    with_rail: bool = True,
    full: bool = False,
) -> Window:
    """Window of wheel ``side`` around the rigid-contact pose (``centre``, ``R``).

    Parameters
    ----------
    locus : tuple of ndarray
        The rigid locus at this pose: sample profile coordinates ``s`` (m), locus angles
        (rad) and vertical gaps (m; +inf, or NaN: not over the rail), sampled every 0.1 mm;
        it is interpolated at the mesh slices (:func:`~lutmpi.contact.kernels.
        locus_at_slices`: window selection only, the interpolation error is a few nm of gap).
    depth : float
        Keep nodes whose vertical gap to the other surface is within ``depth`` of the minimum
        gap (m); slices are kept when their locus gap is. Finite (else ValueError).
    full : bool
        Take every slice over the rail and a wide band of angles (the reference "full mesh").
    """
    if not np.isfinite(depth):   # its angular half-widths would overflow an integer
        raise ValueError(f"window depth must be finite, got {depth!r} m")
    pose = Pose(centre, R)
    ls, lphi, lgap = locus
    if not full:
        n_nodes, k, m, pts, nrm, rp, rn = locus_window(
            side, ls, lphi, lgap, depth, wmesh.h_circ, wmesh.arrays, rmesh.arrays, pose,
            with_rail, MAX_WINDOW_NODES)
        _check_size(n_nodes, wmesh)
        return Window(side=side, k=k, m=m, body_pts=pts, body_nrm=nrm, rail_pts=rp, rail_nrm=rn)
    phi_star, gap_k = locus_at_slices(wmesh.s, ls, lphi, lgap)
    ks = np.nonzero(np.isfinite(gap_k))[0]
    half_arc = np.full(ks.size, 0.25 * wmesh.wheel.r0)
    mc = np.round(phi_star[ks] / wmesh.dphi).astype(int)
    mh = np.ceil(half_arc / wmesh.h_circ).astype(int)
    _check_size(int(np.sum(2 * mh + 1)), wmesh)
    k, m, pts, nrm, rp, rn = window_nodes(
        side, np.asarray(ks, dtype=np.int64), np.asarray(mc, dtype=np.int64),
        np.asarray(mh, dtype=np.int64), wmesh.arrays, rmesh.arrays, pose,
        np.min(gap_k) + depth, False, *wmesh.angles, with_rail)
    return Window(side=side, k=k, m=m, body_pts=pts, body_nrm=nrm, rail_pts=rp, rail_nrm=rn)


def _check_size(n_nodes: int, wmesh: WheelMesh) -> None:
    """A clear error where a window would hold more than :data:`MAX_WINDOW_NODES` wheel nodes
    (e.g. 0.001 mm meshes), not a MemoryError."""
    if n_nodes > MAX_WINDOW_NODES:
        raise GeometryError(
            f"the contact window would hold {n_nodes:.3g} wheel nodes (~{n_nodes * 100 / 1e9:.0f} "
            f"GB), more than {MAX_WINDOW_NODES:.0e}: mesh spacings {wmesh.h_lat * 1e3:g} mm "
            f"across x {wmesh.h_circ * 1e3:g} mm around the wheel are too fine; coarsen [mesh] "
            "(defaults 0.25 x 0.5 mm)")
