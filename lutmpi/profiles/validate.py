"""From a reader's :class:`RawProfile` to a valid :class:`Profile`: every check, one place.

Order of the checks (each error names the file and, where there is one, the 1-based line):

1. **no points** (fewer than 4), NaN or inf;
2. **absurd units** -- lateral extent and height range against plausible ranges
   (:data:`EXTENT_MM`): a wheel 460 m wide or a rail 0.05 mm wide is a unit error, citing the
   line that declares the unit, or where none does the first data line (quoted), with the unit
   the values evidently are in (:data:`UNIT_GUESSES`); before the repeated points, which a file
   written in metres with few decimals has where its points are closer than its last digit;
3. **repeated points** -- two consecutive identical points anywhere;
4. **kind** -- the requested kind against the declared one (header, extension) and against the
   shape (:func:`shape_kind`): a wheel has a narrow flange tip 15-45 mm above its tread at
   ``s ≈ -55 mm``, a rail head has a broad crown with both sides falling away;
5. **function of y** -- :func:`trim_to_function` (documented there): overhangs outside the contact
   region are trimmed (recorded in ``meta['trimmed']``), backtracking or repeated ``y`` inside it
   is an error;
6. the spline: measured data gets a small smoothing (:func:`auto_smoothing`), exact data none;
   an interpolating spline that bulges out of monotone points (a step in them) is warned
   about (:func:`spline_bulge`), naming the lines.
"""

from __future__ import annotations

import logging
import math
from typing import Any

import numpy as np

from lutmpi.errors import ProfileError
from lutmpi.profiles._raw import RawProfile
from lutmpi.profiles.model import Profile

log = logging.getLogger(__name__)

#: Plausible (lateral width, height range) limits in mm, per kind: (w_min, w_max, h_min, h_max).
EXTENT_MM = {"wheel": (40.0, 250.0, 5.0, 150.0), "rail": (15.0, 200.0, 1.0, 250.0),
             "profile": (15.0, 250.0, 1.0, 250.0)}

#: Contact core of a wheel: from the flange tip to this ``s`` (mm) on the field side.
WHEEL_CORE_S_MAX_MM = 50.0
#: The flange tip region -- within this height (mm) below the tip -- is tolerant: a measured tip
#: zig-zags (``Car7216_0001r.whl`` backtracks 0.6 mm there) and only flange climbing touches it.
WHEEL_TIP_ZONE_MM = 1.0
#: Wheel flange back kept down to this far below the flange tip (mm); the rest is trimmed.
WHEEL_BACK_KEEP_MM = 10.0
#: Contact core of a rail: the head down to this depth below its top (mm), both sides.
RAIL_CORE_DEPTH_MM = 5.0
#: Steps in ``y`` smaller than this (mm) count as repeated ``y``.
Y_EPS_MM = 2e-3
#: Shortest wavelength (mm) a measured profile keeps; shorter ripples are treated as noise.
SMOOTHING_WAVELENGTH_MM = 2.0


def _fail(raw_path: str, msg: str, line: int | None = None) -> ProfileError:
    return ProfileError(msg, path=raw_path, line=line)


# -- 1-3 -----------------------------------------------------------------------------------------
def check_points(raw: RawProfile, path: str) -> None:
    """Enough points, all finite (the parsers catch these per line already)."""
    n = raw.y_mm.size
    if n < 4:
        raise _fail(path, f"no profile points found (got {n}, need at least 4)")
    bad = ~(np.isfinite(raw.y_mm) & np.isfinite(raw.z_mm))
    if bad.any():
        k = int(np.argmax(bad))
        raise _fail(path, "NaN or inf in the points", int(raw.lines[k]))


def check_repeats(raw: RawProfile, path: str) -> None:
    """No two consecutive identical points (the second one's line is cited)."""
    same = (np.diff(raw.y_mm) == 0) & (np.diff(raw.z_mm) == 0)
    if same.any():
        k = int(np.argmax(same)) + 1
        first, second = sorted((int(raw.lines[k - 1]), int(raw.lines[k])))
        raise _fail(path, f"repeated point ({raw.y_mm[k]:g}, {raw.z_mm[k]:g}) mm, same as the "
                          f"point on line {first}", second)


#: (factor, unit): values read as mm that fit :data:`EXTENT_MM` once multiplied by the factor
#: were in that unit; named only when exactly one factor fits (10 and 25.4 can both fit)
UNIT_GUESSES = ((1e3, "metres"), (10.0, "centimetres"), (25.4, "inches"), (1e-3, "micrometres"))


