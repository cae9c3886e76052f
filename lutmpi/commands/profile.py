"""``lutmpi profile <sub>``: profile tools. ``show`` prints what lutmpi reads from a profile.

Sub-subcommands register themselves in :data:`SUBCOMMANDS` (name -> function adding its parser to
the ``profile`` subparsers); add ``plot`` etc. by appending one function.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

import numpy as np

from lutmpi.outpath import check_output_file
from lutmpi.profiles import GENERATORS, READERS, Profile, generate, read_profile
from lutmpi.profiles.measures import rail_measures, wheel_measures


def _mm(x: float | None) -> str:
    return "n/a" if x is None else f"{x * 1e3:.3f} mm"


def describe(p: Profile) -> list[str]:
    """Human-readable lines about a profile (pure; used by ``profile show``)."""
    out = [f"source        : {p.source}",
           f"kind          : {p.kind} (detected from: {p.meta.get('kind_source', 'generator')})",
           f"format        : {p.meta.get('format', 'generator')}",
           f"units in file : {p.meta.get('units', 'mm')}",
           f"points        : {p.y.size}",
           f"extent        : y = [{p.y_min * 1e3:.3f}, {p.y_max * 1e3:.3f}] mm, "
           f"z = [{p.z.min() * 1e3:.3f}, {p.z.max() * 1e3:.3f}] mm",
           "spline        : " + ("interpolating" if p.smoothing == 0 else
                                  f"smoothing, lam = {p.smoothing:.3g} m^3")]
    bulge = p.meta.get("spline_bulge")
    if bulge:
        out.append(f"spline bulge  : {bulge['mm']:.3f} mm out of monotone points between lines "
                   f"{min(bulge['lines'])} and {max(bulge['lines'])} (a step in the data?)")
    trimmed = p.meta.get("trimmed")
    if trimmed and trimmed.get("points_dropped"):
        out.append(f"trimmed       : {trimmed['points_dropped']} of {trimmed['points_in_file']} "
                   f"points ({trimmed.get('rule', '')})")
    if p.kind == "wheel":
        m = wheel_measures(p)
        out += [f"flange tip    : s = {_mm(m.tip_s)}",
                f"flange height : {_mm(m.flange_height)} (Sh, tip above the tape circle)",
                f"flange thick. : {_mm(m.flange_thickness)} (Sd, flange back s = -70 mm to the "
                "face 10 mm above the tape circle)",
                f"flange slope  : {_mm(m.flange_slope_qr)} (qR)",
                f"dr at s = 0   : {_mm(m.dr_at_tape)}"]
        hdr = [f"{k[:-3]} = {p.meta[k]:g} mm" for k in ("Sd_mm", "Sh_mm", "qR_mm") if k in p.meta]
        if hdr:
            out.append(f"file header   : {', '.join(hdr)}")
    else:
        m = rail_measures(p)
        gp = f"v = {_mm(m.gauge_point[0])}, z = {_mm(m.gauge_point[1])}"
        if not m.gauge_point_at_depth:
            gp += " (the gauge side ends above 14 mm: outermost point)"
        out += [f"top           : v = {_mm(m.top_v)}, z = {_mm(m.top_z)}",
                f"head width    : {_mm(m.head_width)} (14 mm below the top)",
                f"gauge point   : {gp}",
                f"cant in data  : {p.cant_rad:.6f} rad"
                + (f" (1:{1 / math.tan(p.cant_rad):.1f}; {p.meta.get('cant_source', 'given')})"
                   if p.cant_rad else "")]
    return out


def _show(args: argparse.Namespace) -> int:
    if (args.file is None) == (args.generator is None):
        print("lutmpi profile show: give a FILE or --generator NAME", flush=True)
        return 2
    if args.points:   # before reading: never over the profile it shows
        check_output_file(args.points, "points output", inputs=(args.file,))
    if args.generator:
        p = generate(args.generator)
    else:
        p = read_profile(args.file, kind=args.kind, format=args.format)
    print("\n".join(describe(p)))
    if args.points:
        np.savetxt(args.points, np.c_[p.y, p.z] * 1e3, fmt="%.6f",
                   header="normalized orientation, mm: y z")
    return 0


def _add_show(sub: argparse._SubParsersAction) -> None:
    sp = sub.add_parser("show", help="print points, extent, kind and standard measures")
    sp.add_argument("file", nargs="?", help="profile file")
    sp.add_argument("--generator", choices=sorted(GENERATORS), help="a built-in profile instead")
    sp.add_argument("--kind", choices=["wheel", "rail"], help="expected kind")
    sp.add_argument("--format", choices=sorted(READERS), help="reader (default: detect)")
    sp.add_argument("--points", metavar="OUT", help="also write the normalized points (mm) here")
    sp.set_defaults(func=_show)


#: ``profile`` sub-subcommands: each adds its parser (with ``set_defaults(func=...)``).
def _add_plot(sub: argparse._SubParsersAction) -> None:
    from lutmpi.argtypes import within

    p = sub.add_parser("plot", help="both wheels on both rails, to scale (PNG)",
                       description="Draw the wheelset of CONFIG on its rails at its rigid "
                                   "contact pose for lateral shift --y-mm (yaw 0), to scale, "
                                   "with close-ups.")
    p.add_argument("config", help="run configuration (TOML)")
    p.add_argument("--y-mm", type=within(100.0), default=0.0,
                   help="lateral shift of the wheelset (mm, |y| <= 100)")
    p.add_argument("-o", "--output", default="track.png", help="output PNG")
    p.set_defaults(func=_run_plot)


def _run_plot(args: argparse.Namespace) -> int:
    from lutmpi.config import load_config
    from lutmpi.outpath import check_figure_file
    from lutmpi.reports.track_plot import plot_track
    from lutmpi.scene import Scene

    check_figure_file(args.output, "figure", inputs=(args.config,))
    scene = Scene.from_config(load_config(args.config))
    out = plot_track(scene, args.output, y=args.y_mm * 1e-3)
    print(f"wrote {out}")
    return 0


SUBCOMMANDS: list[Callable[[argparse._SubParsersAction], None]] = [_add_show, _add_plot]


def register(subparsers: argparse._SubParsersAction) -> None:
    """Add ``lutmpi profile`` and its sub-subcommands."""
    parser = subparsers.add_parser("profile", help="wheel and rail profile tools")
    sub = parser.add_subparsers(dest="profile_command", metavar="SUBCOMMAND")
    for add in SUBCOMMANDS:
        add(sub)
    parser.set_defaults(func=lambda args: (parser.print_help(), 2)[1])
