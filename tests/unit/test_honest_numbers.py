"""Numbers that never hide a hole: one test per case of issue 12's list.

Tables and sweeps here use ``tests.support.faulty_solver`` (closed-form conical wheels, Δr = 0.1 y
once its wheels are swapped (below),
so tan γe = 0.05 at every amplitude) with poses made to fail through ``LUTMPI_FAULT``; the dynamics
use the closed-form ``ConedWheelProvider``.
"""

from __future__ import annotations

import json
import logging
import math
import re

import numpy as np
import pytest

from lutmpi.cli import main as cli
from lutmpi.dynamics.stability import MIN_PEAKS, classify, format_rate
from lutmpi.reports.conicity import HoleError, check_dr, conicity_curve
from lutmpi.reports.dynamics_plots import steady_limits
from tests.support import faulty_solver

# faulty_solver with its wheels swapped: Δr = r_left - r_right = +0.1 y, the sign of a stable
# kinematic motion (EN 15302), so the conicity of this cone is 0.05 at every amplitude
HOOK = "tests.unit.test_honest_numbers:solve"
make_scene = faulty_solver.make_scene


def solve(scene, y, yaw, method):
    """``LUTMPI_FAULT=raise@Y/YAW`` poses come back not converged (failure as data)."""
    from lutmpi.equilibrium.result import MAX_ITER, PoseResult

    try:
        res = faulty_solver.solve(scene, y, yaw, method)
    except RuntimeError:
        return PoseResult(y=y, yaw=yaw, method=method, success=False, status=MAX_ITER,
                          message="max_iterations (injected by the test)")
    if getattr(res, "contacts", None):
        res.contacts = {"left": res.contacts["right"], "right": res.contacts["left"]}
    return res
BASE = """
[base.wheel]
generator = "S1002"
[base.rail]
generator = "UIC60"
[base.grid]
y_mm = [-8.0, 8.0, 17]
yaw_rad = [-0.01, 0.01, 3]
[[sweep]]
product = { "wear.wheel.flange_thinning_mm" = [0.0, 1.0, 2.0] }
"""
TABLE = """
[wheel]
generator = "S1002"
[rail]
generator = "UIC60"
[grid]
y_mm = [-8.0, 8.0, {n}]
yaw_rad = [-0.01, 0.01, 3]
"""


def _table(tmp_path, monkeypatch, n=17, fault="", name="t"):
    monkeypatch.setenv("LUTMPI_FAULT", fault)
    cfg = tmp_path / f"{name}.toml"
    cfg.write_text(TABLE.format(n=n))
    out = tmp_path / f"{name}.h5"
    assert cli(["build", str(cfg), "-o", str(out), "--solver", HOOK]) == 0
    return out


def _index(out):
    return {m["id"]: m for m in json.loads((out / "index.json").read_text())["members"]}


# -- "report printed tan γe up to 3.0 by integrating across 8 NaN poses at yaw 0" -------------
def test_report_never_integrates_across_failed_poses(tmp_path, monkeypatch):
    monkeypatch.setenv("LUTMPI_FAULT", "raise@3.0/0.0;raise@-4.0/0.0")
    sweep = tmp_path / "s.toml"
    sweep.write_text(BASE)
    out, rep = tmp_path / "out", tmp_path / "rep"
    assert cli(["sweep", str(sweep), "-o", str(out), "--solver", HOOK]) == 0
    assert cli(["report", str(out), "-o", str(rep)]) == 0
    text = (rep / "report.md").read_text()
    # the last Δr values before the holes are at ±2 mm: larger motions would cross a hole
    assert "Δr missing at y = -4, 3 mm (failed poses): amplitudes above 2 mm not computed" in text
    rows = np.genfromtxt(rep / "conicity.csv", delimiter=",", names=True)
    amp = rows["amplitude_mm"]
    vals = np.array([rows[c] for c in rows.dtype.names[1:]])
    # below the nearest hole the cone's 0.05 (closed form); from it on: no number at all
    np.testing.assert_allclose(vals[:, amp <= 2 + 1e-9], 0.05, atol=1e-6)
    assert np.all(np.isnan(vals[:, amp > 2 + 1e-9]))
    ind = np.genfromtxt(rep / "indices.csv", delimiter=",", names=True, dtype=None,
                        encoding="utf-8")
    assert np.all(np.isnan(ind["tan_gamma_e_4mm"])) and np.allclose(ind["tan_gamma_e_2mm"], 0.05)
    # one row per member against its parameter, one plot per index
    assert ind.dtype.names[1] == "wearwheelflange_thinning_mm"   # genfromtxt drops the dots
    np.testing.assert_allclose(ind["wearwheelflange_thinning_mm"], [0.0, 1.0, 2.0])
    for name in ("tan_gamma_e", "rolling_radii_coeff", "nonlinearity_parameter"):
        assert (rep / f"index_{name}.png").stat().st_size > 5000


