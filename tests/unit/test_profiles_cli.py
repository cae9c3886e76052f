"""``lutmpi profile show``: generator and file output, wrong kind exits non-zero."""

from __future__ import annotations

import pytest

from lutmpi.cli import main
from lutmpi.paths import REPO_ROOT


def test_show_generator(capsys: pytest.CaptureFixture[str]):
    assert main(["profile", "show", "--generator", "S1002"]) == 0
    out = capsys.readouterr().out
    assert "flange height : 28.000 mm" in out and "flange thick. : 32.500 mm" in out
    assert main(["profile", "show", "--generator", "UIC60"]) == 0
    out = capsys.readouterr().out
    assert "head width    : 71.962 mm" in out and "v = -35.981 mm" in out


def test_show_file_and_wrong_kind(capsys: pytest.CaptureFixture[str]):
    f = str(REPO_ROOT / "profiles" / "MBench_UIC60_v3.prr")   # = shared/profiles' copy
    assert main(["profile", "show", f]) == 0
    assert "1:40.0" in capsys.readouterr().out
    assert main(["profile", "show", f, "--kind", "wheel"]) == 1
    assert "where a wheel is expected" in capsys.readouterr().err


def test_profile_without_subcommand_prints_help(capsys: pytest.CaptureFixture[str]):
    assert main(["profile"]) == 2
