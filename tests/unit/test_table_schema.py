"""Schema, grid and pose -> record (issue 4)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from lutmpi.config.model import ALWAYS_STORED as CONFIG_ALWAYS
from lutmpi.config.model import QUANTITIES, GridConfig
from lutmpi.equilibrium.result import STATUS, ContactResult, PoseResult
from lutmpi.errors import ConfigError
from lutmpi.table.compute import pose_to_record
from lutmpi.table.grid import Grid
from lutmpi.table.schema import (
    ALWAYS_STORED,
    FIELDS,
    FIELDS_BY_NAME,
    dataset_attributes,
    fields_of_quantity,
    select_fields,
)


def test_every_config_quantity_maps_to_schema_fields():
    for q in QUANTITIES:
        assert fields_of_quantity(q), q
        assert set(fields_of_quantity(q)) <= set(FIELDS_BY_NAME), q
    covered = {n for q in QUANTITIES for n in fields_of_quantity(q)} | set(ALWAYS_STORED)
    assert covered == set(FIELDS_BY_NAME)
    assert len(CONFIG_ALWAYS) == len(ALWAYS_STORED)


def test_select_fields_subset_keeps_always_stored_and_rejects_unknown():
    names = [f.name for f in select_fields(["normal", "curvatures"])]
    assert names == ["status", "iterations", "compute_time", "normal", "curv_wheel_rolling",
                     "curv_wheel_transverse", "curv_rail_transverse"]
    assert select_fields(["all"]) == FIELDS
    with pytest.raises(ConfigError, match="unknown quantity 'banana'"):
        select_fields(["banana"])


def test_every_field_has_si_units_and_status_codes():
    for f in FIELDS:
        attrs = dataset_attributes(f)
        assert "units" in attrs and attrs["description"]
    codes = json.loads(dataset_attributes(FIELDS_BY_NAME["status"])["status_codes"])
    assert {int(k): v for k, v in codes.items()} == STATUS


def test_grid_axes_in_si_and_flat_index_round_trip():
    g = Grid.from_config(GridConfig(y_mm=(-9.0, 9.0, 37), yaw_rad=(-0.12, 0.12, 5)))
    assert g.shape == (37, 5) and g.y[0] == pytest.approx(-9e-3) and g.y[18] == 0.0
    k = np.arange(g.n_points)
    iy, iyaw = g.ij(k)
    assert np.array_equal(g.flat(iy, iyaw), k)
    assert g.pose(5) == (g.y[1], g.yaw[0])
    assert "iy=1, iyaw=0" in g.describe(5)
    with pytest.raises(ConfigError):
        Grid.from_config(GridConfig(y_mm=(1.0, -1.0, 3)))


def _contact(force: float, y: float) -> ContactResult:
    return ContactResult(wheel_point=np.array([0.0, y, 0.0]), rail_point=np.array([0, y, -1e-5]),
                         normal=np.array([0.0, 0.0, 1.0]), indentation=1e-5, force=force)


def test_record_puts_largest_force_in_slot_zero_and_nan_for_missing():
    res = PoseResult(y=0.0, yaw=0.0, method="load_centre", z_g=1e-3, status=0, nit=7)
    res.contacts = {"left": [_contact(1.0, 0.1)], "right": [_contact(2.0, 0.2), _contact(9.0, 0.3)]}
    rec = pose_to_record(res, FIELDS)
    assert rec["force"].shape == (2, 2)
    assert rec["force"][1].tolist() == [9.0, 2.0]          # right: sorted by force
    assert rec["wheel_point"][1, 0, 1] == 0.3
    assert rec["force"][0, 0] == 1.0 and np.isnan(rec["force"][0, 1])   # left slot 1 missing
    assert np.isnan(rec["wheel_point"][0, 1]).all()
    assert rec["n_contacts"].tolist() == [1, 2]
    assert rec["iterations"] == 7 and rec["z_g"] == 1e-3 and rec["status"] == 0