# -- "conicity refuses a Δr with holes inside the amplitude range (naming the y)" ---------------
def test_conicity_refuses_a_hole_inside_the_amplitudes(tmp_path, monkeypatch, capsys):
    t = _table(tmp_path, monkeypatch, fault="raise@2.0/0.0")
    assert cli(["conicity", str(t), "--amplitudes", "1,3"]) == 1
    err = capsys.readouterr().err
    assert "Δr has no value at y = 2 mm" in err and "±3 mm" in err
    assert cli(["conicity", str(t), "--amplitudes", "1,1.5"]) == 0   # below the hole: fine


def test_check_dr_names_every_hole():
    y = np.linspace(-5e-3, 5e-3, 11)
    dr = 0.1 * y
    dr[[2, 8]] = np.nan                         # y = -3 and +3 mm
    with pytest.raises(HoleError, match=r"y = -3, 3 mm"):
        check_dr(y, dr, [4e-3])
    found = check_dr(y, dr, [1e-3, 2e-3, 4e-3], refuse_holes=False)
    assert found.y.max() < 3e-3 and found.beyond.tolist() == [4e-3]


# -- "conicity gives NaN silently for amplitudes beyond the table" ------------------------------
def test_conicity_flags_amplitudes_beyond_the_table(tmp_path, monkeypatch, capsys):
    t = _table(tmp_path, monkeypatch)
    assert cli(["conicity", str(t), "--amplitudes", "2,7,8.5,9"]) == 0
    out = capsys.readouterr()
    assert "# warning: amplitudes 8.5, 9 mm: beyond the table's y range [-8, 8] mm" in out.out
    assert "beyond the table's y range" in out.err          # logged as a WARNING too
    assert "9.000,nan" in out.out and "2.000,0.05000" in out.out


# -- "says nothing about a coarse Δy" -----------------------------------------------------------
def test_conicity_warns_when_dy_is_above_0p1_mm(tmp_path, monkeypatch, capsys):
    coarse = _table(tmp_path, monkeypatch, n=17, name="coarse")        # 1 mm steps
    fine = _table(tmp_path, monkeypatch, n=161, name="fine")           # 0.1 mm steps
    assert cli(["conicity", str(coarse), "--amplitudes", "2"]) == 0
    # the largest step between the Δr samples (the 1 mm grid's nodes and the table's extra
    # knots at yaw 0)
    assert re.search(r"y step (1|0\.\d+) mm is coarser than 0\.1 mm", capsys.readouterr().out)
    assert cli(["conicity", str(fine), "--amplitudes", "2"]) == 0
    assert "coarser" not in capsys.readouterr().out


# -- "sweep members with 4-24 failed poses are listed as ok and the sweep says 0 failed" --------
def test_member_with_failed_poses_is_partial_with_a_warning(tmp_path, monkeypatch, capsys):
    monkeypatch.setenv("LUTMPI_FAULT", "raise@5.0/0.01;raise@6.0/0.01")
    sweep = tmp_path / "s.toml"
    sweep.write_text(BASE)
    out = tmp_path / "out"
    assert cli(["sweep", str(sweep), "-o", str(out), "--solver", HOOK]) == 0
    err = capsys.readouterr().err
    index = _index(out)
    assert {m["status"] for m in index.values()} == {"partial"}
    assert all(m["failed_points"] == 2 and "2 of 51 points not converged" in m["message"]
               for m in index.values())
    assert err.count("WARNING lutmpi.parallel.sweep_runner: member ft-") == 3
    assert "2 of 51 points not converged" in err
    assert "sweep done: 3 members: 3 partial (ft-0, ft-1, ft-2)" in err


