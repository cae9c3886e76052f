"""What a hostile tester found in ``lutmpi simulate`` and ``lutmpi critical-speed`` (2026-11-28),
each now a clear error, a usage error or a warning instead of a traceback, a silent number or a
failure reported with exit 0:

* the linear analysis read geometry clipped to the table's edge (an amplitude beyond the table's
  y range, yaw derivatives on a 1-D table) and printed a number;
* an unbracketed nonlinear critical speed exited 0; ``--json`` printed text before the JSON;
* option values no run can use (``--amplitude 0``, ``--duration 1e9``, ``--integrator FOO``,
  ``--online --method bogus``) gave tracebacks or were accepted;
* ``simulate`` replaced an earlier run's output without a word, and ``--no-plots`` left the
  earlier run's figures beside the new data;
* ``simulate`` on a 1-D table stopped with "left the table" at a pose inside it;
* with ``--table`` a config of another pair was ignored without a word, and ``--online`` ignored
  ``--table`` without a word;
* ``critical-speed --linear-only`` on a wheelset without a pure-rolling pose printed "critical
  speed 0.000 m/s" and exited 0 (``--json``: ``"speed": 0.0``);
* ``simulate``'s root attributes (speed, growth rate, amplitude, ...) had no units, nor the
  ``fy`` figure's start-up peak in its title.
"""

from __future__ import annotations

import json
import math
import re
from dataclasses import replace

import h5py
import numpy as np
import pytest

from lutmpi.cli import main
from lutmpi.dynamics.contact_provider import FAILED_POINT, ConedWheelProvider, TableProvider
from lutmpi.dynamics.wheelset import WheelsetParams
from lutmpi.errors import TableError
from lutmpi.paths import REPO_ROOT
from lutmpi.table import Table

pytestmark = pytest.mark.timeout(600)

# the paper's pair on a small grid; the rigid reference solver keeps the builds cheap
CONFIG = """[wheel]
generator = "S1002"
[rail]
generator = "UIC60"
inclination = "1:20"
[grid]
y_mm = [-4.0, 4.0, {ny}]
yaw_rad = [{yaw}]
[contact]
method = "reference"
[output]
methods = ["reference"]
"""
#: another pair: a measured wheel, 1:40, half the load (the tester's other.toml)
OTHER = f"""[wheel]
profile = "{REPO_ROOT / 'profiles' / 'Car7216_0001r.whl'}"
[rail]
generator = "UIC60"
inclination = "1:40"
[equilibrium]
vertical_load_N = 50000.0
[grid]
y_mm = [-4.0, 4.0, 5]
yaw_rad = [0.0, 0.0, 1]
"""


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    """``{"2d": (config, table), "1d": (config, table), "other": config}``: S1002/UIC60 1:20,
    y in [-4, 4] mm, yaw in [-0.01, 0.01] rad (5 x 3) and at yaw 0 only (9 x 1)."""
    d = tmp_path_factory.mktemp("hostile_dyn")
    out = {}
    for name, ny, yaw in (("2d", 5, "-0.01, 0.01, 3"), ("1d", 9, "0.0, 0.0, 1")):
        cfg = d / f"{name}.toml"
        cfg.write_text(CONFIG.format(ny=ny, yaw=yaw))
        table = d / f"{name}.h5"
        assert main(["build", str(cfg), "-o", str(table)]) == 0
        out[name] = (cfg, table)
    other = d / "other.toml"
    other.write_text(OTHER)
    out["other"] = other
    return out


@pytest.fixture(scope="module")
def asym(tmp_path_factory):
    """``(config, table)``: the left wheel 5 mm larger in radius, Δr(0) = 5 mm, which no lateral
    shift within the table's ±4 mm cancels: no pose rolls purely."""
    d = tmp_path_factory.mktemp("asym")
    cfg = d / "asym.toml"
    cfg.write_text(CONFIG.format(ny=5, yaw="-0.01, 0.01, 3").replace(
        "[rail]", "[wheel.left]\nnominal_radius_mm = 465.0\n[rail]", 1))
    assert main(["build", str(cfg), "-o", str(d / "asym.h5")]) == 0
    return cfg, d / "asym.h5"


def _critical(tables, kind, *extra, config=None):
    cfg, table = tables[kind]
    return main(["critical-speed", str(config or cfg), "--table", str(table), *extra])


# -- 1. the linear analysis on geometry clipped to the table's edge ------------------------------
def test_an_amplitude_beyond_the_table_is_an_error_naming_it_and_the_range(tables, capsys):
    """Before: ``lam_e ... at 6 mm`` printed, exit 0, from the geometry at the 4 mm edge."""
    assert _critical(tables, "2d", "--linear-only", "--amplitude", "0.006") == 1
    cap = capsys.readouterr()
    assert "--amplitude 0.006 m (6 mm)" in cap.err and "[-4.0000, 4.0000] mm" in cap.err, cap.err
    assert "at most 4.0000 mm" in cap.err and "Traceback" not in cap.err
    assert "critical speed" not in cap.out


