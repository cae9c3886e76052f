"""``lutmpi simulate``: one wheelset run on a lookup table (or on-line contact), to HDF5 + PNGs."""

from __future__ import annotations

import argparse
import json
import logging
from pathlib import Path
from typing import Any

import numpy as np

log = logging.getLogger(__name__)


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import finite, positive

    p = subparsers.add_parser(
        "simulate", help="wheelset dynamics on a lookup table (paper §6)",
        description="Integrate a free wheelset (Table 2 data) running at SPEED on tangent track "
                    "with contact from the lookup table (or --online: a pose solve at every "
                    "evaluation). Writes time histories to HDF5, PNG plots like Figs 11-14 and "
                    "prints a summary line (stable / hunting, growth rate, amplitude, Y/Q).")
    p.add_argument("config",
                   help="configuration TOML (with --table, E, nu, r0 and the load come from "
                        "the table's attributes)")
    p.add_argument("--table", help="lookup table (HDF5); required unless --online")
    p.add_argument("--speed", type=positive, default=27.0, help="forward speed, m/s (default 27)")
    p.add_argument("--duration", type=positive, default=10.0, help="simulated time, s (default 10)")
    p.add_argument("-o", "--output", required=True, help="HDF5 file for the time histories")
    p.add_argument("--online", action="store_true", help="contact by a pose solve at every call")
    p.add_argument("--method", default=None, help="contact method (table group / solver method)")
    p.add_argument("--vy0", type=finite, default=0.1, help="initial lateral velocity, m/s (0.1)")
    p.add_argument("--integrator", default="LSODA", help="solve_ivp method (default LSODA)")
    p.add_argument("--no-plots", action="store_true", help="skip the PNGs")
    p.set_defaults(func=run)


def write_run(path: str | Path, run: Any, source: str) -> None:
    """Time histories to HDF5 (serial h5py), SI units in each dataset's ``units`` attribute."""
    import h5py

    from lutmpi import __version__

    data = {
        "t": (run.t, "s"), "y": (run.y, "m"), "yaw": (run.yaw, "rad"),
        "vy": (run.state[:, 2], "m/s"), "vyaw": (run.state[:, 3], "rad/s"),
        "spin_perturbation": (run.state[:, 4], "rad/s"), "roll": (run.roll, "rad"),
        "z_g": (run.z_g, "m"), "normal_force": (run.normal_force, "N"),
        "tangential_force": (run.tangential, "N"),
        "lateral_tangential_force": (run.lateral_creep_force, "N"),
        "contact_point": (run.contact_point, "m"), "contact_angle": (run.contact_angle, "rad"),
        "n_contacts": (run.n_contacts, ""), "y_over_q": (run.y_over_q, "1"),
        "lift": (run.lift.astype("i1"), ""),
    }
    with h5py.File(path, "w") as f:
        for name, (arr, units) in data.items():
            d = f.create_dataset(name, data=np.asarray(arr))
            d.attrs["units"] = units
        for name, times in run.events.items():
            f.create_dataset(f"events/{name}", data=np.asarray(times, float)).attrs["units"] = "s"
        s = run.summary
        f.attrs.update({
            "lutmpi_version": __version__, "source": source, "speed": run.speed,
            "params": json.dumps(run.params.__dict__), "success": run.success,
            "message": run.message, "nfev": run.nfev, "wall_time_s": run.wall_time,
            "sim_per_wall": run.sim_per_wall, "kind": s.kind, "growth_rate": s.growth_rate,
            "amplitude": s.amplitude, "max_y_over_q": run.max_y_over_q, "nadal_limit": run.nadal,
            "flange_angle": run.flange_angle, "dims": "time, side [0=left, 1=right], slot, xyz"})


def run(args: argparse.Namespace) -> int:
    from lutmpi.dynamics.simulate import simulate
    from lutmpi.outpath import check_output_file
    from lutmpi.providers import make_provider

    check_output_file(args.output, "simulation output", inputs=(args.config, args.table))
    provider, params, source = make_provider(args.config, args.table, args.online, args.method)
    res = simulate(provider, params, args.speed, args.duration, vy0=args.vy0,
                   method=args.integrator)
    write_run(args.output, res, source)
    if not args.no_plots:
        from lutmpi.reports.dynamics_plots import plot_run

        out = Path(args.output)
        paths = plot_run([res], out.with_suffix(""))
        log.info("plots: %s", ", ".join(str(p) for p in paths))
    print(f"{source}: {res.summary_line()}")
    if not res.success:
        log.error("simulation stopped: %s", res.message)
        print(f"{source}: stopped: {res.message}")
    return 0 if res.success else 1
