"""Serial build (in process), Table.open / interp / get, and the reader's refusals (issue 4)."""

from __future__ import annotations

import os
import shutil
import subprocess
import sys

import h5py
import numpy as np
import pytest

from lutmpi.config.load import load_config
from lutmpi.errors import TableError
from lutmpi.parallel.runner import build_table
from lutmpi.table import Table
from lutmpi.table.schema import SCHEMA_VERSION
from tests.support import faulty_solver
from tests.support.tables import differences, write_config


def _build(tmp_path, name="t.h5", **kw):
    cfg = load_config(write_config(tmp_path, ny=7, nyaw=5, methods=("load_centre", "reference")))
    out = tmp_path / name
    summary = build_table(cfg, out, solver=kw.pop("solver", faulty_solver.solve),
                          scene_factory=faulty_solver.make_scene, **kw)
    return cfg, out, summary


@pytest.fixture
def table(tmp_path):
    _, out, summary = _build(tmp_path)
    assert summary.points == 35 and summary.computed == 35
    assert summary.status_counts == {"converged": 68, "max_iterations": 2}
    return Table.open(out)


def test_metadata_units_and_config_are_stored(table):
    assert table.methods == ["load_centre", "reference"]
    assert table.attrs["complete"] and table.attrs["schema_version"] == SCHEMA_VERSION
    assert "[grid]" in table.config_toml and table.attrs["ranks"] == 1
    assert table.units("wheel_point") == "m" and table.units("contact_angle") == "rad"
    assert table.y[0] == pytest.approx(-9e-3) and table.yaw[-1] == pytest.approx(0.12)
    assert table.status_counts() == {"converged": 34, "max_iterations": 1}


def test_interp_reproduces_nodes_and_is_linear_between(table):
    y, yaw = table.y[2], table.yaw[3]
    q = table.interp(y, yaw)
    assert q["roll"] == pytest.approx(0.05 * y)
    assert q["wheel_point"].shape == (2, 2, 3)
    # roll is linear in y: bilinear must be exact anywhere inside
    ys = np.linspace(-8e-3, 8e-3, 11)
    r = table.interp(ys, 0.031, quantities=["roll", "status"])
    assert np.allclose(r["roll"], 0.05 * ys, rtol=0, atol=1e-15)
    assert r["status"].dtype.kind == "i" and (r["status"] == 0).all()
    assert table.interp(ys, 0.0, method="reference")["roll"] == pytest.approx(0.99 * 0.05 * ys)


def test_outside_the_grid_raises_or_is_flagged_never_clipped(table):
    """Issue 11: a query outside the grid is an error, or NaN with an explicit flag."""
    with pytest.raises(ValueError, match="outside the table grid"):
        table.interp(0.05, 0.0, quantities=["roll"])
    with pytest.raises(ValueError, match="outside the table grid"):
        table.interp(0.0, 0.2)
    q = table.interp([0.05, 0.0, np.nan], 0.0, quantities=["roll", "status"], outside="flag")
    assert q["out_of_range"].tolist() == [True, False, True]
    assert np.isnan(q["roll"][0]) and np.isnan(q["roll"][2]) and q["status"][0] == -1
    assert q["roll"][1] == pytest.approx(0.0, abs=1e-15)
    with pytest.raises(ValueError, match="never clips"):
        table.interp(0.0, 0.0, outside="clip")


def test_failed_points_are_nan_and_spread_only_with_weight(table):
    # the corner (y=-9 mm, yaw=-0.12) did not converge in the test solver
    assert np.isnan(table.get("roll")[0, 0]) and not np.isnan(table.get("roll", raw=True)[0, 0])
    assert np.isnan(table.interp(-8.9e-3, -0.119, quantities=["roll"])["roll"])
    # on the neighbouring node the failed corner has zero weight
    assert not np.isnan(table.interp(table.y[1], table.yaw[0], quantities=["roll"])["roll"])
    # missing second contacts are NaN, present ones are not
    f = table.get("force")
    assert np.isnan(f[:, :, 0, 1]).all() and not np.isnan(f[-1, 1:, 1, 1]).any()