def test_the_linear_analysis_on_a_1d_table_says_it_needs_a_yaw_range(tables, capsys):
    """Before: 8.216 m/s from yaw derivatives read outside the table (the 2-D table of the same
    pair gives 9.139 m/s)."""
    assert _critical(tables, "1d", "--linear-only") == 1
    err = capsys.readouterr().err
    assert "needs the yaw derivatives" in err and "1-D" in err and "yaw_rad" in err, err


def test_the_linear_models_refuse_poses_outside_the_table(tables):
    from lutmpi.dynamics.critical import jacobian_critical_speed, linear_parameters, rhs_jacobian

    table = Table.open(tables["2d"][1])
    prov, p = TableProvider(table), WheelsetParams()
    for call in (lambda: linear_parameters(prov, p, amplitude=4.5e-3, centre=0.0),
                 lambda: rhs_jacobian(prov, p, 12.0, amplitude=4.5e-3, centre=0.0),
                 lambda: jacobian_critical_speed(prov, p, amplitude=4.5e-3, centre=0.0)):
        with pytest.raises(TableError, match=r"beyond the table's y range"):
            call()
    linear_parameters(prov, p, amplitude=4e-3, centre=0.0)   # the edge itself is inside


class _FailsBeyond:
    """Coned wheels whose geometry beyond ``|y| > edge`` is a failed point (as a table answers:
    the last good geometry with ``status = FAILED_POINT``)."""

    def __init__(self, edge: float) -> None:
        self.inner, self.edge = ConedWheelProvider(0.46, 0.05, 0.75), edge
        self.flange_angle = self.inner.flange_angle

    def evaluate(self, y: float, yaw: float):
        g = self.inner.evaluate(y, yaw)
        return replace(g, status=FAILED_POINT) if abs(y) > self.edge else g


def test_a_failed_point_inside_the_amplitude_is_an_error_not_a_number():
    from lutmpi.dynamics.critical import linear_parameters

    p = WheelsetParams()
    linear_parameters(_FailsBeyond(1e-3), p, amplitude=0.9e-3, centre=0.0)
    with pytest.raises(TableError, match="on a failed table point"):
        linear_parameters(_FailsBeyond(1e-3), p, amplitude=2e-3, centre=0.0)


# -- 2. failure reported as success; --json that is not JSON -------------------------------------
def test_json_is_the_only_thing_on_standard_output(tables, capsys):
    assert _critical(tables, "2d", "--linear-only", "--json") == 0
    cap = capsys.readouterr()
    res = json.loads(cap.out)
    assert res["linear"]["speed"] > 0 and "nonlinear" not in res
    assert "linearised model" in cap.err and "classical Wickens" in cap.err


def test_an_unbracketed_critical_speed_exits_non_zero_with_the_reason(tables, capsys):
    """Before: ``nonlinear critical speed not bracketed ...`` on standard output, exit 0. Two
    seconds are less than a hunting period here: both runs are undetermined."""
    assert _critical(tables, "2d", "--duration", "2", "--json") == 1
    cap = capsys.readouterr()
    res = json.loads(cap.out)                       # the result is still written, as data
    assert res["nonlinear"]["converged"] is False and res["nonlinear"]["speed"] is None
    assert "error: " in cap.err and "not bracketed" in cap.err
    assert "undetermined" in cap.err and "run longer" in cap.err, cap.err


def test_a_run_that_leaves_the_table_stops_the_bisection_with_its_message(tables):
    """A 1 m/s lateral kick takes the wheelset past the 4 mm edge: the truncated run has no
    verdict (it was classified as if complete)."""
    from lutmpi.dynamics.critical import nonlinear_critical_speed
    from lutmpi.providers import params_from_table

    table = Table.open(tables["2d"][1])
    nl = nonlinear_critical_speed(TableProvider(table), params_from_table(table), 10.0, 14.0,
                                  vy0=1.0, duration=2.0)
    assert not nl.converged and math.isnan(nl.speed)
    assert [k for _, k, _ in nl.runs] == ["stopped", "stopped"]
    assert "left the table" in nl.message and "10 m/s stopped" in nl.message


