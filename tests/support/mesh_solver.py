"""Test-support solver whose error against the ``reference`` method follows a known law.

``lutmpi sweep --solver tests.support.mesh_solver:solve`` (``make_scene`` replaces the real scene).
For a mesh method the result is the reference pose plus ``C_m h**p_m (1 + 0.5 sin(...))`` on every
quantity, with ``h`` the largest mesh spacing: ``max_distance`` p = 1, ``load_centre`` p = 2,
``max_normal_distance`` p = 1.5. ``reference`` is exact (mesh-free). A wheel profile file whose
first line is ``garbage`` makes ``make_scene`` raise ``ProfileError`` (a bad profile file), and
``LUTMPI_MESH_FAULT=<method>`` makes every solve of that method raise ``RuntimeError``.
"""

from __future__ import annotations

import math
import os
import time
from typing import Any

import numpy as np

from lutmpi.equilibrium.result import CONVERGED, ContactResult, PoseResult
from lutmpi.errors import ProfileError

ORDERS = {"max_distance": (1.0, 0.5), "load_centre": (2.0, 200.0),
          "max_normal_distance": (1.5, 10.0), "reference": (0.0, 0.0)}


def make_scene(config: Any) -> dict[str, Any]:
    prof = config.wheel.profile
    if prof is not None and open(prof).readline().startswith("garbage"):
        raise ProfileError("cannot parse the wheel profile (test: garbage)", path=str(prof), line=1)
    m = config.mesh
    h = max(m.wheel_lateral_mm, m.wheel_circumferential_mm, m.rail_lateral_mm,
            m.rail_longitudinal_mm) * 1e-3
    return {"h": h, "r0": config.wheel.nominal_radius_m,
            "half": config.wheelset.tape_half_distance_m}


def _contact(side: int, y: float, e: float, scene: dict[str, Any]) -> ContactResult:
    ang = 0.05 * side + 10 * y + e
    return ContactResult(
        wheel_point=np.array([0.0, side * scene["half"] + y, 0.0]),
        rail_point=np.array([0.0, side * scene["half"] + y, 0.0]),
        normal=np.array([0.0, math.sin(ang), math.cos(ang)]), indentation=1e-5, force=5e4,
        rolling_radius=scene["r0"] + 0.05 * side * y + e, contact_angle=ang,
        wheel_s=y + e, rail_v=-y + e)


def solve(scene: dict[str, Any], y: float, yaw: float, method: str) -> PoseResult:
    t0 = time.process_time()
    if os.environ.get("LUTMPI_MESH_FAULT") == method:
        raise RuntimeError(f"injected fault in method {method}")
    p, c = ORDERS[method]
    e = 0.0 if method == "reference" else c * scene["h"] ** p * (1 + 0.5 * math.sin(300 * y + yaw))
    res = PoseResult(y=y, yaw=yaw, method=method, x_g=0.0, z_g=0.05 * y * y + e,
                     roll=0.05 * y + e, pitch=0.0, success=True, status=CONVERGED,
                     message="converged", nit=3, kc=1e9, indentation=1e-5)
    # y > 0 is to the left: the left wheel (side +1 here) rolls on larger radii, Δr = 0.1 y
    res.contacts = {"left": [_contact(1, y, e, scene)], "right": [_contact(-1, y, e, scene)]}
    res.time = time.process_time() - t0 + 1e-4 * (1 + (method != "reference") / scene["h"] * 1e-4)
    return res
