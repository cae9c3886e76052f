"""Contact-geometry providers for the wheelset dynamics: one protocol, three sources.

A provider answers one question: for an imposed lateral shift ``y`` (m) and yaw ``yaw`` (rad), where
does the wheelset sit (``z_g``, roll) and where are its contacts (points, normals, rolling radii,
contact angles, curvatures, at most two per wheel)? The dynamics never knows which source answered.

* :class:`TableProvider` -- the table's compiled, jump-aware lookup (the paper's off-line
  contact; :mod:`lutmpi.table.interp`): it never blends across a contact jump, and a pose outside
  the table or on a failed point is reported in :attr:`ContactGeometry.status`, never clipped.
* :class:`OnlineProvider` -- a full pose solve at every call (the paper's "on-line" contact).
* :class:`ConedWheelProvider` -- analytic coned wheels on knife-edge rails (Klingel's textbook
  case, and the oracle for the dynamics tests).

Layout of the per-contact arrays: ``(2, 2)`` = (side: 0 = left, 1 = right; slot: 0 = primary,
1 = second contact of a double contact), vectors a further ``(3,)`` (x, y, z in the track frame:
x along the track, y lateral to the LEFT, z up). A missing contact has ``active == False``.

The providers also return the slopes of ``z_g`` and roll with respect to ``y`` and ``yaw``
(one-sided differences with step ``h``): the dynamics needs them for the contact-point velocities
(the roll rate moves the contact point laterally by ``r0 * d(roll)/dt``) and for the gyroscopic
moment.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any, Protocol

import numba
import numpy as np

from lutmpi.equilibrium.result import SIDES
from lutmpi.table.schema import FIELDS, D

#: :attr:`ContactGeometry.status`: the pose is inside the table and converged
GEOMETRY_OK = 0
#: the pose lies outside the table (the geometry is the one at the nearest edge pose)
OUT_OF_TABLE = 1
#: the pose lies on a point whose solve failed (the geometry is the last good one)
FAILED_POINT = 2
GEOMETRY_STATUS = {GEOMETRY_OK: "ok", OUT_OF_TABLE: "outside the table",
                   FAILED_POINT: "on a failed table point"}


@dataclass(frozen=True)
class ContactGeometry:
    """Rigid contact geometry of the wheelset at one pose (SI, track frame).

    Attributes
    ----------
    y, yaw : float
        The imposed pose, m and rad.
    z_g, roll, x_g : float
        Dependent coordinates of the centre of mass: height above rail top (m), roll (rad),
        longitudinal shift (m).
    dz_dy, dz_dyaw, droll_dy, droll_dyaw : float
        Slopes of ``z_g`` (m/m, m/rad) and roll (rad/m, rad/rad).
    wheel_point : ndarray, shape (2, 2, 3)
        Contact points on the wheels, m.
    normal : ndarray, shape (2, 2, 3)
        Rail outward unit normals (from the rail into the wheel).
    rolling_radius, contact_angle : ndarray, shape (2, 2)
        m and rad (> 0 toward the flange).
    curv_wheel_rolling, curv_wheel_transverse, curv_rail_transverse : ndarray, shape (2, 2)
        Principal curvatures, 1/m (convex > 0).
    indentation : ndarray, shape (2, 2)
        Weight of each contact in its wheel's load (the pose solve's normal force, else its
        indentation); only the ratio within a wheel is used (the split of a double contact).
    active : ndarray of bool, shape (2, 2)
        Which contacts exist.
    status : int
        :data:`GEOMETRY_OK`, :data:`OUT_OF_TABLE` or :data:`FAILED_POINT` (table providers).
    piece : int
        Which side of the table's jumps answered (the number of jumps below y; 0 without jumps).
    """

    y: float
    yaw: float
    z_g: float
    roll: float
    x_g: float
    dz_dy: float
    dz_dyaw: float
    droll_dy: float
    droll_dyaw: float
    wheel_point: np.ndarray
    normal: np.ndarray
    rolling_radius: np.ndarray
    contact_angle: np.ndarray
    curv_wheel_rolling: np.ndarray
    curv_wheel_transverse: np.ndarray
    curv_rail_transverse: np.ndarray
    indentation: np.ndarray
    active: np.ndarray
    status: int = GEOMETRY_OK
    piece: int = 0

    @property
    def n_contacts(self) -> np.ndarray:
        """Contacts per wheel, shape (2,) [left, right]."""
        return self.active.sum(axis=1)

    def mirror(self) -> ContactGeometry:
        """The geometry of the mirrored pose (y, yaw) -> (-y, -yaw), reflected about y = 0."""
        flip = np.array([1.0, -1.0, 1.0])
        return ContactGeometry(
            y=-self.y, yaw=-self.yaw, z_g=self.z_g, roll=-self.roll, x_g=self.x_g,
            dz_dy=-self.dz_dy, dz_dyaw=-self.dz_dyaw, droll_dy=self.droll_dy,
            droll_dyaw=self.droll_dyaw, wheel_point=self.wheel_point[::-1] * flip,
            normal=self.normal[::-1] * flip, rolling_radius=self.rolling_radius[::-1],
            contact_angle=self.contact_angle[::-1],
            curv_wheel_rolling=self.curv_wheel_rolling[::-1],
            curv_wheel_transverse=self.curv_wheel_transverse[::-1],
            curv_rail_transverse=self.curv_rail_transverse[::-1],
            indentation=self.indentation[::-1], active=self.active[::-1], status=self.status,
            piece=self.piece)


#: the stored quantities the dynamics reads: the float schema fields that are
#: :class:`ContactGeometry` attributes, plus ``force`` (the split of a double contact's load);
#: derived from :data:`lutmpi.table.schema.FIELDS`, the only list of names
RECORD_NAMES = tuple(f.name for f in FIELDS if f.dtype.startswith("f") and (
    f.name in ContactGeometry.__dataclass_fields__ or f.name == D.force))


class ContactProvider(Protocol):
    """Anything that maps a pose (y, yaw) to its :class:`ContactGeometry`."""

    #: largest contact angle the provider can produce (the flange angle), rad
    flange_angle: float

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Contact geometry at lateral shift ``y`` (m) and yaw ``yaw`` (rad)."""
        ...