def _fits(width: float, height: float, kind: str) -> bool:
    w_lo, w_hi, h_lo, h_hi = EXTENT_MM[kind]
    return w_lo <= width <= w_hi and h_lo <= height <= h_hi


def unit_guess(width: float, height: float, kind: str) -> str | None:
    """The unit of :data:`UNIT_GUESSES` that values read as mm (``width``, ``height``, mm) were
    evidently written in, or None when none or several fit."""
    fit = [unit for f, unit in UNIT_GUESSES if _fits(width * f, height * f, kind)]
    return fit[0] if len(fit) == 1 else None


def check_extent(raw: RawProfile, path: str, kind: str) -> None:
    """Lateral width and height range within :data:`EXTENT_MM`, else a unit error.

    The error cites the line declaring the unit when the file has one (``units.len.f``,
    ``# units:``), else the first data line; it quotes the first data line either way."""
    width = float(raw.y_mm.max() - raw.y_mm.min())
    height = float(raw.z_mm.max() - raw.z_mm.min())
    if _fits(width, height, kind):
        return
    w_lo, w_hi, h_lo, h_hi = EXTENT_MM[kind]
    first = int(raw.lines[0])
    got = (f"implausible {kind} extent: {width:.4g} mm wide, {height:.4g} mm high after reading "
           f"the values as {raw.meta.get('units', 'mm')}")
    expected = (f"expected width {w_lo:g}-{w_hi:g} mm, height {h_lo:g}-{h_hi:g} mm; first data "
                f"line {first}: {raw.quote(first)!r}")
    if raw.unit_line is not None:
        raise _fail(path, f"{got} as declared on line {raw.unit_line} ({expected}); wrong length "
                          "unit?", raw.unit_line)
    guess = unit_guess(width, height, kind)
    hint = f"are the coordinates in {guess}?" if guess else "wrong length unit?"
    raise _fail(path, f"{got}, the file declaring no unit ({expected}): {hint}", first)


# -- 4 -------------------------------------------------------------------------------------------
def _crown_width(y: np.ndarray, z: np.ndarray, k: int, drop: float) -> float:
    """Width (mm) of the connected stretch around index ``k`` with ``z >= z[k] - drop``."""
    lo = k
    while lo > 0 and z[lo - 1] >= z[k] - drop:
        lo -= 1
    hi = k
    while hi < z.size - 1 and z[hi + 1] >= z[k] - drop:
        hi += 1
    return float(abs(y[hi] - y[lo]))


def looks_like_rail(y: np.ndarray, z: np.ndarray) -> bool:
    """A rail head in normalized orientation: a broad crown (within 1 mm of the top over >= 16 mm)
    with both ends of the profile at least 5 mm below the top."""
    k = int(np.argmax(z))
    return (z[0] < z[k] - 5.0 and z[-1] < z[k] - 5.0 and _crown_width(y, z, k, 1.0) >= 16.0)


def looks_like_wheel(y: np.ndarray, z: np.ndarray) -> bool:
    """A wheel in normalized orientation: the highest point (flange tip) at ``s`` in [-80, -30] mm,
    15-45 mm above the tread at the tape circle ``s = 0``."""
    k = int(np.argmax(z))
    if not (-80.0 <= y[k] <= -30.0) or not (y.min() <= 0.0 <= y.max()):
        return False
    side = np.flatnonzero(y > y[k])                     # the tread side of the tip
    order = side[np.argsort(y[side])]
    if order.size < 2 or not (y[order[0]] <= 0.0 <= y[order[-1]]):
        return False
    height = z[k] - float(np.interp(0.0, y[order], z[order]))
    return 15.0 <= height <= 45.0


def shape_kind(y: np.ndarray, z: np.ndarray) -> str | None:
    """``"wheel"``, ``"rail"`` or None (neither, or both) from the normalized shape."""
    w, r = looks_like_wheel(y, z), looks_like_rail(y, z)
    if w != r:
        return "wheel" if w else "rail"
    return None


