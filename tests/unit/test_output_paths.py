"""Every command checks its output path before its work (issue 13, item 6).

Each command is given a *missing* input and a bad output: the error must be about the output,
which shows the check comes first (simulate used to run the whole simulation, then fail).
"""

from __future__ import annotations

import pytest

from lutmpi.cli import main
from lutmpi.errors import OutputError
from lutmpi.outpath import check_output_dir, check_output_file

BAD = {"device": "/dev/null", "no folder": "/nonexistent-lutmpi/x.out", "empty": ""}


@pytest.mark.parametrize("bad", sorted(BAD))
@pytest.mark.parametrize("argv", [
    ["plot", "missing.h5", "z_g", "-o", "{out}"],
    ["conicity", "missing.h5", "--plot", "{out}"],
    ["conicity", "missing.h5", "-o", "{out}"],
    ["simulate", "missing.toml", "--table", "missing.h5", "-o", "{out}"],
])
def test_file_outputs_checked_before_the_work(argv, bad, capsys):
    rc = main([a.replace("{out}", BAD[bad]) for a in argv])
    err = capsys.readouterr().err
    assert rc == 1
    assert "missing" not in err and "Traceback" not in err, err
    assert any(w in err for w in ("not a regular file", "does not exist", "names no file")), err


@pytest.mark.parametrize("argv", [["report", "missing-dir", "-o", "{out}"],
                                  ["sweep", "missing.toml", "-o", "{out}"]])
def test_folder_outputs_checked_before_the_work(argv, capsys):
    rc = main([a.replace("{out}", "/dev/null/report") for a in argv])
    err = capsys.readouterr().err
    assert rc == 1 and "/dev/null is not a folder" in err, err


def test_build_empty_output_is_a_clear_error(repo_root, capsys):
    rc = main(["build", str(repo_root / "configs" / "small_test.toml"), "-o", ""])
    assert rc == 1 and "names no file" in capsys.readouterr().err


def test_proc_is_not_writable_even_for_root():
    # access(2) lets root "write" /proc; the probe file shows it cannot take a new file
    with pytest.raises(OutputError, match="not writable"):
        check_output_file("/proc/lutmpi-test.h5")


def test_good_paths_pass(tmp_path):
    assert check_output_file(tmp_path / "a.png") == tmp_path / "a.png"
    assert check_output_dir(tmp_path / "new" / "deeper") == tmp_path / "new" / "deeper"
    assert list(tmp_path.iterdir()) == []          # the checks write nothing that stays
