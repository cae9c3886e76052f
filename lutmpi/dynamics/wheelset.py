"""A single wheelset on tangent track: the pure right-hand side (paper §6).

Model
-----
States ``x = (y, yaw, vy, vyaw, spin)``: lateral shift y (m), yaw (rad), their rates, and the spin
perturbation ``spin = Omega - V/r0`` (rad/s) of the rotation speed Omega about the axle. The forward
speed V (m/s) is imposed (a constant-speed run, as in the paper: the longitudinal creep forces
would otherwise brake the free wheelset).

**Vertical and roll are constrained, not integrated.** The table is a rigid-contact constraint:
``z = z_g(y, yaw)`` and ``roll = roll(y, yaw)`` (the paper: "the dependent coordinates, consistent
with the contact constraints, are obtained through interpolation from the lookup table"). The
normal forces are then the constraint forces: the two wheel loads Q_L, Q_R follow from vertical
and roll equilibrium with the vertical load (``vertical_load + m g`` on the centre of mass), the
tangential forces' vertical and roll contributions and the gyroscopic roll moment
``-I_yy Omega dyaw/dt``; the inertia terms ``m d2z/dt2`` and ``I_xx d2roll/dt2`` are neglected
(the vertical/roll contact modes are at ~100 Hz, hunting is at 1-5 Hz). Within a wheel, a double
contact's load is split in the ratio of the two indentations of the pose solve (the table's own
split). The alternative, a Hertz spring on the penetration ``z_g - z``, would reintroduce the
100 Hz modes (a stiff system for nothing) and depend on a penetration the table was built to keep
below 0.01 mm. The constraint choice has one consequence to know: a wheel cannot lift; if the roll
balance asks for a negative load, that wheel is unloaded (``Q = 0``), the other carries the
vertical load, and ``lift`` is reported.

**Gravitational stiffness** is not a parameter: it is the lateral component of the normal forces,
whose directions come from the geometry (the rail normals, tilted by the roll).

**Tangential forces** from Kalker's linear theory (:mod:`lutmpi.dynamics.creep`), Hertz ellipse
from the stored curvatures and the normal force (:func:`lutmpi.contact.stiffness.hertz_ellipse`),
saturated to μN (Shen-Hedrick-Elkins). Creepages at every contact point P from the velocity of the
wheel's material point ``v_P = v_G + omega x (P - G)`` (the rail is at rest), in the contact frame
``t1`` = track x projected on the tangent plane, ``t2 = n x t1``, ``n`` the rail outward normal:
``xi = v_P.t1 / V``, ``eta = v_P.t2 / V``, ``phi = omega.n / V`` (1/m). V in the denominator is
regularised as ``sqrt(V^2 + v_floor^2)`` so that all creep forces vanish as V -> 0 at rest.

No primary suspension (the paper's case): the wheelset is free on the track, held laterally only by
the gravitational stiffness and in yaw only by the longitudinal creep forces (and the small yaw
gravitational stiffness). A free wheelset is therefore the least stable running gear there is:
its critical speed is low and set by the gravitational stiffness against the inertia (Wickens),
and the spin creep (C23) cancels part of that stiffness.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, replace
from functools import lru_cache
from typing import Any, ClassVar

import numpy as np

from lutmpi.contact.stiffness import contact_modulus, hertz_geometry
from lutmpi.dynamics.contact_provider import ContactGeometry, ContactProvider
from lutmpi.dynamics.creep import kalker_coefficients, linear_creep_forces

STATE_NAMES = ("y", "yaw", "vy", "vyaw", "spin")
_EX, _EZ = np.array([1.0, 0.0, 0.0]), np.array([0.0, 0.0, 1.0])


@dataclass(frozen=True)
class WheelsetParams:
    """Wheelset data; defaults are the paper's Table 2 and §6 (SI units).

    Attributes
    ----------
    mass : float
        Wheelset mass, kg (1595).
    I_xx, I_yy, I_zz : float
        Roll, spin (axle) and yaw moments of inertia, kg m^2 (935, 174, 935).
    mu : float
        Friction coefficient (0.2).
    vertical_load : float
        Vertical force applied on the centre of mass, N (1e5), in addition to the weight.
    gravity : float
        m/s^2; 0 drops the weight.
    young, poisson : float
        Young's modulus (Pa) and Poisson's ratio of wheel and rail (from the table's config).
    r0 : float
        Nominal rolling radius, m (from the table's config).
    saturation : str
        ``"shen_hedrick_elkins"``, ``"cutoff"`` or ``"none"`` (pure linear Kalker).
    creep_speed_floor : float
        v_floor of the creepage denominator, m/s.
    min_curvature_ratio : float
        The lateral relative curvature is clipped to at least this fraction of the rolling one
        (a conformal or concave-convex contact has no Hertz ellipse).
    gyroscopic : bool
        Include the gyroscopic moments ``I_yy Omega`` x (roll rate, yaw rate).
    """

    mass: float = 1595.0
    I_xx: float = 935.0
    I_yy: float = 174.0
    I_zz: float = 935.0
    mu: float = 0.2
    vertical_load: float = 1.0e5
    gravity: float = 9.81
    young: float = 206.0e9
    poisson: float = 0.3
    r0: float = 0.46
    saturation: str = "shen_hedrick_elkins"
    creep_speed_floor: float = 0.01
    min_curvature_ratio: float = 0.02
    gyroscopic: bool = True

    #: field -> SI unit of the numbers (``"1"`` dimensionless; the two switches have none),
    #: for files that store the parameters (``lutmpi simulate``'s ``params_units``)
    UNITS: ClassVar[dict[str, str]] = {
        "mass": "kg", "I_xx": "kg m^2", "I_yy": "kg m^2", "I_zz": "kg m^2", "mu": "1",
        "vertical_load": "N", "gravity": "m/s^2", "young": "Pa", "poisson": "1", "r0": "m",
        "creep_speed_floor": "m/s", "min_curvature_ratio": "1"}

    @property
    def shear(self) -> float:
        """Shear modulus G, Pa."""
        return self.young / (2.0 * (1.0 + self.poisson))

    @property
    def total_load(self) -> float:
        """Vertical force the contacts carry in equilibrium, N."""
        return self.vertical_load + self.mass * self.gravity

    def with_(self, **changes: Any) -> WheelsetParams:
        """A copy with some fields changed."""
        return replace(self, **changes)

    @classmethod
    def from_config(cls, cfg: Any, **overrides: Any) -> WheelsetParams:
        """E, ν, r0 (and the vertical load) from a :class:`lutmpi.config.model.Config`."""
        kw = dict(young=cfg.material.young_GPa * 1e9, poisson=cfg.material.poisson,
                  r0=0.5 * (cfg.wheel.side("left").nominal_radius_m
                            + cfg.wheel.side("right").nominal_radius_m),
                  vertical_load=cfg.equilibrium.vertical_load_N)
        kw.update(overrides)
        return cls(**kw)

    @classmethod
    def from_toml_text(cls, text: str, **overrides: Any) -> WheelsetParams:
        """E, ν, r0, vertical load from a resolved config TOML (a table's ``config_toml``)."""
        data = tomllib.loads(text)
        kw: dict[str, Any] = {}
        if "young_GPa" in data.get("material", {}):
            kw["young"] = float(data["material"]["young_GPa"]) * 1e9
        if "poisson" in data.get("material", {}):
            kw["poisson"] = float(data["material"]["poisson"])
        if "nominal_radius_mm" in data.get("wheel", {}):
            kw["r0"] = float(data["wheel"]["nominal_radius_mm"]) * 1e-3
        if "vertical_load_N" in data.get("equilibrium", {}):
            kw["vertical_load"] = float(data["equilibrium"]["vertical_load_N"])
        kw.update(overrides)
        return cls(**kw)


@dataclass(frozen=True)
class ContactForces:
    """Everything the contacts do to the wheelset at one instant (track frame, SI).

    Attributes
    ----------
    normal_force : ndarray, shape (2, 2)
        Normal force magnitude per side x slot, N (0 for a missing contact).
    tangential : ndarray, shape (2, 2, 3)
        Creep force vector on the wheel, N.
    spin_moment : ndarray, shape (2, 2)
        Spin moment about the contact normal, N m.
    creepage : ndarray, shape (2, 2, 3)
        (xi, eta, phi [1/m]).
    semi_axes : ndarray, shape (2, 2, 2)
        Hertz semi-axes (rolling, lateral), m.
    wheel_force : ndarray, shape (2, 3)
        Total force of each rail on its wheel, N.
    force, moment : ndarray, shape (3,)
        Resultant contact force (N) and moment about the centre of mass (N m).
    lift : bool
        A wheel load came out negative and was set to zero.
    """

    normal_force: np.ndarray
    tangential: np.ndarray
    spin_moment: np.ndarray
    creepage: np.ndarray
    semi_axes: np.ndarray
    wheel_force: np.ndarray
    force: np.ndarray
    moment: np.ndarray
    lift: bool

    @property
    def y_over_q(self) -> np.ndarray:
        """Derailment quotient Y/Q per wheel [left, right], Y positive toward the outside of the
        track (the flange pushing its rail outward), Q the vertical wheel load."""
        y_out = np.array([-self.wheel_force[0, 1], self.wheel_force[1, 1]])
        q = self.wheel_force[:, 2]
        return np.where(q > 0, y_out / np.where(q > 0, q, 1.0), 0.0)


@lru_cache(maxsize=8)
def _kalker_lookup(nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Kalker's C11..C33 sampled on ln(a/b) once per ν (kalker_coefficients is scalar and slow)."""
    q = np.linspace(-math.log(60.0), math.log(60.0), 721)
    table = np.array([kalker_coefficients(math.exp(v), 1.0, nu) for v in q])
    return q, table


def kalker_fast(a: np.ndarray, b: np.ndarray, nu: float) -> tuple[np.ndarray, ...]:
    """Vectorised :func:`lutmpi.dynamics.creep.kalker_coefficients` (interpolated in ln(a/b))."""
    q, table = _kalker_lookup(float(nu))
    x = np.log(np.asarray(a, float) / np.asarray(b, float))
    return tuple(np.interp(x, q, table[:, i]) for i in range(4))


def wheelset_axes(yaw: float, roll: float) -> tuple[np.ndarray, np.ndarray]:
    """Axle unit vector ``a = Rz(yaw) Rx(roll) e_y`` and the roll axis ``Rz(yaw) e_x``."""
    cy, sy, cr, sr = math.cos(yaw), math.sin(yaw), math.cos(roll), math.sin(roll)
    return np.array([-sy * cr, cy * cr, sr]), np.array([cy, sy, 0.0])


def _kinematics(state: np.ndarray, speed: float, params: WheelsetParams,
                geom: ContactGeometry) -> dict[str, Any]:
    y, yaw, vy, vyaw, spin = (float(v) for v in state)
    omega_axle = speed / params.r0 + spin
    roll_rate = geom.droll_dy * vy + geom.droll_dyaw * vyaw
    z_rate = geom.dz_dy * vy + geom.dz_dyaw * vyaw
    axle, roll_axis = wheelset_axes(yaw, geom.roll)
    omega = vyaw * _EZ + roll_rate * roll_axis + omega_axle * axle
    centre = np.array([geom.x_g, y, geom.z_g])
    v_centre = np.array([speed, vy, z_rate])
    return dict(omega_axle=omega_axle, roll_rate=roll_rate, axle=axle, omega=omega,
                centre=centre, v_centre=v_centre, vyaw=vyaw)


def _contact_frames(normals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """t1 (track x projected on the tangent plane) and t2 = n x t1, shape (k, 3) each."""
    t1 = _EX - normals[:, :1] * normals
    t1 /= np.linalg.norm(t1, axis=1, keepdims=True)
    return t1, _cross(normals, t1)


def _wheel_loads(cols: np.ndarray, moms: np.ndarray, side: np.ndarray, w: np.ndarray,
                 rhs: np.ndarray) -> tuple[np.ndarray, bool]:
    """Solve vertical + roll equilibrium for the wheel loads Q = (Q_L, Q_R).

    ``cols`` (k, 3) normals, ``moms`` (k, 3) r x n, ``side`` (k,) 0/1, ``w`` (k,) split weights,
    ``rhs`` = (vertical force to carry, roll moment to supply).
    """
    A = np.zeros((2, 2))
    for s in (0, 1):
        m = side == s
        A[0, s] = np.sum(w[m] * cols[m, 2])
        A[1, s] = np.sum(w[m] * moms[m, 0])
    present = [s for s in (0, 1) if np.any(side == s)]
    q = np.zeros(2)
    if len(present) == 2:
        try:
            q = np.linalg.solve(A, rhs)
        except np.linalg.LinAlgError:
            q = np.full(2, rhs[0] / max(A[0].sum(), 1e-12))
    if len(present) == 1 or np.any(q < 0):
        s = present[0] if len(present) == 1 else int(np.argmax(q))
        q = np.zeros(2)
        q[s] = rhs[0] / A[0, s]
        return np.maximum(q, 0.0), True
    return q, False


@lru_cache(maxsize=1)
def _hertz_lookup() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """g (minor/major axis ratio) and E(e) of Hertz's problem sampled on ln(B/A) >= 0, once."""
    q = np.linspace(0.0, math.log(1e4), 801)
    rows = np.array([hertz_geometry(1.0, math.exp(v))[:3] for v in q])
    return q, rows[:, 0], rows[:, 2]


def hertz_fast(curv_long: np.ndarray, curv_lat: np.ndarray, load: np.ndarray, E: float,
               nu: float) -> tuple[np.ndarray, np.ndarray]:
    """Vectorised :func:`lutmpi.contact.stiffness.hertz_ellipse` (interpolated in ln(B/A)).

    Parameters
    ----------
    curv_long, curv_lat : ndarray
        Sums of the principal curvatures of wheel and rail in the rolling and lateral
        directions, 1/m (> 0).
    load : ndarray
        Normal force, N (> 0).
    E, nu : float
        Young's modulus (Pa) and Poisson's ratio.

    Returns
    -------
    a, b : ndarray
        Semi-axes in the rolling and lateral directions, m.
    """
    A, B = 0.5 * np.asarray(curv_long, float), 0.5 * np.asarray(curv_lat, float)
    q, gs, es = _hertz_lookup()
    x = np.abs(np.log(B / A))
    g, e_int = np.interp(x, q, gs), np.interp(x, q, es)
    # Johnson (1985) §4.2, as in hertz_ellipse: b_min = (3 N g E(e) / (2 pi E* (A + B)))^(1/3)
    b_min = np.cbrt(3.0 * load * g * e_int / (2.0 * np.pi * contact_modulus(E, nu) * (A + B)))
    a_maj = b_min / g
    major_rolling = A <= B
    return np.where(major_rolling, a_maj, b_min), np.where(major_rolling, b_min, a_maj)


def _cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """Row-wise cross product of (k, 3) arrays (np.cross is slow for tiny arrays)."""
    return np.stack([u[..., 1] * v[..., 2] - u[..., 2] * v[..., 1],
                     u[..., 2] * v[..., 0] - u[..., 0] * v[..., 2],
                     u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]], axis=-1)


def _ellipses(geom: ContactGeometry, idx: tuple[np.ndarray, np.ndarray], load: np.ndarray,
              params: WheelsetParams) -> np.ndarray:
    """Hertz semi-axes (rolling, lateral) per active contact, shape (k, 2); 0 where unloaded."""
    out = np.zeros((load.size, 2))
    ok = load > 0.0
    if not np.any(ok):
        return out
    kl = np.maximum(geom.curv_wheel_rolling[idx][ok], 1e-6)
    kt = geom.curv_wheel_transverse[idx][ok] + geom.curv_rail_transverse[idx][ok]
    kt = np.maximum(kt, params.min_curvature_ratio * kl)
    a, b = hertz_fast(kl, kt, load[ok], params.young, params.poisson)
    out[ok, 0], out[ok, 1] = a, b
    return out


def contact_forces(state: np.ndarray, speed: float, params: WheelsetParams,
                   geom: ContactGeometry, passes: int = 2) -> ContactForces:
    """Normal and creep forces of all contacts for a state on a given contact geometry.

    Parameters
    ----------
    state : ndarray, shape (5,)
        ``(y, yaw, vy, vyaw, spin)`` (m, rad, m/s, rad/s, rad/s).
    speed : float
        Forward speed V, m/s.
    params : WheelsetParams
    geom : ContactGeometry
        Geometry at ``(y, yaw)`` from a provider.
    passes : int
        Fixed-point passes between the wheel loads and the creep forces (whose vertical and roll
        components change the loads); 2 is converged to well below the creep-law accuracy.

    Returns
    -------
    ContactForces
    """
    kin = _kinematics(state, speed, params, geom)
    idx = np.nonzero(geom.active)
    n = geom.normal[idx]
    r = geom.wheel_point[idx] - kin["centre"]
    side = idx[0]
    v = kin["v_centre"] + _cross(kin["omega"], r)
    t1, t2 = _contact_frames(n)
    v_ref = math.hypot(speed, params.creep_speed_floor)
    creep = np.column_stack([np.sum(v * t1, axis=1),
                             np.sum(v * t2, axis=1), n @ kin["omega"]]) / v_ref
    ind = geom.indentation[idx]
    w = np.zeros(side.size)
    for s in (0, 1):
        m = side == s
        tot = ind[m].sum()
        w[m] = ind[m] / tot if tot > 0 else 1.0 / max(m.sum(), 1)
    moms = _cross(r, n)
    gyro_roll = -params.I_yy * kin["omega_axle"] * kin["vyaw"] if params.gyroscopic else 0.0
    tang = np.zeros((side.size, 3))
    mz = np.zeros(side.size)
    axes = np.zeros((side.size, 2))
    load = np.zeros(side.size)
    lift = False
    for _ in range(max(passes, 1)):
        rhs = np.array([params.total_load - tang[:, 2].sum(),
                        gyro_roll - _cross(r, tang)[:, 0].sum()])
        q, lift = _wheel_loads(n, moms, side, w, rhs)
        load = q[side] * w
        axes = _ellipses(geom, idx, load, params)
        tang, mz = _creep(creep, axes, load, t1, t2, params)
    return _assemble(geom, idx, load, tang, mz, creep, axes, n, r, lift)


def _creep(creep: np.ndarray, axes: np.ndarray, load: np.ndarray, t1: np.ndarray, t2: np.ndarray,
           params: WheelsetParams) -> tuple[np.ndarray, np.ndarray]:
    """Kalker linear creep forces (vectors on the wheel) and spin moments, saturated to μN."""
    ok = load > 0.0
    tang = np.zeros((load.size, 3))
    mz = np.zeros(load.size)
    if not np.any(ok):
        return tang, mz
    a, b = axes[ok, 0], axes[ok, 1]
    C = kalker_fast(a, b, params.poisson)
    sat = params.saturation if params.saturation != "none" else "cutoff"
    mu = params.mu if params.saturation != "none" else 1e30   # no saturation
    fx, fy, m = linear_creep_forces((creep[ok, 0], creep[ok, 1], creep[ok, 2]), a, b,
                                    params.shear, C, load[ok], mu, sat)
    tang[ok] = fx[:, None] * t1[ok] + fy[:, None] * t2[ok]
    mz[ok] = m
    return tang, mz


def _assemble(geom: ContactGeometry, idx: tuple[np.ndarray, np.ndarray], load: np.ndarray,
              tang: np.ndarray, mz: np.ndarray, creep: np.ndarray, axes: np.ndarray,
              n: np.ndarray, r: np.ndarray, lift: bool) -> ContactForces:
    f_each = load[:, None] * n + tang
    moment = np.sum(_cross(r, f_each), axis=0) + np.sum(mz[:, None] * n, axis=0)
    shape = geom.active.shape
    nf, sm = np.zeros(shape), np.zeros(shape)
    tg, cr, ax = np.zeros(shape + (3,)), np.zeros(shape + (3,)), np.zeros(shape + (2,))
    nf[idx], sm[idx], tg[idx], cr[idx], ax[idx] = load, mz, tang, creep, axes
    wheel = np.zeros((2, 3))
    np.add.at(wheel, idx[0], f_each)
    return ContactForces(normal_force=nf, tangential=tg, spin_moment=sm, creepage=cr,
                         semi_axes=ax, wheel_force=wheel, force=f_each.sum(axis=0),
                         moment=moment, lift=lift)


def accelerations(state: np.ndarray, speed: float, params: WheelsetParams, geom: ContactGeometry,
                  forces: ContactForces) -> np.ndarray:
    """Time derivative of the state from the contact forces (Newton-Euler, small angles).

    ``m y'' = F_y``; ``I_zz yaw'' = M_z - I_yy Omega roll'`` (gyroscopic);
    ``I_yy Omega' = M . axle``. Returns ``(vy, vyaw, y'', yaw'', Omega')``.
    """
    kin = _kinematics(state, speed, params, geom)
    gyro = params.I_yy * kin["omega_axle"] * kin["roll_rate"] if params.gyroscopic else 0.0
    return np.array([state[2], state[3], forces.force[1] / params.mass,
                     (forces.moment[2] - gyro) / params.I_zz,
                     float(forces.moment @ kin["axle"]) / params.I_yy])


def wheelset_rhs(t: float, state: np.ndarray, speed: float, params: WheelsetParams,
                 provider: ContactProvider) -> np.ndarray:
    """The right-hand side ``dx/dt = f(t, x)`` for :func:`scipy.integrate.solve_ivp`.

    Parameters
    ----------
    t : float
        Time, s (the model is autonomous).
    state : ndarray, shape (5,)
        ``(y, yaw, vy, vyaw, spin)``.
    speed : float
        Forward speed V, m/s.
    params : WheelsetParams
    provider : ContactProvider
        Source of the contact geometry (table, on-line solve, or coned wheels).

    Returns
    -------
    ndarray, shape (5,)
    """
    geom = provider.evaluate(float(state[0]), float(state[1]))
    return accelerations(state, speed, params, geom, contact_forces(state, speed, params, geom))


__all__ = ["STATE_NAMES", "WheelsetParams", "ContactForces", "contact_forces", "accelerations",
           "wheelset_rhs", "kalker_fast", "hertz_fast", "wheelset_axes"]
