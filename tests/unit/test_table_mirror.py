"""The jump step's mirror (``[output] mirror``): on a symmetric pair and a grid symmetric about
(0, 0) the pose (-y, -yaw) is the pose (y, yaw) with the wheels swapped, and the jump step
solves only one of each mirror pair of cells and intervals (``lutmpi/table/mirror.py``,
:class:`~lutmpi.table.mirror.Mirror`).

What makes that the same table: the production solver is mirror-symmetric to the bit, for every
method and every stored field under :meth:`~lutmpi.table.schema.Field.mirrored`'s rules (a wrong
rule, roll kept or the wheels not swapped, fails the first test); a mirrored jump step finds the
direct one's jumps at half its solves; the mirror is refused where it does not hold.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from lutmpi.config import load_config
from lutmpi.config.model import ALL_METHODS
from lutmpi.paths import REPO_ROOT
from lutmpi.scene import Scene
from lutmpi.table import journal
from lutmpi.table import jumps as tj
from lutmpi.table import mirror as tm
from lutmpi.table.compute import compute_points, default_solver, pose_to_record
from lutmpi.table.grid import Grid
from lutmpi.table.schema import (
    FIELDS,
    FIELDS_BY_NAME,
    JUMP_FIELDS,
    D,
    J,
    limit_fields,
    row_reflection,
)

pytestmark = pytest.mark.timeout(600)

MANCHESTER = REPO_ROOT / "configs" / "manchester_s1002_uic60_1in40.toml"
LFIELDS = limit_fields(FIELDS)


@pytest.fixture(scope="module")
def manchester():
    cfg = load_config(MANCHESTER)
    return cfg, Scene.from_config(cfg), default_solver()


def _equal(a, b) -> bool:
    return np.array_equal(np.asarray(a), np.asarray(b), equal_nan=True)


SIDES_ = tm.Reflection(True, False)
LONG = tm.Reflection(False, True)
BOTH = tm.Reflection(True, True)


def test_field_reflection_rules():
    """In the x-z plane (y -> -y) roll changes sign, the wheels swap (n_contacts and every
    per-contact field) and a vector's y component changes sign; in the y-z plane (x -> -x)
    x_g, pitch and a vector's x component change sign; everything else is each wheel's own."""
    assert [f.name for f in FIELDS if f.signs[0] < 0] == [D.roll]
    assert [f.name for f in FIELDS if f.signs[1] < 0] == [D.x_g, D.pitch]
    roll, pitch = FIELDS_BY_NAME[D.roll], FIELDS_BY_NAME[D.pitch]
    assert _equal(roll.reflected(np.float64(0.25), True, False), -0.25)
    assert _equal(roll.reflected(np.float64(0.25), False, True), 0.25)
    assert _equal(pitch.reflected(np.float64(0.25), False, True), -0.25)
    assert _equal(pitch.reflected(np.float64(0.25), True, True), -0.25)
    assert _equal(FIELDS_BY_NAME[D.n_contacts].reflected(np.array([1, 2], "i1"), True, False),
                  [2, 1])
    assert _equal(FIELDS_BY_NAME[D.n_contacts].reflected(np.array([1, 2], "i1"), False, True),
                  [1, 2])
    v = np.arange(12.0).reshape(2, 2, 3)
    want = v[::-1].copy()
    want[..., 1] *= -1
    assert _equal(FIELDS_BY_NAME[D.wheel_point].reflected(v, True, False), want)
    want[..., 0] *= -1
    assert _equal(FIELDS_BY_NAME[D.wheel_point].reflected(v, True, True), want)
    c = np.array([[1.0, 2.0], [3.0, np.nan]])
    assert _equal(FIELDS_BY_NAME[D.contact_angle].reflected(c, True, False), c[::-1])
    assert _equal(FIELDS_BY_NAME[D.contact_angle].reflected(c, False, True), c)


POSES = [(0.0, 0.05), (2.5e-3, 0.0), (6.2e-3, -0.03), (7.5e-3, 0.1), (8.9e-3, 0.12),
         (-4.1e-3, 0.07)]
DISCRETE = (D.status, D.iterations, D.n_contacts, D.n_roots)


@pytest.mark.parametrize("method", ALL_METHODS)
def test_the_solver_is_symmetric_under_both_reflections(manchester, method):
    """Every stored field of every method at (-y, -yaw) is the reflection in the x-z plane of
    the one at (y, yaw), bit for bit, and at (y, -yaw) the reflection in the y-z plane, to
    rounding (the same status, iterations and contacts; the mesh methods' sums run over the
    nodes in another order): tread, flange (single and two-point), yawed flange and centred
    poses of the Manchester pair. What the mirrored jump step relies on."""
    _, scene, solver = manchester
    for y, yaw in POSES:
        a = pose_to_record(solver(scene, y, yaw, method), LFIELDS)
        b = pose_to_record(solver(scene, -y, -yaw, method), LFIELDS)
        c = pose_to_record(solver(scene, y, -yaw, method), LFIELDS)
        assert int(a[D.status]) == 0, (method, y, yaw)
        for f in LFIELDS:
            assert _equal(f.reflected(a[f.name], True, False), b[f.name]), (method, y, f.name)
            assert _equal(SIDES_.record({f.name: b[f.name]})[f.name], a[f.name])
            got = LONG.record({f.name: a[f.name]})[f.name]
            if f.name in DISCRETE:
                assert _equal(got, c[f.name]), (method, y, yaw, f.name)
            else:
                np.testing.assert_allclose(got, c[f.name], rtol=1e-10, atol=1e-13,
                                           err_msg=f"{method} {y} {yaw} {f.name}")
            d = BOTH.record({f.name: a[f.name]})[f.name]
            e = pose_to_record(solver(scene, -y, yaw, method), [f])[f.name]
            if f.name in DISCRETE:
                assert _equal(d, e), (method, y, yaw, f.name)
            else:
                np.testing.assert_allclose(d, e, rtol=1e-10, atol=1e-13)


def _table(manchester, ny: int, nyaw: int):
    cfg, scene, solver = manchester
    y = np.linspace(-9e-3, 9e-3, ny)
    yaw = np.linspace(-0.1, 0.1, nyaw) if nyaw > 1 else np.zeros(1)
    grid = Grid(y, yaw)
    recs, _ = compute_points(scene, grid, np.arange(grid.n_points), ["load_centre"], solver,
                             LFIELDS)
    arrays = {k: v.reshape(grid.shape + v.shape[1:]) for k, v in recs["load_centre"].items()}
    count = [0]
    yaws: list[float] = []

    def solve(y, yaw):
        count[0] += 1
        yaws.append(yaw)
        return pose_to_record(solver(scene, y, yaw, "load_centre"), LFIELDS)

    return grid, arrays, solve, count, yaws


def _reflected_set(mirror, g, js):
    """The jump set ``js`` reflected by ``g`` as whole arrays: (jump_y per column, limits of
    roll per column)."""
    cols = {}
    for j in range(js.knot_y.shape[0]):
        ys = js.arrays[J.jump_y][j]
        n = int(np.isfinite(ys).sum())
        jj = mirror.column(g, j)
        y2 = np.array([mirror.y(g, v) for v in ys[:n]])
        lims = js.limits[D.z_g][j, :n]
        if g.sides:
            y2, lims = y2[::-1], lims[::-1, ::-1]
        cols[jj] = (y2, lims)
    return cols


@pytest.mark.parametrize("nyaw", [3, 1])
def test_mirrored_jump_step_is_symmetric_at_a_fraction_of_the_solves(manchester, nyaw):
    """On a 13 x 3 grid of the Manchester pair (and a 1-D one at yaw 0, the EN 15302 case,
    whose one column is its own image) the mirrored jump step solves a third (a half) of
    the direct step's poses, and its jumps, limits and knots are symmetric under every
    reflection; the limits at a reflected jump's bracket ends are direct solves there (to
    rounding), so the bracket's ends and records are swapped right."""
    grid, arrays, solve, count, _ = _table(manchester, 13, nyaw)
    mirror = tm.Mirror.of(grid.y, grid.yaw, True)
    assert len(mirror.reflections) == (3 if nyaw == 3 else 1)
    direct = tj.locate_jumps(arrays, grid.y, grid.yaw, solve, LFIELDS)
    n_direct, count[0] = count[0], 0
    js = tj.locate_jumps(arrays, grid.y, grid.yaw, solve, LFIELDS, mirror=mirror)
    n_mirrored = count[0]
    print(f"\nsolves: direct {n_direct}, mirrored {n_mirrored}; jumps direct "
          f"{int(direct.count.sum())}, mirrored {int(js.count.sum())}")
    assert js.count.sum() >= 2 * nyaw   # the flange's jumps on both sides, at least
    # 3 columns: the outer two solve a quarter together, the middle one (its own image in yaw)
    # a half: a third in all
    assert n_mirrored <= (0.4 if nyaw == 3 else 0.55) * n_direct
    for g in mirror.reflections:
        for j, (ys, lims) in _reflected_set(mirror, g, js).items():
            n = ys.size
            assert _equal(js.arrays[J.jump_y][j, :n], ys), (g, j)
            np.testing.assert_allclose(js.limits[D.z_g][j, :n], lims, rtol=1e-12, atol=0)
        for j in range(js.knot_y.shape[0]):
            k = js.knot_y[j][np.isfinite(js.knot_y[j])]
            k2 = js.knot_y[mirror.column(g, j)]
            k2 = np.sort([mirror.y(g, v) for v in k2[np.isfinite(k2)]])
            assert _equal(k, k2), (g, j)
    checked = 0
    for j in range(js.knot_y.shape[0]):
        for n in range(int(js.count[j])):
            for side, key in ((0, J.jump_y_lo), (1, J.jump_y_hi)):
                want = solve(float(js.arrays[key][j, n]), float(grid.yaw[j]))
                for name in (D.z_g, D.roll, D.n_contacts, D.wheel_s):
                    np.testing.assert_allclose(js.limits[name][j, n, side].astype(float),
                                               want[name].astype(float), rtol=1e-9, atol=1e-12,
                                               err_msg=f"{j} {n} {key} {name}")
                checked += 1
    assert checked == 2 * js.count.sum()


