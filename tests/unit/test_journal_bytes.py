"""A journaled point's bytes (issue 14): the one-point record is written from its columns'
bytes without the structured array, and must be that array's bytes exactly (resume reads them
back through the array's layout); anything else goes the structured way."""

from __future__ import annotations

import numpy as np

from lutmpi.contact.records import ContactResult
from lutmpi.equilibrium.result import PoseResult
from lutmpi.table.compute import empty_records, fill_record
from lutmpi.table.journal import JournalWriter, read_records, record_dtype, to_records
from lutmpi.table.schema import select_fields

METHODS = ("load_centre", "reference")
SHA = "ab" * 32


def _records():
    fields = select_fields(["all"])
    recs = empty_records(fields, METHODS, 1)
    result = PoseResult(0.004, 0.01, "load_centre", z_g=1.5e-4, roll=-2e-3, status=0)
    contact = ContactResult(wheel_point=np.array([0.0, 0.75, -0.46]),
                            rail_point=np.array([0.0, 0.75, 1e-5]), normal=np.array([0, 0, 1.0]),
                            indentation=1e-5, force=5e4, wheel_s=-1e-3, rail_v=2e-3)
    result.contacts = {"left": [contact], "right": []}
    fill_record(recs["load_centre"], 0, result)
    return fields, recs


def _structured(writer: JournalWriter, points, recs) -> bytes:
    arr = np.zeros(len(points), dtype=writer.dtype)
    arr["point"] = points
    for column, m, name in writer._columns:
        arr[column] = recs[m][name]
    return arr.tobytes()


def test_one_point_bytes_are_the_structured_arrays(tmp_path):
    fields, recs = _records()
    writer = JournalWriter(tmp_path, 0, "run", record_dtype(METHODS, fields), SHA, METHODS,
                           fields, 10.0)
    assert writer._one_point(np.array([11]), recs) == _structured(writer, [11], recs)
    writer.append(np.array([11]), recs)
    writer.close()
    arrays, report = read_records(writer.path, writer.dtype, SHA, 100)
    assert report.good == 1 and report.bad == 0
    points, back = to_records(arrays[0], METHODS, fields)
    assert points.tolist() == [11]
    for m in METHODS:
        for f in fields:
            np.testing.assert_array_equal(back[m][f.name], recs[m][f.name])


def test_other_dtypes_or_shapes_go_the_structured_way(tmp_path):
    fields, recs = _records()
    writer = JournalWriter(tmp_path, 0, "run", record_dtype(METHODS, fields), SHA, METHODS,
                           fields, 10.0)
    name = fields[1].name
    recs["reference"][name] = recs["reference"][name].astype(np.float32)
    assert writer._one_point(np.array([3]), recs) is None
    recs["reference"][name] = np.zeros((1, 3))          # a wrong shape: never silently written
    assert writer._one_point(np.array([3]), recs) is None
