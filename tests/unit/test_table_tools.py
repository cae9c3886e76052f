"""``lutmpi inspect`` and ``lutmpi plot`` on a small table (issue 4)."""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.config.load import load_config
from lutmpi.parallel.runner import build_table
from lutmpi.table import Table
from lutmpi.table.schema import J
from tests.support import faulty_solver
from tests.support.tables import write_config


@pytest.fixture(scope="module")
def table_path(tmp_path_factory):
    d = tmp_path_factory.mktemp("tools")
    cfg = load_config(write_config(d, ny=5, nyaw=3, methods=("load_centre", "max_distance")))
    out = d / "t.h5"
    build_table(cfg, out, solver=faulty_solver.solve, scene_factory=faulty_solver.make_scene)
    return out


def test_inspect_shows_metadata_status_ranges_and_units(table_path, capsys):
    assert main(["inspect", str(table_path), "--config"]) == 0
    text = capsys.readouterr().out
    assert "complete True" in text and "methods    load_centre, max_distance" in text
    assert "[max_distance]  status: converged 14, max_iterations 1" in text
    assert "wheel_point" in text and "(5, 3, 2, 2, 3)" in text
    assert "# stored configuration" in text and "[grid]" in text
    # the root wall time is the grid's; each method's jump step is summarised with its own
    assert "grid wall " in text
    table = Table.open(table_path)
    for m in ("load_centre", "max_distance"):
        jy, knots = table.jumps[m]["arrays"][J.jump_y], table.jumps[m]["arrays"][J.knot_y]
        per = np.isfinite(jy).sum(axis=1)
        line = next(ln for ln in text[text.index(f"[{m}]"):].splitlines() if "jumps:" in ln)
        assert line.strip().startswith(f"jumps: {per.sum()} located (per yaw column at most "
                                       f"{per.max()}), {np.isfinite(knots).sum()} extra knots,")


def test_inspect_of_a_missing_table_is_a_clean_error(tmp_path, capsys):
    assert main(["inspect", str(tmp_path / "nope.h5")]) == 1
    assert "no such table" in capsys.readouterr().err


@pytest.mark.parametrize("args", [["z_g"], ["wheel_point", "--component", "0"],
                                  ["normal", "--side", "right", "--slot", "1",
                                   "--method", "max_distance"]])
def test_plot_writes_a_figure(table_path, tmp_path, args):
    fig = tmp_path / "fig.png"
    assert main(["plot", str(table_path), *args, "-o", str(fig)]) == 0
    assert fig.stat().st_size > 10_000
    assert fig.read_bytes()[:4] == b"\x89PNG"
