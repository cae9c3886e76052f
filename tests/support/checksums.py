"""Checksums of the tables the production solver builds, for the "bit-identical before/after"
checks of issue 15 (contact methods as units) and issue 14 (compiled pose loop).

A checksum is the SHA-256 of the bytes of one dataset of one method group, exactly as
:func:`lutmpi.table.compute.compute_points` produces it for the table writer (timing datasets
excluded). They are computed in-process on the configs' own profiles and meshes, over the
config's grid or a sub-grid of it, for every contact method.

    PYTHONPATH=. .venv/bin/python -m tests.support.checksums   # prints the JSON of the data file
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from pathlib import Path

from lutmpi.config import load_config
from lutmpi.config.model import ALL_METHODS
from lutmpi.paths import REPO_ROOT
from lutmpi.scene import Scene
from lutmpi.table.compute import compute_points, default_solver
from lutmpi.table.grid import Grid
from lutmpi.table.schema import FIELDS, TIMING_FIELDS

DATA = Path(__file__).resolve().parents[1] / "data" / "table_checksums.json"
CONFIGS = {"paper": "configs/paper_s1002_uic60_1in20.toml",
           "manchester": "configs/manchester_s1002_uic60_1in40.toml"}
#: 7 x 7 of the configs' 37 x 37 points (every 6th value of each axis: same range, flange and
#: tread poses, both yaw signs); "full" is the whole 37 x 37 grid
GRIDS = {"7x7": ((-9.0, 9.0, 7), (-0.12, 0.12, 7)), "full": None}


def table_checksums(config: str, grid: str, methods=ALL_METHODS) -> dict[str, dict[str, str]]:
    """``method -> dataset -> sha256 hex`` of the records of ``config`` on grid ``grid``."""
    cfg = load_config(REPO_ROOT / CONFIGS[config])
    if GRIDS[grid] is not None:
        y, yaw = GRIDS[grid]
        cfg = dataclasses.replace(cfg, grid=dataclasses.replace(cfg.grid, y_mm=y, yaw_rad=yaw))
    g = Grid.from_config(cfg.grid)
    scene = Scene.from_config(cfg)
    import numpy as np

    recs, _ = compute_points(scene, g, np.arange(g.n_points), list(methods), default_solver(),
                             FIELDS)
    return {m: {name: hashlib.sha256(arr.tobytes()).hexdigest()
                for name, arr in recs[m].items() if name not in TIMING_FIELDS}
            for m in methods}


def all_checksums(grids=("7x7", "full")) -> dict:
    return {f"{c}/{g}": table_checksums(c, g) for g in grids for c in CONFIGS}


if __name__ == "__main__":
    print(json.dumps(all_checksums(), indent=1, sort_keys=True))
