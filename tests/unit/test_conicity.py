"""Equivalent conicity (EN 15302 Annex B): analytic cone oracle and the standard's benchmark cases.

The benchmark numbers are read from ``shared/validation/en15302/csv`` at test time (CEN/UIC
copyright: never copied into the repository); the tests skip when the folder is absent.
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.reports.conicity import conicity_curve, equivalent_conicity, parse_amplitudes

CASES = [f"E{i}" for i in range(1, 10)]


@pytest.mark.parametrize("lam", [0.05, 0.2, 0.4])
def test_pure_cone_gives_its_cone_angle_at_every_amplitude(lam):
    y = np.linspace(-0.010, 0.010, 201)           # 0.1 mm samples, like measured Δr files
    amps = parse_amplitudes("1:7.5:0.1")
    res = conicity_curve(y, 2.0 * lam * y, amps, r0=0.46, e=1.5)
    assert np.all(np.isfinite(res.tan_gamma_e))
    np.testing.assert_allclose(res.tan_gamma_e, lam, rtol=0, atol=1e-4 * lam)
    # Klingel's wavelength 2 pi sqrt(e r0 / (2 lambda)), e the contact-point distance
    np.testing.assert_allclose(res.wavelength, 2 * np.pi * np.sqrt(1.5 * 0.46 / (2 * lam)),
                               rtol=1e-6)
    np.testing.assert_allclose(res.y_right - res.y_left, 2 * amps, rtol=1e-9)


def test_conicity_does_not_depend_on_r0_and_e_and_cone_offset_recentres():
    y = np.linspace(-0.01, 0.01, 101)
    dr = 0.3 * y + 400 * y**2 + 2e5 * y**3
    a = np.array([1e-3, 3e-3, 5e-3])
    np.testing.assert_allclose(equivalent_conicity(y, dr, a, 0.46, 1.5),
                               equivalent_conicity(y, dr, a, 0.3, 1.9), rtol=1e-8)
    # a diameter offset on a cone only moves the centre: same conicity
    c = equivalent_conicity(y, 0.3 * y + 0.3e-3, a)
    np.testing.assert_allclose(c, 0.15, atol=1e-5)


def test_flat_zone_gives_zero_and_unreachable_amplitude_gives_nan():
    y = np.linspace(-0.005, 0.005, 101)
    dr = np.where(np.abs(y) <= 0.002, 0.0, 0.2 * (y - np.sign(y) * 0.002))
    c = equivalent_conicity(y, dr, [1e-3, 1.5e-3, 6e-3])
    assert c[0] == 0.0 and c[1] == 0.0
    assert np.isnan(c[2])                         # 2 * 6 mm does not fit in ±5 mm


def _load(shared_dir, case):
    folder = shared_dir / "validation" / "en15302" / "csv"
    dr_path, ref_path = folder / f"dr_{case}.csv", folder / f"reference_conicity_{case}.csv"
    if not dr_path.exists() or not ref_path.exists():
        pytest.skip(f"EN 15302 benchmark {case} not available")
    dr = np.loadtxt(dr_path, delimiter=",", skiprows=1)
    ref = np.loadtxt(ref_path, delimiter=",", skiprows=1)
    return dr, ref


@pytest.mark.parametrize("case", CASES)
def test_en15302_benchmark_inside_tolerance_band(shared_dir, case):
    dr, ref = _load(shared_dir, case)
    # the files: Δr = r_right - r_left in mm against y in mm (positive to the right)
    amp = ref[:, 0]
    c = equivalent_conicity(dr[:, 0] * 1e-3, dr[:, 1] * 1e-3, amp * 1e-3)
    reach = np.isfinite(c)
    # The transcribed Δr covers about ±6.8 mm, less than the 7.5 mm amplitudes of the reference;
    # beyond the data's reach the conicity is NaN (never extrapolated), everywhere else it must be
    # inside the band [lower, upper].
    assert reach[amp <= 2.5].all(), f"{case}: small amplitudes must be computable"
    span = dr[-1, 0] - dr[0, 0]
    assert not reach[2 * amp > span + 1e-9].any()
    inside = (c[reach] >= ref[reach, 3] - 1e-12) & (c[reach] <= ref[reach, 2] + 1e-12)
    assert inside.all(), (f"{case}: outside the band at amplitudes {amp[reach][~inside]} mm: "
                          f"{c[reach][~inside]} vs {ref[reach][~inside, 1]}")
    # far closer than the band: the nominal values are met to < 0.01
    assert np.max(np.abs(c[reach] - ref[reach, 1])) < 0.01


def test_parse_amplitudes():
    np.testing.assert_allclose(parse_amplitudes("1:2:0.5"), [1e-3, 1.5e-3, 2e-3])
    np.testing.assert_allclose(parse_amplitudes("3"), [3e-3])
    with pytest.raises(ValueError):
        parse_amplitudes("2:1:0.1")


def test_wrong_sign_gives_nan_not_zero():
    y = np.linspace(-0.005, 0.005, 51)
    assert np.all(np.isnan(equivalent_conicity(y, -0.1 * y, [1e-3, 3e-3])))


def test_dr_from_table_takes_left_minus_right_at_zero_yaw():
    from lutmpi.reports.conicity import dr_from_table

    y = np.linspace(-4e-3, 4e-3, 5)
    yaw = np.array([-0.01, 0.0, 0.01])
    rr = np.full((5, 3, 2, 2), np.nan)
    rr[:, :, 0, 0] = 0.46 + 0.1 * y[:, None] + 1.0 * yaw   # left; yaw columns differ
    rr[:, :, 1, 0] = 0.46 - 0.1 * y[:, None]
    status = np.zeros((5, 3), np.int8)
    status[0, 1] = 4                                          # a failed point is a hole (NaN)
    table = {"y": y, "yaw": yaw, "methods": {"load_centre": {"rolling_radius": rr,
                                                             "status": status}}}
    yy, dr = dr_from_table(table)
    np.testing.assert_allclose(yy, y)
    assert np.isnan(dr[0])
    np.testing.assert_allclose(dr[1:], 0.2 * y[1:], atol=1e-15)
    table["yaw"] = yaw + 0.005
    with pytest.raises(ValueError, match="yaw = 0"):
        dr_from_table(table)


def test_dr_from_a_table_steps_at_its_jumps_and_converges(tmp_path):
    """An asymmetric measured pair (a worn wheel left, a worn rail right) whose 6 mm motion turns
    next to a flange jump of Δr: from the table's 0.1 mm grid alone, Δr runs linearly across
    the jump's cell and the conicity at 6 mm is ~18 % off; with the table's extra knots and
    one-sided jump limits it matches Δr solved directly every 0.01 mm. The config path of
    ``lutmpi conicity`` locates the jumps as a build does and gives the table's value."""
    from lutmpi.cli import main
    from lutmpi.commands.conicity import config_dr
    from lutmpi.config import load_config
    from lutmpi.paths import REPO_ROOT
    from lutmpi.pose.solve import solve_pose
    from lutmpi.reports.conicity import dr_from_table
    from lutmpi.scene import Scene
    from lutmpi.table import Table

    prof = REPO_ROOT / "profiles"
    cfg = tmp_path / "asym.toml"
    cfg.write_text(
        f'[wheel]\nprofile = "{prof / "MBench_S1002_v3.prw"}"\n'
        f'[wheel.left]\nprofile = "{prof / "Car7216_0001r.whl"}"\n'
        f'[rail]\nprofile = "{prof / "MBench_UIC60_v3.prr"}"\ninclination = "none"\n'
        f'[rail.right]\nprofile = "{prof / "rail_left_iter288.ban"}"\ninclination = "1:40"\n'
        '[grid]\ny_mm = [-8.0, 8.0, 161]\nyaw_rad = [0.0, 0.0, 1]\n'
        '[contact]\nmethod = "reference"\n[output]\nmethods = ["reference"]\n')
    out = tmp_path / "t.h5"
    assert main(["build", str(cfg), "-o", str(out)]) == 0
    table = Table.open(out)
    amps = np.array([3e-3, 6e-3])

    scene = Scene.from_config(load_config(cfg))
    ys = np.linspace(-8e-3, 8e-3, 1601)
    direct = []
    for y in ys:
        res = solve_pose(scene, float(y), 0.0, "reference")
        assert res.success
        r = {s: res.contacts[s][0].rolling_radius for s in ("left", "right")}
        direct.append(r["left"] - r["right"])
    want = conicity_curve(ys, np.array(direct), amps).tan_gamma_e

    y, dr = dr_from_table(table)
    got = conicity_curve(y, dr, amps).tan_gamma_e
    np.testing.assert_allclose(got, want, rtol=2e-3)
    # the grid alone (the mapping form without its jumps)
    grid_only = {"y": table.y, "yaw": table.yaw, "methods": {"reference": {
        k: table.get(k, "reference", raw=True) for k in ("rolling_radius", "status")}}}
    yg, drg = dr_from_table(grid_only)
    coarse = conicity_curve(yg, drg, amps).tan_gamma_e
    assert abs(coarse[1] / want[1] - 1.0) > 0.05
    yc, drc, _ = config_dr(cfg)
    np.testing.assert_allclose(conicity_curve(yc, drc, amps).tan_gamma_e, got, rtol=1e-9)


