"""Contact-geometry providers for the wheelset dynamics: one protocol, three sources.

A provider answers one question: for an imposed lateral shift ``y`` (m) and yaw ``yaw`` (rad), where
does the wheelset sit (``z_g``, roll) and where are its contacts (points, normals, rolling radii,
contact angles, curvatures, at most two per wheel)? The dynamics never knows which source answered.

* :class:`TableProvider` -- bilinear interpolation in a lookup table (the paper's off-line contact).
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

import bisect
import math
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np

from lutmpi.equilibrium.result import SIDES

# the table/pose-record names the dynamics reads (see lutmpi.table.schema)
RECORD_NAMES = ("z_g", "roll", "x_g", "wheel_point", "normal", "indentation", "rolling_radius",
                "contact_angle", "curv_wheel_rolling", "curv_wheel_transverse",
                "curv_rail_transverse", "force")


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
            indentation=self.indentation[::-1], active=self.active[::-1])


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
        :data:`RECORD_NAMES` with a leading axis of length 3: the poses ``(y, yaw)``,
        ``(y + h_y, yaw)`` and ``(y, yaw + h_yaw)``.
    h_y, h_yaw : float
        The steps, m and rad (may be negative).
    """
    z, roll = np.asarray(rec["z_g"], float), np.asarray(rec["roll"], float)
    wp = np.asarray(rec["wheel_point"], float)[0]
    nrm = np.asarray(rec["normal"], float)[0]
    rr = np.asarray(rec["rolling_radius"], float)[0]
    ind = np.asarray(rec["indentation"], float)[0]
    active = (np.isfinite(wp).all(axis=-1) & np.isfinite(nrm).all(axis=-1) & np.isfinite(rr)
              & np.isfinite(ind))

    def clean(a: np.ndarray, fill: float = 0.0) -> np.ndarray:
        return np.where(np.isfinite(a), a, fill)

    x_g = float(rec["x_g"][0]) if "x_g" in rec and np.isfinite(rec["x_g"][0]) else 0.0
    n = clean(nrm)
    norm = np.linalg.norm(n, axis=-1, keepdims=True)
    n = np.where(norm > 0, n / np.where(norm > 0, norm, 1.0), 0.0)  # re-normalise after interp
    return ContactGeometry(
        y=float(y), yaw=float(yaw), z_g=float(z[0]), roll=float(roll[0]), x_g=x_g,
        dz_dy=float((z[1] - z[0]) / h_y), dz_dyaw=float((z[2] - z[0]) / h_yaw),
        droll_dy=float((roll[1] - roll[0]) / h_y), droll_dyaw=float((roll[2] - roll[0]) / h_yaw),
        wheel_point=clean(wp), normal=n, rolling_radius=clean(rr),
        contact_angle=clean(np.asarray(rec["contact_angle"], float)[0]),
        curv_wheel_rolling=clean(np.asarray(rec["curv_wheel_rolling"], float)[0]),
        curv_wheel_transverse=clean(np.asarray(rec["curv_wheel_transverse"], float)[0]),
        curv_rail_transverse=clean(np.asarray(rec["curv_rail_transverse"], float)[0]),
        indentation=_split_weights(rec, active), active=active)


def _split_weights(rec: dict[str, np.ndarray], active: np.ndarray) -> np.ndarray:
    """Weights that split a wheel's load between its contacts: the pose solve's normal forces
    (``force``) when stored, else the indentations (both are proportional to the contact force in
    the solve; a rigid ``reference`` solve has zero indentation but its forces)."""
    for name in ("force", "indentation"):
        if name in rec:
            w = np.asarray(rec[name], float)[0]
            w = np.where(active & np.isfinite(w), np.maximum(w, 0.0), 0.0)
            if np.all(w.sum(axis=1)[active.any(axis=1)] > 0):
                return w
    return active.astype(float)


def wheel_flange_angle(cfg: Any) -> float:
    """Steepest angle of the wheel profile's flange flank (rad), between the flange tip and the
    tape circle, for the wheel of config ``cfg``."""
    from lutmpi.scene import load_scene_profiles

    wheel, _ = load_scene_profiles(cfg)
    s = np.linspace(wheel.y_min, 0.0, 4000)
    tip = s[int(np.argmax(wheel.z_at(s)))]
    flank = np.linspace(tip, 0.0, 4000)
    return float(np.arctan(np.max(-wheel.slope(flank))))


