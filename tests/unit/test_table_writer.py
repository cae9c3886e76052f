"""The table writer's guards, in one process (issue 13): the journal's checksums, input hashes by
content, the output lock, output-path checks, and clear errors on damaged table files.

Builds use the closed-form test solver (:mod:`tests.support.faulty_solver`); an interrupted build
is made by a solver that raises at a chosen pose, which leaves the journal as a crash would.
"""

from __future__ import annotations

import dataclasses
import os
import shutil
import stat
import subprocess

import h5py
import numpy as np
import pytest

from lutmpi.config.load import load_config
from lutmpi.errors import TableError
from lutmpi.parallel.runner import build_table
from lutmpi.table import journal, provenance
from lutmpi.table.h5io import read_table
from lutmpi.table.lock import OutputLock
from lutmpi.table.schema import TIMING_FIELDS, select_fields
from tests.support import faulty_solver
from tests.support.tables import differences, write_config

N = 5 * 3


def _build(cfg, out, **kw):
    return build_table(cfg, out, solver=kw.pop("solver", faulty_solver.solve),
                       scene_factory=faulty_solver.make_scene, checkpoint_interval_s=0.0, **kw)


def _stop_at(k_stop: int):
    """A solver that raises after ``k_stop`` poses, as a crash would."""
    calls = {"n": 0}

    def solve(scene, y, yaw, method):
        calls["n"] += 1
        if calls["n"] > k_stop:
            raise RuntimeError("crash (test)")
        return faulty_solver.solve(scene, y, yaw, method)

    return solve


@pytest.fixture
def cfg(tmp_path):
    return load_config(write_config(tmp_path, ny=5, nyaw=3))


@pytest.fixture
def fresh(cfg, tmp_path):
    out = tmp_path / "fresh.h5"
    _build(cfg, out)
    return out


def _interrupted(cfg, out, points: int) -> np.ndarray:
    with pytest.raises(RuntimeError, match="crash"):
        _build(cfg, out, solver=_stop_at(points))   # one method: one solve per point
    done = journal.done_points(journal.journal_dir(out))
    assert len(done) == points
    return done


def test_resume_reuses_exactly_the_journaled_points(cfg, fresh, tmp_path):
    out = tmp_path / "t.h5"
    _interrupted(cfg, out, 6)
    with pytest.raises(TableError, match=r"incomplete .* 6 of 15 points are journaled"):
        read_table(tmp_path / "t.h5.partial")        # what `lutmpi inspect` says of it
    summary = _build(cfg, out, resume=True)
    assert (summary.reused, summary.computed) == (6, N - 6)
    assert differences(fresh, out) == []
    assert not journal.journal_dir(out).exists() and not out.with_name("t.h5.lock").exists()


@pytest.mark.parametrize("damage", ["garbage_value", "torn_tail", "flipped_header"])
def test_damaged_journal_records_are_recomputed_never_reused(cfg, fresh, tmp_path, damage, caplog):
    out = tmp_path / "t.h5"
    _interrupted(cfg, out, 6)
    (path,) = journal.record_files(journal.journal_dir(out))
    data = bytearray(path.read_bytes())
    first = data.find(journal.MAGIC)
    second = data.find(journal.MAGIC, first + 1)
    if damage == "garbage_value":      # a value of the first record doctored to 1e295
        data[second - 8:second] = np.float64(1e295).tobytes()
    elif damage == "torn_tail":        # a kill in the middle of the last write
        data = data[:-7]
    else:                              # the length field of the first record
        data[first + 9] ^= 0xFF
    path.write_bytes(bytes(data))
    summary = _build(cfg, out, resume=True)
    assert summary.reused == 5 and summary.computed == N - 5
    assert "damaged or torn" in caplog.text
    assert differences(fresh, out) == []


def test_journal_of_other_inputs_fails_every_check(cfg, tmp_path):
    """Records are keyed by the inputs' hash: a journal copied from another build reuses nothing."""
    out = tmp_path / "t.h5"
    _interrupted(cfg, out, 4)
    fields = select_fields(cfg.output.quantities)
    dtype = journal.record_dtype(cfg.output.methods, fields)
    (path,) = journal.record_files(journal.journal_dir(out))
    good, ok = journal.read_records(path, dtype, provenance.input_record(cfg)["sha256"], N)
    other, report = journal.read_records(path, dtype, "0" * 64, N)
    assert sum(len(a) for a in good) == 4 and (ok.good, ok.bad) == (4, 0)
    assert other == [] and (report.good, report.bad) == (0, 4)


