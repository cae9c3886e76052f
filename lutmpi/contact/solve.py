"""One pose, one call: ``solve_pose(scene, y, yaw, method)`` -> :class:`PoseResult`.

Steps (§4.3): the rigid contact from the locus method gives the starting pose ``q0`` and tells where
contact can happen; the window of each mesh is built there; the equilibrium with the k_c iteration
runs on the windowed meshes with the chosen contact-point method. The ``reference`` method returns
the rigid locus solution itself. Non-convergence is returned as a status, never raised.
"""

from __future__ import annotations

import time

import numpy as np

from lutmpi.contact.locus import RigidSolution
from lutmpi.contact.mesh import Window, build_window
from lutmpi.contact.methods import (
    NEEDS_RAIL_NODES,
    MeshContact,
    wheel_contacts,
    wheel_contacts_compiled,
)
from lutmpi.contact.stiffness import flange_kc_scale
from lutmpi.equilibrium.result import (
    CONVERGED,
    NO_CONTACT,
    PROFILE_END,
    STATUS,
    WINDOW,
    ContactResult,
    PoseResult,
)
from lutmpi.equilibrium.solver import ContactForce, Equilibrium
from lutmpi.geometry.pose import wheelset_rotation

SIDE_SIGN = {"left": 1.0, "right": -1.0}
# d(indentation)/d(approach) of each method: the load centre's C of eq. (7) is the mean
# separation of the two caps, half the peak interpenetration for paraboloidal caps
INDENTATION_RATE = {"max_distance": 1.0, "max_normal_distance": 1.0, "load_centre": 0.5}
METHOD_NAMES = ("max_distance", "max_normal_distance", "load_centre", "reference")


def solve_pose(
    scene, y: float, yaw: float, method: str | None = None, *, full_mesh: bool = False
) -> PoseResult:
    """Solve the wheelset pose for imposed lateral shift ``y`` (m) and ``yaw`` (rad).

    Parameters
    ----------
    scene : lutmpi.scene.Scene
    method : str, optional
        ``max_distance``, ``max_normal_distance``, ``load_centre`` or ``reference``
        (default: the scene's).
    full_mesh : bool
        Use the whole meshes instead of the contact window (for checking the window).
    """
    method = method or scene.settings.method
    if method not in METHOD_NAMES:
        raise ValueError(f"unknown method {method!r}; valid: {list(METHOD_NAMES)}")
    t0 = time.process_time()
    rigid = scene.locus.solve(y, yaw)
    if not rigid.success:
        res = PoseResult(
            y=y,
            yaw=yaw,
            method=method,
            status=NO_CONTACT,
            message=f"{STATUS[NO_CONTACT]} ({rigid.message})",
            nit=rigid.nit,
        )
    elif method == "reference":
        res = _reference_result(scene, rigid, method)
    else:
        res = _mesh_result(scene, rigid, method, full_mesh)
    res.n_roots = rigid.n_roots
    if rigid.success and rigid.at_end:
        # the data do not reach the contact: the numbers are kept, the status says why
        res.success, res.status = False, PROFILE_END
        res.message = f"{STATUS[PROFILE_END]} ({_end_text(rigid)})"
    res.time = time.process_time() - t0
    return res


def _end_text(rigid: RigidSolution) -> str:
    ends = [f"{name} wheel s = {c.s * 1e3:.2f} mm" for name, cs in rigid.contacts.items()
            for c in cs if c.at_end]
    return "contact at the end of the data: " + ", ".join(ends)


