"""Is every rigid root a root? At the pose the rigid solve returns, both wheels must touch their
rails: the two touching heights of G (each wheel's, on its whole locus) must be equal. A root
whose heights differ lies on a jump of the sampled height, not on a zero of the height
mismatch: the pose is stored with one wheel above or inside its rail.

Random asymmetric pairs (each side its own wheel and rail, drawn with the seed) of the measured
profiles in ``profiles/``, with ``--worn`` each one also worn at random (a wheel's flange thinned
or its tread hollowed by 0.5-2 mm, a rail's gauge side cut by 0.5-3 mm, its face at its own
angle or 5 or 10 degrees from vertical: ``lutmpi.profiles.wear``); y from -12 to 12 mm every
0.5 mm, 13 yaws over +-0.12 rad. Printed: poses solved, poses whose two heights differ by more
than ``--tol``, the largest, and the worst poses.

    .venv/bin/python benchmarks/root_consistency.py --seed 4 --pairs 8 [--worn] [--dump F.npz]

``--dump`` saves every pose's rigid solution (success, root count, roll, z_g, at_end) so that
two trees' solutions can be compared pose by pose (the same seed draws the same pairs).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from rigid_surface_check import MM, RAILS, WHEELS  # noqa: E402  (the same measured pairs)

from lutmpi.profiles import read_profile, wear  # noqa: E402
from lutmpi.scene import Scene  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=4)
    ap.add_argument("--pairs", type=int, default=8)
    ap.add_argument("--worn", action="store_true", help="wear each profile at random")
    ap.add_argument("--tol", type=float, default=0.1, help="height difference reported, um")
    ap.add_argument("--dump", type=Path, help="save every pose's rigid solution (.npz)")
    a = ap.parse_args()
    prof = ROOT / "profiles"
    wheels = {f: read_profile(prof / f, kind="wheel") for f in WHEELS}
    rails = {f: read_profile(prof / f, kind="rail") for f in RAILS}
    rng = np.random.default_rng(a.seed)

    def wheel():
        w = wheels[str(rng.choice(WHEELS))]
        k = int(rng.integers(3)) if a.worn else 0
        if k == 1:
            w = wear.flange_thinning(w, float(rng.uniform(0.5, 2.0)))
        elif k == 2:
            w = wear.tread_hollowing(w, float(rng.uniform(0.5, 2.0)))
        return w

    def rail():
        r = rails[str(rng.choice(RAILS))]
        if a.worn and rng.integers(2):
            r = wear.rail_side_wear(r, float(rng.uniform(0.5, 3.0)),
                                    angle_deg=[None, 5.0, 10.0][int(rng.integers(3))])
        return r

    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())} seed {a.seed}, {a.pairs} "
          f"pairs{', worn' if a.worn else ''}")
    total, bad, worst = 0, [], 0.0
    rows: list[tuple[float, ...]] = []
    t0 = time.perf_counter()
    for _ in range(a.pairs):
        w, r = {"left": wheel(), "right": wheel()}, {"left": rail(), "right": rail()}
        sc = Scene.from_profiles(w, r, inclination=0.0, gauge_depth=14.0 * MM)
        names = " / ".join(f"{w[s].name} on {r[s].name}" for s in ("left", "right"))
        for y in np.arange(-12.0, 12.01, 0.5):
            for yaw in np.linspace(-0.12, 0.12, 13):
                rig = sc.locus.solve(y * MM, float(yaw))
                rows.append((y * MM, float(yaw), float(rig.success), float(rig.n_roots),
                             float(rig.roll) if rig.success else np.nan,
                             float(rig.z_g) if rig.success else np.nan, float(rig.at_end)))
                if not rig.success:
                    continue
                zl, zr = sc.locus.heights(y * MM, float(yaw), rig.roll)
                d = abs(zl - zr) * 1e6
                total += 1
                worst = max(worst, d)
                if d > a.tol:
                    bad.append((d, f"{names}: y {y:+.1f} mm, yaw {yaw:+.2f} rad: heights "
                                   f"{d:.2f} um apart{' (at_end)' if rig.at_end else ''}"))
    print(f"{total} poses, {len(bad)} with the wheels' heights more than {a.tol} um apart "
          f"(largest {worst:.3g} um); {time.perf_counter() - t0:.0f} s")
    for _, text in sorted(bad, reverse=True)[:10]:
        print("  " + text)
    if a.dump:
        np.savez(a.dump, poses=np.array(rows), columns=np.array(
            ["y_m", "yaw_rad", "success", "n_roots", "roll_rad", "z_g_m", "at_end"]))


if __name__ == "__main__":
    main()
