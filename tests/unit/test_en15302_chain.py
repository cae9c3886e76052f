"""Issue 10: EN 15302's chain from the raw reference profiles (Annex E cases E1-E9).

``configs/en15302/E{k}.toml`` read the standard's wheel A/B/H/I and rail A files in place from the
shared validation folder (skipped when absent: they must not be copied into the repository).
Oracles: the standard's Δr tables (``dr_ce_E{k}.dat``) and its equivalent-conicity tables with
their tolerance band (``ben_E{k}.dat``: amplitude, nominal, upper, lower).

Conventions: EN 15302 writes Δr = r_right - r_left with y to the right; lutmpi's y is to the left
and its table Δr = r_left - r_right, so ``Δr_EN(y) = -Δr_lutmpi(-y)`` for the same wheelset
(the configs put the standard's right wheel on lutmpi's right side).
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.commands.conicity import config_dr
from lutmpi.config import load_config
from lutmpi.paths import REPO_ROOT
from lutmpi.pose.solve import solve_pose
from lutmpi.reports.conicity import conicity_curve
from lutmpi.scene import Scene

MM = 1e-3
CASES = range(1, 10)
# issue 10 asks for 0.05 mm (E1, E9: see the test's docstring); not met for wheel I (E4, E8):
# on its flange root (wheel s = -19 ... -30 mm, y = 2 ... 6 mm) lutmpi's Δr differs from the
# table by -0.046 ... +0.080 mm with alternating sign (median 0.019 mm), with or without a
# smoothing spline; README says so
MAX_DR = {4: 0.085, 8: 0.085}


def _config(k: int):
    return load_config(REPO_ROOT / "configs" / "en15302" / f"E{k}.toml")


def _annex_dr(shared_dir, k):
    """The standard's Δr table (the shared csv/ copy, with its y column): y (mm), Δr (mm)."""
    data = np.loadtxt(shared_dir / "validation" / "en15302" / "csv" / f"dr_E{k}.csv",
                      delimiter=",", skiprows=1)
    return data[:, 0], data[:, 1]


def _ours(scene, y_en_mm):
    """Δr_EN (mm) and the left/right wheel contact s (mm) at the standard's y values."""
    out, s = [], []
    for y in y_en_mm:
        r = solve_pose(scene, -y * MM, 0.0, "reference")
        assert r.status == 0, (y, r.message)
        cl, cr = r.contacts["left"][0], r.contacts["right"][0]
        out.append(-(cl.rolling_radius - cr.rolling_radius) / MM)
        s.append((cl.wheel_s / MM, cr.wheel_s / MM))
    return np.array(out), np.array(s)


@pytest.mark.parametrize("k", CASES)
def test_annex_e_delta_r_with_roll_held_at_zero(k, shared_dir):
    """Δr within 0.05 mm of Annex E for |y| <= 6 mm, away from contact jumps: a jump is where
    our contact point on a wheel moves by more than 4 mm between neighbouring 0.1 mm steps;
    the two steps on each side of it are left out (the standard's table may place the jump
    one step apart). E1's and E9's tables are held to their median only: E1's is not E5's
    minus the 1 mm radius offset, although with the roll held at zero a radius offset moves no
    contact point (E2/E6 and E4/E8 obey that identity exactly, E1/E5 differ by up to 0.156 mm);
    lutmpi reproduces E5 to 0.009 mm, and its largest differences to E1 and E9 (0.147, 0.150 mm)
    sit at the same y (5.9 mm) on the same wheel A contact (s = -28.1 mm)."""
    ya, dra = _annex_dr(shared_dir, k)
    keep = np.abs(ya) <= 6.0 + 1e-9
    ya, dra = ya[keep], dra[keep]
    scene = Scene.from_config(_config(k))
    dr, s = _ours(scene, ya)
    jump = np.any(np.abs(np.diff(s, axis=0)) > 4.0, axis=1)
    near = np.zeros(ya.size, bool)
    for i in np.nonzero(jump)[0]:
        near[max(i - 1, 0):i + 3] = True
    d = np.abs(dr - dra)[~near]
    print(f"\nE{k}: max |Δr - Annex E| = {d.max():.4f} mm, median {np.median(d):.4f} mm over "
          f"{d.size} of {ya.size} y values (|y| <= 6 mm, {near.sum()} next to jumps left out)")
    if k in (1, 9):
        assert np.median(d) < 0.03
    else:
        assert d.max() <= MAX_DR.get(k, 0.05)


def test_e1_table_is_e5_minus_the_radius_offset_except_where_it_is_not(shared_dir):
    """The evidence for leaving E1's table out of the 0.05 mm bound (see above)."""
    y1, d1 = _annex_dr(shared_dir, 1)
    y5, d5 = _annex_dr(shared_dir, 5)
    y2, d2 = _annex_dr(shared_dir, 2)
    y6, d6 = _annex_dr(shared_dir, 6)

    def offset_gap(ya, da, yb, db):
        common = np.intersect1d(ya[np.abs(ya) <= 6.0], yb)
        a = da[np.searchsorted(ya, common)]
        b = db[np.searchsorted(yb, common)]
        return np.abs((b - 1.0) - a)

    assert offset_gap(y2, d2, y6, d6).max() < 1e-9
    assert offset_gap(y1, d1, y5, d5).max() > 0.1


