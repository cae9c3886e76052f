"""Convergence metrics on synthetic tables with a known error law (error = C h^p)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from lutmpi.reports.convergence import (
    MemberTable,
    compare,
    convergence_study,
    error_maps,
    mesh_spacing_of,
    observed_order,
)

NY, NYAW = 5, 3


def _group(rng, offset=0.0, status=None, time=1e-3):
    shape = (NY, NYAW)
    g = {
        "status": np.zeros(shape, np.int8) if status is None else status,
        "compute_time": np.full(shape, time),
        "z_g": np.linspace(0, 1e-3, NY * NYAW).reshape(shape) + offset,
        "roll": np.full(shape, 1e-3) + offset,
        "wheel_s": np.ones(shape + (2, 2)) * 0.01 + offset,
        "rail_v": np.ones(shape + (2, 2)) * 0.02 - offset,
        "contact_angle": np.full(shape + (2, 2), 0.05) + offset,
        "normal": np.zeros(shape + (2, 2, 3)),
    }
    ang = 0.05 + offset
    g["normal"][..., 1] = np.sin(ang)
    g["normal"][..., 2] = np.cos(ang)
    return g


def _table(method, group, wall=2.0, ranks=2):
    return {"attrs": {"wall_time_s": wall, "ranks": ranks}, "y": np.linspace(-1e-3, 1e-3, NY),
            "yaw": np.linspace(-0.01, 0.01, NYAW), "methods": {method: group}}


@pytest.mark.parametrize("p", [1.0, 2.0, 1.5])
def test_fitted_order_equals_the_error_law(p):
    h = np.array([2e-3, 1e-3, 5e-4, 2.5e-4])
    order, c, n = observed_order(h, 3.0 * h**p)
    assert n == 4
    assert order == pytest.approx(p, abs=1e-10)
    assert c == pytest.approx(3.0, rel=1e-8)
    assert math.isnan(observed_order([1e-3], [1e-4])[0])


def test_study_recovers_order_and_exact_errors():
    rng = np.random.default_rng(0)
    ref = MemberTable("m-reference", "reference", math.nan, _table("reference", _group(rng)))
    p, c = 2.0, 50.0
    members = [ref]
    for h in (2e-3, 1e-3, 5e-4):
        members.append(MemberTable(f"m-x__h-{h}", "max_distance", h,
                                   _table("max_distance", _group(rng, offset=c * h**p))))
    study = convergence_study(members)
    assert [m.id for m in study.metrics] == [m.id for m in members[1:]]
    for m, h in zip(study.metrics, (2e-3, 1e-3, 5e-4), strict=True):
        e = c * h**p
        for q in ("z_g", "roll", "wheel_s", "rail_v", "contact_angle", "normal"):
            assert m.errors[q].max == pytest.approx(e, rel=1e-6), q
            assert m.errors[q].rms == pytest.approx(e, rel=1e-6), q
        assert m.errors["z_g"].n == NY * NYAW and m.errors["wheel_s"].n == 2 * NY * NYAW
        assert m.cpu_total_s == pytest.approx(NY * NYAW * 1e-3)
        assert m.cpu_per_point_s == pytest.approx(1e-3)
        assert (m.wall_s, m.ranks) == (2.0, 2)
    assert study.orders["max_distance"]["z_g"][0] == pytest.approx(p, abs=1e-6)
    assert study.orders["max_distance"]["normal"][0] == pytest.approx(p, abs=1e-6)


def test_failed_points_are_excluded_and_counted():
    rng = np.random.default_rng(1)
    status = np.zeros((NY, NYAW), np.int8)
    status[0, 0] = 1
    bad = _group(rng, offset=1e-4, status=status)
    bad["z_g"][0, 0] = 1.0                       # garbage at the failed point must not count
    bad["wheel_s"][1, 1, 0, 0] = np.nan          # no contact on the left wheel at one point
    ref = MemberTable("ref", "reference", math.nan, _table("reference", _group(rng)))
    m = compare(MemberTable("a", "load_centre", 1e-3, _table("load_centre", bad)), ref)
    assert m.failures == 1
    assert m.errors["z_g"].excluded == 1 and m.errors["z_g"].max == pytest.approx(1e-4)
    assert m.errors["wheel_s"].excluded == 3     # two sides at the failed point + one NaN
    maps = error_maps(bad, ref.group)
    assert np.isnan(maps["z_g"][0, 0]) and maps["wheel_s"].shape == (NY, NYAW, 2)


def test_grids_must_match_and_finest_reference():
    rng = np.random.default_rng(2)
    a = _table("load_centre", _group(rng, 1e-4))
    b = _table("load_centre", _group(rng, 0.0))
    b["y"] = b["y"] * 2
    with pytest.raises(ValueError, match="same y grid"):
        compare(MemberTable("a", "load_centre", 1e-3, a), MemberTable("b", "load_centre", 5e-4, b))
    members = [MemberTable(f"h{h}", "load_centre", h, _table("load_centre", _group(rng, h**2)))
               for h in (4e-3, 2e-3, 1e-3)]
    study = convergence_study(members, reference="finest")
    assert [m.id for m in study.metrics] == ["h0.004", "h0.002"]
    assert study.metrics[0].errors["z_g"].max == pytest.approx(4e-3**2 - 1e-3**2)
    with pytest.raises(ValueError, match="no member"):
        convergence_study(members)


def test_mesh_spacing_from_config_text():
    text = "[mesh]\nwheel_lateral_mm = 0.5\nrail_lateral_mm = 1.0\n"
    assert mesh_spacing_of(text) == pytest.approx(1e-3)
    assert math.isnan(mesh_spacing_of("[wheel]\n"))