def test_no_pure_rolling_pose_is_no_linear_critical_speed_and_exit_1(asym, capsys):
    """Before: ``critical speed 0.000 m/s, hunting frequency nan Hz``, exit 0; with ``--json``
    ``"speed": 0.0``, a number to read as a speed."""
    cfg, table = asym
    base = ["critical-speed", str(cfg), "--table", str(table)]
    assert main([*base, "--linear-only"]) == 1
    cap = capsys.readouterr()
    assert "error: " in cap.err and "no linear critical speed" in cap.err, cap.err
    assert "no pure-rolling pose" in cap.err and "Δr = 5.0" in cap.err
    assert "m/s" not in cap.out and "Traceback" not in cap.err
    assert main([*base, "--linear-only", "--json"]) == 1
    cap = capsys.readouterr()
    lin = json.loads(cap.out)["linear"]                  # standard output: the JSON alone
    assert lin["speed"] is None and lin["found"] is False and "pure-rolling" in lin["message"]
    # the bisection starts from the linear speed: there is none to start from
    assert main([*base, "--json", "--duration", "2"]) == 1
    nl = json.loads(capsys.readouterr().out)["nonlinear"]
    assert nl["converged"] is False and "there is none" in nl["message"]


# -- 3. option values no run can use --------------------------------------------------------------
@pytest.mark.parametrize("argv", [
    ["critical-speed", "C", "--table", "T", "--amplitude", "0"],
    ["critical-speed", "C", "--table", "T", "--amplitude", "nan"],
    ["critical-speed", "C", "--table", "T", "--amplitude", "-1"],
    ["critical-speed", "C", "--table", "T", "--duration", "-5"],
    ["critical-speed", "C", "--table", "T", "--duration", "nan"],
    ["critical-speed", "C", "--table", "T", "--duration", "1e9"],
    ["critical-speed", "C", "--table", "T", "--vy0", "nan"],
    ["critical-speed", "C", "--table", "T", "--vy0", "0"],
    ["critical-speed", "C", "--table", "T", "--rel-tol", "-1"],
    ["critical-speed", "C", "--table", "T", "--rel-tol", "0"],
    ["critical-speed", "C", "--table", "T", "--rel-tol", "2"],
    ["simulate", "C", "--table", "T", "--integrator", "FOO", "-o", "X.h5"],
    ["simulate", "C", "--table", "T", "--duration", "1e9", "-o", "X.h5"],
])
def test_an_option_value_no_run_can_use_is_a_usage_error(argv, capsys):
    with pytest.raises(SystemExit) as exc:
        main(argv)
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert "expected" in err or "invalid choice" in err, err
    if "1e9" in argv:
        assert "output samples" in err and "at most" in err


def test_an_unknown_online_method_is_a_clear_error(tables, tmp_path, capsys):
    """Before: a ValueError traceback from the first pose solve. Given with ``--table``, which
    ``--online`` does not read, a warning says so (before: ignored without a word)."""
    cfg, table = tables["2d"]
    rc = main(["simulate", str(cfg), "--online", "--table", str(table), "--method", "bogus",
               "-o", str(tmp_path / "r.h5")])
    err = capsys.readouterr().err
    assert rc == 1 and "--method" in err and "'bogus'" in err and "load_centre" in err, err
    assert "is not read" in err and "Traceback" not in err
    assert not (tmp_path / "r.h5").exists()


def test_the_library_refuses_what_no_run_can_use():
    from lutmpi.commands.simulate import INTEGRATORS as CLI_INTEGRATORS
    from lutmpi.commands.simulate import PLOT_KEYS
    from lutmpi.dynamics.simulate import INTEGRATORS, simulate
    from lutmpi.reports.dynamics_plots import _PANELS

    prov, p = ConedWheelProvider(), WheelsetParams()
    for kw, match in (({"duration": 1e9}, "samples"), ({"duration": -5.0}, "duration"),
                      ({"duration": 1.0, "method": "FOO"}, "integrator")):
        with pytest.raises(ValueError, match=match):
            simulate(prov, p, 20.0, **kw)
    assert CLI_INTEGRATORS == INTEGRATORS
    assert PLOT_KEYS == tuple(key for key, *_ in _PANELS)


# -- 4. an earlier run's output and figures -------------------------------------------------------
def test_an_earlier_run_is_kept_unless_forced_and_no_plots_removes_its_figures(tables, tmp_path,
                                                                               capsys):
    cfg, table = tables["2d"]
    out = tmp_path / "sim1.h5"
    base = ["simulate", str(cfg), "--table", str(table), "--duration", "0.2", "-o", str(out)]
    assert main([*base, "--speed", "12"]) == 0
    figures = [tmp_path / f"sim1_{k}.png" for k in ("y", "yaw", "roll", "fy")]
    assert all(f.exists() for f in figures)
    before = out.read_bytes()
    capsys.readouterr()
    assert main([*base, "--speed", "13", "--no-plots"]) == 1
    err = capsys.readouterr().err
    assert "exist" in err and "--force" in err and str(out) in err, err
    assert out.read_bytes() == before and all(f.exists() for f in figures)
    assert main([*base, "--speed", "13", "--no-plots", "--force"]) == 0
    assert "removed the earlier run's figures" in capsys.readouterr().err
    with h5py.File(out, "r") as f:
        assert f.attrs["speed"] == 13.0
    assert not any(f.exists() for f in figures)
    assert not out.with_name(out.name + ".partial").exists()
    # figures alone (an -o of another name once) are an earlier run's too
    figures[0].write_bytes(b"old")
    out.unlink()
    assert main([*base, "--speed", "13"]) == 1
    assert "sim1_y.png exists" in capsys.readouterr().err


