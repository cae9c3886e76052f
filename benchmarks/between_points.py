"""A table between its grid points: a 1-D table (one yaw) queried every STEP along y against
direct solves with the table's own method, for this tree and (``--base``) another one built in
the same run (issues 11 and 14).

    .venv/bin/python benchmarks/between_points.py configs/manchester_s1002_uic60_1in40.toml \
        --method load_centre [--base /tmp/base]

The config's y axis is kept and its yaw axis replaced by ``--yaw`` (one column). Each tree
builds the table with its own ``lutmpi build`` (``PYTHONPATH`` = the tree); the queries
(``Table.interp``, jump-aware) and the direct solves (``solve_pose``) run in this tree.
``--refine-scale 1 3 10`` builds this tree's table once per ``output.refine_scale`` (the error
between the grid points against the build's run time). Printed
per table: build wall time, located jumps, extra knots, and the largest and RMS error of each
wheel's primary rolling radius (um) and contact angle (mrad), and of the wheelset's z_g (um)
and roll (urad), over the query poses, split into
*near* (within 0.02 mm of a located jump) and, by the larger primary contact angle of the two
wheels, *tread* (below 5 degrees), *root* (5 to 30 degrees) and *flange* (above 30).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.config import load_config  # noqa: E402
from lutmpi.pose.solve import solve_pose  # noqa: E402
from lutmpi.scene import Scene  # noqa: E402
from lutmpi.table import Table  # noqa: E402
from lutmpi.table.compute import pose_to_record  # noqa: E402
from lutmpi.table.schema import FIELDS_BY_NAME, D  # noqa: E402

NEAR_M = 2e-5
#: contact-angle bands (rad): tread below the first, flange root up to the second, flange above
BANDS_RAD = (np.radians(5.0), np.radians(30.0))


def one_column_config(config: Path, method: str, yaw: float, out: Path) -> Path:
    """The config with one yaw column and one method, profile paths made absolute."""
    text = config.read_text()
    lines = []
    for line in text.splitlines():
        key = line.split("=")[0].strip()
        if key == "yaw_rad":
            line = f"yaw_rad = [{yaw!r}, {yaw!r}, 1]"
        elif key == "method":
            line = f'method = "{method}"'
        elif key == "profile" and '"' in line:
            rel = line.split('"')[1]
            line = f'profile = "{(config.parent / rel).resolve()}"'
        lines.append(line)
    out.write_text("\n".join(lines) + "\n")
    return out


def with_refine_scale(config: Path, scale: float, out: Path) -> Path:
    """The config with ``output.refine_scale = scale``."""
    lines = config.read_text().splitlines()
    key = f"refine_scale = {scale!r}"
    if "[output]" in (line.strip() for line in lines):
        at = [line.strip() for line in lines].index("[output]")
        lines.insert(at + 1, key)
    else:
        lines += ["[output]", key]
    out.write_text("\n".join(lines) + "\n")
    return out


def build(tree: Path, config: Path, out: Path) -> float:
    """Wall time (s) of the tree's ``lutmpi build`` (its kernels compiled beforehand)."""
    env = dict(os.environ, PYTHONPATH=str(tree), OMP_NUM_THREADS="1")
    subprocess.run([sys.executable, "-m", "lutmpi.warmup"], check=True, capture_output=True,
                   env=env, cwd=str(tree))
    t0 = time.perf_counter()
    res = subprocess.run([sys.executable, "-m", "lutmpi.cli", "build", str(config), "-o",
                          str(out), "--force"], capture_output=True, text=True, env=env,
                         cwd=str(tree))
    if res.returncode != 0:
        sys.exit(f"build in {tree} failed:\n{res.stderr[-3000:]}")
    return time.perf_counter() - t0


def direct(scene: Scene, ys: np.ndarray, yaw: float, method: str) -> np.ndarray:
    """(n, 4): the larger over the wheels of the primary contact's rolling radius and contact
    angle, as the table stores them (slot 0: :func:`lutmpi.table.compute.pose_to_record`),
    then z_g and roll; per wheel for the first two, so (n, 4, 2) with the pose's quantities
    repeated."""
    names = (D.rolling_radius, D.contact_angle, D.z_g, D.roll)
    fields = [FIELDS_BY_NAME[n] for n in names]
    out = np.empty((ys.size, 4, 2))
    for k, y in enumerate(ys):
        rec = pose_to_record(solve_pose(scene, float(y), yaw, method), fields)
        out[k] = _rows(rec)
    return out


