"""The CLI starts, and every discovered command (and sub-command) documents itself."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

import pytest

from lutmpi.cli import build_parser, main


def _subparsers(parser: argparse.ArgumentParser) -> argparse._SubParsersAction | None:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action
    return None


def walk_commands(parser: argparse.ArgumentParser, prefix: tuple[str, ...] = ()):
    """Yield ``(words, help_text, parser)`` for every (nested) sub-command."""
    sub = _subparsers(parser)
    if sub is None:
        return
    helps = {a.dest: (a.help or "") for a in sub._choices_actions}
    for name, child in sub.choices.items():
        yield prefix + (name,), helps.get(name, ""), child
        yield from walk_commands(child, prefix + (name,))


COMMANDS = list(walk_commands(build_parser()))


def test_console_script_help():
    exe = Path(sys.executable).with_name("lutmpi")
    assert exe.is_file(), f"{exe} missing: run scripts/setup.sh (editable install)"
    res = subprocess.run([str(exe), "--help"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert "usage: lutmpi" in res.stdout


def test_main_help_exits_zero(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    assert "usage: lutmpi" in capsys.readouterr().out


def test_main_without_command_prints_help_and_returns_2(capsys):
    assert main([]) == 2
    assert "usage: lutmpi" in capsys.readouterr().out


@pytest.mark.parametrize("words,summary,parser", COMMANDS, ids=[" ".join(c[0]) for c in COMMANDS])
def test_every_command_has_help(words, summary, parser, capsys):
    assert summary.strip(), f"'lutmpi {' '.join(words)}' has no help= summary in its parent's list"
    with pytest.raises(SystemExit) as exc:
        main([*words, "--help"])
    assert exc.value.code == 0
    assert f"usage: lutmpi {' '.join(words)}" in capsys.readouterr().out