#: EN 15302 Annex E's wheel/wheel/rail and diameters (mm) per case (the shared README)
_CASES = {1: ("A", "A", 920, 920), 2: ("B", "B", 920, 920), 3: ("H", "H", 920, 920),
          4: ("I", "I", 920, 920), 5: ("A", "A", 920, 918), 6: ("B", "B", 920, 918),
          7: ("H", "H", 920, 918), 8: ("I", "I", 920, 918), 9: ("A", "B", 920, 920)}


def _independent_dr(raw, k, y_mm):
    """Δr_EN (mm) by an independent 2-D calculation in the standard's own frame: the raw
    points of each wheel and of the rail interpolated by a cubic spline, the wheelset level
    (roll 0), each wheel's contact where its vertical distance to the rail, sampled every
    2 µm, is least. y to the right; the rail's first point is its gauge point at 717.5 mm, the
    wheels' tape circles at 750 mm."""
    from scipy.interpolate import CubicSpline

    def spline(name):
        d = np.loadtxt(raw / f"{name}.dat")
        d = d[np.argsort(d[:, 0])]
        d = d[np.concatenate([[True], np.diff(d[:, 0]) > 0])]
        return CubicSpline(d[:, 0], d[:, 1]), d[0, 0], d[-1, 0]

    rail, r_lo, r_hi = spline("SUIC519A")
    right, left = (spline(f"RUIC519{w}") for w in _CASES[k][:2])
    s = np.arange(-40.0, 60.0, 0.002)

    def radius(wheel, diameter, y):
        w, w_lo, w_hi = wheel
        v = y + 750.0 + s - 717.5 + r_lo             # the wheel's s in the rail file's frame
        ok = (s >= w_lo) & (s <= w_hi) & (v >= r_lo) & (v <= r_hi)
        gap = np.where(ok, w(s) - rail(np.clip(v, r_lo, r_hi)), np.inf)
        return diameter / 2.0 - w(s[np.argmin(gap)])   # the file gives the surface height

    return np.array([radius(right, _CASES[k][2], y) - radius(left, _CASES[k][3], -y)
                     for y in y_mm])


def test_delta_r_equals_an_independent_2d_calculation_and_the_tables_it_misses(shared_dir):
    """lutmpi's Δr (roll held at zero) equals an independent numpy calculation from the raw
    files within 0.01 mm at every y of the Annex tables with |y| <= 6 mm, jumps included
    (measured: 4.4 µm max over the nine cases). The same calculation misses the Annex tables of
    E1, E4, E8 and E9 by more than 0.075 mm (0.080-0.151 mm), while it reproduces E2, E3 away
    from its jump, E5, E6 and E7: the 0.05 mm of issue 10 is not reachable for those four
    from the transcribed profiles by any rigid roll-zero calculation (the tables are not E5's
    identity either, see below). ~10 s."""
    raw = shared_dir / "validation" / "en15302" / "raw"
    misses = {}
    for k in CASES:
        ya, dra = _annex_dr(shared_dir, k)
        keep = np.abs(ya) <= 6.0 + 1e-9
        ya, dra = ya[keep], dra[keep]
        ours, _ = _ours(Scene.from_config(_config(k)), ya)
        other = _independent_dr(raw, k, ya)
        assert np.abs(ours - other).max() < 0.01, k
        misses[k] = float(np.median(np.abs(other - dra))), float(np.abs(other - dra).max())
    print("\nindependent 2-D vs Annex E (median, max mm): "
          + ", ".join(f"E{k} {a:.4f}/{b:.3f}" for k, (a, b) in misses.items()))
    assert all(misses[k][1] > 0.075 for k in (1, 4, 8, 9))
    assert all(misses[k][1] < 0.05 for k in (5, 6))


@pytest.mark.slow
def test_annex_e_conicity_inside_the_tolerance_band(shared_dir):
    """tan γe (EN 15302 Annex B integration of lutmpi's Δr, roll held at zero, the configs'
    0.02 mm y steps) inside the standard's band at >= 95 % of the amplitudes 1.0-7.5 mm of every
    case and >= 97 % over all nine. ~25 s of CPU (1001 poses per case)."""
    total = inside_all = 0
    report = []
    for k in CASES:
        y, dr, r0 = config_dr(REPO_ROOT / "configs" / "en15302" / f"E{k}.toml")
        ben = np.loadtxt(shared_dir / "validation" / "en15302" / "raw" / f"ben_E{k}.dat")
        c = conicity_curve(y, dr, ben[:, 0] * MM, r0=r0 * MM, e=1.5).tan_gamma_e
        inside = (c <= ben[:, 2] + 5e-4) & (c >= ben[:, 3] - 5e-4)  # band given to 3 decimals
        report.append(f"E{k}: {inside.sum()}/{c.size}")
        assert inside.mean() >= 0.95, (k, ben[~inside, 0])
        total += c.size
        inside_all += int(inside.sum())
    print("\n" + ", ".join(report) + f"; all {inside_all}/{total}")
    assert inside_all / total >= 0.97
