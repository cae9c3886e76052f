"""A build on a cold kernel cache under mpirun (issue 14): rank 0 compiles every kernel before
the other ranks load them, since numba does not guard its cache against processes writing the
same entries at once; on a warm cache nothing waits. The compile is replaced by a timed stand-in
(a real cold compile takes ~1.5 min); the ranks, the broadcast and the barrier are real."""

from __future__ import annotations

import time

import pytest

from lutmpi import warmup
from lutmpi.config.model import Config, GridConfig, OutputConfig, RailConfig, WheelConfig
from lutmpi.parallel.runner import build_table
from tests.support import faulty_solver

pytestmark = [pytest.mark.mpi(min_size=2), pytest.mark.timeout(60)]

COMPILE_S = 0.3


class _TimedWarm:
    """The closed-form solver with a ``warm`` that records when each rank started it."""

    def __init__(self) -> None:
        self.started: list[float] = []

    def warm(self, scene, method: str, y: float = 0.0, yaw: float = 0.0) -> None:
        self.started.append(time.time())

    def __call__(self, scene, y: float, yaw: float, method: str):
        return faulty_solver.solve(scene, y, yaw, method)


def _build(path, ready: bool, monkeypatch, split: str = "dynamic") -> tuple[list, list]:
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    compiled: list[tuple[float, float]] = []

    def compile_all() -> float:
        t0 = time.time()
        time.sleep(COMPILE_S)
        compiled.append((t0, time.time()))
        return COMPILE_S

    monkeypatch.setattr(warmup, "kernels_ready", lambda: ready)
    monkeypatch.setattr(warmup, "warm_kernels", compile_all)
    cfg = Config(wheel=WheelConfig(generator="S1002"), rail=RailConfig(generator="UIC60"),
                 grid=GridConfig(y_mm=(-9.0, 9.0, 5), yaw_rad=(-0.12, 0.12, 3)),
                 output=OutputConfig(methods=("load_centre",)))
    solver = _TimedWarm()
    build_table(cfg, path, comm, solver=solver, scene_factory=faulty_solver.make_scene,
                checkpoint_interval_s=0.0, split=split)
    return comm.allgather(compiled), comm.allgather(solver.started)


@pytest.mark.parametrize("split", ["dynamic", "block"])   # block: no collective counter
def test_cold_cache_rank0_compiles_before_the_others_load(mpi_tmp_path, monkeypatch, split):
    compiled, started = _build(mpi_tmp_path / "cold.h5", False, monkeypatch, split)
    assert len(compiled[0]) == 1 and all(not c for c in compiled[1:])
    end = compiled[0][0][1]
    for rank_starts in started[1:]:
        assert rank_starts and min(rank_starts) >= end    # waited for rank 0's compile


def test_warm_cache_compiles_nothing_and_nobody_waits(mpi_tmp_path, monkeypatch):
    compiled, started = _build(mpi_tmp_path / "warm.h5", True, monkeypatch)
    assert all(not c for c in compiled)
    assert all(s for s in started)
