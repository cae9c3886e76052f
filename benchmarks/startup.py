"""A build's fixed cost before its first point (issue 14, start-up): ``lutmpi build`` of a 2 x 2
grid of CONFIG, timed whole, with the solving itself subtracted.

    .venv/bin/python benchmarks/startup.py configs/paper_s1002_uic60_1in20.toml --ranks 1 2

Printed per N: ``command`` (wall time of ``[mpirun -n N] lutmpi build``), ``points`` (the
slowest rank's summed solve time of its points, from the table's ``rank_busy_s``), ``jumps`` (the
post-grid jump location and refinement, its own solves: the ``wall_time_s`` of each method's
``jumps`` group; on a 2 x 2 grid every cell is 9 mm wide and is refined all over) and ``fixed`` =
command - points - jumps: interpreter and MPI start, imports, config, scene (profiles placed,
meshes), compiled kernels loaded from numba's cache, the file created, written and renamed.
Then the same in one process, split into imports, scene and the first solve of each method (the
kernels loaded from the cache, or compiled when it is cold).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from strong_scaling import derived_config, read, run_build  # noqa: E402

IN_PROCESS = """
import time
t0 = time.perf_counter()
import lutmpi.cli, lutmpi.parallel.runner, lutmpi.scene, lutmpi.pose.solve
t1 = time.perf_counter()
from lutmpi.config import load_config
from lutmpi.scene import Scene
from lutmpi.pose.solve import solve_pose
cfg = load_config({config!r})
scene = Scene.from_config(cfg)
t2 = time.perf_counter()
for m in cfg.output.methods:
    solve_pose(scene, 0.0, 0.0, m)
t3 = time.perf_counter()
print(f"one process: imports {{t1 - t0:.2f}} s, config + scene {{t2 - t1:.2f}} s, first solve "
      f"of each method {{t3 - t2:.2f}} s")
"""


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
    a = ap.parse_args()
    tmp = Path(tempfile.mkdtemp(prefix="lutmpi-startup-"))
    config = derived_config(a.config, (2, 2), tmp)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  cores {os.cpu_count()}  "
          f"load {tuple(round(x, 2) for x in os.getloadavg())}  {a.config} (2 x 2 grid)")
    for n in a.ranks:
        total = run_build(config, tmp / f"n{n}.h5", n)
        _, wall, jumps, busy = read(tmp / f"n{n}.h5")
        print(f"{n} rank(s): command {total:.2f} s, grid {wall:.2f} s, points {busy.max():.3f} s,"
              f" jumps {jumps:.2f} s, fixed {total - busy.max() - jumps:.2f} s")
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    subprocess.run([sys.executable, "-c", IN_PROCESS.format(config=config)], env=env, check=True)


if __name__ == "__main__":
    main()
