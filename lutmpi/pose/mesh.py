"""The pose pipeline of the mesh methods (§4.3): from the rigid contact, the window of each
wheel, the equilibrium with the k_c iteration on the windowed meshes using the method's
contact stage, and the pose result. Shared by every :class:`~lutmpi.contact.methods.MeshMethod`.
"""

from __future__ import annotations

import logging
import math
import time

import numpy as np

from lutmpi.contact.locus import LocusSolver, RigidSolution
from lutmpi.contact.mesh import Window, build_window
from lutmpi.contact.records import SIDE_SIGN, contact_records
from lutmpi.contact.rigid_kernels import rotation
from lutmpi.contact.stiffness import check_flange, flange_factor_at
from lutmpi.equilibrium.result import MAX_ITER, STATUS, TIME_BUDGET, WINDOW, PoseResult
from lutmpi.equilibrium.solver import ContactForce, Equilibrium
from lutmpi.errors import GeometryError
from lutmpi.pose.newton import CompiledNewton, contact_force

log = logging.getLogger(__name__)


def flange_factor(scene, name: str, s: float) -> float:
    """k_c factor of §4.5 at profile coordinate ``s`` of wheel ``name`` (1 on the tread):
    :func:`~lutmpi.contact.stiffness.flange_factor_at` with the wheel's flange radii, validated
    on the flange (:func:`~lutmpi.contact.stiffness.check_flange`)."""
    st = scene.settings
    sd = scene.side(name)
    if st.flange and s < 0.0:
        check_flange(sd.flange_base_radius, sd.flange_tip_radius, st.chi)
    return float(flange_factor_at(float(s), bool(st.flange), sd.samp.s, sd.samp.r,
                                  float(sd.flange_base_radius), float(sd.flange_tip_radius),
                                  float(st.chi)))


def _rigid_angle(scene, name: str, c) -> float:
    """Contact angle of a rigid (locus) contact from the rail slope at its lateral position."""
    rail = scene.side(name).rail
    u = min(max(float(c.u), rail.u_min), rail.u_max)
    return float(np.arctan(rail.slope(u)))


def windows(scene, rigid: RigidSolution, method, depth: float, full: bool) -> dict[str, Window]:
    """The window of each wheel at the rigid pose, ``depth`` (m) deep."""
    centre = np.array([0.0, rigid.y, rigid.z_g])
    R = rotation(rigid.yaw, rigid.roll)
    out = {}
    for name, side in SIDE_SIGN.items():
        wm, rm = scene.side(name).wheel_mesh, scene.side(name).rail_mesh
        loc = rigid.loci[name]   # the locus at the rigid pose, sampled every 0.1 mm
        out[name] = build_window(side, wm, rm, centre, R, (loc.s, loc.phi, loc.gap), depth,
                                 with_rail=method.rail_nodes, full=full)
    return out


def solve_mesh_pose(scene, rigid: RigidSolution, method, full: bool,
                    compiled: bool = True) -> PoseResult:
    """The pose result of mesh method ``method`` from the rigid contact ``rigid``.

    The equilibrium's budgets hold for the whole pose: a window widened and solved again continues
    the evaluation count and keeps the deadline (``eq.max_pose_time`` from here). ``compiled``:
    the Newton iteration runs compiled (:mod:`lutmpi.pose.newton`) where it supports the method;
    False runs it in Python (the same results: its oracle)."""
    eq = scene.equilibrium
    deadline = time.perf_counter() + eq.max_pose_time
    nit = 0
    f_min = min(
        (flange_factor(scene, name, c.s) for name, cs in rigid.contacts.items() for c in cs),
        default=1.0,
    )
    # window depth: the margin plus twice the vertical approach of the softest contact at the
    # first k_c (normal approach W / (k f) over cos of the steepest contact angle)
    n_z = min((abs(np.cos(_rigid_angle(scene, name, c)))
               for name, cs in rigid.contacts.items() for c in cs), default=1.0)
    depth = scene.settings.window_gap + 2.0 * eq.load / (eq.kc0 * f_min * max(n_z, 0.2))
    last, last_moved = None, np.inf
    for _ in range(3):
        wins = windows(scene, rigid, method, depth, full or not scene.settings.window)
        evaluate = _evaluator(scene, wins, method, rigid)
        if (last is not None and last_moved < depth and last.nit < eq.max_iterations
                and _same_nodes(evaluate(last.q), last.contacts)):
            # the pose found with the narrower window lies within this one's depth, and this
            # window has no further node in contact there: it is this window's equilibrium
            # too (one evaluation to know it, instead of solving again)
            out = last
            out.nit += 1
            break
        solver = Equilibrium(
            evaluate,
            rigid.y,
            rigid.yaw,
            np.array([rigid.z_g, rigid.roll]),
            eq,
            lever=scene.lever,
            fmin=f_min,
            rate=method.indentation_rate,
            nz_min=n_z,
            nit=nit,
            deadline=deadline,
            fast=(CompiledNewton(scene, wins, method, rigid)
                  if compiled and CompiledNewton.supports(scene, method) else None),
        )
        out = solver.solve()
        nit = out.nit
        if out.status in (MAX_ITER, TIME_BUDGET):
            break
        # how far the wheels moved vertically at their contacts: the nodes left out of the
        # window had a rigid gap above ``depth``, so none of them can be in contact unless a
        # wheel moved that far
        dz, dr = out.q[0] - rigid.z_g, out.q[1] - rigid.roll
        moved = max(abs(dz + sd * scene.side(name).wheel.d * dr)
                    for name, sd in SIDE_SIGN.items()) + 0.1 * abs(dr)
        if full or not scene.settings.window or moved < depth:
            break
        depth *= 4.0  # the pose left the window's depth: widen it and look again
        last, last_moved = out, moved
    else:
        out.success, out.status, out.message = False, WINDOW, STATUS[WINDOW]
    return _pose_from_equilibrium(scene, rigid, method, out)


