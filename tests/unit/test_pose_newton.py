"""The compiled Newton iteration (:mod:`lutmpi.pose.newton`, issue 14) gives the Python
iteration's results to the bit: pose, counts, k_c, contacts and statuses, on every mesh method,
on the standard pair with a soft flange (chi < 1: the §4.5 factor is exercised), on a measured
worn wheel, on an asymmetric pair with one contact allowed per wheel, and when a budget ends
the pose (the pose evaluated last is the result in both)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from contact_fixtures import MESH_METHODS, MM

from lutmpi.contact.methods import get_method
from lutmpi.equilibrium.result import CONVERGED, MAX_ITER, TIME_BUDGET
from lutmpi.equilibrium.solver import EquilibriumOptions
from lutmpi.pose.mesh import solve_mesh_pose
from lutmpi.pose.newton import CompiledNewton
from lutmpi.profiles import read_profile
from lutmpi.profiles.standard import s1002, uic60
from lutmpi.profiles.wear import flange_thinning
from lutmpi.scene import Scene, SolveSettings

PROFILES = Path(__file__).resolve().parents[2] / "profiles"
POSES = [(y * MM, yaw) for y in (-9.0, -6.5, -2.0, 0.0, 3.0, 6.0, 8.0, 9.5)
         for yaw in (0.0, 0.03, -0.1)]


def _scenes():
    soft = Scene.from_profiles(s1002(), uic60(), settings=SolveSettings(chi=0.5))
    worn = Scene.from_profiles(read_profile(PROFILES / "whl_left_iter288.whl", kind="wheel"),
                               read_profile(PROFILES / "MBench_UIC60_v3.prr", kind="rail"),
                               inclination=0.0, settings=SolveSettings(chi=0.7))
    asym = Scene.from_profiles({"left": flange_thinning(s1002(), 2.0), "right": s1002()}, uic60(),
                               inclination=math.atan(1 / 40),
                               settings=SolveSettings(max_contacts=1, chi=0.8))
    return {"soft_flange": soft, "worn": worn, "asymmetric_single": asym}


SCENES = _scenes()


def _solve(scene, y, yaw, method, compiled):
    rigid = scene.locus.solve(y, yaw)
    if not rigid.success:
        return None
    return solve_mesh_pose(scene, rigid, get_method(method), False, compiled=compiled)


def _same(a, b) -> None:
    for f in ("z_g", "roll", "x_g", "pitch", "kc", "indentation"):
        assert np.array_equal(getattr(a, f), getattr(b, f), equal_nan=True), f
    assert (a.status, a.success, a.nit, a.message) == (b.status, b.success, b.nit, b.message)
    assert a.contacts.keys() == b.contacts.keys()
    for side in a.contacts:
        assert len(a.contacts[side]) == len(b.contacts[side])
        for ca, cb in zip(a.contacts[side], b.contacts[side], strict=True):
            for f, va in vars(ca).items():
                assert np.array_equal(va, getattr(cb, f), equal_nan=True), (side, f)


@pytest.mark.parametrize("name", sorted(SCENES))
@pytest.mark.parametrize("method", MESH_METHODS)
def test_compiled_newton_is_the_python_iteration(name, method):
    scene = SCENES[name]
    assert CompiledNewton.supports(scene, get_method(method))
    solved = flange = 0
    for y, yaw in POSES:
        got = _solve(scene, y, yaw, method, True)
        want = _solve(scene, y, yaw, method, False)
        assert (got is None) == (want is None)
        if got is None:
            continue
        _same(got, want)
        solved += got.status == CONVERGED
        flange += any(c.kc < got.kc * 0.999 for cs in got.contacts.values() for c in cs)
    assert solved >= 12
    if name != "asymmetric_single":
        assert flange >= 1  # a contact on the flange, its k_c scaled by §4.5


@pytest.mark.parametrize("budget", ["iterations", "time"])
def test_a_budget_ends_both_alike(budget):
    opts = (EquilibriumOptions(max_iterations=3) if budget == "iterations"
            else EquilibriumOptions(max_pose_time=0.0))
    scene = Scene.from_profiles(s1002(), uic60(), equilibrium=opts)
    for y in (-7.0 * MM, 0.0, 8.5 * MM):
        got = _solve(scene, y, 0.02, "load_centre", True)
        want = _solve(scene, y, 0.02, "load_centre", False)
        assert got.status == (MAX_ITER if budget == "iterations" else TIME_BUDGET)
        _same(got, want)
        if budget == "iterations":
            assert got.nit == 3 and np.isfinite(got.z_g)  # the last evaluated pose


def test_unknown_kernels_and_bad_flange_radii_stay_in_python():
    from dataclasses import replace

    scene = SCENES["soft_flange"]
    other = replace(get_method("load_centre"), name="a_new_method")
    assert not CompiledNewton.supports(scene, other)
    assert CompiledNewton.supports(scene, get_method("load_centre"))


def test_bracketing_evaluates_compiled_as_in_python(monkeypatch):
    # where Newton stalls on a residual that jumps (load centre, paper pair, y = ±5 mm at yaw
    # 0.0867 rad: the paper grid's only such poses since the gauge point is exact, which moved
    # the rail 0.4 um) the nested Brent search takes over; its evaluations run compiled
    # (CompiledNewton.residual): the same pose, contacts and evaluation count as in Python
    from lutmpi.config import load_config
    from lutmpi.equilibrium.solver import Equilibrium
    from lutmpi.paths import REPO_ROOT

    scene = Scene.from_config(load_config(REPO_ROOT / "configs/paper_s1002_uic60_1in20.toml"))
    seen = []
    original = Equilibrium.bracketing

    def spy(self, q, kc):
        seen.append(self.fast is not None)
        return original(self, q, kc)

    monkeypatch.setattr(Equilibrium, "bracketing", spy)
    yaw31 = float(np.linspace(-0.12, 0.12, 37)[31])
    for y, yaw in ((5.0 * MM, yaw31), (-5.0 * MM, yaw31)):
        got = _solve(scene, y, yaw, "load_centre", True)
        want = _solve(scene, y, yaw, "load_centre", False)
        assert got.status == CONVERGED
        _same(got, want)
    assert seen.count(True) >= 2 and seen.count(False) >= 2  # both paths bracketed


@pytest.mark.parametrize("method", ["reference", *MESH_METHODS])
def test_warm_up_changes_no_result(method):
    # pose.solve.warm loads the rarely reached compiled paths (the build's solver calls it
    # before its first point): a pose solved before and after it is the same to the bit
    from lutmpi.pose.solve import solve_pose, warm

    scene = SCENES["soft_flange"]
    before = solve_pose(scene, 6.0 * MM, 0.03, method)
    warm(scene, method)
    scene.locus._memo.clear()
    after = solve_pose(scene, 6.0 * MM, 0.03, method)
    assert before.success
    _same(before, after)