def geometry_from_records(y: float, yaw: float, rec: dict[str, np.ndarray], h_y: float,
                          h_yaw: float) -> ContactGeometry:
    """Build a :class:`ContactGeometry` from three stacked pose records.

    Parameters
    ----------
    y, yaw : float
        The pose, m and rad.
    rec : dict of ndarray
        :data:`RECORD_NAMES` (those present) with a leading axis of length 3: the poses
        ``(y, yaw)``, ``(y + h_y, yaw)`` and ``(y, yaw + h_yaw)``.
    h_y, h_yaw : float
        The steps, m and rad (may be negative).
    """
    z, roll = np.asarray(rec[D.z_g], float), np.asarray(rec[D.roll], float)
    wp = np.asarray(rec[D.wheel_point], float)[0]
    nrm = np.asarray(rec[D.normal], float)[0]
    rr = np.asarray(rec[D.rolling_radius], float)[0]
    ind = np.asarray(rec[D.indentation], float)[0]
    active = (np.isfinite(wp).all(axis=-1) & np.isfinite(nrm).all(axis=-1) & np.isfinite(rr)
              & np.isfinite(ind))

    def clean(a: np.ndarray, fill: float = 0.0) -> np.ndarray:
        return np.where(np.isfinite(a), a, fill)

    x_g = float(rec[D.x_g][0]) if D.x_g in rec and np.isfinite(rec[D.x_g][0]) else 0.0
    n = clean(nrm)
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where(norm > 0, n / np.where(norm > 0, norm, 1.0), 0.0)  # re-normalise after interp
    return ContactGeometry(
        y=float(y), yaw=float(yaw), z_g=float(z[0]), roll=float(roll[0]), x_g=x_g,
        dz_dy=float((z[1] - z[0]) / h_y), dz_dyaw=float((z[2] - z[0]) / h_yaw),
        droll_dy=float((roll[1] - roll[0]) / h_y), droll_dyaw=float((roll[2] - roll[0]) / h_yaw),
        wheel_point=clean(wp), normal=n, rolling_radius=clean(rr),
        contact_angle=clean(np.asarray(rec[D.contact_angle], float)[0]),
        curv_wheel_rolling=clean(np.asarray(rec[D.curv_wheel_rolling], float)[0]),
        curv_wheel_transverse=clean(np.asarray(rec[D.curv_wheel_transverse], float)[0]),
        curv_rail_transverse=clean(np.asarray(rec[D.curv_rail_transverse], float)[0]),
        indentation=_split_weights(rec, active), active=active)


