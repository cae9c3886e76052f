"""One pose, one call: ``solve_pose(scene, y, yaw, method)`` -> :class:`PoseResult`.

Every method starts from the rigid contact of the locus method (§4.3 step 1: the starting pose
``q0``, and where contact can happen); the reference method takes it as its result
(:mod:`lutmpi.pose.rigid`), a mesh method's stage (:mod:`lutmpi.contact.methods`) runs in the
shared mesh pipeline (:mod:`lutmpi.pose.mesh`). Non-convergence is returned as a status, never
raised.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

from lutmpi.contact.locus import MISMATCH_M, RigidSolution
from lutmpi.contact.methods import METHOD_NAMES, get_method
from lutmpi.equilibrium.result import NO_CONTACT, PROFILE_END, RIGID_UNRESOLVED, STATUS, PoseResult
from lutmpi.pose.mesh import solve_mesh_pose, warm_rare_paths
from lutmpi.pose.rigid import rigid_result
from lutmpi.table.schema import D

__all__ = ["METHOD_NAMES", "POINT_QUANTITIES", "solve_pose", "warm"]

#: Per-point quantities the pose layer adds to every result, by schema name: a function of
#: ``(result, rigid, scene)`` each, set as the result's attribute of that name, which
#: ``table/compute.py`` stores. A new per-point quantity of every method is one line here plus
#: its ``Field`` in ``table/schema.py``; a result not made here (an error record) stores the
#: field's fill value.
POINT_QUANTITIES: dict[str, Callable[[PoseResult, RigidSolution, Any], Any]] = {
    D.n_roots: lambda res, rigid, scene: rigid.n_roots,
}


def solve_pose(
    scene, y: float, yaw: float, method: str | None = None, *, full_mesh: bool = False
) -> PoseResult:
    """Solve the wheelset pose for imposed lateral shift ``y`` (m) and ``yaw`` (rad).

    Parameters
    ----------
    scene : lutmpi.scene.Scene
    method : str, optional
        A name of :data:`lutmpi.contact.methods.METHODS` (default: the scene's).
    full_mesh : bool
        Use the whole meshes instead of the contact window (for checking the window).
    """
    name = method or scene.settings.method
    m = get_method(name)
    t0 = time.process_time()
    rigid = scene.locus.solve(y, yaw)
    if not rigid.success:
        res = PoseResult(
            y=y,
            yaw=yaw,
            method=name,
            status=NO_CONTACT,
            message=f"{STATUS[NO_CONTACT]} ({rigid.message})",
            nit=rigid.nit,
        )
    else:
        res = (solve_mesh_pose(scene, rigid, m, full_mesh) if m.uses_mesh
               else rigid_result(scene, rigid, name))
    for name, quantity in POINT_QUANTITIES.items():
        setattr(res, name, quantity(res, rigid, scene))
    if rigid.success and rigid.at_end:
        # the data do not reach the contact: the numbers are kept, the status says why
        res.success, res.status = False, PROFILE_END
        res.message = f"{STATUS[PROFILE_END]} ({_end_text(rigid)})"
    elif rigid.success and not m.uses_mesh and rigid.mismatch > MISMATCH_M:
        # the reference's pose is the rigid root itself: one whose wheels are not both on
        # their rails is no result (a mesh method only starts from it, and solves its own)
        res.success, res.status = False, RIGID_UNRESOLVED
        res.message = (f"{STATUS[RIGID_UNRESOLVED]}: the wheels' touching heights are "
                       f"{rigid.mismatch * 1e6:.3f} um apart at roll {rigid.roll:.6g} rad")
    res.time = time.process_time() - t0
    return res


def warm(scene, method: str) -> None:
    """Load every compiled kernel a pose of ``method`` on ``scene`` may call: one solve, and
    what only some poses reach (:func:`~lutmpi.pose.mesh.warm_rare_paths`); results are not
    kept (the solve is pure)."""
    solve_pose(scene, 0.0, 0.0, method)
    warm_rare_paths(scene, get_method(method))


def _end_text(rigid: RigidSolution) -> str:
    ends = [f"{name} wheel s = {c.s * 1e3:.2f} mm" for name, cs in rigid.contacts.items()
            for c in cs if c.at_end]
    rims = [f"the {name} wheel's end circle (s = {s * 1e3:.2f} mm, the edge of its data) "
            f"{-g * 1e3:.3f} mm into the rail at {phi * 180 / math.pi:+.1f} deg from its lowest "
            "point, off the contact locus" for name, s, phi, g in rigid.rim]
    parts = (["contact at the end of the data: " + ", ".join(ends)] if ends else []) + rims
    return "; ".join(parts)
