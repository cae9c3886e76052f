"""README: "the same table for every N, bit for bit" -- with the REAL solver (issue 16).

The parity tests of tests/unit/test_table_parity.py use a closed-form stand-in solver; here the
production solver (locus reference, compiled mesh kernels, Newton with bracketing, k_c iteration,
extrapolation) builds a small table of the paper's pair over the paper's range (flange and yawed
flange contacts included) with 1, 2 and 3 ranks under real ``mpirun``, and every dataset and
numerical root attribute must be identical bit for bit (``compute_time`` and the run attributes
excepted). A pose solve is pure, so the split must not change one bit; a rank that reused state
between points (a warm start, a cache keyed wrongly) would show up here.

~4 s per build on 2 busy cores (7 x 5 poses, three methods).
"""

from __future__ import annotations

import shutil
import subprocess

import numpy as np
import pytest

from lutmpi.table.schema import TIMING_FIELDS
from tests.support.tables import LUTMPI, datasets, differences, env, root_attrs

pytestmark = [pytest.mark.timeout(300),
              pytest.mark.skipif(shutil.which("mpirun") is None, reason="mpirun not installed")]

CONFIG = """[wheel]
generator = "S1002"
[rail]
generator = "UIC60"
inclination = "1:20"
[grid]
y_mm = [-9.0, 9.0, 7]
yaw_rad = [-0.12, 0.12, 5]
[contact]
method = "load_centre"
[output]
refine = false    # the grid is under test; jumps are still located
methods = ["load_centre", "max_normal_distance", "reference"]
"""


def _build(cfg, out, ranks: int, *args: str) -> subprocess.CompletedProcess:
    cmd = [LUTMPI, "build", str(cfg), "-o", str(out), *args]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks), *cmd]
    return subprocess.run(cmd, capture_output=True, text=True, timeout=240, env=env(),
                          stdin=subprocess.DEVNULL)


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    d = tmp_path_factory.mktemp("real_parity")
    cfg = d / "c.toml"
    cfg.write_text(CONFIG)
    out = d / "one.h5"
    r = _build(cfg, out, 1)
    assert r.returncode == 0, r.stderr[-3000:]
    return cfg, out


def test_serial_real_table_is_a_real_table(serial):
    """Guard against a vacuous parity: the real solver converged everywhere and found flange
    contacts (contact angle > 0.5 rad) and double contacts are allowed to differ from none."""
    _, out = serial
    data = datasets(out)
    for m in ("load_centre", "max_normal_distance", "reference"):
        assert np.all(data[f"{m}/status"] == 0), m
    assert np.nanmax(data["load_centre/contact_angle"]) > 0.5
    assert root_attrs(out)["ranks"] == 1


@pytest.mark.parametrize(("ranks", "split"), [(2, "dynamic"), (3, "dynamic"), (3, "block")])
def test_real_solver_n_ranks_equal_one_rank_bit_for_bit(serial, tmp_path, ranks, split):
    cfg, one = serial
    out = tmp_path / f"n{ranks}-{split}.h5"
    r = _build(cfg, out, ranks, "--split", split)
    assert r.returncode == 0, r.stderr[-3000:]
    assert root_attrs(out)["ranks"] == ranks
    assert differences(one, out) == []


def test_static_split_with_multi_point_batches_equals_serial(tmp_path):
    """A static split journals a rank's points in batches of len(mine) // 200 points; on the
    small grids above every batch is one point, so a writer that misplaced the points *within*
    a batch would pass them. 41 x 21 points on 2 ranks, block split: batches of 2 (closed-form
    stand-in solver: the writer is under test, not the numerics; ~10 s)."""
    from tests.support.tables import build, write_config

    cfg = write_config(tmp_path, ny=41, nyaw=21, methods=("load_centre",))
    one, two = tmp_path / "one.h5", tmp_path / "two.h5"
    r = build(cfg, one, 1, timeout=180)
    assert r.returncode == 0, r.stderr[-3000:]
    r = build(cfg, two, 2, "--split", "block", timeout=180)
    assert r.returncode == 0, r.stderr[-3000:]
    assert differences(one, two) == []


def test_jumps_false_is_the_grid_alone_with_a_warning_on_lookups(serial, tmp_path):
    """``[output] jumps = false`` (a table for a tool that reads the grid and interpolates by
    itself): on 2 ranks, every grid dataset is the bits of the default build's, no jumps group
    is written, the dynamics attributes are, and lutmpi's own lookups on it warn that they
    interpolate across contact jumps (the default table holds some: the flange)."""
    _, one = serial
    cfg = tmp_path / "grid_only.toml"
    cfg.write_text(CONFIG.replace("[output]\n", "[output]\njumps = false\n"))
    out = tmp_path / "grid_only.h5"
    r = _build(cfg, out, 2)
    assert r.returncode == 0, r.stderr[-3000:]
    assert "jump step left out (output.jumps = false)" in r.stderr
    full, grid = datasets(one), datasets(out)
    assert any("/jumps/" in name for name in full)
    assert sorted(grid) == sorted(n for n in full if "/jumps/" not in n)
    for name in grid:
        if name.rsplit("/", 1)[-1] not in TIMING_FIELDS:
            assert grid[name].tobytes() == full[name].tobytes(), name
    ra, rb = root_attrs(one), root_attrs(out)
    for key in ("wheel_flange_angle", "young_modulus", "poisson_ratio", "nominal_radius",
                "vertical_load"):
        assert rb[key] == ra[key], key
    q = subprocess.run([LUTMPI, "query", str(out), "--pose", "4.5", "0.0"], capture_output=True,
                       text=True, timeout=120, env=env(), stdin=subprocess.DEVNULL)
    assert q.returncode == 0, q.stderr[-3000:]
    assert "holds no located contact jumps" in q.stderr
    q = subprocess.run([LUTMPI, "query", str(one), "--pose", "4.5", "0.0"], capture_output=True,
                       text=True, timeout=120, env=env(), stdin=subprocess.DEVNULL)
    assert q.returncode == 0 and "holds no located contact jumps" not in q.stderr
