"""``lutmpi critical-speed``: free-wheelset critical speed from a table, nonlinear and linear."""

from __future__ import annotations

import argparse
import json
import math
from typing import Any


def register(subparsers: Any) -> None:
    p = subparsers.add_parser(
        "critical-speed", help="critical speed of the wheelset: bisection + linear eigenvalues",
        description="Critical speed of the free wheelset on the table's contact geometry: a "
                    "linearised eigenvalue analysis (equivalent conicity, gravitational stiffness, "
                    "Kalker f11..f33) and a bisection on V with the nonlinear simulation.")
    p.add_argument("config", help="configuration TOML")
    p.add_argument("--table", help="lookup table (HDF5); required unless --online")
    p.add_argument("--online", action="store_true", help="contact by a pose solve at every call")
    p.add_argument("--method", default=None, help="contact method")
    p.add_argument("--amplitude", type=float, default=3.5e-4,
                   help="amplitude of the linearisation, m (3.5e-4: the oscillation that "
                        "vy0 = 0.1 m/s starts)")
    p.add_argument("--duration", type=float, default=30.0, help="run length per speed, s (30)")
    p.add_argument("--vy0", type=float, default=0.1, help="initial lateral velocity, m/s (0.1)")
    p.add_argument("--rel-tol", type=float, default=0.02, help="bisection tolerance (0.02)")
    p.add_argument("--linear-only", action="store_true", help="skip the bisection")
    p.add_argument("--json", action="store_true", help="print the result as JSON")
    p.set_defaults(func=run)


def run(args: argparse.Namespace) -> int:
    from lutmpi.dynamics.critical import (
        jacobian_critical_speed,
        linear_critical_speed,
        linear_parameters,
        nonlinear_critical_speed,
        rolling_offset,
    )
    from lutmpi.dynamics.stability import format_rate
    from lutmpi.providers import make_provider

    args.output = None
    provider, params, source = make_provider(args.config, args.table, args.online, args.method)
    y_e = rolling_offset(provider)
    if y_e != 0.0:
        print(f"{source}: the two wheels differ: pure rolling at y = {y_e * 1e3:.3f} mm "
              "(Δr = 0); the linear models are about that pose")
    lp = linear_parameters(provider, params, amplitude=args.amplitude, centre=y_e)
    lin = linear_critical_speed(lp, params)
    v_j, f_j = jacobian_critical_speed(provider, params, amplitude=args.amplitude, centre=y_e)
    out: dict[str, Any] = {"source": source, "classical": lin.as_dict(),
                           "linear": {"speed": v_j, "frequency": f_j}}
    print(f"{source}: linearised model (Jacobian of the simulated rhs): critical speed "
          f"{v_j:.3f} m/s, hunting frequency {f_j:.3f} Hz")
    print(f"{source}: classical Wickens model: {lin.speed:.3f} m/s (lam_e {lp.lam_e:.4f} at "
          f"{args.amplitude * 1e3:g} mm, k_gy {lp.k_gy:.4g} N/m, k_spin {lp.k_spin:.4g} N/m)")
    if not args.linear_only and math.isfinite(v_j) and v_j > 0:
        nl = nonlinear_critical_speed(provider, params, 0.7 * v_j, 1.4 * v_j,
                                      rel_tol=args.rel_tol, vy0=args.vy0,
                                      duration=args.duration)
        out["nonlinear"] = {"speed": nl.speed, "stable_below": nl.stable_below,
                            "hunting_above": nl.hunting_above, "converged": nl.converged,
                            "runs": nl.runs}
        runs = ", ".join(f"{v:.4g} m/s {kind} ({format_rate(rate)})" for v, kind, rate in nl.runs)
        if nl.converged:
            diff = (nl.speed / v_j - 1.0) * 100
            print(f"{source}: nonlinear critical speed {nl.speed:.3f} m/s in "
                  f"[{nl.stable_below:.3f}, {nl.hunting_above:.3f}] ({len(nl.runs)} runs; "
                  f"{diff:+.1f} % vs linearised)")
        else:
            print(f"{source}: nonlinear critical speed not bracketed (needs a stable run at "
                  f"{nl.stable_below:.4g} and a hunting one at {nl.hunting_above:.4g} m/s; "
                  f"an undetermined run stops the bisection): {runs}")
    if args.json:
        print(json.dumps(out, default=float, indent=1))
    return 0
