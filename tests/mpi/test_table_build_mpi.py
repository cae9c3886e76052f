"""build_table under mpirun (issue 4): the collective file equals a serial build of the same
config, with either split, and when some ranks own no rows of the file."""

from __future__ import annotations

import pytest

from lutmpi.config.model import Config, GridConfig, OutputConfig, RailConfig, WheelConfig
from lutmpi.parallel.runner import SelfComm, build_table
from lutmpi.table import Table
from tests.support import faulty_solver
from tests.support.tables import differences

pytestmark = [pytest.mark.mpi(min_size=2), pytest.mark.timeout(60)]


def _config(ny: int, nyaw: int) -> Config:
    return Config(wheel=WheelConfig(generator="S1002"), rail=RailConfig(generator="UIC60"),
                  grid=GridConfig(y_mm=(-9.0, 9.0, ny) if ny > 1 else (0.0, 0.0, 1),
                                  yaw_rad=(-0.12, 0.12, nyaw)),
                  output=OutputConfig(methods=("load_centre", "max_normal_distance")))


def _both(cfg: Config, path, split: str):
    from mpi4py import MPI

    comm = MPI.COMM_WORLD
    par, ser = path / f"par-{split}.h5", path / f"ser-{split}.h5"
    summary = build_table(cfg, par, comm, solver=faulty_solver.solve,
                          scene_factory=faulty_solver.make_scene, split=split,
                          checkpoint_interval_s=0.0)
    assert summary.ranks == comm.size and len(summary.busy_s) == comm.size
    if comm.rank == 0:
        build_table(cfg, ser, SelfComm(), solver=faulty_solver.solve,
                    scene_factory=faulty_solver.make_scene)
    comm.Barrier()
    return par, ser


@pytest.mark.parametrize("split", ["dynamic", "scattered", "cyclic", "block"])
def test_parallel_build_equals_serial(mpi_tmp_path, split):
    par, ser = _both(_config(7, 5), mpi_tmp_path, split)
    assert differences(par, ser) == []
    t = Table.open(par)
    assert t.attrs["complete"] and t.status_counts("max_normal_distance")["converged"] == 34


def test_ranks_without_rows_still_write_collectively(mpi_tmp_path):
    """One grid row: every rank but 0 owns no row of the file and takes part with empty writes."""
    par, ser = _both(_config(1, 3), mpi_tmp_path, "dynamic")
    assert differences(par, ser) == []