def test_inputs_are_content_not_paths(tmp_path, repo_root):
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir(), b.mkdir()
    for d, name in ((a, "w.whl"), (b, "other-name.whl")):
        shutil.copy(repo_root / "profiles" / "avg_wheel.whl", d / name)
        (d / "c.toml").write_text(f'[wheel]\nprofile = "{name}"\n[rail]\ngenerator = "UIC60"\n')
    ca, cb = load_config(a / "c.toml"), load_config(b / "c.toml")
    ra, rb = provenance.input_record(ca), provenance.input_record(cb)
    assert ra["sha256"] == rb["sha256"] and provenance.differences(ra, rb) == []
    (b / "other-name.whl").write_bytes((b / "other-name.whl").read_bytes() + b"\n")
    diffs = provenance.differences(ra, provenance.input_record(cb))
    assert len(diffs) == 1 and diffs[0].startswith("wheel.profile ") and "content differs" in \
        diffs[0]
    changed = dataclasses.replace(ca, track=dataclasses.replace(ca.track, gauge_mm=1432.0))
    assert provenance.differences(ra, provenance.input_record(changed)) == [
        "track.gauge_mm = 1435.0 then, 1432.0 now"]


def test_resume_with_a_changed_setting_is_refused_naming_it(cfg, tmp_path):
    out = tmp_path / "t.h5"
    _interrupted(cfg, out, 3)
    other = dataclasses.replace(cfg, equilibrium=dataclasses.replace(cfg.equilibrium,
                                                                     max_iterations=7))
    was = cfg.equilibrium.max_iterations
    with pytest.raises(TableError, match=rf"equilibrium.max_iterations = {was} then, 7 now"):
        _build(other, out, resume=True)
    assert len(journal.done_points(journal.journal_dir(out))) == 3      # nothing lost
    summary = _build(other, out, force=True)                           # recomputed on request
    assert summary.computed == N and summary.reused == 0


def test_table_records_its_inputs(cfg, fresh):
    import json

    stored = json.loads(read_table(fresh)["attrs"]["inputs"])
    assert stored["sha256"] == provenance.input_record(cfg)["sha256"]


def test_second_lock_is_refused_naming_the_holder(tmp_path):
    first, second = OutputLock(tmp_path / "t.h5"), OutputLock(tmp_path / "t.h5")
    first.acquire()
    try:
        with pytest.raises(TableError, match=rf"pid {os.getpid()} on host"):
            second.acquire()
    finally:
        first.release()
    second.acquire()          # free again once released
    second.release()
    assert not (tmp_path / "t.h5.lock").exists()


def test_build_while_locked_is_refused_before_compute(cfg, tmp_path):
    lock = OutputLock(tmp_path / "t.h5")
    lock.acquire()
    try:
        with pytest.raises(TableError, match="being written by another lutmpi build"):
            _build(cfg, tmp_path / "t.h5", force=True,
                   solver=lambda *a: pytest.fail("compute started"))
    finally:
        lock.release()


@pytest.mark.parametrize("target", ["device", "folder", "symlink", "empty"])
def test_force_never_replaces_what_is_not_a_regular_file(cfg, tmp_path, target):
    out = tmp_path / "t.h5"
    if target == "device":
        out = tmp_path / "null"
        os.mknod(out, 0o666 | stat.S_IFCHR, os.makedev(1, 3))   # a /dev/null twin
    elif target == "folder":
        out.mkdir()
    elif target == "symlink":
        (tmp_path / "precious").write_text("keep")
        out.symlink_to(tmp_path / "precious")
    else:
        out = ""
    with pytest.raises(TableError, match="not a regular file|is a folder|names no file"):
        _build(cfg, out, force=True, solver=lambda *a: pytest.fail("compute started"))
    if target == "device":
        assert stat.S_ISCHR(os.stat(out).st_mode)
    if target == "symlink":
        assert out.is_symlink() and (tmp_path / "precious").read_text() == "keep"


