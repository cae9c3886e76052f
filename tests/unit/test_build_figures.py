"""What a build reports about its own time (issue 14): the solver's warm-up (compiled kernels
loaded) is neither a point's busy time nor overhead, and the grid loop's time outside the solves
(records, journal, hand-out) is measured per rank."""

from __future__ import annotations

import logging
import re
import time

import pytest

from lutmpi.config.load import load_config
from lutmpi.parallel.runner import build_table
from tests.support import faulty_solver
from tests.support.tables import write_config

pytestmark = pytest.mark.timeout(60)

WARM_S = 0.4
SOLVE_S = 0.002


class _SlowWarmSolver:
    """A solver with a costly one-off warm-up per method, as the production one has."""

    def __init__(self) -> None:
        self.warmed: list[tuple[str, float, float]] = []

    def warm(self, scene, method: str, y: float = 0.0, yaw: float = 0.0) -> None:
        if all(m != method for m, _, _ in self.warmed):
            self.warmed.append((method, y, yaw))
            time.sleep(WARM_S)

    def __call__(self, scene, y: float, yaw: float, method: str):
        self.warm(scene, method, y, yaw)
        time.sleep(SOLVE_S)
        return faulty_solver.solve(scene, y, yaw, method)


def test_warm_up_is_outside_busy_time_and_overhead_is_measured(tmp_path, caplog):
    cfg = load_config(write_config(tmp_path, ny=5, nyaw=3))
    solver = _SlowWarmSolver()
    with caplog.at_level(logging.INFO, logger="lutmpi.parallel.runner"):
        summary = build_table(cfg, tmp_path / "t.h5", solver=solver,
                              scene_factory=faulty_solver.make_scene, checkpoint_interval_s=0.0)
    points = 5 * 3
    # warmed once, before the grid, at the first point to compute
    assert [m for m, _, _ in solver.warmed] == list(cfg.output.methods)
    assert solver.warmed[0][1:] == pytest.approx((-0.009, -0.12))
    # busy: the solves only (15 x 2 ms and the closed forms), not the 0.4 s warm-up
    assert points * SOLVE_S <= summary.busy_s[0] < WARM_S
    assert len(summary.overhead_s) == 1 and summary.overhead_s[0] >= 0.0
    assert summary.overhead_fraction == pytest.approx(summary.overhead_s[0] / summary.busy_s[0])
    assert "compiled kernels loaded before the grid" in caplog.text
    assert "grid loop outside the solves" in caplog.text


def test_production_solver_warms_each_method_once(tmp_path):
    from lutmpi.equilibrium.result import CONVERGED
    from lutmpi.pose.solve import solve_pose
    from lutmpi.scene import Scene
    from lutmpi.table.compute import PoseSolver

    scene = Scene.from_config(load_config(write_config(tmp_path, ny=3, nyaw=3)))
    solver = PoseSolver()
    solver.warm(scene, "reference", 0.002, 0.0)
    once = solver.warm_s
    assert once > 0.0
    result = solver(scene, 0.002, 0.0, "reference")
    assert solver.warm_s == once and result.status == CONVERGED
    assert result.z_g == solve_pose(scene, 0.002, 0.0, "reference").z_g   # the same, pure solve


def test_sweep_solver_warms_before_the_grid_not_in_a_point(tmp_path):
    """A sweep member's build wraps the solver (:class:`Tolerant`); the wrapper passes the
    build's warm-up on, so the kernels' load is not the first point's busy or compute time."""
    from lutmpi.parallel.sweep_runner import Tolerant

    cfg = load_config(write_config(tmp_path, ny=5, nyaw=3))
    inner = _SlowWarmSolver()
    summary = build_table(cfg, tmp_path / "t.h5", solver=Tolerant(inner),
                          scene_factory=faulty_solver.make_scene, checkpoint_interval_s=0.0)
    assert [m for m, _, _ in inner.warmed] == list(cfg.output.methods)
    assert 5 * 3 * SOLVE_S <= summary.busy_s[0] < WARM_S


def test_sweep_solver_without_warm_or_raising_there_records_the_pose(tmp_path):
    """A solver without ``warm`` is warmed by a dropped first solve; one that raises at the
    first pose raises there again and that pose becomes an ``error`` record, not an abort."""
    from lutmpi.equilibrium.result import CONVERGED, ERROR
    from lutmpi.parallel.sweep_runner import Tolerant

    scene = faulty_solver.make_scene(load_config(write_config(tmp_path, ny=3, nyaw=3)))
    calls = []

    def plain(scene, y, yaw, method):
        calls.append((y, yaw))
        if y > 0.008:
            raise ValueError("no contact here (test)")
        return faulty_solver.solve(scene, y, yaw, method)

    solver = Tolerant(plain)
    solver.warm(scene, "reference", 0.009, 0.0)        # raises inside: kept for the pose
    assert calls == [(0.009, 0.0)]
    assert solver(scene, 0.009, 0.0, "reference").status == ERROR
    assert solver(scene, 0.0, 0.0, "reference").status == CONVERGED
    assert len(calls) == 3                              # warmed once per method, not again
    solver(scene, 0.0, 0.0, "max_distance")             # a method's first solve warms it
    assert len(calls) == 5


def test_jump_step_reports_its_own_solves_and_busy_time(tmp_path, caplog):
    """The jump step after the grid is most of a real build (BENCHMARKS.md): the log gives its
    wall time, its pose solves and their summed time per rank, as the grid's figures are given,
    so that its parallel efficiency can be read."""
    cfg = load_config(write_config(tmp_path, ny=9, nyaw=3))
    calls = []

    def solver(scene, y, yaw, method):
        calls.append((y, yaw, method))
        time.sleep(SOLVE_S)
        return faulty_solver.solve(scene, y, yaw, method)

    with caplog.at_level(logging.INFO, logger="lutmpi.parallel.jumps_step"):
        build_table(cfg, tmp_path / "t.h5", solver=solver,
                    scene_factory=faulty_solver.make_scene, checkpoint_interval_s=0.0)
    after_grid = len(calls) - 9 * 3 * len(cfg.output.methods)
    line = re.search(r"jump step: wall ([\d.]+) s on 1 rank\(s\); (\d+) pose solves; busy per "
                     r"rank \[([\d.]+)\] s", caplog.text)
    assert line, caplog.text
    assert int(line[2]) == after_grid > 0
    assert after_grid * SOLVE_S <= float(line[3]) + 0.01 <= float(line[1]) + 0.02