def test_config_dr_solves_half_a_symmetric_grid_and_gives_the_same_dr(tmp_path, monkeypatch):
    """``lutmpi conicity CONFIG`` on a symmetric pair solves one pose per orbit of the y -> -y
    reflection (``output.mirror``, as a build's grid), the poses y > 0 filled from -y: Δr is
    the same to the bit as with every pose solved, and the grid's solves are halved."""
    import lutmpi.table.compute as compute
    from lutmpi.commands.conicity import config_dr
    from lutmpi.paths import REPO_ROOT

    prof = REPO_ROOT / "profiles"
    body = (f'[wheel]\nprofile = "{prof / "MBench_S1002_v3.prw"}"\n'
            f'[rail]\nprofile = "{prof / "MBench_UIC60_v3.prr"}"\ninclination = "none"\n'
            '[grid]\ny_mm = [-8.0, 8.0, 33]\nyaw_rad = [0.0, 0.0, 1]\n'
            '[contact]\nmethod = "reference"\n[output]\nmethods = ["reference"]\n'
            'jumps = false\n')
    solved = []
    real = compute.solve_pose

    def counted(scene, y, yaw, method=None, **kw):
        solved.append(y)
        return real(scene, y, yaw, method, **kw)

    monkeypatch.setattr(compute, "solve_pose", counted)
    out = {}
    for mirror in ("true", "false"):
        cfg = tmp_path / f"m_{mirror}.toml"
        cfg.write_text(body + f"mirror = {mirror}\n")
        solved.clear()
        out[mirror] = config_dr(cfg)
        out[mirror + "_n"] = len(solved)
    assert np.array_equal(out["true"][0], out["false"][0])
    assert np.array_equal(out["true"][1], out["false"][1], equal_nan=True)
    assert np.isfinite(out["true"][1]).sum() >= 31
    # 33 poses: 17 orbits (y = 0 alone); one warm-up solve each
    assert out["false_n"] == 33 + 1 and out["true_n"] == 17 + 1


