"""``lutmpi profile plot CONFIG``: a PNG of both wheels on both rails, to scale."""

from pathlib import Path

from lutmpi.cli import main

ROOT = Path(__file__).resolve().parents[2]


def test_profile_plot_writes_a_png(tmp_path):
    out = tmp_path / "track.png"
    rc = main(["profile", "plot", str(ROOT / "configs" / "paper_s1002_uic60_1in20.toml"),
               "--y-mm", "3", "-o", str(out)])
    assert rc == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert out.stat().st_size > 20_000
