"""The schema is the only list of dataset names (issue 15).

1. Every dataset of ``table/schema.py`` is filled from the pose result by its name: a per-point
   field from the :class:`PoseResult` attribute of that name, a per-contact field from the
   :class:`ContactResult` attribute (``table/compute.py``: one short alias map for older names).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lutmpi.equilibrium.result import ContactResult, PoseResult
from lutmpi.table.compute import ATTRIBUTE_OF, DERIVED, fill_record, result_attribute
from lutmpi.table.schema import FIELDS, FIELDS_BY_NAME


def _attributes(cls) -> set[str]:
    return {f.name for f in dataclasses.fields(cls)} | {
        n for n, v in vars(cls).items() if isinstance(v, property)}


def test_every_field_is_an_attribute_of_the_pose_result():
    point, contact = _attributes(PoseResult), _attributes(ContactResult)
    missing = [f.name for f in FIELDS if f.name not in DERIVED
               and result_attribute(f.name) not in (contact if f.per_contact else point)]
    assert not missing, f"schema fields with no result attribute to fill them from: {missing}"


def test_alias_map_names_only_schema_fields():
    # a stale alias (a renamed or removed field) would silently never be used
    assert set(ATTRIBUTE_OF) | set(DERIVED) <= set(FIELDS_BY_NAME)


def test_a_field_without_an_attribute_fails_loudly(monkeypatch):
    # a new schema line whose value nobody produces must not become a silent column of NaN
    monkeypatch.setitem(FIELDS_BY_NAME, "not_a_result_attribute", FIELDS_BY_NAME["z_g"])
    with pytest.raises(AttributeError, match="not_a_result_attribute"):
        fill_record({"not_a_result_attribute": np.zeros(1)}, 0, PoseResult(0.0, 0.0, "reference"))
