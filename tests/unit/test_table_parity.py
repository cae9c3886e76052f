"""Parity and failure drills of ``lutmpi build`` under ``mpirun`` (issue 4; faults of issue 7).

Each test launches real jobs (``mpirun -n K lutmpi build ... --solver <closed-form test solver>``)
with a hard timeout and compares the files bit for bit (timing fields excepted).
"""

from __future__ import annotations

import shutil
import time

import h5py
import pytest

from lutmpi.parallel.partition import split
from lutmpi.table import journal
from tests.support.tables import build, datasets, differences, root_attrs, write_config

pytestmark = [pytest.mark.timeout(120),
              pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun not installed")]


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """One serial build of the small two-method table: the reference of every comparison."""
    d = tmp_path_factory.mktemp("ref")
    cfg = write_config(d, ny=7, nyaw=5, methods=("load_centre", "max_distance"))
    out = d / "ref.h5"
    res = build(cfg, out, 1)
    assert res.returncode == 0, res.stderr
    return cfg, out


@pytest.mark.parametrize(("ranks", "how"), [(2, "dynamic"), (3, "dynamic"), (4, "dynamic"),
                                               (2, "scattered"), (3, "block")])
def test_n_ranks_equal_one_rank_bit_for_bit(reference, tmp_path, ranks, how):
    cfg, ref = reference
    out = tmp_path / f"n{ranks}-{how}.h5"
    res = build(cfg, out, ranks, "--checkpoint-interval", "0", "--split", how)
    assert res.returncode == 0, res.stderr
    assert differences(ref, out) == []
    assert root_attrs(out)["ranks"] == ranks
    assert root_attrs(out)["complete"]
    assert not out.with_name(out.name + ".partial").exists()


def test_more_ranks_than_rows_and_points(tmp_path):
    """5 ranks on a 2 x 2 grid: three ranks own no row, one computes nothing; still identical."""
    cfg = write_config(tmp_path, ny=2, nyaw=2)
    one, three = tmp_path / "one.h5", tmp_path / "five.h5"
    assert build(cfg, one, 1).returncode == 0
    res = build(cfg, three, 5)
    assert res.returncode == 0, res.stderr
    assert differences(one, three) == []


def test_dynamic_rank_raising_ends_job(reference, tmp_path):
    cfg, _ = reference
    out = tmp_path / "t.h5"
    res = build(cfg, out, 3, timeout=60, LUTMPI_FAULT="raise@-6.0/0.12")
    assert res.returncode != 0 and "failed: RuntimeError: injected fault" in res.stderr
    assert "iy=1, iyaw=4" in res.stderr and not out.exists()


def test_rank_raising_mid_build_ends_job_fast_and_names_the_point(reference, tmp_path):
    cfg, _ = reference
    out = tmp_path / "t.h5"
    t0 = time.monotonic()
    # y = 3 mm, yaw = 0.06 rad is flat point 4 * 5 + 3 = 23
    owner = [r for r in range(2) if 23 in split(35, 2, r, "cyclic")][0]
    res = build(cfg, out, 2, "--split", "cyclic", timeout=60, LUTMPI_FAULT="raise@3.0/0.06")
    elapsed = time.monotonic() - t0
    assert res.returncode != 0
    assert elapsed < 30, elapsed
    assert f"rank {owner}/2 failed" in res.stderr
    assert "iy=4, iyaw=3" in res.stderr and "y=3 mm" in res.stderr
    assert not out.exists()


def test_sigkill_of_a_rank_then_resume_equals_fresh_build(reference, tmp_path):
    cfg, ref = reference
    out = tmp_path / "t.h5"
    partial = out.with_name(out.name + ".partial")
    # the kill comes at y = 6 mm (row 5 of 7), late in the build
    res = build(cfg, out, 2, "--checkpoint-interval", "0", timeout=60,
                LUTMPI_FAULT="kill@6.0/0.0")
    assert res.returncode != 0
    assert not out.exists()
    assert partial.exists()
    with h5py.File(partial, "r") as f:
        assert not f.attrs["complete"]
    done = len(journal.done_points(journal.journal_dir(out)))
    assert 0 < done < 35
    res = build(cfg, out, 3, "--resume")   # any number of ranks may resume
    assert res.returncode == 0, res.stderr
    assert f"{35 - done} computed, {done} reused" in res.stderr
    assert differences(ref, out) == []
    assert not partial.exists() and not journal.journal_dir(out).exists()


def test_partial_without_resume_is_refused(reference, tmp_path):
    cfg, _ = reference
    out = tmp_path / "t.h5"
    out.with_name(out.name + ".partial").write_bytes(b"not hdf5")
    res = build(cfg, out, 2)
    assert res.returncode != 0
    assert "--resume" in res.stderr and not out.exists()
    res = build(cfg, out, 2, "--resume")   # a partial without its journal: clear error
    assert res.returncode != 0 and "has no journal" in res.stderr
    assert "Traceback" not in res.stderr


def test_existing_output_refused_without_force(reference, tmp_path):
    cfg, ref = reference
    out = tmp_path / "t.h5"
    out.write_bytes(b"precious")
    res = build(cfg, out, 2)
    assert res.returncode != 0 and "--force" in res.stderr
    assert out.read_bytes() == b"precious"
    res = build(cfg, out, 2, "--force")
    assert res.returncode == 0, res.stderr
    assert differences(ref, out) == []


def test_unwritable_output_fails_before_compute(reference, tmp_path):
    cfg, _ = reference
    blocker = tmp_path / "file"
    blocker.write_text("a file, not a directory")
    # the solver would die on the first point: reaching it would show compute started
    res = build(cfg, blocker / "t.h5", 2, LUTMPI_FAULT="raise@-9.0/-0.12")
    assert res.returncode != 0
    assert "not a directory" in res.stderr
    assert "injected fault" not in res.stderr


@pytest.mark.skipif(not shutil.os.access("/proc/version", shutil.os.R_OK), reason="no /proc")
def test_read_only_filesystem_fails_before_compute(reference):
    cfg, _ = reference
    res = build(cfg, "/proc/lutmpi-t.h5", 2, LUTMPI_FAULT="raise@-9.0/-0.12")
    assert res.returncode != 0
    assert "not writable" in res.stderr and "injected fault" not in res.stderr


def test_only_requested_methods_and_quantities_are_stored(tmp_path):
    cfg = write_config(tmp_path, ny=3, nyaw=3, methods=("max_distance",),
                       quantities=("z_g", "normal", "curvatures"))
    out = tmp_path / "t.h5"
    res = build(cfg, out, 2)
    assert res.returncode == 0, res.stderr
    names = {n for n in datasets(out) if "/" in n and "/jumps/" not in n}
    assert names == {f"max_distance/{q}" for q in (
        "z_g", "normal", "curv_wheel_rolling", "curv_wheel_transverse", "curv_rail_transverse",
        "status", "iterations", "compute_time")}