def warm_rare_paths(scene, method) -> None:
    """Load the compiled code a pose reaches only sometimes, with one evaluation each at the
    rigid pose of (0, 0): the evaluation of the bracketing (:meth:`CompiledNewton.residual`,
    where Newton stalls), the method's stage called from Python (a widened window's check,
    :func:`_same_nodes`) and the locus solver's edge and dip searches. Without this their
    first use in a process loads them from numba's cache (~10-30 ms each) inside that pose's
    time, or compiles them on a cold cache. Only a speed-up: a scene this pose does not suit
    (no rigid contact at (0, 0), flange radii the factor refuses) is left unwarmed, and its
    poses report their own errors."""
    scene.locus.warm()
    if not method.uses_mesh:
        return
    rigid = scene.locus.solve(0.0, 0.0)
    if not rigid.success:
        return
    try:
        wins = windows(scene, rigid, method, scene.settings.window_gap, False)
        q0 = np.array([rigid.z_g, rigid.roll])
        evaluate = _evaluator(scene, wins, method, rigid)
        evaluate(q0)
        if CompiledNewton.supports(scene, method):
            solver = Equilibrium(evaluate, rigid.y, rigid.yaw, q0, scene.equilibrium,
                                 lever=scene.lever, rate=method.indentation_rate,
                                 fast=CompiledNewton(scene, wins, method, rigid))
            solver.residual(q0, scene.equilibrium.kc0)
    except (ValueError, GeometryError) as exc:
        log.debug("rare paths of %s not warmed: %s", method.name, exc)


def _same_nodes(a: dict[str, list[ContactForce]], b: dict[str, list[ContactForce]]) -> bool:
    """True when two evaluations at one pose have, on each wheel, as many contacts made of as
    many wheel and rail nodes: a window holding another's nodes and more finds the same nodes
    in contact (the same contacts, summed in another order)."""
    def counts(cs: list[ContactForce]) -> list[tuple[int, int]]:
        return sorted((c.data.n_wheel_nodes, c.data.n_rail_nodes) for c in cs)

    return a.keys() == b.keys() and all(counts(a[k]) == counts(b[k]) for k in a)


def _evaluator(scene, wins: dict[str, Window], method, rigid: RigidSolution):
    mc = scene.settings.max_contacts
    rate = method.indentation_rate

    def evaluate(q: np.ndarray) -> dict[str, list[ContactForce]]:
        centre = np.array([0.0, rigid.y, q[0]])
        R = rotation(rigid.yaw, q[1])
        out = {}
        for name, win in wins.items():
            wm, rm = scene.side(name).wheel_mesh, scene.side(name).rail_mesh
            cs = method.contacts(win, wm, rm, centre, R, mc)
            out[name] = [contact_force(c, flange_factor(scene, name, c.s), rate) for c in cs]
        return out

    return evaluate


