"""The jump search of a built table, serially: how many poses it solves and how many jumps it
finds (issue 14; the search is :mod:`lutmpi.table.jump_search`, the first part of a
build's jump step), for comparing two trees on the same grid.

    .venv/bin/python benchmarks/jump_search.py CONFIG TABLE.h5 [--columns 0,9,18] [--method M]

The grid nodes are the table's (``read_table``), the solves this tree's (``solve_pose`` through
the build's own solver and record fields). Run it in two trees (``PYTHONPATH=/tmp/base`` for a
``git archive`` of the base) on one table: the counts do not depend on the machine.
``--jumps FILE`` writes the located jumps (``iyaw, lo, hi, kind, side`` per line, m) to compare
the two trees' jumps.
"""

from __future__ import annotations

import argparse
import time

from lutmpi.config import load_config
from lutmpi.scene import Scene
from lutmpi.table import jump_search as tjs
from lutmpi.table.compute import default_solver, pose_to_record
from lutmpi.table.h5io import read_table
from lutmpi.table.schema import limit_fields, select_fields


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("config")
    ap.add_argument("table")
    ap.add_argument("--columns", default=None, help="yaw column indices, comma-separated")
    ap.add_argument("--method", default=None, help="default: the config's contact.method")
    ap.add_argument("--jumps", default=None, help="write the located jumps to this file")
    a = ap.parse_args()
    cfg = load_config(a.config)
    scene = Scene.from_config(cfg)
    method = a.method or cfg.contact.method
    table = read_table(a.table)
    fields = limit_fields(select_fields(cfg.output.quantities))
    arrays = {f.name: table["methods"][method][f.name] for f in fields}
    y, yaw = table["y"], table["yaw"]
    cols = ([int(c) for c in a.columns.split(",")] if a.columns else list(range(yaw.size)))
    solver = default_solver()
    solver.warm(scene, method)
    count = [0]

    def solve(yy: float, aa: float) -> dict:
        count[0] += 1
        return pose_to_record(solver(scene, yy, aa, method), fields)

    cells = [c for c in tjs.candidate_cells(arrays) if c[0] in cols]
    t0 = time.process_time()
    found = []
    for cell in cells:
        found += tjs.refine_cell(arrays, y, yaw, cell, solve)[0]
    print(f"{method}, {len(cols)} yaw columns: {len(cells)} candidate cells, {len(found)} jumps, "
          f"{count[0]} search solves ({time.process_time() - t0:.1f} s CPU)")
    if a.jumps:
        with open(a.jumps, "w") as f:
            for jp in found:
                f.write(f"{jp.iyaw} {jp.lo!r} {jp.hi!r} {jp.kind} {jp.side}\n")


if __name__ == "__main__":
    main()