def test_reflection_in_yaw_alone_is_the_direct_jump_step(manchester):
    """Without the reflection in y (a pair whose sides differ), the y-z plane's reflection
    alone gives the direct step's jumps and knots (the search and the refinement only read
    what that reflection keeps), solving only the columns of yaw <= 0: every cell and
    interval of a column of yaw > 0 is found to be an image."""
    grid, arrays, solve, count, yaws = _table(manchester, 13, 3)
    mirror = tm.Mirror.of(grid.y, grid.yaw, False)
    assert mirror.reflections == (LONG,)
    direct = tj.locate_jumps(arrays, grid.y, grid.yaw, solve, LFIELDS)
    n_direct, count[0] = count[0], 0
    half = sum(a <= 0.0 for a in yaws)
    js = tj.locate_jumps(arrays, grid.y, grid.yaw, solve, LFIELDS, mirror=mirror)
    print(f"\nsolves: direct {n_direct}, at yaw <= 0 {half}, mirrored {count[0]}")
    assert count[0] == half < n_direct
    for f in JUMP_FIELDS:
        assert _equal(js.arrays[f.name], direct.arrays[f.name]), f.name
    assert _equal(js.knot_y, direct.knot_y)
    for f in LFIELDS:
        # to rounding: a small second contact's force (4 kN) by up to 7e-10 of itself
        np.testing.assert_allclose(js.limits[f.name].astype(float),
                                   direct.limits[f.name].astype(float), rtol=1e-8, atol=1e-13,
                                   err_msg=f.name)
        np.testing.assert_allclose(js.knots[f.name].astype(float),
                                   direct.knots[f.name].astype(float), rtol=1e-8, atol=1e-13,
                                   err_msg=f.name)


