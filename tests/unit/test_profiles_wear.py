"""Parametric wear (issue 5 item 3): where and as large as asked, valid, zero = identity."""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.errors import ProfileError
from lutmpi.profiles import s1002, uic60
from lutmpi.profiles.measures import rail_measures, wheel_measures
from lutmpi.profiles.wear import (
    flange_thinning,
    rail_side_wear,
    rail_vertical_wear,
    tread_hollowing,
)

WHEEL = s1002(-69.0, 60.0, step_mm=0.2)
RAIL = uic60(step_mm=0.2)


@pytest.mark.parametrize("fn, prof", [(flange_thinning, WHEEL), (tread_hollowing, WHEEL),
                                      (rail_vertical_wear, RAIL), (rail_side_wear, RAIL)])
def test_zero_wear_is_identity(fn, prof):
    out = fn(prof, 0.0)
    np.testing.assert_array_equal(out.y, prof.y)
    np.testing.assert_array_equal(out.z, prof.z)
    assert out.meta["wear"][0]["type"] == fn.__name__


@pytest.mark.parametrize("t", [0.5, 1.0, 2.0, 4.0])
def test_flange_thinning_reduces_sd_by_the_amount(t):
    new, worn = wheel_measures(WHEEL), wheel_measures(flange_thinning(WHEEL, t))
    assert (new.flange_thickness - worn.flange_thickness) * 1e3 == pytest.approx(t, abs=1e-3)
    assert worn.flange_height == pytest.approx(new.flange_height, abs=1e-9)     # tip untouched
    w = flange_thinning(WHEEL, t)
    tread = WHEEL.y > -0.020                                    # below 2 mm above the tape
    np.testing.assert_array_equal(w.y[tread], WHEEL.y[tread])                   # tread untouched
    assert w.meta["wear"] == [{"type": "flange_thinning", "thickness_mm": t}]


def test_flange_thinning_too_large_is_a_clear_error():
    """A thinning that folds the face names the key and the largest thinning this wheel takes,
    which itself is a profile."""
    with pytest.raises(ProfileError, match=r"flange_thinning_mm = 8 folds .* at most (\d\.\d\d) mm"
                       ) as exc:
        flange_thinning(WHEEL, 8.0)
    most = float(exc.value.args[0].rsplit("at most ", 1)[1].split(" mm")[0])
    assert 1.0 < most < 8.0
    flange_thinning(WHEEL, most)


@pytest.mark.parametrize("depth", [0.5, 1.0, 2.0])
def test_tread_hollowing_depth_place_and_false_flange(depth):
    w = tread_hollowing(WHEEL, depth, centre_mm=0.0, width_mm=40.0)
    dz = (WHEEL.z - w.z) * 1e3
    assert dz.max() == pytest.approx(depth, abs=1e-5)              # nearest point to s = 0
    assert (WHEEL.z_at(0.0) - w.z_at(0.0)) * 1e3 == pytest.approx(depth, abs=1e-6)
    assert abs(w.y[np.argmax(dz)]) < 2e-4                                       # at the centre
    assert np.all(dz[np.abs(WHEEL.y) >= 0.020] == 0)                            # only the band
    # a false flange: dr(s) has a local maximum on the field side of the hollow, so a flat rail
    # has two candidate contact zones (there and toward the flange)
    s = np.linspace(0.0, 0.040, 4001)
    z = w.z_at(s)
    peaks = s[1:-1][(z[1:-1] > z[:-2]) & (z[1:-1] >= z[2:])]
    assert peaks.size == 1 and 0.010 < peaks[0] < 0.020
    assert np.all(np.diff(WHEEL.z_at(s)) < 0)                                   # new: no peak


@pytest.mark.parametrize("depth", [0.5, 2.0, 5.0])
def test_rail_vertical_wear_lowers_the_top(depth):
    r = rail_vertical_wear(RAIL, depth)
    assert (RAIL.z.max() - r.z.max()) * 1e3 == pytest.approx(depth, abs=1e-6)
    assert r.z_at(0.0) * 1e3 == pytest.approx(-depth, abs=1e-6)
    deep = RAIL.z < RAIL.z.max() - (depth + 8.0) * 1e-3                           # flanks untouched
    np.testing.assert_allclose(r.z[deep], RAIL.z[deep], atol=1e-9)
    assert np.all(r.z <= RAIL.z + 1e-15)                                         # only removes


@pytest.mark.parametrize("depth", [0.5, 2.0, 5.0])
def test_rail_side_wear_moves_the_gauge_point(depth):
    r = rail_side_wear(RAIL, depth)
    g_new, g_worn = rail_measures(RAIL).gauge_point[0], rail_measures(r).gauge_point[0]
    assert (g_worn - g_new) * 1e3 == pytest.approx(depth, abs=2e-3)
    field = RAIL.y > 0
    np.testing.assert_array_equal(r.z[field], RAIL.z[field])                     # field side kept
    assert np.all(r.z <= RAIL.z + 1e-15)


def test_wear_rejects_wrong_kind_and_negative_amounts():
    with pytest.raises(ProfileError, match="applies to a wheel"):
        flange_thinning(RAIL, 1.0)
    with pytest.raises(ProfileError, match=">= 0"):
        rail_vertical_wear(RAIL, -1.0)
    combo = rail_side_wear(rail_vertical_wear(RAIL, 1.0), 1.0)
    assert [w["type"] for w in combo.meta["wear"]] == ["rail_vertical_wear", "rail_side_wear"]
