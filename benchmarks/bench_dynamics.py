"""Table vs on-line contact in the wheelset dynamics: cost per contact evaluation, simulated
seconds per wall second, and the trajectory difference (issue 6).

Usage: python benchmarks/bench_dynamics.py CONFIG TABLE.h5 [--speed 27] [--duration 2]
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


def per_call(provider, n: int = 200) -> float:
    rng = np.random.default_rng(0)
    ys, yaws = rng.uniform(-6e-3, 6e-3, n), rng.uniform(-5e-3, 5e-3, n)
    t0 = time.perf_counter()
    for y, yaw in zip(ys, yaws, strict=True):
        provider.evaluate(float(y), float(yaw))
    return (time.perf_counter() - t0) / n


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("config")
    ap.add_argument("table")
    ap.add_argument("--method", default=None)
    ap.add_argument("--speed", type=float, default=27.0)
    ap.add_argument("--duration", type=float, default=2.0)
    a = ap.parse_args()
    cfg = load_config(a.config)
    table = Table.open(a.table)
    method = a.method or table.methods[0]
    params = WheelsetParams.from_toml_text(table.config_toml)
    tab = TableProvider(table, method)
    onl = OnlineProvider(Scene.from_config(cfg), method)
    ct, co = per_call(tab), per_call(onl, 50)
    print(f"contact evaluation (pose + 2 neighbours): table {ct * 1e6:.0f} us, online "
          f"{co * 1e6:.0f} us, ratio {co / ct:.1f}x")
    runs = {}
    for name, prov in (("table", tab), ("online", onl)):
        r = simulate(prov, params, a.speed, a.duration, events=False, dt_out=0.01)
        runs[name] = r
        print(f"{name}: {r.sim_per_wall:.3f} sim-s per wall-s ({r.nfev} rhs, "
              f"{r.provider_calls} contact evaluations, {r.wall_time:.1f} s); {r.summary.line()}")
    dy = np.max(np.abs(runs["table"].y - runs["online"].y))
    amp = np.max(np.abs(runs["online"].y))
    print(f"max |dy| = {dy * 1e6:.2f} um = {100 * dy / amp:.2f} % of the amplitude "
          f"{amp * 1e3:.3f} mm; speed-up of the run "
          f"{runs['online'].wall_time / runs['table'].wall_time:.1f}x")


if __name__ == "__main__":
    main()