def resolve_kind(raw: RawProfile, path: str, requested: str | None) -> str:
    """The kind to build: requested, else declared, else from the shape; all three must agree."""
    if requested is not None and requested not in ("wheel", "rail"):
        raise _fail(path, f"kind must be 'wheel' or 'rail', got {requested!r}")
    if requested and raw.kind and requested != raw.kind:
        raise _fail(path, f"a {raw.kind} profile ({raw.kind_source}) given where a {requested} "
                          "is expected")
    kind = requested or raw.kind
    shape = shape_kind(raw.y_mm, raw.z_mm)
    if kind is None:
        if shape is None:
            raise _fail(path, "cannot tell whether this is a wheel or a rail profile from its "
                              "shape; say which (kind='wheel' or 'rail', --kind)")
        return shape
    ok = looks_like_wheel if kind == "wheel" else looks_like_rail
    if not ok(raw.y_mm, raw.z_mm):
        other = "rail" if kind == "wheel" else "wheel"
        if shape == other:
            raise _fail(path, f"a {other} profile given where a {kind} is expected (the shape is "
                              f"a {other}'s{'; ' + raw.kind_source if raw.kind_source else ''})")
        what = ("a flange tip 15-45 mm above the tread at s = -80..-30 mm" if kind == "wheel"
                else "a broad crown with both sides falling away by > 5 mm")
        raise _fail(path, f"does not look like a {kind} profile in lutmpi's orientation "
                          f"(expected {what}); wrong format, orientation or kind?")
    return kind


# -- 5 -------------------------------------------------------------------------------------------
def _walk(y: np.ndarray, start: int, step: int, direction: float,
          stop: np.ndarray | None = None) -> tuple[list[int], list[int]]:
    """From ``start`` along the path by ``step`` (+1/-1), keep each point strictly beyond the last
    kept one in ``direction`` (+1: increasing y); return (kept, shadowed) indices. ``stop[i]``
    ends the walk (point excluded) -- used to cut the wheel's flange back."""
    kept, shadowed = [], []
    last = y[start]
    i = start + step
    while 0 <= i < y.size:
        if stop is not None and stop[i]:
            break
        ahead = direction * (y[i] - last)
        if ahead > Y_EPS_MM:
            kept.append(i)
            last = y[i]
        elif ahead > 0 and direction * (y[i] - y[i - step]) > 0:
            pass        # still moving on, closer than Y_EPS_MM: dense data thinned, not shadowed
        else:
            shadowed.append(i)
        i += step
    return kept, shadowed


def trim_to_function(raw: RawProfile, path: str, kind: str) -> tuple[np.ndarray, dict[str, Any]]:
    """Indices of the points forming ``z(y)``, and a record of what was trimmed.

    The rule (documented for users in ``profiles/README.md``):

    * The path is walked outward from its **apex** -- the flange tip of a wheel (highest point at
      ``s < -20 mm``), the top of a rail -- to both ends. A point is kept when it lies strictly
      beyond every point kept so far (by more than :data:`Y_EPS_MM`); otherwise it is *shadowed*:
      behind an overhang or on a vertical face, it cannot be touched from above by the other body.
    * A shadowed point inside the **contact core** is an error (backtracking or repeated ``y``
      where contact happens): wheels from just past the flange tip region (1 mm below the tip,
      :data:`WHEEL_TIP_ZONE_MM`) to ``s = +50 mm`` (:data:`WHEEL_CORE_S_MAX_MM`), rails within
      5 mm below the top (:data:`RAIL_CORE_DEPTH_MM`),
      both gauge and field side.
    * Outside the core shadowed points are dropped: overhanging gauge faces of worn rails, a
      field-side lip, the vertical flange back and the field-side chamfer of measured wheels.
    * Wheels: the flange back is kept only down to 10 mm below the flange tip
      (:data:`WHEEL_BACK_KEEP_MM`); the part below cannot meet a rail.
    """
    y, z, lines = raw.y_mm, raw.z_mm, raw.lines
    if kind == "wheel":
        cand = np.flatnonzero(y < -20.0)
        apex = int(cand[np.argmax(z[cand])]) if cand.size else int(np.argmax(z))
    else:
        apex = int(np.argmax(z))
    # Orient the walk: the tread / field side is where the path reaches the larger y.
    fwd = 1 if y[-1] > y[0] else -1
    back_stop = (z < z[apex] - WHEEL_BACK_KEEP_MM) if kind == "wheel" else None
    right, shad_r = _walk(y, apex, fwd, +1.0)
    left, shad_l = _walk(y, apex, -fwd, -1.0, stop=back_stop)
    if kind == "wheel":
        core_bad = [i for i in shad_r
                    if y[i] <= WHEEL_CORE_S_MAX_MM and z[i] < z[apex] - WHEEL_TIP_ZONE_MM]
    else:
        core_bad = [i for i in shad_r + shad_l if z[i] >= z[apex] - RAIL_CORE_DEPTH_MM]
    if core_bad:
        i = min(core_bad, key=lambda j: lines[j])
        where = ("between the flange tip region and s = +50 mm" if kind == "wheel"
                 else "within 5 mm below the rail top")
        # the point walked before it that reaches furthest: an outlier there shows up here
        step, sign = (fwd, 1.0) if i in shad_r else (-fwd, -1.0)
        k = max(range(apex, i, step), key=lambda j: sign * y[j], default=apex)
        raise _fail(path, f"points backtrack or repeat y in the contact region {where}: point "
                          f"({y[i]:g}, {z[i]:g}) mm is not beyond the previous ones "
                          f"(reordered, duplicated or overhanging data; the point of line "
                          f"{int(lines[k])}, ({y[k]:g}, {z[k]:g}) mm, reaches further: one of "
                          "the two is out of place)", int(lines[i]))
    idx = np.array(sorted(left, key=lambda j: y[j]) + [apex] + sorted(right, key=lambda j: y[j]))
    n_dropped = y.size - idx.size
    info = {"points_in_file": int(y.size), "points_dropped": int(n_dropped),
            "y_range_mm": [float(y[idx[0]]), float(y[idx[-1]])]}
    if n_dropped:
        info["rule"] = ("shadowed (overhanging or vertical) points outside the contact core "
                        "dropped" + ("; flange back kept down to 10 mm below the tip"
                                     if kind == "wheel" else ""))
    return idx, info


