"""``lutmpi check`` (issue 7, item 1): the pure suite, its verdicts on the paper config and on a
deliberately bad one, and the CLI exit status."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

import lutmpi.check.suite as suite_mod
from lutmpi.check import CheckOptions, Tolerances, format_report, run_checks
from lutmpi.check.regions import (
    FLANGE_ANGLE,
    ROOT_ANGLE,
    ReferenceGrid,
    band_width,
    classify,
    stratified_sample,
)
from lutmpi.check.suite import Suite
from lutmpi.cli import main
from lutmpi.config import load_config
from lutmpi.equilibrium.result import ContactResult, PoseResult
from lutmpi.scene import Scene

ROOT = Path(__file__).resolve().parents[2]
PAPER = ROOT / "configs" / "paper_s1002_uic60_1in20.toml"
MANCHESTER = ROOT / "configs" / "manchester_s1002_uic60_1in40.toml"
BAD_SPACING = ROOT / "configs" / "bad_spacing_paper.toml"
MM = 1e-3


def _grid(cfg):
    ys = np.linspace(*cfg.grid.y_mm[:2], int(cfg.grid.y_mm[2])) * MM
    return ys, np.linspace(*cfg.grid.yaw_rad[:2], int(cfg.grid.yaw_rad[2]))


@pytest.fixture(scope="module")
def paper():
    cfg = load_config(PAPER)
    return Scene.from_config(cfg), *_grid(cfg)


# -- pure pieces -------------------------------------------------------------------------------
def _pose(angles, method="reference"):
    r = PoseResult(y=0.0, yaw=0.0, method=method, z_g=0.46, roll=0.0, success=True, status=0,
                   message="converged")
    for side, a in zip(("left", "right"), angles, strict=True):
        r.contacts[side].append(ContactResult(np.zeros(3), np.zeros(3), np.array([0, 0, 1.0]),
                                              0.0, contact_angle=a, wheel_s=0.0, rail_v=0.0))
    return r


def test_regions_by_contact_angle_and_zones():
    assert classify(_pose((0.01, 0.02)), 1)[0] == "tread"
    assert classify(_pose((ROOT_ANGLE + 0.01, 0.02)), 1)[0] == "flange_root"
    assert classify(_pose((0.02, FLANGE_ANGLE + 0.1)), 1)[0] == "flange"
    assert classify(_pose((0.02, FLANGE_ANGLE + 0.1)), 2)[0] == "double"


def test_band_width_of_a_parabola():
    s = np.linspace(-0.02, 0.02, 4001)
    gap = 5.0 * s**2  # curvature 10 1/m: band at delta is 2 sqrt(delta / 5)
    assert band_width(s, gap, 2e-5) == pytest.approx(2 * math.sqrt(2e-5 / 5.0), rel=1e-2)


def test_tolerances_at_the_default_mesh(paper):
    t = Tolerances.from_scene(paper[0])
    assert t.z == pytest.approx(0.02 * MM) and t.s == pytest.approx(0.5 * MM)
    assert t.roll == pytest.approx(0.02 * MM / paper[0].wheel.d)


def test_sample_covers_every_region(paper):
    grid = ReferenceGrid(paper[0], paper[1], paper[2], dc_tol=5e-5)
    survey = grid.survey(150)
    regions = {p.region for p in survey}
    assert {"tread", "flange_root", "flange"} <= regions
    sample = stratified_sample(survey, 12)
    assert {p.region for p in sample} == regions
    assert 10 <= len(sample) <= 12


# -- the suite ----------------------------------------------------------------------------------
def test_paper_config_passes_fast(paper):
    report = run_checks(*paper, CheckOptions(points=12, fast=True))
    text = format_report(report)
    print("\n" + text)
    assert report.passed, text
    names = {r.name for r in report.results}
    assert {"convergence", "accuracy vs reference", "sensitivity k_c", "sensitivity k_el",
            "continuity", "mesh window", "mesh spacing"} <= names
    assert report.elapsed < 120


def test_coarse_spacing_fails_and_says_what_to_change():
    """Only the spacing check (reference solves). 5 mm wheel nodes for a patch ~0.5 mm wide."""
    cfg = load_config(BAD_SPACING)
    scene = Scene.from_config(cfg)
    s = Suite(scene, *_grid(cfg), CheckOptions(points=8, fast=True))
    res = s.spacing(stratified_sample(s.ref.survey(60), 8))
    assert not res.passed and res.value < 3
    assert "mesh.wheel_lateral_mm = 5 too coarse for contact.allowed_indentation_mm = 0.001" \
        in res.message
    assert "use <=" in res.message


def test_window_disagreement_fails_with_window_gap_advice(paper, monkeypatch):
    """A windowed solve that differs from the full mesh (as a cut patch would) fails the window
    check with the key to change."""
    real = suite_mod.safe_solve

    def fake(scene, y, yaw, method, full_mesh=False):
        r = real(scene, y, yaw, method, full_mesh=False)
        if full_mesh:
            r = dataclasses.replace(r, z_g=r.z_g + 0.1 * MM)
        return r

    monkeypatch.setattr(suite_mod, "safe_solve", fake)
    s = Suite(*paper, CheckOptions(points=8, fast=True))
    res = s.window(s.ref.survey(60))
    assert not res.passed
    assert "window too narrow: increase mesh.window_gap_mm (now 0.02)" in res.message


def test_solver_exception_becomes_an_error_status(paper, monkeypatch):
    def boom(*a, **k):
        raise FloatingPointError("synthetic")

    monkeypatch.setattr(suite_mod, "solve_pose", boom)
    r = suite_mod.safe_solve(paper[0], 0.0, 0.0, "load_centre")
    assert not r.success and r.status == 7 and "synthetic" in r.message


# -- CLI ------------------------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("config", (PAPER, MANCHESTER), ids=("paper", "manchester"))
def test_cli_check_passes_fast(config, capsys):
    assert main(["check", str(config), "--fast"]) == 0
    out = capsys.readouterr().out
    assert "PASS:" in out and "FAIL" not in out


@pytest.mark.slow
def test_cli_check_fails_on_coarse_spacing(capsys):
    assert main(["check", str(BAD_SPACING), "--fast", "--points", "8"]) == 1
    out = capsys.readouterr().out
    assert "mesh.wheel_lateral_mm = 5 too coarse" in out
    assert "FAIL:" in out


def test_zones_count_the_minima_the_samples_do_not_resolve():
    # S1002 on the measured UIC60 .ban rail at y = -4.5 mm, yaw 0.12 rad: the right wheel's
    # flange minimum dips 26 um below its 0.1 mm sample, so a second zone that lies within
    # dc_tol (50 um) of the sample lies outside it from the true minimum (the rigid contacts
    # are chosen on the resampled gaps, and find one contact)
    from lutmpi.check.regions import reference_point
    from lutmpi.contact.locus import contact_minima
    from lutmpi.profiles import read_profile

    prof = ROOT / "profiles"
    scene = Scene.from_profiles(read_profile(prof / "MBench_S1002_v3.prw", kind="wheel"),
                                read_profile(prof / "MBench_UIC60_v3.ban", kind="rail"),
                                inclination=0.0, gauge_depth=14.0 * MM)
    dc = 5.0 * scene.equilibrium.allowed_indentation
    y, yaw = -4.5 * MM, 0.12
    loc = scene.locus.solve(y, yaw).loci["right"]
    assert len(contact_minima(loc.gap, dc, 2)) == 2          # the samples alone: two zones
    assert np.nanmin(loc.gap) - np.nanmin(loc.gap_min) > 20e-6
    point = reference_point(scene, np.array([y]), np.array([yaw]), 0, 0, dc)
    assert point.n_zones == 1 and point.region != "double"