def test_mirror_needs_a_symmetric_grid_and_the_own_solver(manchester, tmp_path):
    """Refused, with the reason for the log, on a grid symmetric about neither axis, with
    ``output.mirror = false`` and with a solver hook (a sweep's wrapper of lutmpi's own solver
    reflects); on a pair whose sides differ only the reflection in yaw applies."""
    from lutmpi.parallel.jumps_step import mirror_of

    cfg, scene, solver = manchester
    y = np.linspace(-9e-3, 9e-3, 7)
    yaw = np.linspace(-0.1, 0.1, 5)
    m, why = mirror_of(cfg, scene, solver, y, yaw)
    assert m.reflections == (LONG, SIDES_, BOTH) and "(y, yaw) -> (-y, -yaw)" in why
    assert m.y(SIDES_, float(y[1])) == float(y[-2]) and m.y(LONG, float(y[1])) == float(y[1])
    assert mirror_of(cfg, scene, solver, y + 1e-4, yaw)[0].reflections == (LONG,)
    assert mirror_of(cfg, scene, solver, y, yaw[:-1])[0].reflections == (BOTH,)
    assert mirror_of(cfg, scene, solver, y + 1e-4, yaw[:-1])[0] is None
    assert "not symmetric" in mirror_of(cfg, scene, solver, y + 1e-4, yaw[:-1])[1]
    off = dataclasses.replace(cfg, output=dataclasses.replace(cfg.output, mirror=False))
    assert mirror_of(off, scene, solver, y, yaw) == (None, "output.mirror = false")
    assert "solver hook" in mirror_of(cfg, scene, lambda *a: None, y, yaw)[1]
    from lutmpi.parallel.sweep_runner import Tolerant

    assert mirror_of(cfg, scene, Tolerant(solver), y, yaw)[0] is not None   # a sweep's
    assert mirror_of(cfg, scene, Tolerant(lambda *a: None), y, yaw)[0] is None
    from tests.support.tables import TWO_MEASURED_WHEELS

    path = tmp_path / "asym.toml"
    path.write_text(TWO_MEASURED_WHEELS + "\n[mesh]\nwheel_lateral_mm = 1.0\n"
                    "rail_lateral_mm = 1.0\n")
    acfg = load_config(path)
    ascene = Scene.from_config(acfg)
    assert not ascene.symmetric
    m, why = mirror_of(acfg, ascene, solver, y, yaw)
    assert m.reflections == (LONG,) and "profiles (or their placing) differ" in why


