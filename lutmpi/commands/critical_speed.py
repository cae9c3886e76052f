"""``lutmpi critical-speed``: free-wheelset critical speed from a table, nonlinear and linear."""

from __future__ import annotations

import argparse
import json
import math
import sys
from typing import Any

#: output step of the bisection's runs, s (:data:`lutmpi.dynamics.critical.NONLINEAR_DT_OUT`,
#: which imports numba: the parser must not)
_DT_OUT = 0.01
#: bisection tolerances a run can use: below the floor the bisection would outlast the
#: floating-point resolution of V, above the ceiling the first bracket already satisfies it
REL_TOL_RANGE = (1e-6, 0.5)


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import positive
    from lutmpi.providers import duration_type

    p = subparsers.add_parser(
        "critical-speed", help="critical speed of the wheelset: bisection + linear eigenvalues",
        description="Critical speed of the free wheelset on the table's contact geometry: a "
                    "linearised eigenvalue analysis (equivalent conicity, gravitational stiffness, "
                    "Kalker f11..f33) and a bisection on V with the nonlinear simulation. Exit 1 "
                    "when the bisection does not bracket the critical speed, or the linear "
                    "models find none (no pure-rolling pose; unstable or stable at every speed "
                    "scanned).")
    p.add_argument("config", help="configuration TOML (with --table, the pair and the wheelset "
                                  "data are the table's; a config that differs is warned about)")
    p.add_argument("--table", help="lookup table (HDF5); required unless --online")
    p.add_argument("--online", action="store_true", help="contact by a pose solve at every call")
    p.add_argument("--method", default=None, help="contact method")
    p.add_argument("--amplitude", type=positive, default=3.5e-4,
                   help="amplitude of the linearisation, m (3.5e-4: the oscillation that "
                        "vy0 = 0.1 m/s starts); within the table's y range")
    p.add_argument("--duration", type=duration_type(_DT_OUT), default=30.0,
                   help="run length per speed, s (30)")
    p.add_argument("--vy0", type=nonzero, default=0.1, help="initial lateral velocity, m/s (0.1)")
    p.add_argument("--rel-tol", type=rel_tol, default=0.02, help="bisection tolerance (0.02)")
    p.add_argument("--linear-only", action="store_true", help="skip the bisection")
    p.add_argument("--json", action="store_true",
                   help="print the result as JSON on standard output (the text goes to standard "
                        "error)")
    p.set_defaults(func=run)


def nonzero(text: str) -> float:
    """A finite number other than 0."""
    from lutmpi.argtypes import finite

    v = finite(text)
    if v == 0.0:
        raise argparse.ArgumentTypeError(f"expected a number other than 0 (nothing would start "
                                         f"the oscillation), got {text!r}")
    return v


def rel_tol(text: str) -> float:
    """A number in :data:`REL_TOL_RANGE`."""
    from lutmpi.argtypes import finite

    v = finite(text)
    lo, hi = REL_TOL_RANGE
    if not lo <= v <= hi:
        raise argparse.ArgumentTypeError(f"expected a number in [{lo:g}, {hi:g}], got {text!r}")
    return v


def _plain(value: Any) -> Any:
    """``value`` with every non-finite float as None (strict JSON has no NaN or Infinity)."""
    if isinstance(value, dict):
        return {k: _plain(v) for k, v in value.items()}
    if isinstance(value, list | tuple):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def _no_speed(speed: float, v_min: str, v_max: str) -> str | None:
    """Why a scan of the linear models found no critical speed (their 0: unstable at
    ``v_min``, the scan's lowest speed; inf: stable up to ``v_max``), or None for a speed."""
    if speed == 0.0:
        return (f"the linearised model is unstable at every speed scanned, from {v_min} (no "
                "stable rolling to lose)")
    if not math.isfinite(speed):
        return f"the linearised model is stable at every speed scanned, up to {v_max}"
    return None


def _no_rolling_pose(provider: Any, y_e: float) -> str | None:
    """Why the linear models have no pose to linearise about, or None.

    :func:`lutmpi.dynamics.critical.rolling_offset` answers 0 both for a wheelset whose wheels
    roll alike when centred and for one whose Δr has no zero in reach (it warns): only the first
    rolls steadily there; linearised about the second, the eigenvalues describe no motion."""
    from lutmpi.dynamics.critical import PURE_ROLLING_TOL

    if y_e != 0.0:
        return None
    g = provider.evaluate(0.0, 0.0)
    d0 = float(g.rolling_radius[0, 0] - g.rolling_radius[1, 0])
    if abs(d0) < PURE_ROLLING_TOL:
        return None
    return (f"the wheelset has no pure-rolling pose: the rolling radii differ by Δr = "
            f"{d0 * 1e3:.3f} mm when centred and Δr does not vanish in the lateral range "
            "scanned (the warning above says where the scan ended), so there is no steady "
            "rolling to linearise about; check the two wheels' radii and profiles")


