"""Table build benchmark (issue 4): wall time, per-point time and busy fraction for 1 and N
ranks, start-up included, and the load imbalance each split would give for the measured per-point
costs.

    .venv/bin/python benchmarks/table_build.py configs/paper_s1002_uic60_1in20.toml --ranks 1 2

Each build runs ``[mpirun -n N] lutmpi build CONFIG -o <tmp>/nN.h5`` (``--solver`` passes a test
solver through). The figures printed:

* ``total``: the whole command, start-up (Python, MPI, imports) included;
* ``wall``: the build proper (the table's ``wall_time_s``);
* ``per point``: sum of the ranks' busy (solving) wall time / points, and the solver-reported
  ``compute_time``;
* ``busy fraction``: sum of busy times / (ranks x wall) -- how busy the ranks were (not a
  speed-up; ``benchmarks/strong_scaling.py`` measures speed-up against a 1-rank run);
* ``speed-up``: total(1 rank) / total(N ranks).

Then, from the 1-rank table's per-point costs, the imbalance (max rank load / mean rank load)
each split (scattered, cyclic, block) and an ideal dynamic hand-out would give for 2..64 ranks:
the measurement behind the choice of the split.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.parallel.mpi import mpirun_env  # noqa: E402
from lutmpi.parallel.partition import split  # noqa: E402


def run_build(config: str, out: Path, ranks: int, extra: list[str]) -> float:
    """Run one build; return the total command time, s."""
    cmd = [str(ROOT / ".venv/bin/lutmpi"), "build", config, "-o", str(out), "--force", *extra]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks), *cmd]
    env = mpirun_env()
    env["PYTHONPATH"] = str(ROOT)
    t0 = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=str(ROOT))
    total = time.perf_counter() - t0
    if res.returncode != 0:
        sys.exit(f"build with {ranks} rank(s) failed:\n{res.stderr[-3000:]}")
    return total


def point_costs(path: Path) -> tuple[np.ndarray, float, np.ndarray]:
    """Per-point solver time (sum over methods, s) as (ny, nyaw), the build wall time and the
    busy (solving) wall time of each rank."""
    with h5py.File(path, "r") as f:
        methods = [m for m in f if isinstance(f[m], h5py.Group)]
        cost = sum(f[m]["compute_time"][...] for m in methods)
        return cost, float(f.attrs["wall_time_s"]), np.asarray(f.attrs["rank_busy_s"])


def imbalance(cost: np.ndarray, size: int, how: str) -> float:
    """Max rank load / mean rank load of a static split, or of an ideal dynamic hand-out
    (``how="dynamic"``: each point, in flat order, to the rank that is free first; no overhead)."""
    flat = cost.ravel()
    if how == "dynamic":
        loads = np.zeros(size)
        for c in flat:
            loads[np.argmin(loads)] += c
    else:
        loads = np.array([flat[split(flat.size, size, r, how)].sum() for r in range(size)])
    return float(loads.max() / loads.mean())


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("config")
    p.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    p.add_argument("--solver", default=None, help="module:function test solver hook")
    p.add_argument("--costs-from", default=None, metavar="TABLE",
                   help="only print the split analysis for the compute_time of an existing table")
    args = p.parse_args()
    if args.costs_from:
        analyse(point_costs(Path(args.costs_from))[0])
        return
    extra = ["--solver", args.solver] if args.solver else []
    tmp = Path(tempfile.mkdtemp(prefix="lutmpi-bench-"))
    rows, base = [], None
    for n in args.ranks:
        out = tmp / f"n{n}.h5"
        total = run_build(args.config, out, n, extra)
        cost, wall, busy = point_costs(out)
        base = base or total
        rows.append((n, total, wall, cost))
        print(f"{n:3d} rank(s): total {total:7.2f} s (start-up incl.), build {wall:7.2f} s, "
              f"{cost.size} points, per point {busy.sum() / cost.size * 1e3:8.2f} ms wall "
              f"({cost.mean() * 1e3:.1f} ms solver-reported, max {cost.max() * 1e3:.1f}), "
              f"busy/rank {np.round(busy, 2).tolist()} s, imbalance "
              f"{busy.max() / busy.mean():.3f}, busy fraction {busy.sum() / (n * wall):6.1%}, "
              f"speed-up {base / total:5.2f}", flush=True)
    analyse(rows[0][3])


def analyse(cost: np.ndarray) -> None:
    """Print the cost profile over rows and the imbalance of each split."""
    ny = cost.shape[0]
    by_row = cost.mean(axis=1)
    print(f"cost per row (y): min {by_row.min() * 1e3:.1f} ms, max {by_row.max() * 1e3:.1f} ms, "
          f"ratio {by_row.max() / by_row.min():.1f}; rows {ny}")
    for size in (2, 4, 8, 16, 32, 64):
        if size <= cost.size:
            print(f"  {size:2d} ranks, imbalance: " + ", ".join(
                f"{how} {imbalance(cost, size, how):.3f}"
                for how in ("scattered", "cyclic", "block", "dynamic")))


if __name__ == "__main__":
    main()
