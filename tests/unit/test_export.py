"""``lutmpi export``: csv / mat / kpf written from real tables and read back (issue 12).

Tables are built here by ``lutmpi build`` on a small grid (about 1 s each); ``scipy.io.loadmat``
and h5py read the outputs back independently of lutmpi's own reader.
"""

from __future__ import annotations

import csv
import math

import h5py
import numpy as np
import pytest
import scipy.io

from lutmpi.cli import main as cli
from lutmpi.table.schema import FIELDS
from tests.support.tables import datasets

CONFIG = """
[wheel]
generator = "S1002"
{wheel_side}
[rail]
generator = "UIC60"
inclination = "{cant}"
{rail_side}
[grid]
y_mm = [-8.0, 8.0, 9]
yaw_rad = [-0.01, 0.01, 3]
[mesh]
wheel_lateral_mm = 1.0
wheel_circumferential_mm = 1.0
rail_lateral_mm = 1.0
rail_longitudinal_mm = 1.0
[output]
methods = ["load_centre", "reference"]
{wear}
"""


def _build(tmp, name: str, cant: str = "1:40", wear: str = "", wheel_side: str = "",
           rail_side: str = "") -> str:
    cfg = tmp / f"{name}.toml"
    cfg.write_text(CONFIG.format(cant=cant, wear=wear, wheel_side=wheel_side,
                                 rail_side=rail_side))
    out = tmp / f"{name}.h5"
    assert cli(["build", str(cfg), "-o", str(out)]) == 0
    return str(out)


