"""Wheelset dynamics on a real (small) lookup table: the packed TableProvider equals
Table.interp, ``lutmpi simulate`` end to end, and table vs on-line trajectories (issue 6)."""

from __future__ import annotations

import math

import h5py
import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.dynamics.contact_provider import (
    OnlineProvider,
    TableProvider,
    geometry_from_records,
)
from lutmpi.dynamics.simulate import simulate
from lutmpi.dynamics.wheelset import WheelsetParams
from lutmpi.table import Table

# S1002 on UIC60 1:20, the paper's profiles; the rigid reference solver keeps the build cheap
CONFIG = """
[wheel]
generator = "S1002"
nominal_radius_mm = 460.0
[rail]
generator = "UIC60"
inclination = "1:20"
[grid]
y_mm = [-{ymax}, {ymax}, {ny}]
yaw_rad = [-{wmax}, {wmax}, {nw}]
[contact]
method = "reference"
[output]
methods = ["reference"]
"""


def _build(tmp: object, name: str, ymax: float, ny: int, wmax: float, nw: int) -> tuple:
    cfg = tmp / f"{name}.toml"
    cfg.write_text(CONFIG.format(ymax=ymax, ny=ny, wmax=wmax, nw=nw))
    out = tmp / f"{name}.h5"
    assert main(["build", str(cfg), "-o", str(out)]) == 0
    return cfg, out


@pytest.fixture(scope="module")
def small_table(tmp_path_factory: pytest.TempPathFactory) -> tuple:
    """9 x 5 table over +-9 mm, +-0.12 rad (1 rank, serial writer)."""
    return _build(tmp_path_factory.mktemp("dyn"), "small", 9, 9, 0.12, 5)


def test_table_provider_equals_table_interp(small_table):
    """The provider's compiled lookup gives what Table.interp gives (the same jump-aware
    interpolant), and its z_g / roll slopes are the interpolant's derivatives (centred
    differences of Table.interp on the same side of every jump)."""
    table = Table.open(small_table[1])
    prov = TableProvider(table)
    rng = np.random.default_rng(3)
    poses = [(table.y[k], table.yaw[1 + k % (table.yaw.size - 2)])
             for k in range(1, table.y.size - 1)]
    poses += list(zip(rng.uniform(-8.5e-3, 8.5e-3, 60), rng.uniform(-0.11, 0.11, 60),
                      strict=True))
    h = 1e-8
    for y, yaw in poses:
        g = prov.evaluate(y, yaw)
        assert g.status == 0
        rec = table.interp(np.array([y, y - h, y + h, y, y]),
                           np.array([yaw, yaw, yaw, yaw - h, yaw + h]), quantities=prov.names,
                           info=True)
        ref = geometry_from_records(y, yaw, {k: v[[0, 0, 0]] for k, v in rec.items()}, 1.0, 1.0)
        for name in ("z_g", "roll", "wheel_point", "normal", "rolling_radius", "contact_angle",
                     "curv_wheel_rolling", "active"):
            np.testing.assert_allclose(np.asarray(getattr(g, name), float),
                                       np.asarray(getattr(ref, name), float), rtol=1e-12,
                                       atol=1e-15, err_msg=name)
        if len(set(rec["jump_side"].tolist())) == 1 and abs(rec["jump_distance"][0]) > 2 * h:
            for slope, name, a, b in (("dz_dy", "z_g", 1, 2), ("droll_dy", "roll", 1, 2),
                                      ("dz_dyaw", "z_g", 0, 4), ("droll_dyaw", "roll", 0, 4)):
                # y: centred (the interpolants are C1 in y); yaw: forward, the slope of the
                # cubic of the cell above (the same as the cell below's where both are cubics)
                fd = (rec[name][b] - rec[name][a]) / ((2 if a else 1) * h)
                assert getattr(g, slope) == pytest.approx(fd, rel=1e-4, abs=1e-7), slope


def test_table_provider_reads_build_attributes_not_profiles(small_table):
    """Issue 15: the flange angle and E, nu, r0, load come from attributes written at build
    time (S1002's flange flank: 70 deg = 1.2217 rad to within the profile's tabulation)."""
    from lutmpi.providers import params_from_table

    table = Table.open(small_table[1])
    assert math.degrees(table.attribute("wheel_flange_angle")) == pytest.approx(70.0, abs=0.1)
    assert TableProvider(table).flange_angle >= table.attribute("wheel_flange_angle")
    p = params_from_table(table)
    assert (p.r0, p.young, p.poisson) == (0.46, 206e9, 0.3)


def test_simulate_command_on_a_real_table(small_table, tmp_path):
    cfg, tab = small_table
    out = tmp_path / "run.h5"
    rc = main(["simulate", str(cfg), "--table", str(tab), "--speed", "27", "--duration", "1",
               "-o", str(out)])
    assert rc == 0
    with h5py.File(out, "r") as f:
        # 1 s at 27 m/s is about one hunting period (Klingel wavelength ~ 20 m): too short to
        # tell stable from hunting, and the one classification (dynamics/stability.py) says so
        assert f.attrs["success"] and f.attrs["kind"] == "undetermined"
        for name in ("t", "y", "yaw", "roll", "normal_force", "lateral_tangential_force"):
            assert np.all(np.isfinite(f[name][()])), name
            assert f[name].attrs["units"] in ("s", "m", "rad", "N")
        assert f["t"][-1] == pytest.approx(1.0)
        load = f["normal_force"][()].sum(axis=(1, 2))
        assert np.all(load > 1e5)          # carries the vertical load and the weight
    for key in ("y", "yaw", "roll", "fy"):
        assert (tmp_path / f"run_{key}.png").stat().st_size > 1000


@pytest.mark.slow
def test_table_and_online_trajectories_agree(tmp_path):
    """Same scenario (27 m/s, 0.1 m/s initial lateral velocity, 1.5 s), same contact method: the
    table run and the on-line run differ by at most 5 % of the amplitude."""
    cfg, tab = _build(tmp_path, "fine", 2.0, 9, 0.012, 5)   # 0.5 mm x 6 mrad cells
    table = Table.open(tab)
    params = WheelsetParams.from_toml_text(table.config_toml)
    from lutmpi.config.load import load_config
    from lutmpi.scene import Scene

    online = OnlineProvider(Scene.from_config(load_config(cfg)), "reference")
    kw = dict(events=False, dt_out=0.01)
    a = simulate(TableProvider(table), params, 27.0, 1.5, **kw)
    b = simulate(online, params, 27.0, 1.5, **kw)
    amp = float(np.max(np.abs(b.y)))
    assert amp > 1e-4 and online.failures == 0
    assert float(np.max(np.abs(a.y - b.y))) <= 0.05 * amp
    assert math.isfinite(a.sim_per_wall) and a.wall_time < b.wall_time
