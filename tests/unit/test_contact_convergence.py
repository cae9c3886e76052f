"""Mesh convergence of the three contact-point methods against the reference (issue 3, "Must
show": convergence over >= 3 refinements, observed order printed).

All four spacings are refined together, h = 1, 0.5, 0.25, 0.125 mm, and the allowed indentation
with h^2 (0.01 mm x (h / 0.5 mm)^2): the pose error of a penalty method contains the indentation
(partly removed by the zero-indentation extrapolation), which must fall at least as fast as the
discretisation error for the study to measure the mesh. The error of one method at one h is the
largest over representative poses (two tread, two flange, with and without yaw) of |dz_g|,
|droll| and |dwheel_s| (primary contact, both wheels).

Acceptance, decided before measuring: the fitted order (least squares of log e on log h) exceeds
0.5 AND the finest error is below a third of the coarsest. Both, because a node-snapping method
has a staircase error: the fit alone can be bent by one lucky coarse mesh, the ratio alone by one
lucky fine mesh. 0.5 rather than the nominal 1 (node methods) or 2 (centroid): the error of a
node-snapping estimator is not monotone in h, and four levels do not average that out.
"""

from __future__ import annotations

import numpy as np
import pytest
from contact_fixtures import MESH_METHODS, MM, standard_scene

from lutmpi.pose.solve import solve_pose

H = (1.0, 0.5, 0.25, 0.125)  # mm
POSES = ((2 * MM, 0.0), (3 * MM, 0.06), (9 * MM, 0.0), (8 * MM, 0.12))
QUANTITIES = ("z_g", "roll", "wheel_s")


def _errors(method, hs):
    refs = {p: solve_pose(standard_scene(), *p, "reference") for p in POSES}
    errs = np.zeros((len(hs), 3))
    for i, h in enumerate(hs):
        scene = standard_scene(spacing=(h * MM,) * 4, allowed=1e-5 * (h / 0.5) ** 2)
        for p in POSES:
            r, f = solve_pose(scene, *p, method), refs[p]
            assert r.success, (h, p, r.message)
            ds = max(abs(r.contacts[n][0].wheel_s - f.contacts[n][0].wheel_s)
                     for n in ("left", "right"))
            errs[i] = np.maximum(errs[i], [abs(r.z_g - f.z_g), abs(r.roll - f.roll), ds])
    return errs


def observed_order(h, e):
    return float(np.polyfit(np.log(h), np.log(e), 1)[0])


def _report_and_check(method, hs, errs):
    for j, q in enumerate(QUANTITIES):
        p = observed_order(np.array(hs), errs[:, j])
        unit = {"z_g": "m", "roll": "rad", "wheel_s": "m"}[q]
        print(f"\n{method:20s} {q:8s} errors ({unit}) " + " ".join(f"{e:.2e}" for e in errs[:, j])
              + f"  at h = {hs} mm -> observed order {p:.2f}, coarse/fine "
              f"{errs[0, j] / errs[-1, j]:.1f}")
        assert p > 0.5, (q, errs[:, j])
        assert errs[-1, j] < errs[0, j] / 3, (q, errs[:, j])


@pytest.mark.parametrize("method", MESH_METHODS)
def test_error_falls_with_mesh_spacing(method):
    _report_and_check(method, H, _errors(method, H))


@pytest.mark.slow
@pytest.mark.parametrize("method", MESH_METHODS)
def test_error_falls_with_mesh_spacing_five_levels(method):
    hs = H + (0.0625,)
    _report_and_check(method, hs, _errors(method, hs))