# -- "sweep --only X records every other member as failed" --------------------------------------
def test_only_marks_the_others_not_selected(tmp_path, monkeypatch):
    monkeypatch.setenv("LUTMPI_FAULT", "")
    sweep = tmp_path / "s.toml"
    sweep.write_text(BASE)
    out = tmp_path / "out"
    ids = [line.split("\t")[0] for line in _list(sweep)]
    assert cli(["sweep", str(sweep), "-o", str(out), "--solver", HOOK, "--only", ids[1]]) == 0
    index = _index(out)
    assert index[ids[1]]["status"] == "ok"
    assert [index[i]["status"] for i in (ids[0], ids[2])] == ["not selected"] * 2


def _list(sweep):
    from lutmpi.config.sweep import expand_sweep

    return [f"{m.id}\t" for m in expand_sweep(sweep)]


# -- "critical-speed logs the same run as hunting and stable; growth rates as ±0.000" -----------
def test_one_classification_and_rates_in_significant_digits(caplog):
    from lutmpi.dynamics.contact_provider import ConedWheelProvider
    from lutmpi.dynamics.critical import nonlinear_critical_speed
    from lutmpi.dynamics.wheelset import WheelsetParams

    prov = ConedWheelProvider(0.46, 0.05, 0.75)
    with caplog.at_level(logging.INFO):
        # 8 s: > 4 hunting periods at 12 m/s (wavelength 2 pi sqrt(0.46 0.75 / 0.05) = 16.5 m);
        # a free wheelset on cones hunts at every speed of practical interest (Wickens' yaw
        # gravitational stiffness of a yawed cone), so both runs hunt and
        # the bisection stops at once -- what matters is that each run has one verdict
        nl = nonlinear_critical_speed(prov, WheelsetParams(), 12.0, 30.0, rel_tol=0.5,
                                      duration=8.0)
    assert len(nl.runs) == 2 and not nl.converged
    by_logger: dict[str, list[str]] = {}
    for r in caplog.records:
        msg = r.getMessage()
        if msg.startswith("V = ") and r.name in ("lutmpi.dynamics.simulate",
                                                 "lutmpi.dynamics.critical"):
            by_logger.setdefault(r.name, []).append(msg.split(": ")[1])
    kinds = [k for _, k, _ in nl.runs]
    assert by_logger["lutmpi.dynamics.simulate"] == by_logger["lutmpi.dynamics.critical"] == kinds
    assert not any("0.000 1/s" in r.getMessage() for r in caplog.records)
    assert format_rate(1.234e-4) == "+0.000123 1/s" and format_rate(-0.0381) == "-0.0381 1/s"


# -- "a 0.5 s simulate reports hunting with a NaN growth rate" ----------------------------------
def test_a_run_too_short_is_undetermined_not_hunting():
    t = np.linspace(0.0, 0.5, 501)
    s = classify(t, 1e-3 * np.exp(0.5 * t) * np.sin(2 * math.pi * 2.0 * t))   # 2 Hz, 1 period
    assert s.kind == "undetermined" and math.isnan(s.growth_rate)
    assert "too short to tell" in s.line() and "nan 1/s" in s.line()
    t = np.linspace(0.0, 10.0, 5001)                  # 20 periods: decided, rate to 1e-3
    for rate, kind in ((0.05, "hunting"), (-0.05, "stable")):
        s = classify(t, 1e-3 * np.exp(rate * t) * np.sin(2 * math.pi * 2.0 * t))
        assert s.kind == kind and s.n_peaks >= MIN_PEAKS
        assert s.growth_rate == pytest.approx(rate, abs=1e-3)


# -- "the F_y plot's scale is set by the t = 0 spike so the oscillation is invisible" -----------
def test_time_history_axis_scales_to_the_steady_part():
    t = np.linspace(0.0, 10.0, 2001)
    fy = 1e3 * np.sin(2 * math.pi * 2.0 * t)
    fy[:4] = 5e4                                       # start-up spike, 50x the oscillation
    lo, hi = steady_limits(t, [fy])
    assert -1.2e3 < lo < -0.9e3 and 0.9e3 < hi < 1.2e3


def test_conicity_curve_still_exact_for_a_cone():
    y = np.linspace(-8e-3, 8e-3, 161)
    np.testing.assert_allclose(conicity_curve(y, 0.1 * y, [2e-3, 6e-3]).tan_gamma_e, 0.05,
                               rtol=1e-6)