# -- 6 -------------------------------------------------------------------------------------------
def auto_smoothing(y_m: np.ndarray) -> float:
    """Smoothing ``lam`` (m^3) of :func:`scipy.interpolate.make_smoothing_spline` for measured data.

    The smoothing spline minimises ``sum (z_i - f(y_i))^2 + lam * int f''^2 dy``. For spacing ``h``
    the sum is about ``(1/h) int (z - f)^2``, so the spline acts as a low-pass filter with
    response ``1 / (1 + h lam w^4)``: choosing ``lam = 1 / (h w_c^4)`` with
    ``w_c = 2 pi / L`` keeps wavelengths longer than ``L`` = :data:`SMOOTHING_WAVELENGTH_MM`
    (2 mm -- the S1002 flange arcs R12/R13 span > 5 mm) and damps the 0.01 mm measurement ripple
    at the 0.2-0.5 mm point spacing of MiniProf data, which would otherwise give curvatures of
    hundreds of 1/m on a tread whose true curvature is below ~20 1/m (``avg_wheel.whl``: 422 1/m
    unsmoothed, 28 1/m smoothed over s = -15..15 mm). Cost: a smoothing spline in ``z(y)`` also
    smooths steep flanks, where the vertical residual is large; the normal deviation from the points
    stays below 0.06 mm in the contact core of the measured files (0.12-0.34 mm at the flange tip
    and the deep flanks).
    """
    h = float(np.median(np.diff(y_m)))
    w_c = 2.0 * math.pi / (SMOOTHING_WAVELENGTH_MM * 1e-3)
    return 1.0 / (h * w_c ** 4)


#: an isolated point further than this (mm) off the chord of its neighbours, with both sides
#: steeper than 45 deg in opposite directions, is a spike (a typo, a glitch of the gauge), not
#: shape. No point of the repository's ten measured and benchmark files has both sides that
#: steep in opposite directions at all (a flange tip or a rail crown turns over many points);
#: a 0.5 mm glitch on a measured tread (0.25 mm spacing) became a 0.21 mm bump 3.8 mm wide
#: after smoothing and moved a contact onto it (s 5.2 -> 9.9 mm, roll 5.04 -> 4.78 mrad) under
#: the 1 mm this was. Noise of dense data (0.01 mm spacing) stays below it.
SPIKE_MM = 0.1


def check_spikes(y: np.ndarray, z: np.ndarray, lines: np.ndarray, path: str) -> None:
    """Refuse a single-point spike (issue 13): it would become a contact bump in every table.

    ``y``, ``z`` in mm, sorted by ``y`` (the trimmed profile); the line of the first spike is named.
    """
    if y.size < 3:
        return
    up, down = z[1:-1] - z[:-2], z[2:] - z[1:-1]
    h_left, h_right = y[1:-1] - y[:-2], y[2:] - y[1:-1]
    chord = z[:-2] + (z[2:] - z[:-2]) * h_left / (y[2:] - y[:-2])
    dev = z[1:-1] - chord
    bad = np.flatnonzero((np.abs(dev) > SPIKE_MM) & (np.sign(up) == -np.sign(down))
                         & (np.abs(up) > h_left) & (np.abs(down) > h_right))
    if bad.size:
        i = int(bad[0]) + 1
        raise _fail(path, f"point ({y[i]:g}, {z[i]:g}) mm is a single-point spike, "
                          f"{abs(dev[i - 1]):.3g} mm off the line through its neighbours: a typo "
                          "or a measurement glitch? Fix or remove it", int(lines[i]))


