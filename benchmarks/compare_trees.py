"""Per-pose CPU time of two source trees measured alternately in one session (a baseline and the
change), so that a shared machine's drifting load hits both alike: ``contact_methods.py`` runs
``--rounds`` times per tree, A B A B ..., and the smallest mean (and p99, max) per method and tree
is printed.

``--pinned`` (a machine with two or more cores) runs the two trees at the same time instead, each
pinned to its own core (``taskset``), and swaps the cores every round: a drift of the machine's
speed then hits both runs at once (but each core's own share of it does not). The ratio
new/base of each round is printed too: its spread is the noise. On the 2-core VM of 2026-11-23,
whose speed drifted by 20 % between runs, the unchanged reference method came out at 0.77 of
its baseline in alternating runs, and at 0.83-1.03 per pinned round (mean 0.93): read a change
below ~5 % as none on such a machine.

    git archive BASE | tar -x -C /tmp/base
    .venv/bin/python benchmarks/compare_trees.py /tmp/base . configs/paper_s1002_uic60_1in20.toml \
        --grid 37 37 --rounds 3 [--pinned]
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def start(tree: str, args: list[str], core: int | None = None) -> subprocess.Popen:
    env = dict(os.environ, PYTHONPATH=str(Path(tree).resolve()), OMP_NUM_THREADS="1")
    cmd = [sys.executable, str(HERE / "contact_methods.py"), *args]
    if core is not None:
        cmd = ["taskset", "-c", str(core), *cmd]
    return subprocess.Popen(cmd, env=env, stdout=subprocess.PIPE, text=True)


def rows_of(proc: subprocess.Popen) -> dict[str, tuple[float, float, float]]:
    out, _ = proc.communicate()
    if proc.returncode:
        raise SystemExit(f"contact_methods.py failed ({proc.returncode})")
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
    ap.add_argument("--pinned", action="store_true",
                    help="both trees at once, each on its own core, cores swapped every round")
    a = ap.parse_args()
    args = [a.config, "--grid", *a.grid] + (["--methods", *a.methods] if a.methods else [])
    best: dict[str, dict[str, list[float]]] = {a.base: {}, a.new: {}}
    ratios: dict[str, list[float]] = {}
    loads = []

    def keep(tree: str, rows: dict[str, tuple[float, float, float]]) -> None:
        for m, v in rows.items():
            old = best[tree].get(m, [float("inf")] * 3)
            best[tree][m] = [min(x, y) for x, y in zip(old, v, strict=True)]

    for r in range(a.rounds):
        loads.append(os.getloadavg()[0])
        if a.pinned:
            cores = (r % 2, 1 - r % 2)
            procs = [start(tree, args, core) for tree, core in zip((a.base, a.new), cores,
                                                                    strict=True)]
            try:
                got = [rows_of(p) for p in procs]
            finally:              # one failed: the other is not left running on its core
                for p in procs:
                    if p.poll() is None:
                        p.kill()
                        p.wait()
            for tree, rows in zip((a.base, a.new), got, strict=True):
                keep(tree, rows)
            for m in got[0]:
                ratios.setdefault(m, []).append(got[1][m][0] / got[0][m][0])
        else:
            for tree in (a.base, a.new):
                keep(tree, rows_of(start(tree, args)))
    how = "pinned rounds (both at once, cores swapped)" if a.pinned else "alternating rounds"
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}  cores {os.cpu_count()}  "
          f"load {min(loads):.1f}-{max(loads):.1f}  {a.config} grid {' x '.join(a.grid)}  "
          f"best of {a.rounds} {how}, CPU ms per pose")
    print(f"{'method':22s} {'base mean':>9s} {'new mean':>9s} {'new/base':>8s} {'base p99':>9s} "
          f"{'new p99':>8s} {'base max':>9s} {'new max':>8s}")
    for m in best[a.base]:
        b, n = best[a.base][m], best[a.new][m]
        print(f"{m:22s} {b[0]:9.2f} {n[0]:9.2f} {n[0] / b[0]:8.2f} {b[1]:9.2f} {n[1]:8.2f} "
              f"{b[2]:9.1f} {n[2]:8.1f}")
    for m, rs in ratios.items():
        print(f"# {m}: new/base of the means, per pinned round: "
              f"{' '.join(f'{x:.3f}' for x in rs)} (mean {sum(rs) / len(rs):.3f})")


if __name__ == "__main__":
    main()
