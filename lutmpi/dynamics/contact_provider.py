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


def _steps(y: float, yaw: float, y_axis: np.ndarray | None, yaw_axis: np.ndarray | None,
           h_y: float, h_yaw: float) -> tuple[float, float]:
    """One-sided steps that stay inside the table range (step backwards at the upper edge)."""
    if y_axis is not None and y + h_y > y_axis[-1]:
        h_y = -h_y
    if yaw_axis is not None and yaw + h_yaw > yaw_axis[-1]:
        h_yaw = -h_yaw
    return h_y, h_yaw


class TableProvider:
    """Contact geometry by bilinear interpolation in a lookup table.

    Parameters
    ----------
    table : object
        An open table with ``interp(y, yaw, method=None) -> dict[name, ndarray]`` (vectorised over
        points) and, optionally, axes ``y`` and ``yaw`` (clip range) -- :class:`lutmpi.table.Table`.
    method : str or None
        Contact method group of the table (``None``: the table's default).
    h_y, h_yaw : float
        Difference steps for the slopes, m and rad. Inside one cell of a bilinear table the slope
        does not depend on the step, so a small step gives the cell's own slope.
    """

    def __init__(self, table: Any, method: str | None = None, h_y: float = 1e-6,
                 h_yaw: float = 1e-6) -> None:
        self.table = table
        self.method = method
        self.h_y, self.h_yaw = h_y, h_yaw
        self.y_axis = np.asarray(getattr(table, "y", None)) if hasattr(table, "y") else None
        self.yaw_axis = np.asarray(getattr(table, "yaw", None)) if hasattr(table, "yaw") else None
        self.flange_angle = self._flange_angle()
        self.calls = 0
        stored = getattr(table, "quantities", None)
        self.names = [k for k in RECORD_NAMES if stored is None or k in stored]
        self._packed = self._pack()

    def _pack(self) -> tuple[np.ndarray, list[tuple[str, tuple[int, ...], int]]] | None:
        """All needed quantities as one (ny, nyaw, K) array: one bilinear step per evaluation
        instead of one per quantity (``Table.interp`` loops over quantities)."""
        if not (hasattr(self.table, "get") and self.y_axis is not None and self.y_axis.size > 1
                and self.yaw_axis is not None and self.yaw_axis.size > 1):
            return None
        cols, layout, k = [], [], 0
        for name in self.names:
            arr = np.asarray(self.table.get(name, self.method), float)
            suffix = arr.shape[2:]
            flat = arr.reshape(arr.shape[:2] + (-1,))
            cols.append(flat)
            layout.append((name, suffix, k))
            k += flat.shape[2]
        return np.concatenate(cols, axis=2), layout

    def _interp_packed(self, ys: np.ndarray, yaws: np.ndarray) -> dict[str, np.ndarray]:
        data, layout = self._packed  # type: ignore[misc]
        ya, wa = self.y_axis, self.yaw_axis
        i = np.clip(np.searchsorted(ya, ys, side="right") - 1, 0, ya.size - 2)
        j = np.clip(np.searchsorted(wa, yaws, side="right") - 1, 0, wa.size - 2)
        u = ((ys - ya[i]) / (ya[i + 1] - ya[i]))[:, None]
        v = ((yaws - wa[j]) / (wa[j + 1] - wa[j]))[:, None]
        # NaN corners (a missing second contact) make the result NaN: the contact is inactive
        val = ((1 - u) * (1 - v) * data[i, j] + u * (1 - v) * data[i + 1, j]
               + (1 - u) * v * data[i, j + 1] + u * v * data[i + 1, j + 1])
        out = {}
        for name, suffix, k in layout:
            size = int(np.prod(suffix)) if suffix else 1
            out[name] = val[:, k:k + size].reshape((-1,) + suffix)
        return out

    def _flange_angle(self) -> float:
        try:
            data = self.table.get("contact_angle", self.method)
            return float(np.nanmax(data))
        except Exception:  # noqa: BLE001 - an optional accessor; fall back to S1002's 70 deg
            return math.radians(70.0)

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        """Interpolate the table at ``(y, yaw)`` and at two nearby points for the slopes."""
        if self.y_axis is not None and self.y_axis.size:
            y = float(np.clip(y, self.y_axis[0], self.y_axis[-1]))
        if self.yaw_axis is not None and self.yaw_axis.size:
            yaw = float(np.clip(yaw, self.yaw_axis[0], self.yaw_axis[-1]))
        h_y, h_yaw = _steps(y, yaw, self.y_axis, self.yaw_axis, self.h_y, self.h_yaw)
        ys = np.array([y, y + h_y, y])
        yaws = np.array([yaw, yaw, yaw + h_yaw])
        self.calls += 1
        if self._packed is not None:
            rec = self._interp_packed(ys, yaws)
        else:
            rec = self.table.interp(ys, yaws, method=self.method, quantities=self.names)
        return geometry_from_records(y, yaw, rec, h_y, h_yaw)


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
        Difference steps, m and rad.
    """

    def __init__(self, scene: Any, method: str = "reference", h_y: float = 1e-6,
                 h_yaw: float = 1e-6, flange_angle: float = math.radians(70.0)) -> None:
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
