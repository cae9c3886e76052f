"""Simpack rail-wheel profile files, ``.prw`` (wheel) and ``.prr`` (rail).

Layout: ``key = value ! comment`` lines inside ``header.begin/end`` and ``spline.begin/end``
blocks; the points, one ``y z [weight]`` per line, between ``point.begin`` and ``point.end``;
``!`` starts a comment (a commented-out point is skipped).

Honoured header keys, applied in Simpack's numbered order:

1. ``point.dist.min`` -- a point closer than this to the previous kept point is dropped;
2. ``shift.y``, ``shift.z`` -- added to the data;
3. ``rotate`` -- only 0 is supported (a non-zero value raises: its sign convention is not
   documented in the files);
4. ``bound.y.min/max``, ``bound.z.min/max`` -- active when min < max: points outside are dropped;
5. ``mirror.y``, ``mirror.z`` -- 1 negates that coordinate;
6. ``inversion`` -- 1 reverses the point order;
7. ``units.len.f`` -- length unit factor ``l[user] / l[m]`` (1000 for mm).

``header.begin: type`` says the kind: 0 rail, 1 wheel.

Orientation: after steps 1-6 Simpack's profile frame has ``y`` positive toward the field side (the
wheel flange and the rail gauge face at negative ``y``) and ``z`` **downward**. So a wheel's ``z``
is its radius increment (``s = y``, ``dr = z``) and a rail's height is ``-z`` (``v = y``).
Checked on the Manchester files: ``MBench_S1002_v3.prw`` has its flange at +y in the raw points and
``mirror.y = 1``; ``MBench_UIC60_v3.prr`` has its highest point 6.9 mm field-side (+y) of the head
centre, as a head canted toward the track centre must.

Cant: a rail file whose ``comment`` says it is canted (``"1:40"`` or ``"canted"``) gets
``cant_rad`` from the ratio when it gives one; otherwise it is estimated from the 1:20 flanks
(:func:`estimate_cant_from_flanks`) and snapped to 1:20, 1:30 or 1:40. ``read_profile(...,
cant_rad=...)`` overrides both; use ``[rail] inclination = "none"`` for such a file.
"""

from __future__ import annotations

import math
import re

import numpy as np

from lutmpi.errors import ProfileError
from lutmpi.profiles._raw import RawProfile, looks_numeric, parse_point, points_array

EXTENSIONS = (".prw", ".prr")
_KV = re.compile(r"^\s*([A-Za-z][\w.]*)\s*=\s*(.*)$")
_STANDARD_CANTS = {"1:20": math.atan(1 / 20), "1:30": math.atan(1 / 30), "1:40": math.atan(1 / 40)}


def sniff(text: str) -> bool:
    """Simpack markers in the first few kB."""
    head = text[:4000]
    return "point.begin" in head or "header.begin" in head or "SIMPACK" in head.upper()


def _value(rest: str) -> str:
    """Value of ``key = value ! comment`` (quoted strings may contain ``!``)."""
    rest = rest.strip()
    if rest.startswith("'"):
        end = rest.find("'", 1)
        return rest[1:end] if end > 0 else rest[1:]
    return rest.split("!", 1)[0].strip()


def _scan(lines: list[str], path: str) -> tuple[dict, dict, list[tuple[float, float, int]]]:
    """Header and spline keys ``{key: (value, line)}`` and the raw points ``[(y, z, line)]``."""
    blocks: list[str] = []
    header: dict[str, tuple[str, int]] = {}
    spline: dict[str, tuple[str, int]] = {}
    pts: list[tuple[float, float, int]] = []
    closed = False
    for ln, text in enumerate(lines, start=1):
        t = text.strip()
        if not t or t.startswith("!"):
            continue
        word = t.split()[0]
        if word.endswith(".begin"):
            blocks.append(word[:-6])
            continue
        if word.endswith(".end"):
            if not blocks or blocks[-1] != word[:-4]:
                raise ProfileError(f"unexpected {word!r} (open blocks: {blocks})", path=path,
                                   line=ln)
            closed = closed or word == "point.end"
            blocks.pop()
            continue
        if blocks and blocks[-1] == "point":
            pts.append((*parse_point(t.split("!", 1)[0], path, ln), ln))
            continue
        m = _KV.match(t)
        if m is None:
            if looks_numeric(t):
                raise ProfileError("point line outside point.begin ... point.end", path=path,
                                   line=ln)
            raise ProfileError(f"cannot parse Simpack line {t!r}", path=path, line=ln)
        target = header if blocks and blocks[-1] == "header" else spline
        target[m.group(1)] = (_value(m.group(2)), ln)
    if blocks or (pts and not closed):
        raise ProfileError(f"unterminated block(s) {blocks or ['point']} (truncated file?)",
                           path=path, line=len(lines))
    return header, spline, pts


def _num(keys: dict, key: str, default: float, path: str) -> tuple[float, int | None]:
    if key not in keys:
        return default, None
    text, ln = keys[key]
    try:
        val = float(text)
    except ValueError:
        raise ProfileError(f"{key} = {text!r} is not a number", path=path, line=ln) from None
    if not math.isfinite(val):
        raise ProfileError(f"{key} = {text!r} is not finite", path=path, line=ln)
    return val, ln


def _flag(keys: dict, key: str, path: str) -> bool:
    val, ln = _num(keys, key, 0.0, path)
    if val not in (0.0, 1.0):
        raise ProfileError(f"{key} must be 0 or 1, got {val:g}", path=path, line=ln)
    return val == 1.0