def _split_weights(rec: dict[str, np.ndarray], active: np.ndarray) -> np.ndarray:
    """Weights that split a wheel's load between its contacts: the pose solve's normal forces
    (``force``) when stored, else the indentations (both are proportional to the contact force in
    the solve; a rigid ``reference`` solve has zero indentation but its forces)."""
    for name in (D.force, D.indentation):
        if name in rec:
            w = np.asarray(rec[name], float)[0]
            w = np.where(active & np.isfinite(w), np.maximum(w, 0.0), 0.0)
            if np.all(w.sum(axis=1)[active.any(axis=1)] > 0):
                return w
    return active.astype(float)


#: per-contact fields the compiled post-processing reads, in its index order
_PC_FIELDS = (D.rolling_radius, D.contact_angle, D.curv_wheel_rolling, D.curv_wheel_transverse,
              D.curv_rail_transverse, D.force, D.indentation)


@numba.njit(cache=True)
def _geometry_arrays(v, wp_i, nrm_i, pc_i):  # noqa: ANN001, ANN202
    """From a looked-up value vector ``v``: contact points, unit normals, the per-contact fields
    of :data:`_PC_FIELDS` (NaN -> 0), ``active`` and the load-split weights (as
    :func:`_split_weights`: forces, else indentations, else 1 per active contact). Index arrays:
    ``wp_i``, ``nrm_i`` (2, 2, 3), ``pc_i`` (7, 2, 2); -1 where a field is not stored."""
    wp = np.zeros((2, 2, 3))
    nrm = np.zeros((2, 2, 3))
    pc = np.zeros((7, 2, 2))
    active = np.zeros((2, 2), np.bool_)
    for a in range(2):
        for b in range(2):
            ok = pc_i[0, a, b] >= 0 and np.isfinite(v[pc_i[0, a, b]])
            norm = 0.0
            for c in range(3):
                x = v[wp_i[a, b, c]] if wp_i[a, b, c] >= 0 else np.nan
                n = v[nrm_i[a, b, c]] if nrm_i[a, b, c] >= 0 else np.nan
                ok = ok and np.isfinite(x) and np.isfinite(n)
                wp[a, b, c] = x
                nrm[a, b, c] = n
                norm += n * n
            active[a, b] = ok
            for c in range(3):
                if ok and norm > 0:
                    nrm[a, b, c] /= np.sqrt(norm)
                else:
                    nrm[a, b, c] = 0.0
                if not np.isfinite(wp[a, b, c]):
                    wp[a, b, c] = 0.0
            for f in range(7):
                x = v[pc_i[f, a, b]] if pc_i[f, a, b] >= 0 else np.nan
                pc[f, a, b] = x if np.isfinite(x) else 0.0
    weights = np.zeros((2, 2))
    for f in (5, 6):                                  # force, then indentation
        if pc_i[f, 0, 0] < 0:
            continue
        good = True
        for a in range(2):
            total = 0.0
            has = False
            for b in range(2):
                weights[a, b] = max(pc[f, a, b], 0.0) if active[a, b] else 0.0
                total += weights[a, b]
                has = has or active[a, b]
            if has and not total > 0:
                good = False
        if good:
            return wp, nrm, pc, active, weights
    for a in range(2):
        for b in range(2):
            weights[a, b] = 1.0 if active[a, b] else 0.0
    return wp, nrm, pc, active, weights


