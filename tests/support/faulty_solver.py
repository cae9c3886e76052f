"""Test-support solver: closed-form poses, plus faults injected through ``LUTMPI_FAULT``.

Used by the table tests directly and through ``lutmpi build --solver
tests.support.faulty_solver:solve`` (the module's ``make_scene`` replaces the real scene).

``LUTMPI_FAULT`` (read only here), comma-free items separated by ``;``:

``raise@Y_MM/YAW``   raise RuntimeError when solving the pose (y = Y_MM mm, yaw = YAW rad)
``kill@Y_MM/YAW``    SIGKILL this process at that pose
``sleep=S``          sleep ``S * (1 + 4 |y| / 9 mm)`` seconds per solve (flange points cost more)
``gridsleep=S/STEP`` the same, only at poses whose y is a multiple of ``STEP`` mm (a grid's
                     nodes): the jump step after the grid, which solves between them, runs
                     at full speed
"""

from __future__ import annotations

import math
import os
import signal
import time
from typing import Any

import numpy as np

from lutmpi.equilibrium.result import CONVERGED, MAX_ITER, ContactResult, PoseResult


def make_scene(config: Any) -> dict[str, float]:
    """A stand-in scene: what the closed forms need, picklable."""
    return {"r0": config.wheel.nominal_radius_m, "half": config.wheelset.tape_half_distance_m}


def _faults() -> list[tuple[str, str]]:
    spec = os.environ.get("LUTMPI_FAULT", "")
    out = []
    for item in filter(None, spec.split(";")):
        if "@" in item:
            kind, where = item.split("@", 1)
        else:
            kind, where = item.split("=", 1)
        out.append((kind, where))
    return out


def _at(where: str, y: float, yaw: float) -> bool:
    y_mm, yaw_s = where.split("/")
    return math.isclose(y * 1e3, float(y_mm), abs_tol=1e-9) and math.isclose(
        yaw, float(yaw_s), abs_tol=1e-12)


def _inject(y: float, yaw: float) -> None:
    for kind, where in _faults():
        if kind == "sleep":
            time.sleep(float(where) * (1.0 + 4.0 * abs(y) / 9e-3))
        elif kind == "gridsleep":
            pause, step = (float(v) for v in where.split("/"))
            q = y * 1e3 / step
            if math.isclose(q, round(q), abs_tol=1e-9):
                time.sleep(pause * (1.0 + 4.0 * abs(y) / 9e-3))
        elif kind == "raise" and _at(where, y, yaw):
            raise RuntimeError(f"injected fault at y={y}, yaw={yaw}")
        elif kind == "kill" and _at(where, y, yaw):
            os.kill(os.getpid(), signal.SIGKILL)


def _contact(side: int, y: float, yaw: float, scene: dict[str, float], k: int) -> ContactResult:
    """A contact whose every field is a smooth closed form of (y, yaw)."""
    lat = side * scene["half"] + y + 1e-3 * k
    normal = np.array([0.0, math.sin(0.05 * side + 10 * y), math.cos(0.05 * side + 10 * y)])
    force = 5e4 * (1 + side * 10 * y) / (1 + k)
    return ContactResult(
        wheel_point=np.array([scene["r0"] * yaw * side, lat, 1e-5 * k]),
        rail_point=np.array([scene["r0"] * yaw * side, lat, -1e-5]),
        normal=normal, indentation=1e-5 * (1 + y), kc=1e9 * (1 + k), force=force,
        rolling_radius=scene["r0"] + 0.05 * side * y, contact_angle=0.05 + side * 10 * y,
        wheel_s=y + 0.001 * k, rail_v=-y, wheel_curv_rolling=1 / scene["r0"],
        wheel_curv_transverse=2.0 + y, rail_curv_transverse=1 / 0.3 + yaw)


def solve(scene: dict[str, float], y: float, yaw: float, method: str) -> PoseResult:
    """Closed-form pose: conical wheels, a second (flange) contact on the right when y > 3 mm."""
    t0 = time.process_time()
    _inject(y, yaw)
    m = {"load_centre": 1.0, "max_distance": 1.01, "max_normal_distance": 1.02,
         "reference": 0.99}[method]
    res = PoseResult(y=y, yaw=yaw, method=method, x_g=1e-4 * yaw * m, z_g=m * 0.05 * y * y,
                     roll=m * 0.05 * y, pitch=1e-6 * yaw, kc=1e9, indentation=1e-5 * (1 + y))
    res.contacts = {"left": [_contact(-1, y, yaw, scene, 0)],
                    "right": [_contact(1, y, yaw, scene, 0)]}
    if y > 3e-3:
        res.contacts["right"].insert(0, _contact(1, y, yaw, scene, 1))  # weaker one listed first
    corner = y < -8.9e-3 and yaw < -0.119
    res.status, res.success = (MAX_ITER, False) if corner else (CONVERGED, True)
    res.message, res.nit = ("max_iterations" if corner else "converged"), 3 + int(1e3 * abs(y))
    res.time = time.process_time() - t0
    return res