def _rows(rec: dict) -> np.ndarray:
    """(…, 4, 2) from a record or a query's arrays: the primary contact's rolling radius and
    contact angle per wheel, z_g and roll twice."""
    per = [np.asarray(rec[n])[..., 0] for n in (D.rolling_radius, D.contact_angle)]
    pose = [np.repeat(np.asarray(rec[n], float)[..., None], 2, axis=-1) for n in (D.z_g, D.roll)]
    return np.stack(per + pose, axis=-2)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config", type=Path)
    ap.add_argument("--method", default="load_centre")
    ap.add_argument("--yaw", type=float, default=0.0, help="the column's yaw, rad")
    ap.add_argument("--step-mm", type=float, default=0.05, help="query step along y, mm")
    ap.add_argument("--base", type=Path, help="another tree to build the same table with")
    ap.add_argument("--refine-scale", type=float, nargs="+", metavar="S",
                    help="build this tree's table once per output.refine_scale S")
    a = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="lutmpi-between-"))
    cfgp = one_column_config(a.config.resolve(), a.method, a.yaw, tmp / "one_column.toml")
    cfg = load_config(cfgp)
    scene = Scene.from_config(cfg)
    y0, y1, _ = cfg.grid.y_mm
    ys = np.round(np.arange(y0, y1 + 1e-9, a.step_mm), 6) * 1e-3
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  load {os.getloadavg()}  "
          f"{a.config} {a.method}, yaw {a.yaw} rad, queries every {a.step_mm} mm")
    trees = [(f"this, refine_scale {s:g}", ROOT,
              with_refine_scale(cfgp, s, tmp / f"scale_{k}.toml"))
             for k, s in enumerate(a.refine_scale)] if a.refine_scale else [("this", ROOT, cfgp)]
    trees += [("base", a.base.resolve(), cfgp)] if a.base else []
    walls = {name: build(tree, path, tmp / f"{k}.h5")
             for k, (name, tree, path) in enumerate(trees)}
    ref = direct(scene, ys, a.yaw, a.method)
    gamma = np.nanmax(np.abs(ref[:, 1, :]), axis=1)
    bands = {"tread": gamma < BANDS_RAD[0],
             "root": (gamma >= BANDS_RAD[0]) & (gamma <= BANDS_RAD[1]),
             "flange": gamma > BANDS_RAD[1]}
    for k, (name, _, _) in enumerate(trees):
        t = Table.open(tmp / f"{k}.h5")
        rec = t.interp(ys, np.full_like(ys, a.yaw), a.method)
        err = np.nanmax(np.abs(_rows(rec) - ref), axis=2)
        jy = t.jump_positions(a.method)[0]
        jy = jy[np.isfinite(jy)]
        near = (np.min(np.abs(ys[:, None] - jy[None, :]), axis=1) < NEAR_M if jy.size
                else np.zeros(ys.size, bool))
        knots = int(np.isfinite(t.jumps[a.method]["arrays"]["knot_y"]).sum())
        print(f"{name}: build {walls[name]:.1f} s, {jy.size} jumps, {knots} extra knots")
        for label, sel in [(k, ~near & b) for k, b in bands.items()] + [("near", near)]:
            if not sel.any():
                continue
            e = err[sel]
            mx, rms = e.max(axis=0), np.sqrt(np.mean(e ** 2, axis=0))
            print(f"  {label:6s} n={sel.sum():4d}  rolling radius max {mx[0] * 1e6:7.2f} "
                  f"rms {rms[0] * 1e6:6.2f} um   contact angle max {mx[1] * 1e3:6.3f} "
                  f"rms {rms[1] * 1e3:6.3f} mrad   z_g max {mx[2] * 1e6:6.2f} rms "
                  f"{rms[2] * 1e6:5.2f} um   roll max {mx[3] * 1e6:6.2f} rms {rms[3] * 1e6:5.2f} "
                  "urad")


if __name__ == "__main__":
    main()