@pytest.mark.parametrize("half", [3e-3, 6.8e-3, 10e-3])
@pytest.mark.parametrize("lam", [0.05, 0.2])
def test_amplitude_at_the_datas_edge_gives_the_cones_conicity(half, lam):
    """Regression (hostile tester, 2026-11-28): on a cone sampled on ±half, the amplitude
    ``half`` (turning points at both ends of the data: a one-point bracket) was NaN, its integral
    of Δr over the whole data -3e-23 instead of 0. The closed form: tan γe = λ, Klingel's
    wavelength; also for an amplitude a few ulps above the edge (``2.9:3:0.1`` in mm)."""
    y = np.round(np.linspace(-half, half, int(round(2 * half / 1e-4)) + 1), 12)
    amps = np.array([half - 1e-4, half, half * (1 + 2e-16), np.nextafter(half, 1.0)])
    res = conicity_curve(y, 2.0 * lam * y, amps, r0=0.46, e=1.5)
    np.testing.assert_allclose(res.tan_gamma_e, lam, rtol=1e-6)
    np.testing.assert_allclose(res.wavelength, 2 * np.pi * np.sqrt(1.5 * 0.46 / (2 * lam)),
                               rtol=1e-6)
    np.testing.assert_allclose(res.y_left[1:], y[0], atol=1e-15)
    # clearly beyond the data: still NaN (never extrapolated)
    assert np.isnan(equivalent_conicity(y, 2.0 * lam * y, [half + 1e-6])).all()


def test_amplitude_at_the_edge_with_an_offset_centre_leaves_the_data():
    """A diameter offset moves the centre: the motion of amplitude half-span then cannot turn
    back inside the data, and stays NaN (the rounding tolerance does not hide it)."""
    y = np.round(np.linspace(-3e-3, 3e-3, 61), 12)
    c = equivalent_conicity(y, 0.4 * y + 0.04e-3, [2.5e-3, 3e-3])
    assert c[0] == pytest.approx(0.2, rel=1e-6) and np.isnan(c[1])