# -- shared per-contact outputs ---------------------------------------------------------------
def _contact_record(
    sd,
    side: float,
    wheel_point: np.ndarray,
    rail_point: np.ndarray,
    normal: np.ndarray,
    C: float,
    s: float,
    kc: float,
) -> ContactResult:
    wheel, rail = sd.wheel, sd.rail
    u_r = side * rail_point[1]
    dr = float(wheel.dr(s))
    r = float(wheel.radius(s))
    return ContactResult(
        wheel_point=np.asarray(wheel_point, float),
        rail_point=np.asarray(rail_point, float),
        normal=np.asarray(normal, float),
        indentation=float(C),
        kc=float(kc),
        force=float(kc * C) if np.isfinite(kc) else float("nan"),
        rolling_radius=r,
        contact_angle=float(np.arctan2(-side * normal[1], normal[2])),
        wheel_s=float(s),
        rail_v=float(rail.profile_coordinate(u_r, rail_point[2])),
        wheel_curv_rolling=1.0 / (r * np.sqrt(1.0 + dr * dr)),
        wheel_curv_transverse=float(wheel.convex_curvature(s)),
        rail_curv_transverse=float(rail.convex_curvature(np.clip(u_r, rail.u_min, rail.u_max))),
    )


def _reference_result(scene, rigid: RigidSolution, method: str) -> PoseResult:
    res = PoseResult(
        y=rigid.y,
        yaw=rigid.yaw,
        method=method,
        x_g=0.0,
        z_g=rigid.z_g,
        roll=rigid.roll,
        pitch=0.0,
        success=True,
        status=CONVERGED,
        message=STATUS[CONVERGED],
        nit=rigid.nit,
        indentation=0.0,
    )
    for name, side in SIDE_SIGN.items():
        sd = scene.side(name)
        rail = sd.rail
        for c in rigid.contacts[name]:
            u = float(np.clip(c.u, rail.u_min, rail.u_max))
            sl = float(rail.slope(u))
            n = np.array([0.0, side * -sl, 1.0]) / np.hypot(1.0, sl)
            rp = np.array([c.point[0], side * u, float(rail.height(u))])
            res.contacts[name].append(
                _contact_record(sd, side, c.point, rp, n, max(-c.gap, 0.0), c.s, np.nan)
            )
    return res


# -- mesh methods ---------------------------------------------------------------------------
def _flange_factor(scene, name: str, s: float) -> float:
    """k_c factor of §4.5 at profile coordinate ``s`` of wheel ``name`` (1 on the tread)."""
    st = scene.settings
    if not st.flange or s >= 0.0:  # the flange is on the s < 0 side of the tape circle
        return 1.0
    sd = scene.side(name)
    r = sd.flange_radius(s)
    return float(flange_kc_scale(r, sd.flange_base_radius, sd.flange_tip_radius, st.chi))


def _rigid_angle(scene, name: str, c) -> float:
    """Contact angle of a rigid (locus) contact from the rail slope at its lateral position."""
    rail = scene.side(name).rail
    u = float(np.clip(c.u, rail.u_min, rail.u_max))
    return float(np.arctan(rail.slope(u)))


def _windows(
    scene, rigid: RigidSolution, method: str, depth: float, full: bool
) -> dict[str, Window]:
    centre = np.array([0.0, rigid.y, rigid.z_g])
    R = wheelset_rotation(rigid.yaw, rigid.roll)
    out = {}
    for name, side in SIDE_SIGN.items():
        wm, rm = scene.side(name).wheel_mesh, scene.side(name).rail_mesh
        # the locus at the rigid pose, sampled every 0.1 mm, interpolated at the mesh slices
        # (window selection only: the interpolation error is a few nm of gap)
        loc = rigid.loci[name]
        phi = np.interp(wm.s, loc.s, loc.phi)
        gap = np.interp(wm.s, loc.s, np.where(np.isfinite(loc.gap), loc.gap, 1.0))
        gap[(wm.s < loc.s[0]) | (wm.s > loc.s[-1])] = np.inf
        gap[gap >= 1.0] = np.inf
        out[name] = build_window(
            side, wm, rm, centre, R, phi, gap, depth,
            with_rail=method in NEEDS_RAIL_NODES, full=full,
        )
    return out


