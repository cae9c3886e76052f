"""Cost of the build journal (issue 13): time spent appending and fsync-ing computed points,
against the build's wall time, for 1 and N ranks and for two fsync intervals.

    .venv/bin/python benchmarks/journal_cost.py configs/paper_s1002_uic60_1in20.toml --ranks 1 2

Each build runs ``[mpirun -n N] lutmpi build CONFIG -o <tmp>/t.h5 --checkpoint-interval S``; the
runner measures the time every rank spends in the journal (``write`` of each record + ``fsync``)
and logs it with the build's wall time, which this script prints:

* ``journal``: seconds in the journal, summed over ranks;
* ``share``: journal / (ranks x wall) -- the fraction of the build the journal costs.

``S = 0`` syncs after every point (the worst case); the default is 10 s.
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.parallel.mpi import mpirun_env  # noqa: E402


def one(config: str, ranks: int, interval: float, workdir: Path) -> tuple[float, float, int]:
    """(journal seconds over ranks, wall seconds, points) of one build."""
    out = workdir / f"t{ranks}-{interval:g}.h5"
    cmd = [str(ROOT / ".venv/bin/lutmpi"), "build", config, "-o", str(out), "--force",
           "--checkpoint-interval", str(interval)]
    if ranks > 1:
        cmd = ["mpirun", "-n", str(ranks), *cmd]
    env = mpirun_env()
    env["PYTHONPATH"] = str(ROOT)
    res = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd=str(ROOT))
    if res.returncode != 0:
        sys.exit(f"build failed:\n{res.stderr[-3000:]}")
    journal = float(re.search(r"journal: ([\d.]+) s", res.stderr).group(1))
    wall = float(re.search(r"wall ([\d.]+) s on", res.stderr).group(1))
    points = int(re.search(r": (\d+) points \(", res.stderr).group(1))
    return journal, wall, points


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--intervals", type=float, nargs="+", default=[10.0, 0.0])
    args = ap.parse_args()
    print(f"# {args.config}; load average {os.getloadavg()[0]:.2f} at start")
    print(f"{'ranks':>5} {'fsync s':>8} {'points':>7} {'wall s':>8} {'journal s':>10} "
          f"{'share %':>8}")
    with tempfile.TemporaryDirectory(prefix="lutmpi-journal-", dir=ROOT) as tmp:
        for ranks in args.ranks:
            for interval in args.intervals:
                journal, wall, points = one(args.config, ranks, interval, Path(tmp))
                share = 100 * journal / (ranks * wall)
                print(f"{ranks:5d} {interval:8g} {points:7d} {wall:8.2f} {journal:10.4f} "
                      f"{share:8.3f}", flush=True)
    print(f"# load average {os.getloadavg()[0]:.2f} at end")


if __name__ == "__main__":
    main()