@pytest.fixture(scope="module")
def tables(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("export")
    # a symmetric pair, a worn one (flange thinning + hollow tread: a different Δr(y)) and an
    # asymmetric one (left wheel 2 mm smaller in diameter, right rail at 1:20, left at 1:40)
    return {"new": _build(tmp, "new"),
            "worn": _build(tmp, "worn", "1:20",
                           "[wear.wheel]\nflange_thinning_mm = 2.0\ntread_hollowing_mm = 1.0"),
            "asym": _build(tmp, "asym", wheel_side="[wheel.left]\nnominal_radius_mm = 459.0",
                           rail_side="[rail.right]\ninclination = \"1:20\"")}


@pytest.mark.parametrize("case", ["new", "worn", "asym"])
def test_mat_reads_back_every_dataset_equal_to_the_hdf5(tables, tmp_path, case):
    assert cli(["export", tables[case], "--format", "mat", "-o", str(tmp_path / "t.mat")]) == 0
    mat = scipy.io.loadmat(tmp_path / "t.mat", simplify_cells=True)
    h5 = datasets(tables[case])
    assert h5, "no datasets read from the HDF5"
    for name, ref in h5.items():
        got = mat
        for part in name.split("/"):           # /method/name, /method/jumps/limits/name, ...
            got = got[part]
        got = np.asarray(got)
        assert got.size == ref.size, name
        got = got.reshape(ref.shape)
        # (MATLAB keeps no type on an empty array: loadmat gives float64 for any empty one)
        assert ref.size == 0 or got.dtype == ref.dtype, (name, got.dtype, ref.dtype)
        assert np.array_equal(got, ref, equal_nan=ref.dtype.kind == "f"), name
    with h5py.File(tables[case]) as f:
        assert mat["units"]["load_centre"]["rolling_radius"] == f["load_centre/rolling_radius"
                                                                  ].attrs["units"] == "m"
        assert mat["attrs"]["config_toml"] == f.attrs["config_toml"]
    assert any(s.startswith("0: converged") for s in mat["status_codes"])


def _read_csv(path):
    with open(path, newline="") as fh:
        lines = [ln for ln in fh if not ln.startswith("#")]
    return list(csv.DictReader(lines))


@pytest.mark.parametrize("case", ["new", "worn", "asym"])
def test_csv_columns_are_the_schema_in_mm_and_deg(tables, tmp_path, case):
    out = tmp_path / "f.csv"
    assert cli(["export", tables[case], "--format", "csv", "-o", str(out)]) == 0
    rows = _read_csv(out)
    with h5py.File(tables[case]) as f:
        y = f["y"][...]
        j = int(np.argmin(np.abs(f["yaw"][...])))
        rr = f["load_centre/rolling_radius"][:, j]
        ang = f["load_centre/contact_angle"][:, j]
        zg = f["load_centre/z_g"][:, j]
    assert len(rows) == y.size
    for i, row in enumerate(rows):
        # mm and degrees at the edge: 1 m = 1000 mm, 1 rad = 180/pi deg
        assert float(row["y_mm"]) == pytest.approx(y[i] * 1e3, rel=1e-9)
        assert float(row["z_g_mm"]) == pytest.approx(zg[i] * 1e3, rel=1e-9)
        assert float(row["rolling_radius_right_s0_mm"]) == pytest.approx(rr[i, 1, 0] * 1e3,
                                                                         rel=1e-9)
        assert float(row["contact_angle_left_s0_deg"]) == pytest.approx(
            math.degrees(ang[i, 0, 0]), rel=1e-9)
        assert row["status_text"] == "converged"
    header = list(rows[0])
    # every schema field has its columns (both wheels, both slots for per-contact fields)
    for fld in FIELDS:
        assert any(c.startswith(fld.name) for c in header), fld.name
    assert "rolling_radius_left_s1_mm" in header and "wheel_point_x_right_s1_mm" in header


def test_csv_refuses_a_yaw_off_the_grid(tables, tmp_path, capsys):
    rc = cli(["export", tables["new"], "--format", "csv", "--yaw-rad", "0.005", "-o",
              str(tmp_path / "x.csv")])
    assert rc == 1
    assert "yaw 0.005 rad is not on the grid" in capsys.readouterr().err


# GENSYS KPF manual (https://gensys.se/doc_html/kpf.html, "Wheel profile input data"): the example
# wheel file, Y toward the track centre, Z downwards, origin at the nominal running circle. These
# (Y, Z) pairs are printed there; they are the S1002 profile.
KPF_MANUAL_WHEEL = [(-60.0, -2.63568), (-59.9, -2.62901), (-59.0, -2.56901), (-58.3, -2.52234),
                    (-0.6, -0.01959), (-0.3, -0.00994), (-0.1, -0.00334), (0.0, 0.0),
                    (0.1, 0.00337), (0.3, 0.01022), (0.6, 0.02072), (68.8, 16.43012),
                    (69.0, 15.84381), (69.3, 14.83057)]


def test_kpf_wheel_file_reproduces_the_manuals_example(tables, tmp_path):
    paths = [tmp_path / "pair.wheel", tmp_path / "pair.rail"]
    assert cli(["export", tables["new"], "--format", "kpf", "-o", str(tmp_path / "pair")]) == 0
    assert all(p.is_file() for p in paths)
    w = np.loadtxt(paths[0])                  # '#' lines are comments, as in KPF
    assert np.all(np.diff(w[:, 0]) > 0)       # no back-steps in Y
    for y, z in KPF_MANUAL_WHEEL:
        # the file is sampled along the arc; linear interpolation between samples 0.1 mm apart
        # on a curve of radius >= 13 mm is good to 1e-4 mm, the manual prints 5 decimals
        assert np.interp(y, w[:, 0], w[:, 1]) == pytest.approx(z, abs=2e-4), y


def test_kpf_rail_origin_and_gauge_point(tables, tmp_path):
    cli(["export", tables["new"], "--format", "kpf", "-o", str(tmp_path / "pair")])
    r = np.loadtxt(tmp_path / "pair.rail")
    assert np.all(np.diff(r[:, 0]) > 0)
    assert np.interp(0.0, r[:, 0], r[:, 1]) == pytest.approx(0.0, abs=1e-5)   # Z(Y=0) = 0 (5 dec.)
    top = r[:, 1].min()                                  # top of rail (Z down)
    near = r[(r[:, 1] >= top) & (r[:, 1] <= top + 14.0)]   # GAUGE_MEAS_INTERVAL = 14 mm
    # gauge point GAUGE_TO_ORIGO = 32.5 mm from the origin: (1500 - 1435) / 2 for tape circles
    # at +-750 mm and gauge 1435 mm; the samples are 0.1 mm apart
    assert near[:, 0].max() == pytest.approx(32.5, abs=0.1)
    assert top <= 0.0


def test_kpf_asymmetric_pair_writes_each_side(tables, tmp_path):
    assert cli(["export", tables["asym"], "--format", "kpf", "-o", str(tmp_path / "p")]) == 0
    files = {s: {k: np.loadtxt(tmp_path / f"p_{s}.{k}") for k in ("wheel", "rail")}
             for s in ("left", "right")}
    assert not (tmp_path / "p.wheel").exists()
    # the same S1002 on both wheels: the radius increase is relative to each wheel's own tape
    # circle, so the files are equal; the rails differ by their inclination (1:40 vs 1:20):
    # over the 70 mm head the slope difference atan(1/20) - atan(1/40) moves points by ~0.9 mm
    np.testing.assert_allclose(files["left"]["wheel"], files["right"]["wheel"])
    assert not np.array_equal(files["left"]["rail"], files["right"]["rail"])
    for s in ("left", "right"):
        r = files[s]["rail"]
        top = r[:, 1].min()
        near = r[(r[:, 1] >= top) & (r[:, 1] <= top + 14.0)]
        assert near[:, 0].max() == pytest.approx(32.5, abs=0.1), s
