"""Sweeps and the convergence report, end to end with a solver of known convergence order.

The sweep runs under ``mpirun -n 2`` in a subprocess (skipped without mpirun); the report's
numbers are checked against a direct recomputation from the HDF5 files with h5py + numpy.
"""

from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from lutmpi.cli import main as cli
from lutmpi.paths import REPO_ROOT

SOLVER = "tests.support.mesh_solver:solve"
MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1", "OMPI_MCA_btl": "self,vader"}
BASE = """
[base.wheel]
generator = "S1002"
[base.rail]
generator = "UIC60"
[base.grid]
y_mm = [-3.0, 3.0, 3]
yaw_rad = [-0.01, 0.01, 3]
"""
CONVERGENCE = BASE + """
[[sweep]]
product = { "contact.method" = ["max_distance", "load_centre"], """ + """\
"mesh.spacing_mm" = [2.0, 1.0, 0.5] }
[[sweep]]
product = { "contact.method" = ["reference"] }
"""


def _env(**extra: str) -> dict[str, str]:
    env = dict(os.environ, **MPI_ENV, **extra)
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(REPO_ROOT), env.get("PYTHONPATH")]))
    for key in [k for k in env if k.startswith(("OMPI_COMM_WORLD", "PMI_", "PMIX_"))]:
        del env[key]                      # never inherit a parent job's rank
    return env


def _sweep_mpi(sweep: Path, out: Path, n: int = 2, solver: str | None = SOLVER,
               timeout: float = 240, **extra: str) -> subprocess.CompletedProcess:
    """``mpirun -n n lutmpi sweep``; ``solver=None`` runs the production solver."""
    mpirun = shutil.which("mpirun")
    if mpirun is None:
        pytest.skip("mpirun not found")
    cmd = [mpirun, "-n", str(n), sys.executable, "-m", "lutmpi.cli", "sweep", str(sweep), "-o",
           str(out)] + (["--solver", solver] if solver else [])
    return subprocess.run(cmd, env=_env(**extra), capture_output=True, text=True,
                          timeout=timeout, cwd=REPO_ROOT)


def _index(out: Path) -> dict[str, dict]:
    return {m["id"]: m for m in json.loads((out / "index.json").read_text())["members"]}


def _recompute(out: Path, member: str, ref: str = "m-reference") -> dict[str, float]:
    """Max |error| straight from the files, independently of lutmpi.reports."""
    import h5py

    def group(name):
        with h5py.File(out / f"{name}.h5", "r") as f:
            method = json.loads(f.attrs["methods"])[0]
            return {k: v[...] for k, v in f[method].items()
                    if isinstance(v, h5py.Dataset)}, f.attrs["wall_time_s"]

    a, _ = group(member)
    b, _ = group(ref)
    ok = (a["status"] == 0) & (b["status"] == 0)
    res = {"z_g": np.abs(a["z_g"] - b["z_g"])[ok].max() * 1e3,
           "roll": np.abs(a["roll"] - b["roll"])[ok].max() * 1e3,
           "wheel_s": np.abs(a["wheel_s"] - b["wheel_s"])[..., 0][ok].max() * 1e3,
           "cpu_s": a["compute_time"].sum()}
    na, nb = a["normal"][..., 0, :], b["normal"][..., 0, :]
    cosang = np.clip(np.sum(na * nb, axis=-1), -1, 1)
    res["normal"] = np.arccos(cosang)[ok].max() * 1e3
    res["z_g_rms"] = np.sqrt(np.mean((a["z_g"] - b["z_g"])[ok] ** 2)) * 1e3
    return res


def test_convergence_sweep_on_two_ranks_and_report(tmp_path):
    sweep = tmp_path / "conv.toml"
    sweep.write_text(CONVERGENCE)
    out, rep = tmp_path / "out", tmp_path / "rep"
    proc = _sweep_mpi(sweep, out)
    assert proc.returncode == 0, proc.stderr[-3000:]
    index = _index(out)
    assert len(index) == 7 and all(m["status"] == "ok" for m in index.values())
    assert all(m["ranks"] == 2 and m["points"] == 9 for m in index.values())
    assert cli(["report", str(out), "-o", str(rep)]) == 0
    text = (rep / "report.md").read_text()
    assert "## Convergence" in text and (rep / "error_vs_time_z_g.png").stat().st_size > 1000
    assert (rep / "error_vs_spacing_z_g.png").exists()
    assert (rep / "map_m-load_centre__h-1_z_g.png").exists()
    rows = {r["member"]: r for r in csv.DictReader(open(rep / "errors.csv"))}
    assert len(rows) == 6
    for method in ("max_distance", "load_centre"):
        errs = [float(rows[f"m-{method}__h-{h}"]["z_g_max_mm"]) for h in ("2", "1", "0.5")]
        assert errs[0] > errs[1] > errs[2] > 0, (method, errs)   # error falls with refinement
    for member, row in rows.items():
        direct = _recompute(out, member)
        assert float(row["z_g_max_mm"]) == pytest.approx(direct["z_g"], rel=1e-12)
        assert float(row["z_g_rms_mm"]) == pytest.approx(direct["z_g_rms"], rel=1e-12)
        assert float(row["roll_max_mrad"]) == pytest.approx(direct["roll"], rel=1e-12)
        assert float(row["wheel_s_max_mm"]) == pytest.approx(direct["wheel_s"], rel=1e-12)
        assert float(row["normal_max_mrad"]) == pytest.approx(direct["normal"], rel=1e-6)
        assert float(row["cpu_s"]) == pytest.approx(direct["cpu_s"], rel=1e-12)
        assert float(row["cpu_ms_per_point"]) == pytest.approx(direct["cpu_s"] / 9 * 1e3)
    # observed orders of the test solver: 1 (max_distance) and 2 (load_centre)
    assert "| max_distance | 1 | 1 |" in text and "| load_centre | 2 | 2 |" in text
    # a rerun skips every finished member and rebuilds nothing
    mtimes = {p.name: p.stat().st_mtime_ns for p in out.glob("*.h5")}
    proc = _sweep_mpi(sweep, out)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert all(m["skipped"] for m in _index(out).values())
    assert mtimes == {p.name: p.stat().st_mtime_ns for p in out.glob("*.h5")}