class TableProvider:
    """Contact geometry from a table's compiled, jump-aware lookup.

    One call of :func:`lutmpi.table.lookup.lookup_point` gives every stored quantity at the pose
    with its y and yaw slopes (the z_g / roll slopes the dynamics needs are the interpolant's
    analytic derivatives), which side of the jumps answered, and whether the pose is inside the
    table. The flange angle (Nadal's limit) is the table's ``wheel_flange_angle`` attribute,
    written at build time from the wheel profile.

    Parameters
    ----------
    table : lutmpi.table.Table
    method : str or None
        Contact method group of the table (``None``: the table's default).

    Attributes
    ----------
    bounds : tuple of float
        ``(y_min, y_max, yaw_min, yaw_max)`` of the table, m and rad.
    """

    def __init__(self, table: Any, method: str | None = None) -> None:
        from lutmpi.table.lookup import lookup_point

        self.table = table
        self.method = method or table.methods[0]
        ip = table.interpolator(self.method, quantities=RECORD_NAMES)
        self._args = ip.arrays
        self._lookup = lookup_point
        self.bounds = (float(ip.y_axis[0]), float(ip.y_axis[-1]), float(ip.yaw_axis[0]),
                       float(ip.yaw_axis[-1]))
        self.names = [n for n in RECORD_NAMES if n in ip.layout.slots]
        self._slot = {n: ip.layout.slots[n] for n in self.names}
        self._iz, self._ir = self._slot[D.z_g][0], self._slot[D.roll][0]
        self._ix = self._slot[D.x_g][0] if D.x_g in self._slot else -1
        self._wp_i = self._index(D.wheel_point, (2, 2, 3))
        self._nrm_i = self._index(D.normal, (2, 2, 3))
        self._pc_i = np.stack([self._index(n, (2, 2)) for n in _PC_FIELDS])
        angles = table.get(D.contact_angle, self.method) if D.contact_angle in self.names else 0.0
        self.flange_angle = max(float(np.nanmax(angles, initial=0.0)),
                                float(table.attribute("wheel_flange_angle")))
        q = ip.kv.shape[2]
        self._v, self._dy, self._dw = np.empty(q), np.empty(q), np.empty(q)
        self._tv, self._td = np.empty((8, q)), np.empty((8, q))
        self._last_good: ContactGeometry | None = None
        self.calls = 0

    def _index(self, name: str, shape: tuple[int, ...]) -> np.ndarray:
        """Positions of a field's values in the looked-up vector (-1: not stored)."""
        if name not in self._slot:
            return np.full(shape, -1, np.int64)
        off, suffix = self._slot[name]
        return (off + np.arange(int(np.prod(suffix, dtype=int)))).reshape(shape).astype(np.int64)

    def status(self, y: float, yaw: float) -> int:
        """:data:`GEOMETRY_OK`, :data:`OUT_OF_TABLE` or :data:`FAILED_POINT` at a pose (the
        lookup alone, no geometry)."""
        if self.lookup(y, yaw)[0] & 1:
            return OUT_OF_TABLE
        return GEOMETRY_OK if math.isfinite(self._v[self._iz]) else FAILED_POINT

    def lookup(self, y: float, yaw: float) -> tuple[int, int, float]:
        """The compiled lookup alone: fills the value / slope buffers, returns ``(flags, piece,
        jump_distance)`` (:meth:`lutmpi.table.interp.Interpolator.evaluate`)."""
        return self._lookup(self._args, float(y), float(yaw), self._v, self._dy, self._dw,
                            self._tv, self._td)

    def inside(self, y: float, yaw: float) -> float:
        """Signed margin to the table's edge (> 0 inside), m-equivalent (yaw scaled by the
        table's y/yaw extent ratio): the event function of leaving the table."""
        y0, y1, a0, a1 = self.bounds
        scale = (y1 - y0) / (a1 - a0) if a1 > a0 else 1.0
        return min(y - y0, y1 - y, (yaw - a0) * scale, (a1 - yaw) * scale)

    def piece(self, y: float, yaw: float) -> int:
        """Which side of the jumps a pose is on (-1 outside the table)."""
        return int(self.lookup(y, yaw)[1])

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Geometry at ``(y, yaw)``. Outside the table: the geometry at the nearest edge pose
        with ``status = OUT_OF_TABLE``; on a failed point: the last good geometry with
        ``status = FAILED_POINT`` (the integrator's trial steps stay finite; the simulation
        stops at the crossing, located as an event)."""
        self.calls += 1
        y, yaw = float(y), float(yaw)
        flags, piece, _ = self.lookup(y, yaw)
        status = GEOMETRY_OK
        if flags & 1:
            y0, y1, a0, a1 = self.bounds
            flags, piece, _ = self.lookup(min(max(y, y0), y1), min(max(yaw, a0), a1))
            status = OUT_OF_TABLE
        v = self._v
        z_g = float(v[self._slot[D.z_g][0]])
        if not math.isfinite(z_g):
            if self._last_good is None:        # NaN geometry, no contact: data, not a number
                return self._geometry(y, yaw, FAILED_POINT, int(piece))
            return replace(self._last_good, y=y, yaw=yaw, status=FAILED_POINT, piece=piece)
        geom = self._geometry(y, yaw, status, int(piece))
        if status == GEOMETRY_OK:
            self._last_good = geom
        return geom

    def _geometry(self, y: float, yaw: float, status: int, piece: int) -> ContactGeometry:
        v, dy, dw = self._v, self._dy, self._dw
        wp, nrm, pc, active, weights = _geometry_arrays(v, self._wp_i, self._nrm_i, self._pc_i)
        iz, ir, ix = self._iz, self._ir, self._ix
        x_g = float(v[ix]) if ix >= 0 else 0.0
        dz_dyaw, droll_dyaw = float(dw[iz]), float(dw[ir])
        return ContactGeometry(
            y=y, yaw=yaw, z_g=float(v[iz]), roll=float(v[ir]),
            x_g=x_g if math.isfinite(x_g) else 0.0, dz_dy=float(dy[iz]),
            dz_dyaw=dz_dyaw if math.isfinite(dz_dyaw) else 0.0, droll_dy=float(dy[ir]),
            droll_dyaw=droll_dyaw if math.isfinite(droll_dyaw) else 0.0, wheel_point=wp,
            normal=nrm, rolling_radius=pc[0], contact_angle=pc[1], curv_wheel_rolling=pc[2],
            curv_wheel_transverse=pc[3], curv_rail_transverse=pc[4], indentation=weights,
            active=active, status=status, piece=piece)


class OnlineProvider:
    """Contact geometry from a pose solve at every call (``solve_pose`` three times: the pose and
    its two neighbours for the slopes).

    Parameters
    ----------
    scene : object
        :class:`lutmpi.scene.Scene`.
    method : str
        Contact method passed to :func:`lutmpi.pose.solve.solve_pose`.
    h_y, h_yaw : float
        Difference steps, m and rad. Not smaller: a pose is solved to ~0.1 um, so a 1 um step
        gives slopes with O(1) noise on the mesh-based methods (``load_centre``: d z_g / dy off
        by 50x at h = 1e-6); 0.1 mm is still 5x finer than the paper's table cells.
    """

    def __init__(self, scene: Any, method: str = "reference", h_y: float = 1e-4,
                 h_yaw: float = 1e-4, flange_angle: float | None = None) -> None:
        from lutmpi.pose.solve import solve_pose
        from lutmpi.table.compute import pose_to_record
        from lutmpi.table.schema import FIELDS

        self._fields = FIELDS
        self.scene, self.method = scene, method
        self.h_y, self.h_yaw = h_y, h_yaw
        if flange_angle is None:
            from lutmpi.table.jumps import wheelset_flange_angle

            flange_angle = wheelset_flange_angle(scene.side(name).wheel.profile
                                                 for name in SIDES)
        self.flange_angle = flange_angle
        self._solve, self._record = solve_pose, pose_to_record
        self.calls = 0
        self.failures = 0

    def _one(self, y: float, yaw: float) -> dict[str, np.ndarray]:
        res = self._solve(self.scene, y, yaw, self.method)
        if not res.success:
            self.failures += 1
        return self._record(res, self._fields)

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Solve the pose and its two neighbours."""
        self.calls += 1
        recs = [self._one(y, yaw), self._one(y + self.h_y, yaw), self._one(y, yaw + self.h_yaw)]
        stacked = {k: np.stack([np.asarray(r[k], float) for r in recs]) for k in RECORD_NAMES
                   if k in recs[0]}
        return geometry_from_records(y, yaw, stacked, self.h_y, self.h_yaw)