def _mesh_result(scene, rigid: RigidSolution, method: str, full: bool) -> PoseResult:
    eq = scene.equilibrium
    f_min = min(
        (_flange_factor(scene, name, c.s) for name, cs in rigid.contacts.items() for c in cs),
        default=1.0,
    )
    # window depth: the margin plus twice the vertical approach of the softest contact at the
    # first k_c (normal approach W / (k f) over cos of the steepest contact angle)
    n_z = min((abs(np.cos(_rigid_angle(scene, name, c)))
               for name, cs in rigid.contacts.items() for c in cs), default=1.0)
    depth = scene.settings.window_gap + 2.0 * eq.load / (eq.kc0 * f_min * max(n_z, 0.2))
    for _ in range(3):
        wins = _windows(scene, rigid, method, depth, full or not scene.settings.window)
        solver = Equilibrium(
            _evaluator(scene, wins, method, rigid),
            rigid.y,
            rigid.yaw,
            np.array([rigid.z_g, rigid.roll]),
            eq,
            lever=scene.lever,
            fmin=f_min,
            rate=INDENTATION_RATE[method],
            nz_min=n_z,
        )
        out = solver.solve()
        # how far the wheels moved vertically at their contacts: the nodes left out of the
        # window had a rigid gap above ``depth``, so none of them can be in contact unless a
        # wheel moved that far
        dz, dr = out.q[0] - rigid.z_g, out.q[1] - rigid.roll
        moved = max(abs(dz + sd * scene.side(name).wheel.d * dr)
                    for name, sd in SIDE_SIGN.items()) + 0.1 * abs(dr)
        if full or not scene.settings.window or moved < depth:
            break
        depth *= 4.0  # the pose left the window's depth: widen it and solve again
    else:
        out.success, out.status, out.message = False, WINDOW, STATUS[WINDOW]
    return _pose_from_equilibrium(scene, rigid, method, out)


def _evaluator(scene, wins: dict[str, Window], method: str, rigid: RigidSolution):
    mc = scene.settings.max_contacts

    def evaluate(q: np.ndarray) -> dict[str, list[ContactForce]]:
        centre = np.array([0.0, rigid.y, q[0]])
        R = wheelset_rotation(rigid.yaw, q[1])
        out = {}
        for name, win in wins.items():
            wm, rm = scene.side(name).wheel_mesh, scene.side(name).rail_mesh
            if scene.settings.compiled:
                cs = wheel_contacts_compiled(method, win, wm, rm, centre, R, mc)
            else:
                cs = wheel_contacts(method, win, wm, rm, centre, R, mc)
            out[name] = [
                ContactForce(
                    point=c.wheel_point,
                    normal=-c.n_wheel,
                    indentation=c.indentation,
                    factor=_flange_factor(scene, name, c.s),
                    data=c,
                    nodes=c.n_wheel_nodes,
                    rate=INDENTATION_RATE[method],
                )
                for c in cs
            ]
        return out

    return evaluate


def _pose_from_equilibrium(scene, rigid: RigidSolution, method: str, out) -> PoseResult:
    eq = scene.equilibrium
    z, roll = float(out.q[0]), float(out.q[1])
    G = np.array([0.0, rigid.y, z])
    if out.q_extrapolated is not None:
        z, roll = float(out.q_extrapolated[0]), float(out.q_extrapolated[1])
    F = np.zeros(3)
    M = np.zeros(3)
    res = PoseResult(
        y=rigid.y,
        yaw=rigid.yaw,
        method=method,
        z_g=z,
        roll=roll,
        success=out.success,
        status=out.status,
        message=out.message,
        nit=out.nit,
        kc=out.kc,
        indentation=out.indentation,
    )
    for name, side in SIDE_SIGN.items():
        for cf in out.contacts.get(name, []):
            c: MeshContact = cf.data
            k = out.kc * cf.factor
            f = k * cf.indentation * cf.normal
            F += f
            M += np.cross(cf.point - G, f)
            res.contacts[name].append(
                _contact_record(
                    scene.side(name), side, c.wheel_point, c.rail_point, cf.normal,
                    c.indentation, c.s, k
                )
            )
    res.x_g = float(-F[0] / eq.k_el)  # eq. (1): the x spring carries the longitudinal force
    res.pitch = float(-M[1] / eq.k_rot)  # eq. (1): the pitch spring carries M_y
    return res