def test_a_runs_root_attributes_and_its_force_title_carry_their_units(tables, tmp_path):
    """Before: ``speed``, ``growth_rate``, ``amplitude``, ``flange_angle``, the parameters: bare
    numbers; the force figure's title ``start-up peak 19.9 off the axis``."""
    cfg, table = tables["2d"]
    out = tmp_path / "u.h5"
    assert main(["simulate", str(cfg), "--table", str(table), "--duration", "0.2", "-o",
                 str(out), "--no-plots"]) == 0
    with h5py.File(out, "r") as f:
        attrs = dict(f.attrs)
        assert all("units" in d.attrs for d in f.values() if isinstance(d, h5py.Dataset))
    numbers = [k for k, v in attrs.items() if isinstance(v, float | np.floating)]
    assert {"speed", "growth_rate", "amplitude", "flange_angle"} <= set(numbers)
    for name in numbers:       # a unit beside it, or in its name as a table's wall_time_s
        assert f"{name}_units" in attrs or name.endswith("_s"), name
    assert attrs["speed_units"] == "m/s" and attrs["growth_rate_units"] == "1/s"
    params, units = json.loads(attrs["params"]), json.loads(attrs["params_units"])
    assert {k for k, v in params.items() if not isinstance(v, bool | str)} == set(units)
    assert units["mass"] == "kg" and units["young"] == "Pa"
    from lutmpi.dynamics.simulate import simulate
    from lutmpi.providers import params_from_table
    from lutmpi.reports.dynamics_plots import panel

    t = Table.open(table)
    run = simulate(TableProvider(t), params_from_table(t), 12.0, 1.0)
    fig = panel([run], "fy")
    try:
        title = fig.axes[0].get_title()
        assert "start-up peak" in title and re.search(r"peak [\d.e+-]+ kN off", title), title
        assert fig.axes[0].get_ylabel() == "F_y [kN]"
    finally:
        import matplotlib.pyplot as plt

        plt.close(fig)


# -- 5. simulate on a 1-D table ------------------------------------------------------------------
def test_simulate_on_a_1d_table_says_the_dynamics_needs_a_yaw_range(tables, tmp_path, capsys):
    """Before: ``left the table at t = 0.00000 s, pose y = 0.0000 mm, yaw = 0.000000 rad``, a
    pose inside the table."""
    cfg, table = tables["1d"]
    out = tmp_path / "r.h5"
    assert main(["simulate", str(cfg), "--table", str(table), "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert "1-D" in err and "yaw range" in err and "left the table" not in err, err
    assert not out.exists()


# -- 6. a config of another pair given with the table ---------------------------------------------
def test_a_config_of_another_pair_is_warned_about_naming_what_differs(tables, capsys):
    assert _critical(tables, "2d", "--linear-only", config=tables["other"]) == 0
    err = capsys.readouterr().err
    assert "describes another wheelset" in err, err
    for key in ("wheel.profile", "wheel.generator", "rail.inclination: '1:40' (config), "
                "'1:20' (table)", "equilibrium.vertical_load_N: 50000.0 (config), 100000.0"):
        assert key in err, (key, err)
    assert _critical(tables, "2d", "--linear-only") == 0       # its own config: no warning
    assert "describes another" not in capsys.readouterr().err


def test_the_critical_speed_numbers_do_not_move(tables, capsys):
    """The checks change no number: the 2-D table's linear speed at the default amplitude is the
    one the same analysis gives without the command (a guard against a changed default)."""
    from lutmpi.dynamics.critical import jacobian_critical_speed
    from lutmpi.providers import params_from_table

    assert _critical(tables, "2d", "--linear-only", "--json") == 0
    got = json.loads(capsys.readouterr().out)["linear"]["speed"]
    table = Table.open(tables["2d"][1])
    want, _ = jacobian_critical_speed(TableProvider(table), params_from_table(table),
                                      amplitude=3.5e-4, centre=0.0)
    assert got == pytest.approx(want, rel=1e-12) and np.isfinite(got)