class ConedWheelProvider:
    """Coned wheels (conicity ``lam``) on knife-edge rails at ``y = ±b``: a closed form.

    Geometry (small angles, exact to first order in y and yaw): roll ``atan(k*y)`` with ``k =
    lam/(b - lam*r0)`` and rolling radii ``r0 ± lam*y*b/(b - lam*r0)`` (left larger for y > 0):
    the roll moves each contact along its cone by ``r0*roll`` beyond the shift ``y``, and both
    wheels touching their rails makes ``r_L - r_R = 2*b*roll`` (the knife edges at ``±b``; the
    exact relation is ``tan(roll) = lam*y/(b - lam*z_g)``), ``z_g = r0``, contact points on the
    rails
    ``(x_c, ±b, 0)`` with the longitudinal shift ``x_c = ∓(b - lam*r)*tan(yaw)`` of a yawed
    cone (the lowest point of the cone along the rail line: the yaw carries the wheel's centre
    to ``x = ∓b sin(yaw)``, and the cone's slope moves the lowest point back by ``lam r`` per
    radian; the tables' own ``wheel_point`` x, −7.6 mm on the left at yaw 0.01 rad on 1:20),
    normals the cone normals ``(0, ∓sin γ, cos γ)`` with ``γ = atan(lam) ± roll``. The lateral
    components of the normal loads at these points give Wickens' destabilising yaw
    gravitational stiffness ``-W lam (b - lam r0)``: a free wheelset on cones is unstable at
    every speed.

    Parameters
    ----------
    r0 : float
        Nominal rolling radius, m.
    lam : float
        Conicity (tan of the cone angle).
    b : float
        Half the lateral distance between the contact points, m.
    gravitational : bool
        ``False`` gives Klingel's kinematic case: vertical normals, no roll, no contact-point
        shift, hence no gravitational stiffness and no spin from the cone angle.
    rail_crown_radius : float
        Transverse radius of the rail head used only for the Hertz ellipse, m (a knife edge has
        no finite ellipse; UIC60's crown radius 0.3 m by default).
    offset : float
        Lateral pose of pure rolling, m: the geometry is the centred one moved by ``offset``
        (the left wheel smaller than the right by ``2 b k offset`` at ``y = 0``: two wheels of
        different diameters). 0 by default.
    """

    def __init__(self, r0: float = 0.46, lam: float = 0.2, b: float = 0.75,
                 gravitational: bool = True, rail_crown_radius: float = 0.3,
                 offset: float = 0.0) -> None:
        self.r0, self.lam, self.b, self.offset = float(r0), float(lam), float(b), float(offset)
        self.gravitational = gravitational
        self.rail_crown_radius = float(rail_crown_radius)
        self.flange_angle = math.atan(lam)
        self.calls = 0

    def _pose(self, y: float, yaw: float) -> dict[str, np.ndarray]:
        r0, lam, b = self.r0, self.lam, self.b
        y = y - self.offset
        if self.gravitational:
            k = lam / (b - lam * r0)
            roll = math.atan(k * y)
            r = np.array([r0 + b * k * y, r0 - b * k * y])
            delta = math.atan(lam)
            gamma = np.array([delta + roll, delta - roll])
            x_c = np.array([-1.0, 1.0]) * (b - lam * r) * math.tan(yaw)
        else:   # Klingel: the radii r0 +- lam*y of the shift alone, no roll
            r = np.array([r0 + lam * y, r0 - lam * y])
            roll, gamma, x_c = 0.0, np.zeros(2), np.zeros(2)
        sgn = np.array([-1.0, 1.0])   # the normal leans toward the track centre
        wp = np.full((2, 2, 3), np.nan)
        nrm = np.full((2, 2, 3), np.nan)
        # with roll, the rails are level and the tilted axle gives the radii; without (Klingel's
        # idealisation) the radii r0 +- lam*y need the contact points at z_g - r
        z_c = np.zeros(2) if self.gravitational else r0 - r
        wp[:, 0] = np.column_stack([x_c, [b, -b], z_c])
        nrm[:, 0] = np.column_stack([np.zeros(2), sgn * np.sin(gamma), np.cos(gamma)])
        per = np.full((2, 2), np.nan)

        def slot0(v: np.ndarray) -> np.ndarray:
            out = per.copy()
            out[:, 0] = v
            return out

        cos_d = math.cos(math.atan(lam)) if self.gravitational else 1.0
        return {D.z_g: np.float64(r0), D.roll: np.float64(roll), D.x_g: np.float64(0.0),
                D.wheel_point: wp, D.normal: nrm, D.indentation: slot0(np.ones(2)),
                D.rolling_radius: slot0(r), D.contact_angle: slot0(gamma),
                D.force: slot0(np.ones(2)),
                D.curv_wheel_rolling: slot0(cos_d / r),
                D.curv_wheel_transverse: slot0(np.zeros(2)),
                D.curv_rail_transverse: slot0(np.full(2, 1.0 / self.rail_crown_radius))}

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Closed-form geometry at ``(y, yaw)``."""
        self.calls += 1
        h = 1e-7
        recs = [self._pose(y, yaw), self._pose(y + h, yaw), self._pose(y, yaw + h)]
        stacked = {k: np.stack([np.asarray(r[k]) for r in recs]) for k in RECORD_NAMES}
        return geometry_from_records(y, yaw, stacked, h, h)


__all__ = ["ContactGeometry", "ContactProvider", "TableProvider", "OnlineProvider",
           "ConedWheelProvider", "geometry_from_records", "RECORD_NAMES", "SIDES", "GEOMETRY_OK",
           "OUT_OF_TABLE", "FAILED_POINT", "GEOMETRY_STATUS"]
