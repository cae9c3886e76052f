"""The compiled, jump-aware table lookup (issue 11): microseconds per contact state, one pose per
call (what the dynamics does) and batched (one call for many poses).

A contact state is every quantity the dynamics reads (``RECORD_NAMES``: z_g, roll, x_g, contact
points, normals, radii, angles, curvatures, forces; 56 values) with its y and yaw slopes, on the
query's side of every located jump.

Usage: python benchmarks/bench_lookup.py TABLE.h5 [--method M] [--n 10000]
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from lutmpi.dynamics.contact_provider import RECORD_NAMES, TableProvider
from lutmpi.table import Table


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("table")
    ap.add_argument("--method", default=None)
    ap.add_argument("--n", type=int, default=10000)
    ap.add_argument("--repeat", type=int, default=5, help="best of this many timings")
    a = ap.parse_args()
    table = Table.open(a.table)
    prov = TableProvider(table, a.method)
    ip = table.interpolator(prov.method, quantities=RECORD_NAMES)
    rng = np.random.default_rng(0)
    y0, y1, w0, w1 = prov.bounds
    ys = rng.uniform(y0, y1, a.n)
    ws = rng.uniform(w0, w1, a.n) if w1 > w0 else np.full(a.n, w0)
    yl, wl = ys.tolist(), ws.tolist()
    prov.lookup(yl[0], wl[0])
    ip.evaluate(ys[:10], ws[:10])                          # compiled (numba cache) before timing
    single, batched, evaluate = [], [], []
    for _ in range(a.repeat):
        t0 = time.perf_counter()
        for y, w in zip(yl, wl, strict=True):
            prov.lookup(y, w)
        single.append((time.perf_counter() - t0) / a.n)
        t0 = time.perf_counter()
        ip.evaluate(ys, ws)
        batched.append((time.perf_counter() - t0) / a.n)
        t0 = time.perf_counter()
        for y, w in zip(yl[:2000], wl[:2000], strict=True):
            prov.evaluate(y, w)
        evaluate.append((time.perf_counter() - t0) / 2000)
    print(f"{a.table} ({prov.method}): {ip.kv.shape[2]} values per state, "
          f"{ip.ky.shape[1]} knots per yaw column at most, {int(ip.nj.sum())} jumps")
    print(f"single pose per call: {min(single) * 1e6:.2f} us per contact state (best of "
          f"{a.repeat}; median {np.median(single) * 1e6:.2f})")
    print(f"batched ({a.n} poses per call): {min(batched) * 1e6:.3f} us per contact state "
          f"(median {np.median(batched) * 1e6:.3f})")
    print(f"TableProvider.evaluate (lookup + ContactGeometry in Python): "
          f"{min(evaluate) * 1e6:.1f} us")


if __name__ == "__main__":
    main()