def run(args: argparse.Namespace) -> int:
    from lutmpi.dynamics.critical import (
        check_linear_range,
        jacobian_critical_speed,
        linear_critical_speed,
        linear_parameters,
        nonlinear_critical_speed,
        rolling_offset,
    )
    from lutmpi.dynamics.stability import format_rate
    from lutmpi.errors import ConvergenceError
    from lutmpi.providers import make_provider

    # with --json, standard output holds the JSON alone
    text = sys.stderr if args.json else sys.stdout

    def say(line: str) -> None:
        print(line, file=text, flush=True)

    args.output = None
    provider, params, source = make_provider(args.config, args.table, args.online, args.method)
    y_e = rolling_offset(provider)
    if y_e != 0.0:
        say(f"{source}: the two wheels differ: pure rolling at y = {y_e * 1e3:.3f} mm "
            "(Δr = 0); the linear models are about that pose")
    check_linear_range(provider, args.amplitude, y_e, name="--amplitude")
    out: dict[str, Any] = {"source": source}
    why = _no_rolling_pose(provider, y_e)
    v_j = math.nan
    if why is None:
        lp = linear_parameters(provider, params, amplitude=args.amplitude, centre=y_e)
        lin = linear_critical_speed(lp, params)
        v_j, f_j = jacobian_critical_speed(provider, params, amplitude=args.amplitude,
                                           centre=y_e)
        out.update(classical=lin.as_dict(),
                   linear={"speed": v_j, "frequency": f_j, "found": True})
        why = _no_speed(v_j, "1 m/s", "100 m/s")
        if why is None:
            say(f"{source}: linearised model (Jacobian of the simulated rhs): critical speed "
                f"{v_j:.3f} m/s, hunting frequency {f_j:.3f} Hz")
        classical = _no_speed(lin.speed, "0.5 m/s", "200 m/s")
        if classical is not None:
            out["classical"].update(speed=None, message=classical)
        say(f"{source}: classical Wickens model: {classical or f'{lin.speed:.3f} m/s'} (lam_e "
            f"{lp.lam_e:.4f} at {args.amplitude * 1e3:g} mm, k_gy {lp.k_gy:.4g} N/m, k_spin "
            f"{lp.k_spin:.4g} N/m)")
    failure = None
    if why is not None:   # the error line says it (exit 1, as an unbracketed bisection)
        # 0 or inf is no speed: as data it is null, never a number to read as a speed
        out["linear"] = {"speed": None, "frequency": None, "found": False, "message": why}
        failure = f"{source}: no linear critical speed: {why}"
    if not args.linear_only and why is not None:
        failure = (f"{source}: nonlinear critical speed not bracketed: the bisection starts "
                   f"from the linear critical speed, and there is none: {why}")
        out["nonlinear"] = {"speed": None, "converged": False, "message": failure, "runs": []}
    elif not args.linear_only:
        nl = nonlinear_critical_speed(provider, params, 0.7 * v_j, 1.4 * v_j,
                                      rel_tol=args.rel_tol, vy0=args.vy0,
                                      duration=args.duration)
        out["nonlinear"] = {"speed": nl.speed, "stable_below": nl.stable_below,
                            "hunting_above": nl.hunting_above, "converged": nl.converged,
                            "runs": nl.runs, "message": nl.message}
        runs = ", ".join(f"{v:.4g} m/s {kind} ({format_rate(rate)})" for v, kind, rate in nl.runs)
        if nl.converged:
            diff = (nl.speed / v_j - 1.0) * 100
            say(f"{source}: nonlinear critical speed {nl.speed:.3f} m/s in "
                f"[{nl.stable_below:.3f}, {nl.hunting_above:.3f}] ({len(nl.runs)} runs; "
                f"{diff:+.1f} % vs linearised)")
        else:
            failure = (f"{source}: nonlinear critical speed not bracketed: {nl.message} "
                       f"(runs: {runs})")
    if args.json:
        print(json.dumps(_plain(out), default=float, indent=1, allow_nan=False), flush=True)
    if failure is not None:
        raise ConvergenceError(failure)
    return 0
