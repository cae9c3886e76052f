"""A build on a cold kernel cache under mpirun (issue 14): one rank per cache folder compiles
every kernel before the other ranks of that folder load them, since numba does not guard its
cache against processes writing the same entries at once; on a warm cache nothing waits. The
compile is replaced by a timed stand-in (a real cold compile takes ~1.5 min); the ranks, the
collectives, the probe files and the barriers are real. Node-local cache folders are made by
giving rank 0 a folder of its own."""

from __future__ import annotations

import time
from pathlib import Path

import pytest

from lutmpi import warmup
from lutmpi.config.model import Config, GridConfig, OutputConfig, RailConfig, WheelConfig
from lutmpi.parallel.runner import _cache_leader, build_table
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


def _build(path, ready: bool | None, monkeypatch, split: str = "dynamic") -> tuple[list, list]:
    """Build on every rank with the compile timed; ``ready`` None: the real mark decides (the
    caller points :func:`lutmpi.warmup.ready_marker` at the folders), and the stand-in writes
    it as the warm-up does."""
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    compiled: list[tuple[float, float]] = []

    def compile_all() -> float:
        t0 = time.time()
        time.sleep(COMPILE_S)
        if ready is None:
            warmup.ready_marker().write_text("complete\n")
        compiled.append((t0, time.time()))
        return COMPILE_S

    if ready is not None:   # the probes go to a test folder, not the project's cache
        monkeypatch.setattr(warmup, "kernels_ready", lambda: ready)
        monkeypatch.setattr(warmup, "ready_marker",
                            lambda: path.parent / "kernels" / warmup.READY_NAME)
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


def _folders(base, rank: int):
    """Rank 0 on a warm folder of its own (a node whose local cache was filled), the other
    ranks sharing a cold one (another node's)."""
    folder = base / ("cache-a" if rank == 0 else "cache-b")
    folder.mkdir(parents=True, exist_ok=True)
    if rank == 0:
        (folder / warmup.READY_NAME).write_text("complete\n")
    return folder


def test_node_local_caches_each_compile_once_before_their_ranks_load(mpi_tmp_path,
                                                                      monkeypatch):
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    folder = _folders(mpi_tmp_path, comm.rank)
    monkeypatch.setattr(warmup, "ready_marker", lambda: folder / warmup.READY_NAME)
    comm.Barrier()
    compiled, started = _build(mpi_tmp_path / "local.h5", None, monkeypatch)
    assert not compiled[0]                       # its own folder was warm
    assert len(compiled[1]) == 1 and all(not c for c in compiled[2:])
    end = compiled[1][0][1]
    for rank_starts in started[2:]:
        assert rank_starts and min(rank_starts) >= end    # waited for rank 1's compile
    assert not [p.name for p in (mpi_tmp_path / "cache-b").iterdir()
                if p.name.startswith(".lutmpi-probe")]    # the probes are gone


def test_cache_leader_is_the_lowest_rank_of_each_folder(mpi_tmp_path, monkeypatch):
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    shared = mpi_tmp_path / "shared"
    assert _cache_leader(comm, shared) == (0, True)
    assert _cache_leader(comm, _folders(mpi_tmp_path, comm.rank)) == (min(comm.rank, 1), True)
    # one folder under a different name on each rank (links, or a mount seen at two paths)
    link = mpi_tmp_path / f"link-{comm.rank}"
    link.symlink_to(shared)
    assert _cache_leader(comm, link) == (0, True)
    # one name for a different folder on each rank (node-local scratch at the same path)
    own = mpi_tmp_path / f"cwd-{comm.rank}"
    own.mkdir()
    monkeypatch.chdir(own)
    assert _cache_leader(comm, Path("cache")) == (comm.rank, True)
    # a folder no rank can write (its parent is a file): each rank on its own
    blocker = mpi_tmp_path / f"file-{comm.rank}"
    blocker.write_text("")
    assert _cache_leader(comm, blocker / "cache") == (comm.rank, False)


def test_an_unwritable_cache_is_not_compiled_ahead_and_the_build_completes(mpi_tmp_path,
                                                                          monkeypatch):
    """numba cannot cache there, so there is nothing to order and no mark to write: each rank
    compiles what it needs in its own solves (the stand-in would record a compile ahead)."""
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    blocker = mpi_tmp_path / f"file-{comm.rank}"
    blocker.write_text("")
    monkeypatch.setattr(warmup, "ready_marker",
                        lambda: blocker / "cache" / warmup.READY_NAME)
    comm.Barrier()
    compiled, started = _build(mpi_tmp_path / "unwritable.h5", None, monkeypatch)
    assert all(not c for c in compiled) and all(s for s in started)
    assert (mpi_tmp_path / "unwritable.h5").exists()


def test_a_resume_with_every_point_journaled_still_orders_the_compile(mpi_tmp_path,
                                                                       monkeypatch):
    """The jump step solves after the grid on every rank, so a resumed build whose grid is all
    in the journal compiles first too (the ordering does not depend on points being left)."""
    from mpi4py import MPI

    from lutmpi.parallel import runner

    comm = MPI.COMM_WORLD
    path = mpi_tmp_path / "resumed.h5"

    def stop_after_the_grid(*args, **kwargs):
        raise RuntimeError("stopped after the grid")

    cfg = Config(wheel=WheelConfig(generator="S1002"), rail=RailConfig(generator="UIC60"),
                 grid=GridConfig(y_mm=(-9.0, 9.0, 5), yaw_rad=(-0.12, 0.12, 3)),
                 output=OutputConfig(methods=("load_centre",)))
    if comm.rank == 0:   # every point journaled by one process, which then fails: no table
        with monkeypatch.context() as m:
            m.setattr(runner, "add_jumps", stop_after_the_grid)
            with pytest.raises(RuntimeError, match="stopped after the grid"):
                build_table(cfg, path, None, solver=_TimedWarm(),
                            scene_factory=faulty_solver.make_scene, checkpoint_interval_s=0.0)
    comm.Barrier()
    assert not path.exists()
    compiled: list[tuple[float, float]] = []
    monkeypatch.setattr(warmup, "kernels_ready", lambda: False)
    monkeypatch.setattr(warmup, "warm_kernels",
                        lambda: compiled.append((time.time(), time.time())) or 0.0)
    summary = build_table(cfg, path, comm, solver=_TimedWarm(), resume=True,
                          scene_factory=faulty_solver.make_scene, checkpoint_interval_s=0.0)
    assert summary.computed == 0 and summary.reused == summary.points
    assert path.exists()
    counts = comm.allgather(len(compiled))
    assert counts[0] == 1 and not any(counts[1:])
