"""A journaled point's bytes (issue 14): a build fills its points in place in a store of the
journal's record layout (``TableWriter.claim``) and journals those rows as they are. They must be
the bytes the records' structured way gives (resume reads them back through that layout), and a
store's untouched fields must hold each field's fill value."""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.contact.records import ContactResult
from lutmpi.equilibrium.result import PoseResult
from lutmpi.table.compute import empty_records, fill_record
from lutmpi.table.journal import (
    JournalWriter,
    empty_rows,
    read_records,
    record_dtype,
    to_records,
)
from lutmpi.table.schema import select_fields

METHODS = ("load_centre", "reference")
SHA = "ab" * 32


def _result() -> PoseResult:
    result = PoseResult(0.004, 0.01, "load_centre", z_g=1.5e-4, roll=-2e-3, status=0)
    contact = ContactResult(wheel_point=np.array([0.0, 0.75, -0.46]),
                            rail_point=np.array([0.0, 0.75, 1e-5]), normal=np.array([0, 0, 1.0]),
                            indentation=1e-5, force=5e4, wheel_s=-1e-3, rail_v=2e-3)
    result.contacts = {"left": [contact], "right": []}
    return result


def _writer(tmp_path, fields) -> JournalWriter:
    return JournalWriter(tmp_path, 0, "run", record_dtype(METHODS, fields), SHA, 10.0)


def _structured(dtype, points, recs) -> np.ndarray:
    """The records as the journal's structured rows, field by field (the layout's definition)."""
    arr = np.zeros(len(points), dtype=dtype)
    arr["point"] = points
    for m in METHODS:
        for f in select_fields(["all"]):
            arr[f"{m}/{f.name}"] = recs[m][f.name]
    return arr


def _assert_same(back, recs) -> None:
    for m in METHODS:
        for f in select_fields(["all"]):
            np.testing.assert_array_equal(back[m][f.name], recs[m][f.name], err_msg=f.name)


def test_empty_rows_hold_every_fields_fill_value():
    fields = select_fields(["all"])
    rows = empty_rows(record_dtype(METHODS, fields), METHODS, fields, 3)
    recs = empty_records(fields, METHODS, 3)
    _, back = to_records(rows, METHODS, fields)
    assert rows["point"].tolist() == [-1, -1, -1]
    _assert_same(back, recs)


def test_rows_filled_in_place_are_the_records_bytes_and_read_back(tmp_path):
    fields = select_fields(["all"])
    writer = _writer(tmp_path, fields)
    recs = empty_records(fields, METHODS, 1)
    fill_record(recs["load_centre"], 0, _result())
    rows = empty_rows(writer.dtype, METHODS, fields, 4)
    views = {m: {f.name: rows[f"{m}/{f.name}"] for f in fields} for m in METHODS}
    fill_record(views["load_centre"], 2, _result())        # row 2 of the store, in place
    rows["point"][2] = 11

    writer.append_rows(_structured(writer.dtype, [11], recs))   # field by field
    writer.append_rows(rows[2:3])                                # the store's row as it is
    writer.close()
    arrays, report = read_records(writer.path, writer.dtype, SHA, 100)
    assert report.good == 2 and report.bad == 0
    assert arrays[0].tobytes() == arrays[1].tobytes()
    points, back = to_records(arrays[1], METHODS, fields)
    assert points.tolist() == [11]
    _assert_same(back, recs)


def test_rows_of_another_layout_are_refused(tmp_path):
    fields = select_fields(["all"])
    writer = _writer(tmp_path, fields)
    other = record_dtype(METHODS[:1], fields)
    with pytest.raises(TypeError, match="record's dtype"):
        writer.append_rows(empty_rows(other, METHODS[:1], fields, 1))
    with pytest.raises(TypeError, match="1-D"):
        writer.append_rows(empty_rows(writer.dtype, METHODS, fields, 4).reshape(2, 2))
    writer.close()
    assert read_records(writer.path, writer.dtype, SHA, 100)[1].good == 0
