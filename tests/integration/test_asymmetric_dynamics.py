"""Issue 10: the dynamics on a wheelset with two different measured wheels on two different rails.

One table (reference method, 33 x 5 poses, ~12 s): two worn wheels of ``profiles/`` (their
``Δr(0)`` is ~0.35 mm) on the MBench rail and a worn rail. Before this was fixed the online
provider refused the scene (``scene.wheel``), the table's flange angle was the left wheel's, and
``simulate`` died with a SciPy traceback ("f(a) and f(b) must have different signs") at 0.9 s,
where the wheelset presses onto the flange jump; once past that, it crawled at 0.005 simulated s
per wall s through thousands of microsecond pieces along the jump (887 518 evaluations for 2 s).
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lutmpi.config import load_config
from lutmpi.dynamics.contact_provider import OnlineProvider, TableProvider
from lutmpi.dynamics.simulate import simulate
from lutmpi.paths import REPO_ROOT
from lutmpi.providers import params_from_table
from lutmpi.scene_config import scene_from_config, side_profiles
from lutmpi.table import Table
from lutmpi.table.jumps import wheel_flange_angle
from tests.support.tables import TWO_MEASURED_WHEELS, env

pytestmark = [pytest.mark.slow, pytest.mark.timeout(900)]
LUTMPI = str(Path(sys.executable).with_name("lutmpi"))
CONFIG = TWO_MEASURED_WHEELS.replace("[rail.left]", "nominal_radius_mm = 459.0\n[rail.left]") + """
[grid]
y_mm = [-8.0, 8.0, 33]
yaw_rad = [-0.01, 0.01, 5]
[contact]
method = "reference"
[output]
methods = ["reference"]
"""


@pytest.fixture(scope="module")
def asym(tmp_path_factory):
    d = tmp_path_factory.mktemp("asym_dyn")
    cfg, out = d / "asym.toml", d / "asym.h5"
    cfg.write_text(CONFIG)
    res = subprocess.run([LUTMPI, "build", str(cfg), "-o", str(out)], capture_output=True,
                         text=True, timeout=600, env=env(), cwd=str(REPO_ROOT))
    assert res.returncode == 0, res.stdout + res.stderr
    return cfg, Table.open(out)


def test_the_table_carries_both_wheels_data(asym):
    """Flange angle: the smaller of the two wheels' (the lower Nadal limit); nominal radius:
    the mean of 460 and 459 mm. Each from the profiles themselves, not from the table."""
    cfg, table = asym
    wheels, _ = side_profiles(load_config(cfg))
    angles = [wheel_flange_angle(wheels[n]) for n in ("left", "right")]
    assert abs(angles[0] - angles[1]) > 0.01            # the two wheels do differ
    assert table.attribute("wheel_flange_angle") == pytest.approx(min(angles), abs=1e-12)
    assert table.attribute("nominal_radius") == pytest.approx(0.4595, abs=1e-12)
    online = OnlineProvider(scene_from_config(load_config(cfg)), "reference")
    assert online.flange_angle == pytest.approx(min(angles), abs=1e-12)


def test_simulate_passes_the_flange_jump_it_slides_along(asym):
    """The standard run (20 m/s, 0.1 m/s lateral kick) reaches the end: with the right wheel
    1 mm smaller the wheelset runs onto the flange jump from ~0.15 s and slides along it in
    blended windows instead of crashing or crawling (9 153 evaluations for 1 s, 13 windows; the
    bound is about six times that)."""
    _, table = asym
    res = simulate(TableProvider(table, "reference"), params_from_table(table), 20.0, 1.0)
    assert res.status == 0, res.message
    assert res.t[-1] == pytest.approx(1.0)
    assert res.events["sliding"].size >= 1
    assert res.nfev < 60_000
    assert np.all(np.isfinite(res.state))