def build_profile(raw: RawProfile, path: str, kind: str | None, name: str,
                  smoothing: float | None = None, cant_rad: float | None = None) -> Profile:
    """Run checks 1-6 and return the :class:`Profile` (SI units)."""
    check_points(raw, path)
    check_extent(raw, path, kind or raw.kind or "profile")   # a unit error before the shape
    check_repeats(raw, path)
    k = resolve_kind(raw, path, kind)
    check_extent(raw, path, k)
    idx, info = trim_to_function(raw, path, k)
    check_spikes(raw.y_mm[idx], raw.z_mm[idx], raw.lines[idx], path)
    y = raw.y_mm[idx] * 1e-3
    z = raw.z_mm[idx] * 1e-3
    if y.size < 4:
        raise _fail(path, f"only {y.size} points left after trimming to a function of y")
    if smoothing is None:
        smoothing = raw.smoothing
    if smoothing is None:
        smoothing = auto_smoothing(y)
    meta = dict(raw.meta)
    meta["trimmed"] = info
    meta["kind_source"] = raw.kind_source or "shape"
    cant = cant_rad if cant_rad is not None else raw.cant_rad
    if k == "wheel" and cant:
        raise _fail(path, "a cant angle only applies to rails")
    try:
        prof = Profile(kind=k, y=y, z=z, name=name, source=path, cant_rad=float(cant or 0.0),
                       smoothing=float(smoothing), meta=meta)
    except ProfileError:
        raise
    except (ValueError, np.linalg.LinAlgError) as exc:   # spline construction on degenerate data
        raise _fail(path, f"cannot build the profile spline: {exc}") from None
    bulge, i = spline_bulge(prof)
    if bulge > BULGE_MM * 1e-3:
        prof.meta["spline_bulge"] = {"mm": round(bulge * 1e3, 4),
                                     "lines": [int(raw.lines[idx[i]]), int(raw.lines[idx[i + 1]])]}
        a, b = prof.meta["spline_bulge"]["lines"]
        log.warning("%s: the interpolating spline bulges %.3f mm out of the points between "
                    "lines %d and %d, where the points are monotone: a step in the data? "
                    "Contacts can sit on the bulge; check the points there", path, bulge * 1e3,
                    min(a, b), max(a, b))
    return prof


#: an interpolating spline further than this (mm) out of the range of two points in a stretch
#: of monotone points is warned about (:func:`spline_bulge`): a cubic through exact data with a
#: step (0.3 mm within one 0.5 mm point spacing) rang 8-32 um beside it; the exact files in
#: ``profiles/`` and EN 15302's raw rail do not leave that range at all
BULGE_MM = 0.01
#: points per interval at which :func:`spline_bulge` evaluates the spline
BULGE_SAMPLES = 16


def spline_bulge(prof: Profile) -> tuple[float, int]:
    """Largest excursion (m) of an interpolating spline (``smoothing == 0``) between two points
    ``i, i + 1`` out of their range, over the intervals whose four points ``i - 1 .. i + 2``
    are monotone (a curve through them should not turn there), and that interval's index
    ``i``; ``(0.0, -1)`` for a smoothing spline (it does not pass through the points) or none.
    Beside a step the cubic rings; where the points turn (a crown, a flange tip) it overshoots
    them by about ``h^2 kappa / 8`` even through smooth data (25 um at a 5 mm flange tip
    sampled every 1 mm), so those intervals are not tested."""
    if prof.smoothing != 0.0 or prof.y.size < 4:
        return 0.0, -1
    y, z = prof.y, prof.z
    d = np.diff(z)
    mono = ((d[:-2] >= 0) & (d[1:-1] >= 0) & (d[2:] >= 0)) | (
        (d[:-2] <= 0) & (d[1:-1] <= 0) & (d[2:] <= 0))
    idx = np.flatnonzero(mono) + 1                     # interval [i, i + 1]
    if idx.size == 0:
        return 0.0, -1
    t = np.linspace(0.0, 1.0, BULGE_SAMPLES + 1)[1:-1]
    ys = y[idx, None] + t[None, :] * (y[idx + 1] - y[idx])[:, None]
    zs = prof.z_at(ys.ravel()).reshape(ys.shape)
    lo, hi = np.minimum(z[idx], z[idx + 1]), np.maximum(z[idx], z[idx + 1])
    out = np.maximum(zs.max(axis=1) - hi, lo - zs.min(axis=1))
    k = int(np.argmax(out))
    return (float(out[k]), int(idx[k])) if out[k] > 0 else (0.0, -1)
