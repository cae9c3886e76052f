"""``lutmpi simulate``: one wheelset run on a lookup table (or on-line contact), to HDF5 + PNGs."""

from __future__ import annotations

import argparse
import json
import logging
import os
from pathlib import Path
from typing import Any

import numpy as np

log = logging.getLogger(__name__)


#: output step of a run, s (:func:`lutmpi.dynamics.simulate.simulate`'s ``dt_out``)
DT_OUT = 0.005
#: solve_ivp's method names (:data:`lutmpi.dynamics.simulate.INTEGRATORS`, which imports numba:
#: the parser must not; a test keeps the two equal)
INTEGRATORS = ("LSODA", "BDF", "Radau", "RK45", "RK23", "DOP853")
#: root attributes of a run's file -> SI unit, written beside each as ``<name>_units`` (the
#: datasets carry ``units``; ``wall_time_s`` has its unit in its name, as a table's has)
ROOT_UNITS = {"speed": "m/s", "growth_rate": "1/s", "amplitude": "m", "max_y_over_q": "1",
              "nadal_limit": "1", "flange_angle": "rad", "sim_per_wall": "1"}
#: the figures a run writes, ``<stem>_<key>.png`` (:func:`lutmpi.reports.dynamics_plots.plot_run`,
#: which imports matplotlib; a test keeps the two equal)
PLOT_KEYS = ("y", "yaw", "roll", "fy")


def register(subparsers: Any) -> None:
    from lutmpi.argtypes import finite, positive
    from lutmpi.providers import duration_type

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
    p.add_argument("--duration", type=duration_type(DT_OUT), default=10.0,
                   help=f"simulated time, s (default 10; output every {DT_OUT:g} s)")
    p.add_argument("-o", "--output", required=True,
                   help="HDF5 file for the time histories; the figures are OUTPUT's stem + "
                        f"{', '.join(f'_{k}.png' for k in PLOT_KEYS)}")
    p.add_argument("--force", action="store_true",
                   help="replace an earlier run's output and figures (refused without); with "
                        "--no-plots its figures are removed")
    p.add_argument("--online", action="store_true", help="contact by a pose solve at every call")
    p.add_argument("--method", default=None, help="contact method (table group / solver method)")
    p.add_argument("--vy0", type=finite, default=0.1, help="initial lateral velocity, m/s (0.1)")
    p.add_argument("--integrator", default="LSODA", choices=INTEGRATORS,
                   help="solve_ivp method (default LSODA)")
    p.add_argument("--no-plots", action="store_true", help="skip the PNGs")
    p.set_defaults(func=run)


def run_outputs(output: str | Path, inputs: tuple[str | None, ...], force: bool
                ) -> list[Path]:
    """Check the paths of a run before its work; return its figures' paths.

    A run owns ``output`` and the figures ``<stem>_<key>.png`` of :data:`PLOT_KEYS` (written,
    or with ``--no-plots`` removed: an earlier run's figures must not stay beside new data).

    Raises
    ------
    OutputError
        What :func:`lutmpi.outpath.check_output_file` refuses, for any of them; without
        ``force``, any of them that exists (an earlier run's), each named.
    """
    from lutmpi.errors import OutputError
    from lutmpi.outpath import check_output_file

    out = check_output_file(output, "simulation output", inputs=inputs)
    figures = [out.parent / f"{out.stem}_{key}.png" for key in PLOT_KEYS]
    for fig in figures:
        check_output_file(fig, "simulation figure", inputs=inputs)
    there = [str(p) for p in (out, *figures) if p.exists()]
    if there and not force:
        raise OutputError(f"{', '.join(there)} exist{'s' if len(there) == 1 else ''} (an earlier "
                          "run's output); pass --force to replace "
                          f"{'it' if len(there) == 1 else 'them'}, or give another -o")
    return figures


def write_run(path: str | Path, run: Any, source: str) -> None:
    """Time histories to HDF5 (serial h5py), SI units in each dataset's ``units`` attribute and
    in ``<name>_units`` beside each root attribute of :data:`ROOT_UNITS` (``params_units``:
    the JSON of the parameters' units)."""
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
    path = Path(path)
    # written beside, then renamed: an earlier run's file (--force) stays whole until the new
    # one is, and no half-written file is left under the output's name
    partial = path.with_name(path.name + ".partial")
    try:
        _write_h5(h5py, partial, data, run, source, __version__)
    except BaseException:
        partial.unlink(missing_ok=True)
        raise
    os.replace(partial, path)


def _write_h5(h5py: Any, path: Path, data: dict[str, tuple[Any, str]], run: Any, source: str,
              version: str) -> None:
    from lutmpi.dynamics.wheelset import WheelsetParams

    with h5py.File(path, "w") as f:
        for name, (arr, units) in data.items():
            d = f.create_dataset(name, data=np.asarray(arr))
            d.attrs["units"] = units
        for name, times in run.events.items():
            f.create_dataset(f"events/{name}", data=np.asarray(times, float)).attrs["units"] = "s"
        s = run.summary
        f.attrs.update({
            "lutmpi_version": version, "source": source, "speed": run.speed,
            "params": json.dumps(run.params.__dict__), "success": run.success,
            "message": run.message, "nfev": run.nfev, "wall_time_s": run.wall_time,
            "sim_per_wall": run.sim_per_wall, "kind": s.kind, "growth_rate": s.growth_rate,
            "amplitude": s.amplitude, "max_y_over_q": run.max_y_over_q, "nadal_limit": run.nadal,
            "flange_angle": run.flange_angle, "dims": "time, side [0=left, 1=right], slot, xyz",
            "params_units": json.dumps(WheelsetParams.UNITS)})
        f.attrs.update({f"{name}_units": unit for name, unit in ROOT_UNITS.items()})


def run(args: argparse.Namespace) -> int:
    from lutmpi.dynamics.simulate import simulate
    from lutmpi.providers import make_provider

    figures = run_outputs(args.output, (args.config, args.table), args.force)
    provider, params, source = make_provider(args.config, args.table, args.online, args.method)
    res = simulate(provider, params, args.speed, args.duration, vy0=args.vy0,
                   method=args.integrator, dt_out=DT_OUT)
    write_run(args.output, res, source)
    if not args.no_plots:
        from lutmpi.reports.dynamics_plots import plot_run

        out = Path(args.output)
        paths = plot_run([res], out.parent / out.stem)
        log.info("plots: %s", ", ".join(str(p) for p in paths))
    else:
        stale = [p for p in figures if p.exists()]
        for p in stale:
            p.unlink()
        if stale:
            log.warning("--no-plots: removed the earlier run's figures %s",
                        ", ".join(str(p) for p in stale))
    print(f"{source}: {res.summary_line()}")
    if not res.success:
        log.error("simulation stopped: %s", res.message)
        print(f"{source}: stopped: {res.message}")
    return 0 if res.success else 1
