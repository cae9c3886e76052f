"""lutmpi's whole ``build`` command on 1 rank against a simple numpy rigid-contact solver on one
core, measured in the same run, on the same grid and profiles (issue 14, "Must show" 2).

    .venv/bin/python benchmarks/numpy_ratio.py configs/manchester_s1002_uic60_1in40.toml

The simple solver is what a vehicle-dynamics engineer would write in an afternoon: for each pose
(y, yaw) it finds the rigid two-point contact (z_g, roll) by brute force on a wheel surface grid.
Per wheel and roll, every profile slice (0.25 mm apart over the placed profile) is a circle; its
points on 11 angles over +-0.2 rad, then 2 x 5 angles around each slice's best (for the slices
within 0.5 mm of the lowest), are moved to the track frame and their vertical gap to the rail
profile (``np.interp`` on 0.05 mm samples) is taken; the smallest gap of each wheel is the height
at which it touches. The roll making both wheels touch comes from a secant iteration on the
height mismatch (Brent's bracket as fallback). The inputs are the placed profiles of lutmpi's
scene (the same geometry); nothing else is shared. Its cost per pose is printed: the ratio is
only as meaningful as this baseline (issue 14 quotes 2.9 ms per pose for the one it used).

Printed: the wall time of ``lutmpi build CONFIG`` (whole command: start-up, imports, compiled
kernels loaded, every point, the HDF5 file) on one rank, the numpy solver's time over the same
grid, their ratio, the same ratio for the build's time up to the end of its grid (the whole
command less the jump step and final write its log reports: the work the numpy solver does, so
the like-for-like figure; the jump step solves ~7x the grid's solved poses to locate and
refine the contact jumps, which no grid-only solver does; both solve one pose per orbit of the
table's reflections, a quarter of a symmetric pair's, docs/TABLES.md), and the numpy solver's
deviation from the table's z_g and roll (a sanity check that it solves the same problem: a few
µm, its angular grid).

``--pinned ROUNDS`` measures both at once instead, the build on one core and the numpy solver
on the other for the whole of the build (cores swapped every round; the numpy solver's time is
that of the grid at the rate it ran meanwhile): on a VM whose speed drifts by tens of percent
within minutes, two runs one after the other compare two machines. Each run then slows the
other (shared cache and memory; on the 2-core Intel VM of 2026-11-27 the build by ~20 %, more
than the numpy solver), so the pinned ratio is higher than the quiet machine's: it is the
figure to compare two trees or two runs by, not the issue's absolute one.

``--grid-only`` also builds the config with ``[output] jumps = false`` (the table of the grid's
points only, what a tool that reads the grid and interpolates by itself needs) in each round and
prints its whole command's ratio.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.config import load_config  # noqa: E402
from lutmpi.scene import Scene  # noqa: E402
from lutmpi.table.grid import Grid  # noqa: E402


class NumpyRigid:
    """Brute-force rigid two-point contact (module docstring). SI units."""

    def __init__(self, scene: Scene, ds: float = 2.5e-4):
        w, r = scene.wheel, scene.rail
        self.s = np.arange(w.s_min, w.s_max, ds)
        self.r = w.radius(self.s)
        self.d = w.d
        self.ru = np.arange(r.u_min, r.u_max, 5e-5)
        self.rz = r.height(self.ru)

    def _gap_min(self, side: float, y: float, R: np.ndarray) -> float:
        """Smallest vertical gap of wheel ``side`` to its rail with G at height 0."""
        sel = np.arange(self.s.size)
        phi0 = np.zeros(self.s.size)
        for span, n in ((0.2, 11), (0.04, 5), (0.008, 5)):
            r, s = self.r[sel], self.s[sel]
            phi = phi0[:, None] + np.linspace(-span, span, n)[None, :]
            bx, bz = r[:, None] * np.sin(phi), -r[:, None] * np.cos(phi)
            by = side * (self.d + s)[:, None]
            py = R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz + y
            pz = R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz
            u = side * py
            gap = pz - np.interp(u, self.ru, self.rz, left=np.inf, right=np.inf)
            gap[(u < self.ru[0]) | (u > self.ru[-1])] = np.inf
            k = np.argmin(gap, axis=1)
            phi0 = phi[np.arange(sel.size), k]
            best = gap[np.arange(sel.size), k]
            # refine only the slices within 0.5 mm of the lowest (the coarse grid's error is
            # below r (1 - cos 0.02) = 0.09 mm)
            keep = best <= np.min(best) + 5e-4
            sel, phi0 = sel[keep], phi0[keep]
        return float(np.min(best[keep]))

    @staticmethod
    def rotation(yaw: float, roll: float) -> np.ndarray:
        cy, sy, cr, sr = np.cos(yaw), np.sin(yaw), np.cos(roll), np.sin(roll)
        return np.array([[cy, -sy * cr, sy * sr], [sy, cy * cr, -cy * sr], [0.0, sr, cr]])

    def solve(self, y: float, yaw: float) -> tuple[float, float]:
        """(z_g, roll) of the rigid two-point contact."""

        def heights(roll: float) -> tuple[float, float]:
            R = self.rotation(yaw, roll)
            return -self._gap_min(1.0, y, R), -self._gap_min(-1.0, y, R)

        def h(roll: float) -> float:
            zl, zr = heights(roll)
            return zl - zr

        x0, f0 = 0.0, h(0.0)
        x1 = f0 / (2.0 * self.d)
        f1 = h(x1)
        for _ in range(20):
            if f1 == f0 or abs(x1 - x0) < 1e-10:
                break
            x0, f0, x1 = x1, f1, x1 - f1 * (x1 - x0) / (f1 - f0)
            f1 = h(x1)
        if not abs(f1) < 1e-8:
            x1 = brentq(h, -0.02, 0.02, xtol=1e-10)
        zl, zr = heights(x1)
        return 0.5 * (zl + zr), x1


def run_build(config: str, out: Path, core: int | None = None) -> tuple[float, float]:
    """Wall time of ``lutmpi build CONFIG`` on one rank (on core ``core`` when given), and the
    part of it after the grid (the jump step and the final write, from the build's log), s."""
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    cmd = [str(ROOT / ".venv/bin/lutmpi"), "build", config, "-o", str(out), "--force"]
    if core is not None:
        cmd = ["taskset", "-c", str(core), *cmd]
    t0 = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=str(ROOT))
    wall = time.perf_counter() - t0
    if res.returncode != 0:
        sys.exit(f"lutmpi build failed:\n{res.stderr[-3000:]}")
    after = re.search(r"after the grid: .*? ([0-9.]+) s; whole build", res.stderr)
    if after is None:
        sys.exit(f"no 'after the grid' line in the build log:\n{res.stderr[-3000:]}")
    return wall, float(after.group(1))


