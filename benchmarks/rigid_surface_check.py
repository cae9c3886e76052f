"""The rigid solve against a brute-force search over the wheel surfaces, on random asymmetric
pairs of the measured profiles in ``profiles/`` (each side its own wheel and rail, drawn with
the seed): y from -12 to 12 mm every 1 mm, yaw 0, 0.04, -0.08 and 0.12 rad. Per pose and wheel
the smallest vertical gap of the wheel's surface to its rail at the chosen rigid root
(``tests/support/surface.py``: no contact locus) should be 0: below 0 the wheel penetrates its
rail, above it hovers. Printed per pair: rigid solves that failed, the largest |gap| and the poses
above ``--tol`` (with whether the pose is flagged ``at_end``: a contact on the end of a profile's
data), and with ``--methods`` the poses where a mesh method did not converge or lies more than
0.1 mm of z_g from the rigid root. About 50 s per pair on one core.

    .venv/bin/python benchmarks/rigid_surface_check.py --seed 7 --pairs 8 [--methods load_centre]
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from lutmpi.equilibrium.result import CONVERGED  # noqa: E402
from lutmpi.pose.solve import solve_pose  # noqa: E402
from lutmpi.profiles import read_profile  # noqa: E402
from lutmpi.scene import Scene  # noqa: E402
from tests.support.surface import surface_min  # noqa: E402

MM = 1e-3
WHEELS = ("MBench_S1002_v3.prw", "avg_wheel.whl", "Car7216_0001r.whl", "Car7358_0001r.whl",
          "whl_left_iter288.whl")
RAILS = ("MBench_UIC60_v3.prr", "MBench_UIC60_v3.ban", "rail_left_iter288.ban")  # no cant
YAWS = (0.0, 0.04, -0.08, 0.12)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--pairs", type=int, default=8)
    ap.add_argument("--tol", type=float, default=1.0, help="gap reported above this, um")
    ap.add_argument("--methods", nargs="*", default=[])
    a = ap.parse_args()
    prof = ROOT / "profiles"
    wheels = {f: read_profile(prof / f, kind="wheel") for f in WHEELS}
    rails = {f: read_profile(prof / f, kind="rail") for f in RAILS}
    rng = np.random.default_rng(a.seed)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} seed {a.seed}")
    over = total = 0
    for _ in range(a.pairs):
        wl, wr = rng.choice(WHEELS, 2)
        rl, rr = rng.choice(RAILS, 2)
        sc = Scene.from_profiles({"left": wheels[wl], "right": wheels[wr]},
                                 {"left": rails[rl], "right": rails[rr]},
                                 inclination=0.0, gauge_depth=14.0 * MM)
        t0, worst, fails, bad = time.perf_counter(), (0.0, None), 0, []
        for y in np.arange(-12.0, 12.01, 1.0):
            for yaw in YAWS:
                rig = sc.locus.solve(y * MM, yaw)
                if not rig.success:
                    fails += 1
                    continue
                for name in ("left", "right"):
                    g = surface_min(sc, name, y * MM, yaw, rig.roll, rig.z_g)[0] * 1e6
                    total += 1
                    if abs(g) > abs(worst[0]):
                        worst = (g, (float(y), yaw, name))
                    if abs(g) > a.tol:
                        over += 1
                        bad.append(f"({y:+.0f} mm, {yaw:+.2f}) {name} {g:+.3f} um"
                                   f"{' at_end' if rig.at_end else ''}")
                for m in a.methods:
                    r = solve_pose(sc, y * MM, yaw, m)
                    if r.status != CONVERGED:
                        bad.append(f"({y:+.0f} mm, {yaw:+.2f}) {m} status {r.status}")
                    elif abs(r.z_g - rig.z_g) > 0.1 * MM:
                        bad.append(f"({y:+.0f} mm, {yaw:+.2f}) {m} z_g "
                                   f"{(r.z_g - rig.z_g) / MM:+.4f} mm from the rigid root")
        print(f"{wl} / {wr} on {rl} / {rr}: {time.perf_counter() - t0:.0f} s, rigid fails "
              f"{fails}, largest |gap| {worst[0]:+.3f} um at {worst[1]}", flush=True)
        for b in bad:
            print("    " + b, flush=True)
    print(f"wheel-poses with |gap| > {a.tol} um: {over} of {total}")


if __name__ == "__main__":
    main()
