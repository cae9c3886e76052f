"""Strong scaling of ``lutmpi build`` (issue 14, "Must show" 4): the same table on N = 1, 2, 4, ...
ranks, with the whole command and the build proper timed, speed-up and efficiency against the
1-rank run of the same session, and the parity check (every dataset of every N-rank table equal,
bit for bit, to the 1-rank table; timing datasets excepted).

    .venv/bin/python benchmarks/strong_scaling.py configs/paper_s1002_uic60_1in20.toml \
        --grid 145 73 --ranks 1 2 4

``--grid NY NYAW`` overrides the config's grid (same range; 145 x 73 is the dense grid of
issue 14). Names of the figures printed:

* ``command``: wall time of ``[mpirun -n N] lutmpi build`` -- start-up, imports, compiled kernels
  loaded, every point, the file;
* ``grid``: the table's root ``wall_time_s``: from the build's start to its last grid point
  (every rank's points solved);
* ``jumps``: the jump step after the grid (issue 11: jumps located, the pieces between them
  refined), the ``wall_time_s`` of every method's ``/<method>/jumps`` summed; on the paper's
  table most of the whole command;
* ``speed-up`` = T(1 rank) / T(N ranks) and ``efficiency`` = speed-up / N, for each;
* ``busy``: per rank, the summed wall time of its grid's pose solves; ``work growth`` = sum of
  busy over N ranks / busy of the 1-rank run (> 1: each point got slower with N ranks busy, e.g.
  shared caches, memory bandwidth, or more ranks than cores).

On a machine with fewer cores than N, ranks share cores (Open MPI oversubscribed): those rows
measure the overhead, not scaling. The machine's core count is printed.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.config import load_config  # noqa: E402
from lutmpi.parallel.mpi import mpirun_env  # noqa: E402
from lutmpi.table.schema import TIMING_FIELDS  # noqa: E402


def derived_config(config: str, grid: tuple[int, int] | None, tmp: Path) -> str:
    """``config`` with its grid counts replaced (the resolved TOML, so paths stay valid)."""
    if grid is None:
        return config
    cfg = load_config(config)
    (y0, y1, _), (a0, a1, _) = cfg.grid.y_mm, cfg.grid.yaw_rad
    text = re.sub(r"(?m)^y_mm = .*$", f"y_mm = [{y0!r}, {y1!r}, {grid[0]}]", cfg.text)
    text = re.sub(r"(?m)^yaw_rad = .*$", f"yaw_rad = [{a0!r}, {a1!r}, {grid[1]}]", text)
    path = tmp / "scaling.toml"
    path.write_text(text)
    return str(path)


def run_build(config: str, out: Path, ranks: int) -> float:
    cmd = [str(ROOT / ".venv/bin/lutmpi"), "build", config, "-o", str(out), "--force"]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks), *cmd]
    env = mpirun_env()
    env.update(PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1")
    t0 = time.perf_counter()
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=str(ROOT))
    total = time.perf_counter() - t0
    if res.returncode != 0:
        sys.exit(f"build with {ranks} rank(s) failed:\n{res.stderr[-3000:]}")
    return total


def read(path: Path) -> tuple[dict[str, np.ndarray], float, float, np.ndarray]:
    """The table's datasets (timing fields left out), its grid wall time, its jump steps'
    summed wall time (s) and the per-rank busy time of its grid (s)."""
    data: dict[str, np.ndarray] = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda n, o: data.__setitem__(n, o[...])
                     if isinstance(o, h5py.Dataset) and n.split("/")[-1] not in TIMING_FIELDS
                     else None)
        jumps = sum(float(f[m]["jumps"].attrs["wall_time_s"])
                    for m in json.loads(f.attrs["methods"]) if "jumps" in f[m])
        return (data, float(f.attrs["wall_time_s"]), jumps,
                np.atleast_1d(f.attrs["rank_busy_s"]))


def identical(a: dict[str, np.ndarray], b: dict[str, np.ndarray]) -> bool:
    return a.keys() == b.keys() and all(
        a[k].dtype == b[k].dtype and a[k].tobytes() == b[k].tobytes() for k in a)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2],
                    help="rank counts, run in the order given after the 1-rank base (largest "
                         "first keeps it where a time limit cuts the run short)")
    ap.add_argument("--grid", type=int, nargs=2, metavar=("NY", "NYAW"))
    a = ap.parse_args()
    ranks = [1] + list(dict.fromkeys(n for n in a.ranks if n != 1))   # 1 first, then as given
    tmp = Path(tempfile.mkdtemp(prefix="lutmpi-scaling-"))
    config = derived_config(a.config, tuple(a.grid) if a.grid else None, tmp)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  cores {os.cpu_count()}  "
          f"load {tuple(round(x, 2) for x in os.getloadavg())}  {a.config}"
          f"{f' grid {a.grid[0]} x {a.grid[1]}' if a.grid else ''}")
    print(f"{'N':>3s} {'command s':>10s} {'speed-up':>8s} {'eff':>6s} {'grid s':>7s} "
          f"{'speed-up':>8s} {'eff':>6s} {'jumps s':>8s} {'speed-up':>8s} {'eff':>6s} "
          f"{'work growth':>11s} {'parity':>7s}  grid busy per rank s")
    base = None
    for n in ranks:
        out = tmp / f"n{n}.h5"
        total = run_build(config, out, n)
        data, wall, jumps, busy = read(out)
        if base is None:
            base = (total, wall, jumps, busy.sum(), data)
        same = identical(base[4], data)
        su_c, su_g = base[0] / total, base[1] / wall
        su_j = base[2] / jumps if jumps > 0 else float("nan")
        print(f"{n:3d} {total:10.2f} {su_c:8.2f} {su_c / n:6.1%} {wall:7.2f} {su_g:8.2f} "
              f"{su_g / n:6.1%} {jumps:8.2f} {su_j:8.2f} {su_j / n:6.1%} "
              f"{busy.sum() / base[3]:11.3f} {'ok' if same else 'DIFFERS':>7s}  "
              f"{np.round(busy, 2).tolist()}", flush=True)
        if not same:
            sys.exit(f"parity: the {n}-rank table differs from the 1-rank table")


if __name__ == "__main__":
    main()