def test_grid_plan_solves_one_point_per_orbit():
    """Every point to do is solved or filled from a solved point of its orbit, once; on a
    resumed build whose orbit's smallest point is done, the rest of the orbit is solved."""
    ny, nyaw = 5, 3
    y, yaw = np.linspace(-2e-3, 2e-3, ny), np.linspace(-0.1, 0.1, nyaw)
    for pair, per in ((True, 4), (False, 2)):
        mirror = tm.Mirror.of(y, yaw, pair)
        todo = np.arange(ny * nyaw)
        solve, images = mirror.grid_plan(todo)
        filled = [q for p in solve for q, _ in images[int(p)]]
        assert sorted([*solve.tolist(), *filled]) == todo.tolist()
        # the corner orbits have 4 (2) points; the middle row and column fewer
        assert len(solve) == (6 if pair else 10) and max(len(v) for v in images.values()) \
            == per - 1
        for p in solve.tolist():
            i, j = divmod(p, nyaw)
            for q, g in images[p]:
                want = (ny - 1 - i if g.sides else i) * nyaw + (nyaw - 1 - j if g.flips_yaw
                                                                 else j)
                assert q == want
    mirror = tm.Mirror.of(y, yaw, True)
    todo = np.arange(1, ny * nyaw)              # point 0 done before (a resumed build)
    solve, images = mirror.grid_plan(todo)
    orbit0 = {2, 12, 14}                        # (0, 2), (4, 2), (4, 0): 0's images
    assert orbit0 <= set(solve.tolist()) and all(images[p] == [] for p in orbit0)


def _awkward(rng: np.random.Generator, shape: tuple[int, ...], dtype: np.dtype) -> np.ndarray:
    """Values a reflection must keep to the bit: floats with zeros and NaN of either sign
    among them, integers of either sign."""
    if dtype.kind != "f":
        return rng.integers(-3, 100, size=shape).astype(dtype)
    v = rng.normal(size=shape)
    pick = rng.random(shape)
    v[pick < 0.4] = 0.0
    v[pick < 0.3] = -0.0
    v[pick < 0.2] = np.nan
    v[pick < 0.1] = -np.nan
    return v.astype(dtype)


def test_a_journal_row_reflected_on_its_bytes_is_every_field_reflected():
    """The build's grid reflects a journal row at once on its bytes (``row_reflection``):
    the same bits as :meth:`Field.reflected` field by field (``fill_row``) for each reflection,
    NaN of either sign, signed zeros, integers; compute time 0 and the point index copied."""
    methods = ("load_centre", "reference")
    dtype = journal.record_dtype(methods, FIELDS)
    rows = journal.empty_rows(dtype, methods, FIELDS, 4)
    rng = np.random.default_rng(7)
    for name in dtype.names:
        rows[name][...] = _awkward(rng, rows[name].shape, rows[name].dtype)
    rows["point"] = [11, -1, -1, -1]
    for g in (SIDES_, LONG, BOTH):
        want = rows.copy()
        g.fill_row({m: {f.name: want[f"{m}/{f.name}"] for f in FIELDS} for m in methods}, 0, 2)
        got = rows.copy()
        row_reflection(dtype, g.sides, g.longitudinal).apply(got, 0, 2)
        for name in dtype.names:
            if name == "point":
                assert got[name][2] == 11
            else:
                assert got[name][2].tobytes() == want[name][2].tobytes(), (g, name)
        assert got[1].tobytes() == rows[1].tobytes() and got["load_centre/compute_time"][2] == 0