def _numpy_worker(config: str, core: int, stop, out) -> None:  # noqa: ANN001 - mp objects
    """``--pinned``: the numpy solver on core ``core``, pose after pose over the grid (again
    and again) until ``stop`` is set; puts the end time of every pose into ``out``."""
    os.sched_setaffinity(0, {core})
    cfg = load_config(config)
    grid = Grid.from_config(cfg.grid)
    solver = NumpyRigid(Scene.from_config(cfg))
    poses = [(y, yaw) for y in grid.y for yaw in grid.yaw]
    solver.solve(*poses[0])
    ends = []
    out.put("ready")
    k = 0
    while not stop.is_set():
        solver.solve(*poses[k % len(poses)])
        ends.append(time.perf_counter())
        k += 1
    out.put(ends)


def pinned_round(config: str, out: Path, build_core: int, n_points: int
                 ) -> tuple[float, float, float]:
    """The build on core ``build_core`` while the numpy solver runs on the other core for the
    whole of it (a drift of the machine's speed then hits both alike). Returns the build's
    wall time, the part after its grid, and the numpy solver's time for the whole grid at
    the rate it ran during the build (poses completed in the build's window, s)."""
    import multiprocessing as mp

    ctx = mp.get_context("spawn")
    stop, q = ctx.Event(), ctx.Queue()
    proc = ctx.Process(target=_numpy_worker, args=(config, 1 - build_core, stop, q))
    proc.start()
    if q.get() != "ready":
        sys.exit("numpy worker failed to start")
    t0 = time.perf_counter()
    wall, after = run_build(config, out, core=build_core)
    t1 = time.perf_counter()
    stop.set()
    ends = np.array(q.get())
    proc.join()
    done = ends[(ends > t0) & (ends <= t1)]
    if done.size < 2:
        sys.exit("the numpy solver completed fewer than two poses during the build")
    per_pose = (done[-1] - done[0]) / (done.size - 1)
    return wall, after, per_pose * n_points


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--repeat", type=int, default=1, help="take the best of this many runs")
    ap.add_argument("--grid-only", action="store_true",
                    help="also build with [output] jumps = false and print its ratio")
    ap.add_argument("--pinned", type=int, default=0, metavar="ROUNDS",
                    help="instead: ROUNDS rounds of the build on one core while the numpy "
                         "solver runs on the other for the whole of it (cores swapped each "
                         "round); the ratio per round (needs two cores)")
    a = ap.parse_args()
    cfg = load_config(a.config)
    grid = Grid.from_config(cfg.grid)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  load {os.getloadavg()}  "
          f"{a.config}: {grid.shape[0]} x {grid.shape[1]} poses")
    if a.pinned:
        tmp = Path(tempfile.mkdtemp(prefix="lutmpi-ratio-"))
        for r in range(a.pinned):
            wall, after, numpy_s = pinned_round(a.config, tmp / "t.h5", r % 2, grid.n_points)
            print(f"round {r + 1} (build on core {r % 2}): whole command {wall:.2f} s, up to "
                  f"the end of its grid {wall - after:.2f} s; numpy solver {numpy_s:.2f} s "
                  f"for the grid at its rate meanwhile; ratio {wall / numpy_s:.2f}, up to the "
                  f"end of the grid {(wall - after) / numpy_s:.2f}")
        return
    solver = NumpyRigid(Scene.from_config(cfg))
    tmp = Path(tempfile.mkdtemp(prefix="lutmpi-ratio-"))
    builds, grids, numpys, plain = [], [], [], []
    if a.grid_only:
        import dataclasses

        only = tmp / "grid_only.toml"
        only.write_text(dataclasses.replace(
            cfg, output=dataclasses.replace(cfg.output, jumps=False)).text)
    for _ in range(a.repeat):
        wall, after = run_build(a.config, tmp / "t.h5")
        builds.append(wall)
        grids.append(wall - after)
        if a.grid_only:
            plain.append(run_build(str(only), tmp / "g.h5")[0])
        t0 = time.perf_counter()
        sol = np.array([[solver.solve(y, yaw) for yaw in grid.yaw] for y in grid.y])
        numpys.append(time.perf_counter() - t0)
    import h5py

    with h5py.File(tmp / "t.h5", "r") as f:
        method = cfg.output.methods[0]
        ref = "/reference/z_g" in f
        z, roll = f[f"{method}/z_g"][...], f[f"{method}/roll"][...]
    ok = np.isfinite(z)
    print(f"lutmpi build, 1 rank, whole command ({method}): {min(builds):.2f} s "
          f"(runs {', '.join(f'{b:.2f}' for b in builds)})")
    print(f"numpy rigid solver, one core:                {min(numpys):.2f} s "
          f"(runs {', '.join(f'{b:.2f}' for b in numpys)})")
    print(f"  ({min(numpys) / grid.n_points * 1e3:.2f} ms per pose)")
    print(f"ratio lutmpi / numpy: {min(builds) / min(numpys):.2f}")
    print(f"the same command up to the end of its grid (start-up and the grid's poses, what the "
          f"numpy solver does; without the jump step): {min(grids):.2f} s, ratio "
          f"{min(grids) / min(numpys):.2f}")
    if a.grid_only:
        print(f"the same build with [output] jumps = false (the grid's points only), whole "
              f"command: {min(plain):.2f} s (runs {', '.join(f'{b:.2f}' for b in plain)}), "
              f"ratio {min(plain) / min(numpys):.2f}")
    print(f"numpy vs table ({'reference' if ref else method}): max |dz_g| "
          f"{np.max(np.abs(sol[..., 0] - z)[ok]) * 1e3:.4f} mm, max |droll| "
          f"{np.max(np.abs(sol[..., 1] - roll)[ok]):.2e} rad")


if __name__ == "__main__":
    main()