def test_failing_members_are_recorded_and_others_complete(tmp_path):
    bad = tmp_path / "bad.whl"
    bad.write_text("garbage\n")
    sweep = tmp_path / "fail.toml"
    sweep.write_text(BASE + f"""
[[sweep]]
product = {{ "contact.method" = ["max_distance", "load_centre"] }}
[[sweep]]
product = {{ "wheel.profile" = ["{bad}"] }}
""")
    out = tmp_path / "out"
    proc = _sweep_mpi(sweep, out, LUTMPI_MESH_FAULT="max_distance")
    assert proc.returncode == 1                       # a failed member: non-zero, not a crash
    index = _index(out)
    assert index["m-load_centre"]["status"] == "ok" and (out / "m-load_centre.h5").exists()
    assert index["m-max_distance"]["status"] == "failed"
    assert "all 9 points failed" in index["m-max_distance"]["message"]
    assert index["w-bad"]["status"] == "failed" and "ProfileError" in index["w-bad"]["message"]
    assert "garbage" in index["w-bad"]["message"]
    assert not (out / "w-bad.h5").exists()
    lines = (out / "index.csv").read_text().splitlines()
    assert len(lines) == 4 and lines[0].startswith("id,status,message")


@pytest.mark.parametrize("body, needle", [
    ('[[sweep]]\nproduct = { "contact.methd" = ["load_centre"] }\n', "contact.methd"),
    ('[[sweep]]\nproduct = { "contact.method" = [] }\n', "empty"),
    ('[[sweep]]\nproduct = { "wheel.profile" = ["does_not_exist.whl"] }\n', "does_not_exist"),
])
def test_bad_sweep_is_a_clear_error_before_anything_runs(tmp_path, capsys, body, needle):
    sweep = tmp_path / "bad.toml"
    sweep.write_text(BASE + body)
    out = tmp_path / "out"
    assert cli(["sweep", str(sweep), "-o", str(out), "--solver", SOLVER]) == 1
    err = capsys.readouterr().err
    assert "error" in err and needle in err and str(sweep) in err
    assert not out.exists()


def test_wear_sweep_report_and_conicity_command(tmp_path, capsys):
    sweep = tmp_path / "wear.toml"
    sweep.write_text(BASE.replace("y_mm = [-3.0, 3.0, 3]", "y_mm = [-8.0, 8.0, 17]") + """
[[sweep]]
product = { "wear.wheel.flange_thinning_mm" = [0.0, 1.0] }
""")
    out, rep = tmp_path / "out", tmp_path / "rep"
    assert cli(["sweep", str(sweep), "-o", str(out), "--solver", SOLVER]) == 0
    assert cli(["report", str(out), "-o", str(rep)]) == 0
    text = (rep / "report.md").read_text()
    assert "## Wear" in text and "## Convergence" not in text
    for name in ("wear_dr.png", "wear_conicity.png", "wear_contact_angle.png", "wear_roll.png"):
        assert (rep / name).stat().st_size > 1000
    # the test solver's Δr = 0.1 y is a cone of conicity 0.05
    rows = list(csv.reader(open(rep / "conicity.csv")))
    assert rows[0] == ["amplitude_mm", "ft-0", "ft-1"]
    vals = np.array([[float(v) for v in r[1:]] for r in rows[1:]])
    reach = np.array([float(r[0]) for r in rows[1:]]) <= 8.0
    np.testing.assert_allclose(vals[reach], 0.05, atol=1e-6)
    capsys.readouterr()
    table = out / "ft-0.h5"
    assert cli(["conicity", str(table), "--amplitudes", "1:3:1", "-o",
                str(tmp_path / "c.csv"), "--plot", str(tmp_path / "c.png")]) == 0
    printed = capsys.readouterr().out
    assert "3.000,0.05000" in printed and "at 3 mm: 0.0500" in printed
    assert (tmp_path / "c.png").exists()
    np.testing.assert_allclose(np.loadtxt(tmp_path / "c.csv", delimiter=",", skiprows=1)[:, 1],
                               0.05, atol=1e-6)