def test_records_from_other_ranks_reflect_in_columns_to_the_same_bits():
    """Records that arrive from other ranks (``jumps_step._unpack``: rows of stacked columns)
    reflect by their columns, once for all rows: the same bits and dtypes as
    :meth:`Field.reflected` record by record, for each reflection, NaN of either sign and
    signed zeros; and as plain dicts to every reader."""
    from lutmpi.parallel.jumps_step import _pack, _unpack

    rng = np.random.default_rng(11)
    recs = []
    for _ in range(9):
        recs.append({f.name: _awkward(rng, f.suffix, np.dtype(f.dtype)) for f in LFIELDS})
    got = _unpack(*_pack(recs))
    for g in (SIDES_, LONG, BOTH):
        for plain, col in zip(recs, got, strict=True):
            assert isinstance(col, tm.ColumnRecord) and dict(col).keys() == plain.keys()
            want, have = g.record(plain), g.record(col)
            assert not isinstance(want, tm.ColumnRecord)
            for name in plain:
                a, b = np.asarray(want[name]), np.asarray(have[name])
                assert a.dtype == b.dtype and a.tobytes() == b.tobytes(), (g, name)
            with pytest.raises(TypeError, match="read-only"):
                have[D.z_g] = 0.0        # rows of shared columns: never changed in place
            back = g.record(have)        # a reflection is an involution, in columns too
            assert all(np.asarray(back[n]).tobytes() == np.asarray(plain[n]).tobytes()
                       for n in plain)


def test_a_mirrored_grid_is_the_direct_grid(tmp_path, monkeypatch):
    """A build's grid on a symmetric pair solves a quarter of its points (corner orbits of
    four; the middle row and column pair up) and fills the rest by reflection: every dataset
    is the direct build's, the discrete ones to the bit, the others to rounding."""
    from lutmpi.parallel.runner import build_table
    from lutmpi.table import compute as tc
    from tests.support.tables import datasets, write_config

    cfg = write_config(tmp_path, ny=7, nyaw=5, methods=("load_centre", "reference"))
    base = load_config(cfg)
    off = dataclasses.replace(base, output=dataclasses.replace(base.output, jumps=False,
                                                               mirror=False))
    on = dataclasses.replace(off, output=dataclasses.replace(off.output, mirror=True))
    solves: list[tuple[float, float]] = []
    real = tc.solve_pose

    def counted(scene, y, yaw, *a, **k):
        solves.append((y, yaw))
        return real(scene, y, yaw, *a, **k)

    monkeypatch.setattr(tc, "solve_pose", counted)
    tables, counts = {}, []
    for name, c in (("direct", off), ("mirrored", on)):
        solves.clear()
        build_table(c, tmp_path / f"{name}.h5", solver=tc.PoseSolver())
        counts.append(len(solves))
        tables[name] = datasets(tmp_path / f"{name}.h5")
    # 35 points x 2 methods (+ one warm-up solve each): 12 of 35 points solved
    assert counts == [2 * 35 + 2, 2 * 12 + 2], counts
    a, b = tables["direct"], tables["mirrored"]
    assert sorted(a) == sorted(b)
    for name in a:
        if name.endswith("compute_time"):
            continue
        if a[name].dtype.kind != "f":
            assert _equal(a[name], b[name]), name
        else:
            np.testing.assert_allclose(b[name], a[name], rtol=1e-9, atol=1e-12, err_msg=name)


def test_a_reflected_build_failed_and_resumed_is_the_uninterrupted_one(tmp_path):
    """A reflected grid journals each solved point with its images in one batch: a build that
    fails after five solves and is resumed gives the uninterrupted build's table, bit for
    bit, reusing those points and their images."""
    from lutmpi.parallel.runner import build_table
    from lutmpi.table.compute import PoseSolver
    from tests.support.tables import differences, write_config

    base = load_config(write_config(tmp_path, ny=7, nyaw=5, methods=("reference",)))
    cfg = dataclasses.replace(base, output=dataclasses.replace(base.output, jumps=False))

    class FailsAfter(PoseSolver):
        """lutmpi's own solver (so the build reflects) that raises after ``n`` solves."""

        def __init__(self, n: int) -> None:
            super().__init__()
            self.n = n

        def __call__(self, scene, y, yaw, method):
            self.n -= 1
            if self.n < 0:
                raise RuntimeError("injected failure")
            return super().__call__(scene, y, yaw, method)

    whole = build_table(cfg, tmp_path / "whole.h5", solver=PoseSolver())
    assert whole.computed == 35
    out = tmp_path / "t.h5"
    with pytest.raises(RuntimeError, match="injected failure"):
        build_table(cfg, out, solver=FailsAfter(5))
    assert not out.exists()
    resumed = build_table(cfg, out, solver=PoseSolver(), resume=True)
    assert resumed.reused >= 5 + 3     # five solved points, and images of the corner ones
    assert resumed.reused + resumed.computed == 35
    assert differences(tmp_path / "whole.h5", out) == []
