"""``lutmpi check CONFIG [--points N] [--fast] [--method M]``: the stability suite of the config's
profile pair and grid (issue 7), printed as a verdict table. Exit status 1 when a check fails,
so it can gate a batch job. Serial (no MPI)."""

from __future__ import annotations

import logging
from typing import Any

from lutmpi.errors import ConfigError
from lutmpi.pose.solve import METHOD_NAMES

log = logging.getLogger(__name__)


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "check", help="check the solver's stability on a config's profiles and grid",
        description="Run the stability suite on the config's profile pair and grid: convergence "
                    "and iterations per region (tread, flange root, flange, double contact), "
                    "accuracy against the reference solver, sensitivity to k_c and to the "
                    "fictitious springs, continuity between neighbouring grid points, mesh "
                    "window and spacing. Prints a verdict table; exit status 1 if a check fails.")
    p.add_argument("config", help="run configuration (TOML)")
    p.add_argument("--points", type=int, default=None,
                   help="poses in the convergence/accuracy sample (default 60, --fast 24)")
    p.add_argument("--fast", action="store_true", help="smaller samples (for CI)")
    p.add_argument("--method", choices=METHOD_NAMES, help="contact method (default: the config's)")
    p.set_defaults(func=run)


def run(args: Any) -> int:
    import numpy as np

    from lutmpi.check import CheckOptions, format_report, run_checks
    from lutmpi.config import load_config
    from lutmpi.scene import Scene

    points = args.points if args.points is not None else (24 if args.fast else 60)
    if points < 1:
        raise ConfigError(f"--points must be >= 1, got {points}")
    cfg = load_config(args.config)
    scene = Scene.from_config(cfg)
    ys = np.linspace(*cfg.grid.y_mm[:2], int(cfg.grid.y_mm[2])) * 1e-3
    yaws = np.linspace(*cfg.grid.yaw_rad[:2], int(cfg.grid.yaw_rad[2]))
    opts = CheckOptions(points=points, fast=args.fast, method=args.method)
    report = run_checks(scene, ys, yaws, opts)
    print(format_report(report, title=f"lutmpi check {args.config}"), flush=True)
    if not report.passed:
        log.warning("%d checks failed", sum(not r.passed for r in report.results))
    return 0 if report.passed else 1
