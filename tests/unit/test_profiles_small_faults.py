"""Small profile-file faults of issue 13, item 8: each is a clear error naming the line, or is read
right. Profiles are plain-text rails ``z = -y^2 / 200`` (a 100 mm crown radius, falling 6 mm at
y = +-35 mm as a rail head does) written here, in lutmpi's normalized orientation."""

from __future__ import annotations

import time

import numpy as np
import pytest

from lutmpi.errors import ProfileError
from lutmpi.profiles.model import Profile
from lutmpi.profiles.readers import read_profile
from lutmpi.profiles.validate import spline_bulge


def _rail_text(y: np.ndarray, fmt: str = "{:.6f} {:.6f}") -> str:
    return "# kind: rail\n" + "\n".join(fmt.format(a, -a * a / 200.0) for a in y) + "\n"


def test_decimal_commas_are_a_clear_error_naming_the_line(tmp_path):
    path = tmp_path / "comma.txt"
    path.write_text(_rail_text(np.linspace(-35, 35, 71), "{:.3f};{:.3f}").replace(".", ","))
    with pytest.raises(ProfileError, match=r"comma\.txt:2: decimal commas"):
        read_profile(path)


def test_utf8_bom_keeps_the_first_point(tmp_path):
    y = np.linspace(-35, 35, 71)
    plain, bom = tmp_path / "plain.txt", tmp_path / "bom.txt"
    plain.write_text(_rail_text(y)[len("# kind: rail\n"):])
    bom.write_bytes(b"\xef\xbb\xbf" + plain.read_bytes())
    a, b = read_profile(plain, kind="rail"), read_profile(bom, kind="rail")
    assert a.meta["trimmed"]["points_in_file"] == b.meta["trimmed"]["points_in_file"] == 71
    assert np.array_equal(a.y, b.y) and np.array_equal(a.z, b.z)


def test_million_point_monotonic_profile_is_read(tmp_path):
    """Points 0.07 um apart are dense, not backtracking: thinned to the 2 um resolution."""
    path = tmp_path / "dense.txt"
    path.write_text(_rail_text(np.linspace(-35, 35, 1_000_000)))
    t0 = time.perf_counter()
    prof = read_profile(path)
    assert prof.kind == "rail"
    assert prof.meta["trimmed"]["points_in_file"] == 1_000_000
    # the head is the closed form z = -y^2/600 to the written precision
    yy = np.linspace(-0.03, 0.03, 7)
    assert np.allclose(prof.z_at(yy),
                       -(yy * 1e3) ** 2 / 200.0 * 1e-3, atol=1e-8)
    assert time.perf_counter() - t0 < 60


def test_a_step_back_in_the_head_is_still_an_error(tmp_path):
    """Thinning dense data must not hide a step back, however small (0.5 um here)."""
    y = np.linspace(-35, 35, 71)
    y[40] = y[39] - 5e-4
    path = tmp_path / "rep.txt"
    path.write_text(_rail_text(y))
    with pytest.raises(ProfileError, match="backtrack or repeat"):
        read_profile(path)


def test_single_point_spike_on_a_tread_is_an_error_naming_its_line(tmp_path, repo_root):
    """The issue's case: one point of a measured wheel's tread (MiniProf) moved 5 mm."""
    from lutmpi.profiles.readers import get_reader

    src = repo_root / "profiles" / "avg_wheel.whl"
    lines = src.read_text().splitlines()
    raw = get_reader("miniprof").parse(lines, str(src))
    line = int(raw.lines[np.argmin(np.abs(raw.y_mm - 10.0))])    # s = 10 mm: on the tread
    a, b, *rest = lines[line - 1].split()
    lines[line - 1] = " ".join([a, f"{float(b) + 5.0:.2f}", *rest])
    path = tmp_path / "spike.whl"
    path.write_text("\n".join(lines) + "\n")
    read_profile(src)                                             # the original reads
    with pytest.raises(ProfileError, match=rf"spike\.whl:{line}: .* single-point spike, 5"):
        read_profile(path)


