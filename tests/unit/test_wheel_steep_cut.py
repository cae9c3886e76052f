"""The wheel placement keeps the profile around the tape circle up to the first stretch steeper
than its slope limit (85 deg): dropping the flange tip that way is an error, dropping other surface
a warning, a steep end face (the flange back, a rim) is dropped silently (hostile tester's F2).
A flange thinning that would make the placement drop the tip is a ConfigError naming the key and
the largest thinning the wheel takes."""

from __future__ import annotations

import logging
import math
import re
from pathlib import Path

import numpy as np
import pytest

from lutmpi.config import config_from_dict
from lutmpi.errors import ConfigError, GeometryError
from lutmpi.geometry.track import WheelCut, WheelGeometry
from lutmpi.profiles import s1002
from lutmpi.profiles.readers import read_profile
from lutmpi.profiles.wear import flange_thinning
from lutmpi.scene_config import side_profiles

PROFILES = Path(__file__).resolve().parents[2] / "profiles"
MM = 1e-3
THIN = {"wheel": {"generator": "S1002"}, "rail": {"generator": "UIC60", "inclination": "1:40"}}


def _thin(value, side=None):
    wear = {"flange_thinning_mm": value} if side is None else {side: {"flange_thinning_mm": value}}
    return config_from_dict({**THIN, "wear": {"wheel": wear}}, path="/x/thin.toml")


def test_a_thinning_the_wheel_takes_keeps_the_flange_tip(caplog):
    # the tester's numbers: up to 3.8 mm the usable wheel starts at s = -69.9 mm, tip 488.0 mm
    with caplog.at_level(logging.WARNING, logger="lutmpi"):
        g = WheelGeometry.place(flange_thinning(s1002(), 3.8), 0.46, 0.75)
    assert g.s_min / MM == pytest.approx(-69.9, abs=0.01)
    assert g.flange_tip_radius() / MM == pytest.approx(488.0, abs=0.01)
    assert not caplog.records   # only the steep flange back (0.1 mm) dropped: by design


def test_placing_a_wheel_whose_flange_tip_lies_beyond_a_steep_stretch_is_an_error():
    # 4 mm: the face above Sd reaches 85.3 deg at s = -42.8 mm; the placement kept only
    # s >= -42.79 mm, the tip radius 474.85 mm instead of 488 mm (flange contacts profile_end)
    with pytest.raises(GeometryError) as err:
        WheelGeometry.place(flange_thinning(s1002(), 4.0), 0.46, 0.75)
    msg = str(err.value)
    assert "S1002+flange_thinning" in msg and "steeper than the 85 deg" in msg
    assert "s = -70.00 .. -42.8" in msg and "flange tip (s = -54.99 mm, dr = 28.00 mm" in msg


@pytest.mark.parametrize("name", ["MBench_S1002_v3.prw", "Car7216_0001r.whl",
                                  "Car7358_0001r.whl", "avg_wheel.whl", "whl_left_iter288.whl"])
def test_the_measured_wheels_place_without_a_word(name, caplog):
    # whl_left_iter288 drops its 0.3 mm field-side rim face, steep all through: nothing lost
    wheel = read_profile(PROFILES / name, kind="wheel")
    with caplog.at_level(logging.WARNING, logger="lutmpi"):
        WheelGeometry.place(wheel, 0.46, 0.75)
    assert not caplog.records
    assert not WheelCut.of(wheel).tip_dropped


def test_surface_beyond_a_steep_step_is_dropped_with_a_warning_naming_it(caplog):
    # a 2 mm step down between s = 45.0 and 45.1 mm (a measuring fault): the tread beyond it,
    # 45.1 .. 60 mm, is no contact candidate any more, and the log says so
    w = s1002()
    z = np.where(w.y > 0.04505, w.z - 2.0 * MM, w.z)
    stepped = w.with_points(w.y.copy(), z, name="stepped")
    with caplog.at_level(logging.WARNING, logger="lutmpi"):
        g = WheelGeometry.place(stepped, 0.46, 0.75)
    assert 44.9 < g.s_max / MM < 45.1
    (rec,) = caplog.records
    assert rec.levelno == logging.WARNING
    text = rec.getMessage()
    assert re.match(r"wheel stepped: s = 4[45]\.\d\d \.\. 60\.00 mm \(field side\) is not used "
                    r"for contact: it lies beyond s = 4[45].* steeper than 85 deg", text)


def test_a_thinning_that_would_drop_the_flange_tip_is_a_config_error_with_the_largest():
    # tester's F2: 3.9 .. 4.99 mm were accepted and cut the flange off silently
    cfg = _thin(4.0)
    with pytest.raises(ConfigError) as err:
        side_profiles(cfg)
    msg = str(err.value)
    assert err.value.key == "wear.wheel.flange_thinning_mm" and "/x/thin.toml" in msg
    assert "4 mm is more than the wheel S1002 takes" in msg and "steeper than 85 deg" in msg
    most = float(msg.rsplit("every thinning up to ", 1)[1].split(" mm")[0])
    assert most == pytest.approx(3.83)
    # every thinning up to the one named is taken, and keeps the tip where it was
    for t in np.arange(0.5, most + 1e-9, 0.01 if most - 0.5 < 0.1 else 0.5).tolist() + [most]:
        wheels, _ = side_profiles(_thin(round(t, 2)))
        g = WheelGeometry.place(wheels["left"], 0.46, 0.75)
        assert g.flange_tip_radius() / MM == pytest.approx(488.0, abs=0.01)
    # a thinning that folds the face names the same largest value
    with pytest.raises(ConfigError, match=r"at 5 mm it folds the flange face.* up to 3\.83 mm"):
        side_profiles(_thin(5.0))


def test_a_side_thinning_error_names_the_side_key():
    with pytest.raises(ConfigError) as err:
        side_profiles(_thin(4.5, side="left"))
    assert err.value.key == "wear.wheel.left.flange_thinning_mm"
    assert math.isclose(float(str(err.value).rsplit("up to ", 1)[1].split(" mm")[0]), 3.83)
