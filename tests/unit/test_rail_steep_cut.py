"""The rail placement keeps the profile around the top of rail up to the first stretch steeper
than its slope limit (85 deg, as placed): usable surface dropped beyond a steep stretch is a
warning naming the rail, the dropped v-range, the steep stretch and the usable range (it was
dropped without a word); a steep end face dropped whole stays silent; dropping the head's top is
an error. The rail's counterpart of ``test_wheel_steep_cut.py``."""

from __future__ import annotations

import logging
import re

import numpy as np
import pytest

from lutmpi.errors import GeometryError
from lutmpi.geometry.track import PlacedRail
from lutmpi.paths import REPO_ROOT
from lutmpi.profiles import read_profile
from lutmpi.profiles.model import Profile
from lutmpi.profiles.standard import uic60

PROFILES = REPO_ROOT / "profiles"
GAUGE, DEPTH = 1.435, 0.014
INCLINATIONS = {"none": 0.0, "1:40": np.arctan(1 / 40), "1:20": np.arctan(1 / 20)}


def _mbench() -> Profile:
    """The pre-canted MBench UIC60 (exact data: an interpolating spline), placed upright."""
    return read_profile(PROFILES / "MBench_UIC60_v3.prr", kind="rail")


def _stepped(rail: Profile, v_mm: float, drop_mm: float) -> Profile:
    """``rail`` with everything beyond ``v_mm`` (away from its top) ``drop_mm`` lower, the edge
    between two points 0.02 mm apart: a step a measuring fault leaves in exact data."""
    vs = v_mm * 1e-3
    far_side = 1.0 if vs > rail.y[np.argmax(rail.z)] else -1.0
    keep = np.abs(rail.y - vs) > 1e-4
    y = np.concatenate([rail.y[keep], [vs - 1e-5, vs + 1e-5]])
    z = np.concatenate([rail.z[keep], rail.z_at(np.array([vs - 1e-5, vs + 1e-5]))])
    z = np.where(far_side * (y - vs) > 0, z - drop_mm * 1e-3, z)
    order = np.argsort(y)
    return rail.with_points(y[order], z[order], name="stepped")


@pytest.mark.parametrize(("v_mm", "drop_mm", "dropped", "steep", "kept"), [
    (25.0, 2.0, r"24\.8\d \.\. 30\.60 mm \(field side\)", r"24\.8\d \.\. 25\.0\d",
     r"-43\.10 \.\. 24\.8\d"),
    (-30.0, 0.5, r"-43\.70 \.\. -29\.9\d mm \(gauge side\)", r"-30\.0\d \.\. -29\.9\d",
     r"-29\.9\d \.\. 28\.84"),
], ids=["field", "gauge"])
def test_surface_beyond_a_steep_step_is_dropped_with_a_warning_naming_it(v_mm, drop_mm, dropped,
                                                                         steep, kept, caplog):
    # before: the placed rail ended at the step without a word (field: 5.7 mm of the head's
    # field side gone; gauge: the gauge corner and face, 14 mm below the top, gone)
    stepped = _stepped(_mbench(), v_mm, drop_mm)
    with caplog.at_level(logging.WARNING, logger="lutmpi"):
        rail = PlacedRail.place(stepped, 0.0, GAUGE, DEPTH)
    (rec,) = caplog.records              # the steep end face beyond 28.84 mm: no word
    assert rec.levelno == logging.WARNING
    text = rec.getMessage()
    assert re.match(rf"rail stepped: v = {dropped} is not used for contact: it lies beyond "
                    rf"v = {steep} mm, steeper than 85 deg as placed \(up to 8[5-9]\.\d deg\); "
                    rf"the usable profile is v = {kept} mm$", text), text
    # the placed rail ends at the step: upright, u = gauge / 2 + v - v'(gauge point)
    end = rail.u_min if v_mm < 0 else rail.u_max
    assert (end - 0.5 * GAUGE + rail.v_gp) * 1e3 == pytest.approx(v_mm, abs=0.2)


@pytest.mark.parametrize("inc", INCLINATIONS)
@pytest.mark.parametrize("name", ["MBench_UIC60_v3.prr", "MBench_UIC60_v3.ban",
                                  "rail_left_iter288.ban", "UIC60"])
def test_the_repository_rails_place_without_a_word(name, inc, caplog):
    # each drops only its steep end faces (UIC60's lower head flanks below 13-16 mm, 0.5-1.8 mm
    # of MBench's and rail_left_iter288's ends), steep all through: by design
    rail = uic60() if name == "UIC60" else read_profile(PROFILES / name, kind="rail")
    with caplog.at_level(logging.WARNING, logger="lutmpi"):
        PlacedRail.place(rail, INCLINATIONS[inc], GAUGE, DEPTH)
    assert not caplog.records


def test_a_step_at_the_crown_that_leaves_a_sliver_of_the_top_is_an_error():
    # a 2 mm step 2 mm beside the crown: the interpolating spline overshoots beside it, higher
    # than the crown, between two stretches steeper than 85 deg; what is kept is 0.05 mm wide
    # (before: a 0.05 mm rail placed, with no word)
    stepped = _stepped(_mbench(), 1.8, 2.0)
    with pytest.raises(GeometryError) as err:
        PlacedRail.place(stepped, 0.0, GAUGE, DEPTH)
    msg = str(err.value)
    assert msg.startswith("rail stepped: the placement would keep only v = 1.")
    assert "nowhere more than 0." in msg and "the head's top would be dropped" in msg
    assert "on the gauge side (up to 8" in msg and "on the field side (up to 8" in msg


def test_a_top_of_rail_between_steep_stretches_is_an_error_naming_the_rail():
    # a tower 1 mm high and 0.1 mm wide on the crown: its top sample has steep intervals on both
    # sides (before: "profile is steeper than the slope limit at its reference point")
    r = _mbench()
    k = int(np.argmax(r.z))
    y = np.concatenate([r.y[:k], r.y[k] + np.array([-5e-5, 0.0, 5e-5]), r.y[k + 1:]])
    z = np.concatenate([r.z[:k], r.z[k] + np.array([0.0, 1e-3, 0.0]), r.z[k + 1:]])
    with pytest.raises(GeometryError) as err:
        PlacedRail.place(r.with_points(y, z, name="tower"), 0.0, GAUGE, DEPTH)
    assert re.match(r"rail tower: the top of rail \(its highest point as placed, v = -0\.\d\d mm\) "
                    r"lies between stretches steeper than the 85 deg", str(err.value))
