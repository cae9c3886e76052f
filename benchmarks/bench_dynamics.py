"""Table vs on-line contact in the wheelset dynamics: cost per contact evaluation, simulated
seconds per wall second, and the trajectory difference (issue 6).

A contact evaluation is what the dynamics asks for once per right-hand side: the geometry at
(y, yaw) and the slopes of z_g and roll. The table answers with one bilinear step; the on-line
provider solves three poses (the pose and two neighbours for the slopes), so its cost per
evaluation is three pose solves (the per-solve cost is printed too).

Usage: python benchmarks/bench_dynamics.py CONFIG TABLE.h5 [--speed 27] [--duration 1]
           [--online-methods load_centre reference] [--no-runs]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lutmpi.config.load import load_config
from lutmpi.dynamics.contact_provider import OnlineProvider, TableProvider
from lutmpi.dynamics.simulate import simulate
from lutmpi.dynamics.wheelset import WheelsetParams
from lutmpi.scene import Scene
from lutmpi.table import Table


def per_call(provider, n: int, warmup: int = 2) -> float:
    """Mean wall time of one ``evaluate`` at random poses in the central region, s."""
    rng = np.random.default_rng(0)
    ys, yaws = rng.uniform(-6e-3, 6e-3, n + warmup), rng.uniform(-5e-3, 5e-3, n + warmup)
    for y, yaw in zip(ys[:warmup], yaws[:warmup], strict=True):   # JIT / caches
        provider.evaluate(float(y), float(yaw))
    t0 = time.perf_counter()
    for y, yaw in zip(ys[warmup:], yaws[warmup:], strict=True):
        provider.evaluate(float(y), float(yaw))
    return (time.perf_counter() - t0) / n


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("config")
    ap.add_argument("table")
    ap.add_argument("--method", default=None, help="table method group")
    ap.add_argument("--online-methods", nargs="+", default=["load_centre", "reference"])
    ap.add_argument("--speed", type=float, default=27.0)
    ap.add_argument("--duration", type=float, default=1.0)
    ap.add_argument("--n-online", type=int, default=20, help="evaluations timed per method")
    ap.add_argument("--no-runs", action="store_true", help="only the per-evaluation costs")
    a = ap.parse_args()
    cfg = load_config(a.config)
    table = Table.open(a.table)
    method = a.method or table.methods[0]
    params = WheelsetParams.from_toml_text(table.config_toml)
    tab = TableProvider(table, method)
    scene = Scene.from_config(cfg)
    ct = per_call(tab, 20000)
    print(f"table ({method}): {ct * 1e6:.1f} us per contact evaluation")
    online = {m: OnlineProvider(scene, m) for m in a.online_methods}
    for m, prov in online.items():
        co = per_call(prov, a.n_online)
        print(f"online {m}: {co * 1e3:.1f} ms per contact evaluation ({co / 3 * 1e3:.1f} ms per "
              f"pose solve); table is {co / ct:.0f}x cheaper per evaluation")
    if a.no_runs:
        return
    runs = {"table": simulate(tab, params, a.speed, a.duration, events=False, dt_out=0.01)}
    for m, prov in online.items():
        runs[f"online {m}"] = simulate(prov, params, a.speed, a.duration, events=False,
                                       dt_out=0.01)
    for name, r in runs.items():
        print(f"{name}: {r.sim_per_wall:.4f} sim-s per wall-s ({r.nfev} rhs, "
              f"{r.provider_calls} contact evaluations, {r.wall_time:.1f} s); {r.summary.line()}")
    for name, r in runs.items():
        if name == "table":
            continue
        dy = np.max(np.abs(runs["table"].y - r.y))
        amp = np.max(np.abs(r.y))
        print(f"table vs {name}: max |dy| = {dy * 1e6:.2f} um = {100 * dy / amp:.2f} % of the "
              f"amplitude {amp * 1e3:.3f} mm; run speed-up "
              f"{r.wall_time / runs['table'].wall_time:.1f}x")


if __name__ == "__main__":
    main()
