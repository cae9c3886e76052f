"""Per-pose CPU time of two source trees measured alternately in one session (a baseline and the
change), so that a shared machine's drifting load hits both alike: ``contact_methods.py`` runs
``--rounds`` times per tree, A B A B ..., and the smallest mean (and p99, max) per method and tree
is printed.

    git archive BASE | tar -x -C /tmp/base
    .venv/bin/python benchmarks/compare_trees.py /tmp/base . configs/paper_s1002_uic60_1in20.toml \
        --grid 37 37 --rounds 3
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def run(tree: str, args: list[str]) -> dict[str, tuple[float, float, float]]:
    env = dict(os.environ, PYTHONPATH=str(Path(tree).resolve()), OMP_NUM_THREADS="1")
    out = subprocess.run([sys.executable, str(HERE / "contact_methods.py"), *args], env=env,
                         capture_output=True, text=True, check=True).stdout
    rows = {}
    for line in out.splitlines():
        f = line.split()
        if len(f) == 8 and not line.startswith(("#", "method")):
            rows[f[0]] = (float(f[1]), float(f[4]), float(f[5]))  # mean, p99, max (ms)
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("base")
    ap.add_argument("new")
    ap.add_argument("config")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--grid", nargs=2, default=["37", "37"])
    ap.add_argument("--methods", nargs="+", default=None)
    a = ap.parse_args()
    args = [a.config, "--grid", *a.grid] + (["--methods", *a.methods] if a.methods else [])
    best: dict[str, dict[str, list[float]]] = {a.base: {}, a.new: {}}
    loads = []
    for _ in range(a.rounds):
        for tree in (a.base, a.new):
            loads.append(os.getloadavg()[0])
            for m, v in run(tree, args).items():
                old = best[tree].get(m, [float("inf")] * 3)
                best[tree][m] = [min(x, y) for x, y in zip(old, v, strict=True)]
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  cores {os.cpu_count()}  "
          f"load {min(loads):.1f}-{max(loads):.1f}  {a.config} grid {' x '.join(a.grid)}  "
          f"best of {a.rounds} alternating rounds, CPU ms per pose")
    print(f"{'method':22s} {'base mean':>9s} {'new mean':>9s} {'new/base':>8s} {'base p99':>9s} "
          f"{'new p99':>8s} {'base max':>9s} {'new max':>8s}")
    for m in best[a.base]:
        b, n = best[a.base][m], best[a.new][m]
        print(f"{m:22s} {b[0]:9.2f} {n[0]:9.2f} {n[0] / b[0]:8.2f} {b[1]:9.2f} {n[1]:8.2f} "
              f"{b[2]:9.1f} {n[2]:8.1f}")


if __name__ == "__main__":
    main()