def _declared_kind(header: dict, path: str) -> tuple[str | None, str]:
    if "type" not in header:
        return None, ""
    val, ln = _num(header, "type", -1.0, path)
    if val not in (0.0, 1.0):
        raise ProfileError(f"header type must be 0 (rail) or 1 (wheel), got {val:g}", path=path,
                           line=ln)
    return ("wheel" if val == 1.0 else "rail"), f"Simpack header type = {int(val)} (line {ln})"


def _process(spline: dict, pts: list, path: str) -> tuple[np.ndarray, ...]:
    """Steps 1-6 of the module docstring on the raw points (user units)."""
    y, z, lines = points_array(pts)
    dmin, _ = _num(spline, "point.dist.min", 0.0, path)
    if dmin > 0 and y.size:
        keep = [0]
        for i in range(1, y.size):
            if math.hypot(y[i] - y[keep[-1]], z[i] - z[keep[-1]]) >= dmin:
                keep.append(i)
        y, z, lines = y[keep], z[keep], lines[keep]
    y = y + _num(spline, "shift.y", 0.0, path)[0]
    z = z + _num(spline, "shift.z", 0.0, path)[0]
    rot, ln = _num(spline, "rotate", 0.0, path)
    if rot != 0.0:
        raise ProfileError(f"rotate = {rot:g} is not supported (convert the file without "
                           "rotation)", path=path, line=ln)
    for c, arr in (("y", y), ("z", z)):
        lo, _ = _num(spline, f"bound.{c}.min", 1.0, path)
        hi, _ = _num(spline, f"bound.{c}.max", 0.0, path)
        if lo < hi:
            keep = (arr >= lo) & (arr <= hi)
            y, z, lines = y[keep], z[keep], lines[keep]
    if _flag(spline, "mirror.y", path):
        y = -y
    if _flag(spline, "mirror.z", path):
        z = -z
    if _flag(spline, "inversion", path):
        y, z, lines = y[::-1], z[::-1], lines[::-1]
    return y, z, lines


def estimate_cant_from_flanks(v_mm: np.ndarray, h_mm: np.ndarray) -> float | None:
    """Cant (rad) of a rail head from its two flanks 18-35 mm below the top, or None.

    The flanks of a new head are lines symmetric about the head axis, so the mean of their
    lateral slopes ``dv/d(depth)`` is ``tan`` of the axis tilt (positive: crown facing -v).
    """
    top = float(h_mm.max())
    k = int(np.argmax(h_mm))
    slopes = []
    for side in (slice(0, k + 1), slice(k, None)):
        v, d = v_mm[side], top - h_mm[side]
        m = (d >= 18.0) & (d <= 35.0)
        if m.sum() < 5 or np.ptp(d[m]) < 8.0:
            return None
        slopes.append(np.polyfit(d[m], v[m], 1)[0])
    return math.atan(0.5 * (slopes[0] + slopes[1]))


def _cant(comment: str, v: np.ndarray, h: np.ndarray, path: str) -> tuple[float | None, str]:
    low = comment.lower()
    if "cant" not in low or re.search(r"\b(not|un)[ -]?cant", low):
        return None, ""
    m = re.search(r"1\s*:\s*(\d+(?:\.\d+)?)", comment)
    if m:
        return math.atan(1.0 / float(m.group(1))), f"file comment ({m.group(0)})"
    est = estimate_cant_from_flanks(v, h)
    if est is not None:
        name, val = min(_STANDARD_CANTS.items(), key=lambda kv: abs(kv[1] - est))
        if abs(val - est) < 0.004:
            return val, f"file comment says canted; flank symmetry gives {est:.4f} rad ≈ {name}"
    raise ProfileError("the file says the rail is canted but not by how much, and the flanks do "
                       "not show it; pass cant_rad (e.g. atan(1/40))", path=path)


def parse(lines: list[str], path: str) -> RawProfile:
    """Read a Simpack ``.prw`` / ``.prr`` into a :class:`RawProfile` (mm, normalized)."""
    header, spline, pts = _scan(lines, path)
    kind, kind_source = _declared_kind(header, path)
    factor, unit_line = _num(spline, "units.len.f", 1000.0, path)
    if factor <= 0:
        raise ProfileError(f"units.len.f must be > 0, got {factor:g}", path=path, line=unit_line)
    y, z, lines_arr = _process(spline, pts, path)
    scale = 1000.0 / factor                       # user unit -> mm
    y_mm, z_mm = y * scale, z * scale
    if kind == "rail":
        z_mm = -z_mm                              # Simpack z is downward
    smooth, _ = _num(spline, "approx.smooth", 0.0, path)
    comment = spline.get("comment", ("", None))[0]
    meta = {"format": "simpack", "units": f"1/{factor:g} m (units.len.f = {factor:g})",
            "unit_factor_to_m": 1.0 / factor, "comment": comment,
            "simpack": {k: v for k, (v, _) in spline.items()}}
    raw = RawProfile(y_mm=y_mm, z_mm=z_mm, lines=lines_arr, kind=kind, kind_source=kind_source,
                     meta=meta, smoothing=0.0 if smooth == 0 else None, unit_line=unit_line,
                     text=lines)
    if kind == "rail" and y_mm.size >= 4:
        from lutmpi.profiles.validate import check_extent

        check_extent(raw, path, "rail")           # a unit error first, then the cant
        raw.cant_rad, src = _cant(comment, y_mm, z_mm, path)
        if src:
            meta["cant_source"] = src
    return raw