def test_read_only_output_folder_is_a_clear_error(cfg, tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    if shutil.which("mount") is None:
        pytest.skip("mount not available")
    res = subprocess.run(["mount", "--bind", "-o", "ro", str(ro), str(ro)], capture_output=True)
    if res.returncode != 0:
        pytest.skip("cannot bind-mount read-only here")
    try:
        subprocess.run(["mount", "-o", "remount,bind,ro", str(ro)], capture_output=True)
        with pytest.raises(TableError, match="not writable"):
            _build(cfg, ro / "t.h5", solver=lambda *a: pytest.fail("compute started"))
    finally:
        subprocess.run(["umount", str(ro)], capture_output=True)


# -- damaged or foreign table files --------------------------------------------------------------

def _doctor(src, dst, edit):
    shutil.copy(src, dst)
    with h5py.File(dst, "r+") as f:
        edit(f)
    return dst


@pytest.mark.parametrize(("edit", "message"), [
    (lambda f: f.attrs.__delitem__("methods"), "root attribute 'methods' is missing"),
    (lambda f: f.attrs.modify("methods", "[not json"), "'methods' is not a JSON list"),
    (lambda f: f.__delitem__("load_centre"), "group /load_centre"),
    (lambda f: f["load_centre"].__delitem__("status"), "/load_centre/status is missing"),
    (lambda f: f.__delitem__("yaw"), "dataset /yaw is missing"),
    (lambda f: f.attrs.__delitem__("schema_version"), "not a lutmpi table"),
    (lambda f: f.attrs.modify("config_toml", "not = [toml"), "'config_toml' is not valid TOML"),
])
def test_damaged_table_is_a_clear_error_naming_file_and_what(fresh, tmp_path, edit, message):
    bad = _doctor(fresh, tmp_path / "bad.h5", edit)
    with pytest.raises(TableError, match=message) as info:
        read_table(bad)
    assert str(bad) in str(info.value)


def test_foreign_hdf5_is_a_clear_error(tmp_path):
    path = tmp_path / "foreign.h5"
    with h5py.File(path, "w") as f:
        f["x"] = np.arange(3)
    with pytest.raises(TableError, match="not a lutmpi table"):
        read_table(path)


def test_sweep_rerun_compares_contents_not_paths(tmp_path, repo_root):
    """A member whose profile changed since its table was built is not kept (issue 13, item 1);
    ``--force`` recomputes it; an unchanged member is skipped."""
    from lutmpi.parallel.sweep_runner import run_sweep

    wheel = tmp_path / "w.whl"
    shutil.copy(repo_root / "profiles" / "avg_wheel.whl", wheel)
    sweep = tmp_path / "s.toml"
    sweep.write_text('[base.wheel]\nprofile = "w.whl"\n[base.rail]\ngenerator = "UIC60"\n'
                     '[base.grid]\ny_mm = [-3.0, 3.0, 3]\nyaw_rad = [-0.01, 0.01, 3]\n'
                     '[[sweep]]\nproduct = { "track.gauge_mm" = [1435.0] }\n')
    out = tmp_path / "out"
    kw = {"solver": faulty_solver.solve, "scene_factory": faulty_solver.make_scene}
    first = run_sweep(sweep, out, **kw)
    assert [m.status for m in first.members] == ["ok"]
    again = run_sweep(sweep, out, **kw)
    assert again.members[0].skipped
    wheel.write_bytes(wheel.read_bytes() + b"\n")
    changed = run_sweep(sweep, out, **kw)
    (member,) = changed.members
    assert member.status == "failed" and "wheel.profile" in member.message
    forced = run_sweep(sweep, out, force=True, **kw)
    assert forced.members[0].status == "ok" and not forced.members[0].skipped


def test_commands_on_an_all_failed_table_are_clear_errors(fresh, tmp_path, capsys):
    """``conicity`` on a table whose every point failed raised TypeError (issue 13, item 7)."""
    from lutmpi.cli import main

    bad = _doctor(fresh, tmp_path / "failed.h5",
                  lambda f: f["load_centre/status"].__setitem__(Ellipsis, 2))
    assert main(["conicity", str(bad)]) == 1
    err = capsys.readouterr().err
    assert "lutmpi conicity: error:" in err and "Traceback" not in err


def test_kill_while_the_journal_was_being_created_resumes_afresh(cfg, fresh, tmp_path):
    out = tmp_path / "t.h5"
    journal.journal_dir(out).mkdir()          # mkdir done, header not yet written
    summary = _build(cfg, out, resume=True)
    assert (summary.computed, summary.reused) == (N, 0)
    assert differences(fresh, out) == []


@pytest.mark.parametrize("chunk, split", [(4, "dynamic"), (4, "block"), (256, "dynamic")])
def test_points_filled_in_the_store_reach_the_table(cfg, tmp_path, monkeypatch, chunk, split):
    """Issue 14: a rank fills its points in place in a store of the journal's layout, in chunks.
    Across chunk boundaries (4 rows: the 9 points left over 3 chunks; batches of 3 points with
    ``block``, which leave a chunk's last row unused) and mixed with the records a resume reads
    back, every point lands in its own cell with the values the plain records give."""
    from lutmpi.parallel import runner
    from lutmpi.parallel import writer as writer_mod
    from lutmpi.table.compute import compute_points
    from lutmpi.table.grid import Grid

    monkeypatch.setattr(writer_mod, "STORE_CHUNK", chunk)
    monkeypatch.setattr(runner, "N_STEPS", 3)          # a static split: batches of 3 points
    out = tmp_path / "t.h5"
    _interrupted(cfg, out, 6)
    summary = _build(cfg, out, resume=True, split=split)
    assert (summary.reused, summary.computed) == (6, N - 6)
    grid = Grid.from_config(cfg.grid)
    fields = select_fields(cfg.output.quantities)
    methods = tuple(cfg.output.methods)
    plain, _ = compute_points(faulty_solver.make_scene(cfg), grid, np.arange(grid.n_points),
                              methods, faulty_solver.solve, fields)
    table = read_table(out)["methods"]
    for m in methods:
        for f in fields:
            if f.name in TIMING_FIELDS:
                continue           # the time each solve took: differs from run to run
            want = plain[m][f.name].reshape(grid.shape + f.suffix)
            np.testing.assert_array_equal(table[m][f.name], want, err_msg=f"{m}/{f.name}")