def test_a_half_millimetre_glitch_on_a_measured_tread_is_a_spike(tmp_path, repo_root):
    """A hostile tester's case: one point of Car7216's tread (MiniProf, 0.25 mm spacing)
    raised by 0.5 mm. Smoothed, it was a 0.21 mm bump 3.8 mm wide that a contact moved onto;
    now the file is refused at that line. Every measured and benchmark file of the repository
    still reads (none has a point with both sides that steep in opposite directions)."""
    for src in sorted((repo_root / "profiles").glob("*.*")):
        if src.suffix != ".md":
            read_profile(src)
    src = repo_root / "profiles" / "Car7216_0001r.whl"
    lines = src.read_text().splitlines()
    line = 1 + next(k for k, t in enumerate(lines) if t.startswith("79.9392"))  # s ~ +9.9 mm
    a, b, *rest = lines[line - 1].split()
    lines[line - 1] = " ".join([a, f"{float(b) + 0.5:.3f}", *rest])
    path = tmp_path / "glitch.whl"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(ProfileError, match=rf"glitch\.whl:{line}: .* single-point spike, 0\.5"):
        read_profile(path)


def test_a_step_in_exact_data_warns_naming_its_lines(tmp_path, caplog):
    """A rail head ``z = -y^2 / 200`` (mm) written every 0.5 mm with the points from y = 2 mm
    on lowered by 0.3 mm, read as exact (plain text: the interpolating spline). Beside the
    step the cubic rings out of the points around it (0.029 mm between y = 1.0 and 1.5 mm,
    where the data fall monotonically: it must stay between them), and a contact can sit on
    that bulge: a warning names the file, the two lines and the size, and ``profile show``
    lists it. The same head without the step is quiet, and so is a smooth crown of 5 mm
    radius (a flange tip's) sampled every 1 mm: the cubic overshoots its top points by about
    ``h^2 kappa / 8`` = 25 um where they turn, which is not a step."""
    from lutmpi.commands.profile import describe

    y = np.arange(-35.0, 35.01, 0.5)
    z = -y * y / 200.0
    z[y >= 2.0] -= 0.3
    step = tmp_path / "step.txt"
    step.write_text("# kind: rail\n" + "\n".join(f"{a:.6f} {b:.6f}" for a, b in
                                                  zip(y, z, strict=True)) + "\n")
    with caplog.at_level("WARNING", logger="lutmpi.profiles.validate"):
        prof = read_profile(step)
    k = int(np.flatnonzero(y == 1.0)[0])         # the point at y = 1 mm: file line k + 2
    (rec,) = [r for r in caplog.records if "bulges" in r.getMessage()]
    bulge = prof.meta["spline_bulge"]
    assert sorted(bulge["lines"]) == [k + 2, k + 3]
    assert f"between lines {k + 2} and {k + 3}" in rec.getMessage()
    assert "step.txt" in rec.getMessage() and bulge["mm"] > 0.02
    assert any(line.startswith("spline bulge") for line in describe(prof))
    caplog.clear()
    smooth = tmp_path / "smooth.txt"
    smooth.write_text(_rail_text(y))
    with caplog.at_level("WARNING", logger="lutmpi.profiles.validate"):
        quiet = read_profile(smooth)
    assert "spline_bulge" not in quiet.meta and not caplog.records
    yt = np.arange(-4.5, 4.51, 1.0) * 1e-3                 # the apex between two points, m
    tip = Profile(kind="rail", y=yt, z=np.sqrt(25e-6 - yt * yt) - 5e-3)
    top = tip.z_at(np.linspace(-0.5e-3, 0.5e-3, 101)).max() - tip.z.max()
    assert 20e-6 < top < 30e-6                   # ~ h^2 kappa / 8 = 25 um above its points
    assert spline_bulge(tip) == (0.0, -1)


@pytest.mark.parametrize("name", ["MBench_S1002_v3.prw", "MBench_UIC60_v3.prr"])
def test_the_exact_shipped_files_do_not_bulge(repo_root, name, caplog):
    """The Simpack files are exact (interpolating spline) and smooth: no bulge warning."""
    with caplog.at_level("WARNING", logger="lutmpi.profiles.validate"):
        prof = read_profile(repo_root / "profiles" / name)
    assert prof.smoothing == 0.0 and "spline_bulge" not in prof.meta and not caplog.records
