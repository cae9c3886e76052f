"""The stored per-contact geometry computed compiled (:func:`lutmpi.contact.records.
record_geometry`, issue 14) against the numpy form it replaced (the geometry's former methods,
``tests/support/locus_oracle.record_geometry``): rolling radius, contact angle, rail profile
coordinate and the three curvatures, on both sides of an asymmetric pair (a worn left wheel),
over wheel points from flange to field side, rail points near the rail's ends (the
curvature's base is clipped there) and steep normals."""

from __future__ import annotations

import math

import numpy as np

from lutmpi.contact.records import CURV_BASE, record_geometry
from lutmpi.profiles.standard import s1002, uic60
from lutmpi.profiles.wear import flange_thinning
from lutmpi.scene import Scene
from tests.support.locus_oracle import record_geometry as oracle

#: record_geometry's columns: ContactResult attributes
COLUMNS = ("rolling_radius", "contact_angle", "rail_v", "wheel_curv_rolling",
           "wheel_curv_transverse", "rail_curv_transverse")
#: last-bit differences: numba's arctan/arctan2 round differently from numpy's
TOL = {"rolling_radius": 0.0, "contact_angle": 1e-15, "rail_v": 0.0,
       "wheel_curv_rolling": 0.0, "wheel_curv_transverse": 1e-11, "rail_curv_transverse": 1e-11}


def test_compiled_record_geometry_equals_the_geometry_methods():
    scene = Scene.from_profiles({"left": flange_thinning(s1002(), 2.0), "right": s1002()},
                                uic60(), inclination=math.atan(1 / 40))
    rng = np.random.default_rng(16)
    for name, sgn in (("left", 1.0), ("right", -1.0)):
        sd = scene.side(name)
        wheel, rail = sd.wheel, sd.rail
        n = 400
        s = np.concatenate([rng.uniform(wheel.s_min, wheel.s_max, n - 4),
                            [wheel.s_min, wheel.s_max, 0.0, wheel.s_min + 0.5 * CURV_BASE]])
        u = np.concatenate([rng.uniform(rail.u_min - 1e-3, rail.u_max + 1e-3, n - 2),
                            [rail.u_min, rail.u_max]])
        ang = rng.uniform(-1.3, 1.3, n)  # contact angles up to ~75 deg
        side = np.full(n, sgn)
        rp = np.column_stack([rng.uniform(-0.02, 0.02, n), sgn * u, rng.uniform(-0.03, 0.0, n)])
        nrm = np.column_stack([np.zeros(n), -sgn * np.sin(ang), np.cos(ang)])
        want = oracle(sd, side, rp, s, nrm, CURV_BASE)
        got = record_geometry(side, rp, s, nrm, wheel.profile.ppolys, wheel.r0, wheel.s_min,
                              wheel.s_max, rail.ppolys,
                              (rail.u_min, rail.u_max, rail.gauge, rail.v_gp, rail.w_top,
                               rail.inclination), CURV_BASE)
        for k, col in enumerate(COLUMNS):
            err = np.abs(got[:, k] - want[:, k])
            scale = np.maximum(np.abs(want[:, k]), 1.0)
            assert np.all(err <= TOL[col] * scale), (name, col, float(err.max()))
        assert np.allclose(got[:, 1], ang, rtol=0.0, atol=1e-12)  # the angle is the normal's