class TableProvider:
    """Contact geometry by bilinear interpolation in a lookup table.

    The hot path is one small matrix product: every quantity the dynamics reads is packed at
    construction into one ``(ny, nyaw, 2K)`` array -- the K values with NaN replaced by 0, then K
    NaN indicators -- so an evaluation is: locate the cell (``bisect`` on Python lists), four
    bilinear weights, ``w @ corners`` for all 2K columns at once, and the z_g/roll slopes as the
    cell's analytic derivatives (exactly what a difference step inside the cell gives). A value
    whose stencil gives a NaN node a non-zero weight is NaN, as in :meth:`lutmpi.table.Table.interp`
    (the NaN indicator interpolates to > 0 exactly then).

    Parameters
    ----------
    table : object
        An open table with ``get(name, method)``, axes ``y``, ``yaw`` (increasing, at least two
        nodes each) and ``quantities`` -- :class:`lutmpi.table.Table`.
    method : str or None
        Contact method group of the table (``None``: the table's default).
    """

    def __init__(self, table: Any, method: str | None = None) -> None:
        self.table = table
        self.method = method
        self.y_axis = np.asarray(table.y, float)
        self.yaw_axis = np.asarray(table.yaw, float)
        if self.y_axis.size < 2 or self.yaw_axis.size < 2:
            raise ValueError(f"TableProvider needs at least 2 x 2 grid nodes, got "
                             f"{self.y_axis.size} x {self.yaw_axis.size}")
        self._ylist, self._wlist = self.y_axis.tolist(), self.yaw_axis.tolist()
        stored = getattr(table, "quantities", None)
        self.names = [k for k in RECORD_NAMES if stored is None or k in stored]
        self.flange_angle = self._flange_angle()
        self.calls = 0
        self._data, self._fields, self._f = self._pack()
        self._k = self._data.shape[2] // 2

    def _pack(self) -> tuple[np.ndarray, dict[str, slice], int]:
        """``(ny, nyaw, 2K)``: cleaned values then NaN indicators, K = 4 F + 3.

        The first ``4 F`` columns are the per-contact fields as a ``(2, 2, F)`` block (side,
        slot, field: wheel point xyz, normal xyz, then the scalar fields, then an "inactive"
        indicator, 1 where a node lacks any of the fields that define a contact); then z_g, roll,
        x_g. Returns the array, ``name -> slice of the field axis`` and F.
        """
        get = lambda name: np.asarray(self.table.get(name, self.method), float)  # noqa: E731
        ny, na = self.y_axis.size, self.yaw_axis.size
        per = [n for n in self.names if n not in _SCALARS]
        blocks, fields, f = [], {}, 0
        for name in per:
            arr = get(name).reshape(ny, na, 2, 2, -1)
            fields[name] = slice(f, f + arr.shape[-1])
            blocks.append(arr)
            f += arr.shape[-1]
        pc = np.concatenate(blocks, axis=-1)
        lacking = np.zeros((ny, na, 2, 2), bool)
        for name in _DEFINING:
            lacking |= ~np.isfinite(pc[..., fields[name]]).all(axis=-1)
        fields["_inactive"] = slice(f, f + 1)
        pc = np.concatenate([pc, lacking[..., None] * 1.0], axis=-1)
        f += 1
        scal = np.stack([get(n) if n in self.names else np.zeros((ny, na)) for n in _SCALARS], -1)
        v = np.concatenate([pc.reshape(ny, na, -1), scal], axis=2)
        nan = ~np.isfinite(v)
        data = np.concatenate([np.where(nan, 0.0, v), nan * 1.0], axis=2)
        return np.ascontiguousarray(data), fields, f

    def _flange_angle(self) -> float:
        """The flange angle for Nadal's limit: the steepest flank of the table's wheel profile
        (from the stored config), not the largest contact angle the table happens to reach."""
        table_max = (float(np.nanmax(self.table.get("contact_angle", self.method)))
                     if "contact_angle" in self.names else 0.0)
        try:
            import tomllib

            from lutmpi.config import config_from_dict

            cfg = config_from_dict(tomllib.loads(self.table.config_toml))
            return max(table_max, wheel_flange_angle(cfg))
        except Exception:  # noqa: BLE001 - a table whose profile file moved: S1002's 70 deg
            return max(table_max, math.radians(70.0))

    def _cell(self, y: float, yaw: float) -> tuple[int, int, float, float, float, float]:
        ya, wa = self._ylist, self._wlist
        i = min(bisect.bisect_right(ya, y) - 1, len(ya) - 2)
        j = min(bisect.bisect_right(wa, yaw) - 1, len(wa) - 2)
        dy, dw = ya[i + 1] - ya[i], wa[j + 1] - wa[j]
        return i, j, (y - ya[i]) / dy, (yaw - wa[j]) / dw, dy, dw

    def interp_vector(self, y: float, yaw: float) -> np.ndarray:
        """One bilinear step for everything at a pose inside the grid: rows (value, d/dy per m,
        d/dyaw per rad) of the packed columns (values, then NaN indicators), shape ``(3, 2K)``."""
        i, j, u, v, dy, dw = self._cell(y, yaw)
        c = self._data[i:i + 2, j:j + 2].reshape(4, -1)     # corners 00, 01, 10, 11
        w = np.array([[(1 - u) * (1 - v), (1 - u) * v, u * (1 - v), u * v],
                      [-(1 - v) / dy, -v / dy, (1 - v) / dy, v / dy],
                      [-(1 - u) / dw, (1 - u) / dw, -u / dw, u / dw]])
        return w @ c

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Interpolate the table at ``(y, yaw)`` (clipped to the grid)."""
        self.calls += 1
        ya, wa = self._ylist, self._wlist
        y = min(max(float(y), ya[0]), ya[-1])
        yaw = min(max(float(yaw), wa[0]), wa[-1])
        out = self.interp_vector(y, yaw)
        k, nf = self._k, 4 * self._f
        flag = out[0, k:]
        clean = np.where(flag > 0.0, 0.0, out[0, :k])
        pc = clean[:nf].reshape(2, 2, self._f)
        fs = self._fields
        active = pc[..., fs["_inactive"].start] <= 0.0
        n = pc[..., fs["normal"]]
        norm = np.sqrt(np.einsum("ijk,ijk->ij", n, n))[..., None]
        n = np.where(norm > 0, n / np.where(norm > 0, norm, 1.0), 0.0)
        z_g, roll, x_g = out[0, nf:nf + 3].tolist()
        zf, rf = flag[nf:nf + 2].tolist()
        dz_dy, droll_dy = out[1, nf:nf + 2].tolist()
        dz_dyaw, droll_dyaw = out[2, nf:nf + 2].tolist()
        return ContactGeometry(
            y=y, yaw=yaw, z_g=z_g if zf <= 0 else math.nan, roll=roll if rf <= 0 else math.nan,
            x_g=x_g if flag[nf + 2] <= 0 else 0.0, dz_dy=dz_dy, dz_dyaw=dz_dyaw,
            droll_dy=droll_dy, droll_dyaw=droll_dyaw, wheel_point=pc[..., fs["wheel_point"]],
            normal=n, rolling_radius=pc[..., fs["rolling_radius"].start],
            contact_angle=self._field(pc, "contact_angle"),
            curv_wheel_rolling=self._field(pc, "curv_wheel_rolling"),
            curv_wheel_transverse=self._field(pc, "curv_wheel_transverse"),
            curv_rail_transverse=self._field(pc, "curv_rail_transverse"),
            indentation=self._weights(pc, active), active=active)

    def _field(self, pc: np.ndarray, name: str) -> np.ndarray:
        sl = self._fields.get(name)
        return pc[..., sl.start] if sl is not None else np.zeros((2, 2))

    def _weights(self, pc: np.ndarray, active: np.ndarray) -> np.ndarray:
        """:func:`_split_weights` on the packed block (force, else indentation, else 1); the
        NaN entries are already 0 in ``pc``."""
        has = active.any(axis=1).tolist()
        for name in ("force", "indentation"):
            if name in self._fields:
                w = np.where(active, np.maximum(pc[..., self._fields[name].start], 0.0), 0.0)
                s = w.sum(axis=1).tolist()
                if all(s[i] > 0 for i in (0, 1) if has[i]):
                    return w
        return active.astype(float)


#: scalar (per pose) table quantities, packed after the per-contact block
_SCALARS = ("z_g", "roll", "x_g")
#: the per-contact fields whose absence means "no contact" (as in :func:`geometry_from_records`)
_DEFINING = ("wheel_point", "normal", "rolling_radius", "indentation")


class OnlineProvider:
    """Contact geometry from a pose solve at every call (``solve_pose`` three times: the pose and
    its two neighbours for the slopes).

    Parameters
    ----------
    scene : object
        :class:`lutmpi.scene.Scene`.
    method : str
        Contact method passed to :func:`lutmpi.contact.solve.solve_pose`.
    h_y, h_yaw : float
        Difference steps, m and rad. Not smaller: a pose is solved to ~0.1 um, so a 1 um step
        gives slopes with O(1) noise on the mesh-based methods (``load_centre``: d z_g / dy off
        by 50x at h = 1e-6); 0.1 mm is still 5x finer than the paper's table cells.
    """

    def __init__(self, scene: Any, method: str = "reference", h_y: float = 1e-4,
                 h_yaw: float = 1e-4, flange_angle: float = math.radians(70.0)) -> None:
        from lutmpi.contact.solve import solve_pose
        from lutmpi.table.compute import pose_to_record
        from lutmpi.table.schema import FIELDS

        self._fields = FIELDS
        self.scene, self.method = scene, method
        self.h_y, self.h_yaw = h_y, h_yaw
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

    Geometry (small angles, exact to first order in y and yaw): rolling radii ``r0 ± lam*y``
    (left larger for y > 0), roll ``atan(lam*y/b)``, ``z_g = r0``, contact points on the rails
    ``(x_c, ±b, 0)`` with the longitudinal shift ``x_c = ±lam*r*tan(yaw)`` of a yawed cone (the
    lowest point of the cone along the rail line), normals the cone normals ``(0, ∓sin γ, cos γ)``
    with ``γ = atan(lam) ± roll``.

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
    """

    def __init__(self, r0: float = 0.46, lam: float = 0.2, b: float = 0.75,
                 gravitational: bool = True, rail_crown_radius: float = 0.3) -> None:
        self.r0, self.lam, self.b = float(r0), float(lam), float(b)
        self.gravitational = gravitational
        self.rail_crown_radius = float(rail_crown_radius)
        self.flange_angle = math.atan(lam)
        self.calls = 0

    def _pose(self, y: float, yaw: float) -> dict[str, np.ndarray]:
        r0, lam, b = self.r0, self.lam, self.b
        r = np.array([r0 + lam * y, r0 - lam * y])
        if self.gravitational:
            roll = math.atan(lam * y / b)
            delta = math.atan(lam)
            gamma = np.array([delta + roll, delta - roll])
            x_c = np.array([lam, -lam]) * r * math.tan(yaw)
        else:
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
        return {"z_g": np.float64(r0), "roll": np.float64(roll), "x_g": np.float64(0.0),
                "wheel_point": wp, "normal": nrm, "indentation": slot0(np.ones(2)),
                "rolling_radius": slot0(r), "contact_angle": slot0(gamma),
                "force": slot0(np.ones(2)),
                "curv_wheel_rolling": slot0(cos_d / r),
                "curv_wheel_transverse": slot0(np.zeros(2)),
                "curv_rail_transverse": slot0(np.full(2, 1.0 / self.rail_crown_radius))}

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Closed-form geometry at ``(y, yaw)``."""
        self.calls += 1
        h = 1e-7
        recs = [self._pose(y, yaw), self._pose(y + h, yaw), self._pose(y, yaw + h)]
        stacked = {k: np.stack([np.asarray(r[k]) for r in recs]) for k in RECORD_NAMES}
        return geometry_from_records(y, yaw, stacked, h, h)


__all__ = ["ContactGeometry", "ContactProvider", "TableProvider", "OnlineProvider",
           "ConedWheelProvider", "geometry_from_records", "RECORD_NAMES", "SIDES"]