def _extrapolation_touches(locus: LocusSolver, y: float, yaw: float, q: np.ndarray,
                           q_star: np.ndarray) -> bool:
    """Whether the zero-indentation extrapolation ``q_star`` of the penalty pose ``q`` (z_g,
    roll; m, rad) is one, judged by the rigid geometry: each wheel's gap there (its touching
    height from its whole locus, :meth:`~lutmpi.contact.locus.LocusSolver.heights`, against
    z_g), the larger of the two. Kept where that falls to at most 3/4 of the penalty pose's
    (plus 1 um), or where the step moves no wheel further than that gap and does not make it
    worse (plus 1 um): a small correction where the mesh and the exact surfaces differ by a
    few micrometres at one wheel (the bracket ends of the Manchester table's flange jumps:
    14.1 -> 12.1 um, a 2 um step). The extrapolation is one linear solve
    ``q* = q - J^-1 F_c``; where the two wheels' touching heights move nearly in parallel
    with the roll (a flat height mismatch, next to a fold where a tread and a flange root
    meet), J is nearly singular and the step runs off: on a measured worn flange (Car7216 on
    the Manchester rail, y = 4.757 mm, yaw 0) it moved z_g by 0.75 mm and the roll by 1 mrad
    to a pose 119 um above the rail, while the penalty pose was 28 um into it. Not kept where
    a wheel has no point over its rail at either pose (a height not finite), on either side
    alike."""
    zl0, zr0 = locus.heights(y, yaw, float(q[1]))
    zl1, zr1 = locus.heights(y, yaw, float(q_star[1]))
    if not all(math.isfinite(v) for v in (zl0, zr0, zl1, zr1)):
        return False
    before = max(abs(float(q[0]) - zl0), abs(float(q[0]) - zr0))
    after = max(abs(float(q_star[0]) - zl1), abs(float(q_star[0]) - zr1))
    dz, dr = float(q_star[0] - q[0]), float(q_star[1] - q[1])
    step = abs(dz) + locus.lever * abs(dr)     # the larger vertical move of the two wheels
    return bool(after <= 0.75 * before + 1e-6
                or (step <= before + 1e-6 and after <= before + 1e-6))


def _pose_from_equilibrium(scene, rigid: RigidSolution, method, out) -> PoseResult:
    eq = scene.equilibrium
    z, roll = float(out.q[0]), float(out.q[1])
    gy, gz = float(rigid.y), z  # G of the solved pose: the contacts' lever arms
    kept = ""
    if out.q_extrapolated is not None:
        if _extrapolation_touches(scene.locus, rigid.y, rigid.yaw, out.q, out.q_extrapolated):
            z, roll = float(out.q_extrapolated[0]), float(out.q_extrapolated[1])
        else:
            kept = ("; the pose at the final k_c, not extrapolated to zero indentation (the "
                    "extrapolation did not bring the wheels nearer to touching their rails: "
                    "an ill-conditioned roll)")
    # eq. (1)'s spring loads from the contact forces, summed in Python floats (the same
    # operations as on numpy vectors, without their per-call cost)
    F = [0.0, 0.0, 0.0]
    M = [0.0, 0.0, 0.0]
    rows = []
    res = PoseResult(
        y=rigid.y,
        yaw=rigid.yaw,
        method=method.name,
        z_g=z,
        roll=roll,
        success=out.success,
        status=out.status,
        message=out.message + kept,
        nit=out.nit,
        kc=out.kc,
        indentation=out.indentation,
    )
    for name, side in SIDE_SIGN.items():
        for cf in out.contacts.get(name, []):
            c = cf.data
            k = out.kc * cf.factor
            ki = k * cf.indentation
            f = [ki * v for v in cf.normal.tolist()]
            px, py, pz = cf.point.tolist()
            r = (px - 0.0, py - gy, pz - gz)
            for j in range(3):
                F[j] += f[j]
            M[0] += r[1] * f[2] - r[2] * f[1]
            M[1] += r[2] * f[0] - r[0] * f[2]
            M[2] += r[0] * f[1] - r[1] * f[0]
            rows.append((side, c.wheel_point, c.rail_point, cf.normal, c.indentation, c.s, k))
    records = iter(contact_records(scene, rows))
    for name in SIDE_SIGN:
        for _ in out.contacts.get(name, []):
            res.contacts[name].append(next(records))
    res.x_g = float(-F[0] / eq.k_el)  # eq. (1): the x spring carries the longitudinal force
    res.pitch = float(-M[1] / eq.k_rot)  # eq. (1): the pitch spring carries M_y
    return res