def test_reader_refuses_newer_schema_incomplete_and_missing(tmp_path, table):
    newer = tmp_path / "newer.h5"
    shutil.copy(table.path, newer)
    with h5py.File(newer, "r+") as f:
        f.attrs["schema_version"] = SCHEMA_VERSION + 1
    with pytest.raises(TableError, match="newer than this lutmpi"):
        Table.open(newer)
    with h5py.File(newer, "r+") as f:
        f.attrs["schema_version"] = SCHEMA_VERSION
        f.attrs["complete"] = False
    with pytest.raises(TableError, match="incomplete"):
        Table.open(newer)
    with pytest.raises(TableError, match="no such table"):
        Table.open(tmp_path / "nope.h5")


def test_a_table_another_process_holds_open_is_named_as_locked(tmp_path, table):
    """A second process has the file open for writing (as a running build has its
    ``.partial``): reading it says so and what to do, not "not a readable HDF5 file"."""
    held = tmp_path / "t.h5.partial"
    shutil.copy(table.path, held)
    code = ("import h5py, sys, time\nf = h5py.File(sys.argv[1], 'r+')\n"
            "print('open', flush=True)\ntime.sleep(60)\n")
    env = {k: v for k, v in os.environ.items() if k != "HDF5_USE_FILE_LOCKING"}
    with subprocess.Popen([sys.executable, "-c", code, str(held)], stdout=subprocess.PIPE,
                          text=True, env=env) as proc:
        try:
            assert proc.stdout.readline().strip() == "open"
            with pytest.raises(TableError, match="unfinished output, locked by another "
                                                 "process") as info:
                Table.open(held)
            assert str(held) in str(info.value)
        finally:
            proc.kill()
    assert Table.open(held).path is not None          # readable once the other process ended
    # a file that is no HDF5, in a folder whose name holds "lock": not taken for a locked one
    from lutmpi.table.h5io import read_attrs
    junk = tmp_path / "clock" / "t.h5"
    junk.parent.mkdir()
    junk.write_text("not hdf5")
    with pytest.raises(TableError, match="not a readable HDF5 file"):
        read_attrs(junk)


def test_differences_detects_a_changed_value(tmp_path, table):
    other = tmp_path / "other.h5"
    shutil.copy(table.path, other)
    assert differences(table.path, other) == []
    with h5py.File(other, "r+") as f:
        f["reference/roll"][3, 3] = np.nextafter(f["reference/roll"][3, 3], 1.0)
    assert differences(table.path, other) == ["reference/roll"]


def test_existing_output_and_full_disk_fail_before_compute(tmp_path, monkeypatch):
    calls = []

    def counting(*args):
        calls.append(args)
        return faulty_solver.solve(*args)

    _, out, _ = _build(tmp_path, solver=counting)
    n = len(calls)
    with pytest.raises(TableError, match="--force"):
        _build(tmp_path, solver=counting)
    monkeypatch.setattr(shutil, "disk_usage", lambda p: shutil._ntuple_diskusage(1, 1, 1000))
    with pytest.raises(TableError, match="MB free"):
        _build(tmp_path, name="u.h5", solver=counting)
    assert len(calls) == n and not (tmp_path / "u.h5").exists()
    assert not (tmp_path / "u.h5.partial").exists()


def test_resume_of_a_partial_recomputes_only_missing_points(tmp_path):
    _, ref, _ = _build(tmp_path, name="ref.h5")
    calls = []

    def dies_late(scene, y, yaw, method):
        if y > 5e-3:
            raise KeyboardInterrupt  # an interrupted run
        calls.append((y, yaw))
        return faulty_solver.solve(scene, y, yaw, method)

    with pytest.raises(KeyboardInterrupt):
        _build(tmp_path, name="t.h5", solver=dies_late, checkpoint_interval_s=0.0)
    out = tmp_path / "t.h5"
    assert not out.exists() and (tmp_path / "t.h5.partial").exists()
    with pytest.raises(TableError, match="--resume"):
        _build(tmp_path, name="t.h5")
    _, _, summary = _build(tmp_path, name="t.h5", resume=True)
    assert 0 < summary.reused < 35 and summary.computed == 35 - summary.reused
    assert differences(ref, out) == []
