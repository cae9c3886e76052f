"""The console script's quick end (``lutmpi.cli.run``, issue 14): a command that succeeded ends
with ``os._exit`` after flushing, skipping Python's teardown. Nothing it wrote may be lost: the
table, the files next to it and every line of its output are those of the same command run in
the usual way; a failed command still ends the usual way, with its message and status."""

from __future__ import annotations

import os
import subprocess
import sys

import pytest

from lutmpi.cli import main
from lutmpi.table import Table
from tests.support.tables import differences, write_config

pytestmark = pytest.mark.timeout(120)


def _run(*args: str, cwd) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=os.getcwd())
    env.pop("PYTHONUNBUFFERED", None)     # buffered, as a pipe is by default: flushing counts
    return subprocess.run([sys.executable, "-m", "lutmpi.cli", *args], capture_output=True,
                          text=True, env=env, cwd=cwd, timeout=100)


def test_a_build_ended_quickly_leaves_the_same_files_as_one_in_process(tmp_path, capsys):
    cfg = write_config(tmp_path, ny=5, nyaw=3)
    (tmp_path / "quick").mkdir()
    (tmp_path / "usual").mkdir()
    hook = ["--solver", "tests.support.faulty_solver:solve"]
    res = _run("build", str(cfg), "-o", str(tmp_path / "quick" / "t.h5"), *hook,
               cwd=os.getcwd())
    assert res.returncode == 0, res.stderr
    assert "table " in res.stderr and "status {'converged'" in res.stderr   # the log's last lines
    assert main(["build", str(cfg), "-o", str(tmp_path / "usual" / "t.h5"), *hook]) == 0
    assert sorted(p.name for p in (tmp_path / "quick").iterdir()) == sorted(
        p.name for p in (tmp_path / "usual").iterdir())
    assert Table.open(tmp_path / "quick" / "t.h5").attrs["complete"]
    assert differences(tmp_path / "quick" / "t.h5", tmp_path / "usual" / "t.h5") == []

    # every line of a command's output arrives, through a pipe too
    capsys.readouterr()
    assert main(["inspect", str(tmp_path / "usual" / "t.h5")]) == 0
    usual = capsys.readouterr().out
    quick = _run("inspect", str(tmp_path / "quick" / "t.h5"), cwd=os.getcwd())
    assert quick.returncode == 0, quick.stderr
    timing = ("created ", "compute time per point", "compute_time ")   # the run's own clock
    same = [line for line in usual.splitlines() if not line.lstrip().startswith(timing)]
    assert [line for line in quick.stdout.replace(str(tmp_path / "quick"), str(
        tmp_path / "usual")).splitlines() if not line.lstrip().startswith(timing)] == same
    assert len(same) > 10 and quick.stdout.endswith("\n")


def test_a_failed_command_ends_the_usual_way_with_its_message(tmp_path):
    res = _run("build", str(tmp_path / "missing.toml"), "-o", str(tmp_path / "t.h5"),
               cwd=os.getcwd())
    assert res.returncode == 1
    assert "lutmpi build: error:" in res.stderr and "missing.toml" in res.stderr
