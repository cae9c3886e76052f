"""MiniProf profile files, ``.whl`` (wheel) and ``.ban`` (rail); always in mm.

Header variants seen in the data (all accepted): free text lines (``MINIPROF 101 148 1994 3 24``,
``Stock.......:``), ``Key=Value`` lines (``XYPoints=495``, ``Sd=36.4023``), header lines wrapped in
or started by a double quote (``"RefPoint1="``), and the flange parameters as a line of three
numbers labelled ``(Sd/Sh/qR)`` on the same or the next line. The data are one point per line,
``X Y`` followed by extra columns (``ColumnDef=X,Y,A,C``) and optionally a trailing comment (``"
zig-zag pattern``, ``add point to extend gauge face``), and may start with a double quote. When
``XYPoints`` is given, fewer points than that is an error (a truncated file).

Kind: the extension (``.whl`` wheel, ``.ban`` rail), else ``MPTypeNo`` (101 wheel, 299 rail, as in
these files; also the second word of a ``MINIPROF 101 ...`` first line), else ``#MINIWHEELPROF``.

Orientation (established from the files in ``profiles/``):

* **wheels**: ``X`` is measured from the flange back (``X ≈ 0`` on the back face) toward the field
  side; ``Y`` is the radius increment, up (flange tip ≈ +28 mm, ``Y ≈ 0`` at ``X = 70`` in every
  file, e.g. ``avg_wheel.whl``: ``Y(70.02) = -0.000``). The tape circle is 70 mm from the flange
  back (:data:`TAPE_OFFSET_MM`), so ``s = X - 70``, ``dr = Y``. ``Y`` is negated when the flange
  region lies below the tread (a file written upside down).
* **rails**: ``X`` is positive toward the **gauge** side (``avg_low2.ban`` extends its gauge face at
  +X, ``rail_left_iter288.ban`` has its side wear at +X, and ``MBench_UIC60_v3.ban`` is
  ``MBench_UIC60_v3.prr`` with X = -y), so ``v = -X``. ``Y`` is up in measured files but down in
  ``MBench_UIC60_v3.ban``; it is negated when both ends of the profile lie above its median (the
  head top is then a minimum).

Cant: MiniProf files carry no usable cant; pass ``cant_rad`` (and ``inclination = "none"``) for a
pre-canted rail such as ``MBench_UIC60_v3.ban``. Measured data get an automatic smoothing
(:func:`lutmpi.profiles.validate.auto_smoothing`).
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

from lutmpi.errors import ProfileError
from lutmpi.profiles._raw import (
    RawProfile,
    leading_numbers,
    looks_numeric,
    parse_point,
    points_array,
    strip_quote,
)

EXTENSIONS = (".whl", ".ban")
TAPE_OFFSET_MM = 70.0
_KV = re.compile(r'^"?\s*([A-Za-z][\w .]*?)\s*=\s*(.*?)"?\s*$')
_TYPES = {"101": "wheel", "299": "rail"}


def sniff(text: str) -> bool:
    head = text[:3000]
    return any(m in head for m in ("MINIPROF", "MiniProf", "MPTypeNo", "XYPoints", "ColumnDef",
                                   "#MINIWHEELPROF"))


def _is_label_line(text: str) -> bool:
    return "(sd" in text.lower()


def _data_start(lines: list[str]) -> int:
    """Index of the first data line: numeric, and not the ``Sd Sh qR`` header triple."""
    for i, text in enumerate(lines):
        t = strip_quote(text)
        if not looks_numeric(t) or _is_label_line(t):
            continue
        nxt = next((s for s in lines[i + 1:] if s.strip()), "")
        if _is_label_line(nxt):
            continue
        return i
    return len(lines)


def _header(lines: list[str]) -> tuple[dict[str, tuple[str, int]], list[str]]:
    keys: dict[str, tuple[str, int]] = {}
    free: list[str] = []
    for ln, text in enumerate(lines, start=1):
        t = text.strip()
        if not t:
            continue
        m = _KV.match(t)
        if m:
            keys[m.group(1).strip()] = (m.group(2).strip(), ln)
            continue
        nums = leading_numbers(strip_quote(t))
        nxt = lines[ln].strip() if ln < len(lines) else ""
        if len(nums) >= 3 and (_is_label_line(t) or _is_label_line(nxt)):
            for k, v in zip(("Sd", "Sh", "qR"), nums[:3], strict=True):
                keys.setdefault(k, (v, ln))
            continue
        free.append(t)
    return keys, free


def _flange_params(keys: dict, path: str) -> dict[str, float]:
    out = {}
    for k in ("Sd", "Sh", "qR"):
        if k in keys and keys[k][0]:
            try:
                out[f"{k}_mm"] = float(keys[k][0])
            except ValueError:
                raise ProfileError(f"{k} = {keys[k][0]!r} is not a number", path=path,
                                   line=keys[k][1]) from None
    return out


def _declared_kind(path: str, keys: dict, free: list[str]) -> tuple[str | None, str]:
    ext = Path(path).suffix.lower()
    if ext == ".whl":
        return "wheel", "MiniProf extension .whl"
    if ext == ".ban":
        return "rail", "MiniProf extension .ban"
    if "MPTypeNo" in keys and keys["MPTypeNo"][0] in _TYPES:
        return _TYPES[keys["MPTypeNo"][0]], f"MPTypeNo={keys['MPTypeNo'][0]}"
    for t in free[:2]:
        words = t.split()
        if len(words) > 1 and words[0].upper() == "MINIPROF" and words[1] in _TYPES:
            return _TYPES[words[1]], f"'{words[0]} {words[1]}' header"
        if t.upper().startswith("#MINIWHEELPROF"):
            return "wheel", "#MINIWHEELPROF header"
    return None, ""


def _read_points(lines: list[str], start: int, path: str) -> list[tuple[float, float, int]]:
    pts = []
    for i in range(start, len(lines)):
        text = lines[i].strip()
        if not text:
            continue
        body = strip_quote(text)
        if text.startswith('"') and not looks_numeric(body):
            continue                                  # a quoted comment line
        pts.append((*parse_point(body.split('"', 1)[0], path, i + 1), i + 1))
    return pts


def _orient_wheel(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
    s = x - TAPE_OFFSET_MM
    flange = (s > -65.0) & (s < -35.0)
    tread = np.abs(s) < 5.0
    flip = bool(flange.any() and tread.any() and y[flange].mean() < y[tread].mean() - 10.0)
    return s, (-y if flip else y), flip


def _orient_rail(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
    flip = bool(y.size and 0.5 * (y[0] + y[-1]) > np.median(y))
    return -x, (-y if flip else y), flip


def _guess(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, str | None, bool]:
    from lutmpi.profiles.validate import looks_like_rail, looks_like_wheel

    if x.size >= 4:
        for kind, orient, test in (("wheel", _orient_wheel, looks_like_wheel),
                                   ("rail", _orient_rail, looks_like_rail)):
            yn, zn, flip = orient(x, y)
            if test(yn, zn):
                return yn, zn, kind, flip
    return x, y, None, False


def parse(lines: list[str], path: str) -> RawProfile:
    """Read a MiniProf ``.whl`` / ``.ban`` into a :class:`RawProfile` (mm, normalized)."""
    start = _data_start(lines)
    keys, free = _header(lines[:start])
    kind, kind_source = _declared_kind(path, keys, free)
    x, y, ln = points_array(_read_points(lines, start, path))
    declared_n = keys.get("XYPoints", ("", None))
    if declared_n[0].strip().isdigit() and x.size < int(declared_n[0]):
        raise ProfileError(f"XYPoints={declared_n[0]} but only {x.size} points found (truncated "
                           "file?)", path=path, line=len(lines))
    meta = {"format": "miniprof", "units": "mm", "unit_factor_to_m": 1e-3,
            "header": {k: v for k, (v, _) in keys.items()}, "header_text": free}
    meta.update(_flange_params(keys, path))
    flip = False
    if kind == "rail":
        y_n, z_n, flip = _orient_rail(x, y)
    elif kind == "wheel":
        y_n, z_n, flip = _orient_wheel(x, y)
        meta["tape_offset_mm"] = TAPE_OFFSET_MM
    else:                                               # no kind stated: try both readings
        y_n, z_n, kind, flip = _guess(x, y)
        kind_source = f"shape (read as a MiniProf {kind})" if kind else ""
    meta["y_negated"] = flip
    return RawProfile(y_mm=y_n, z_mm=z_n, lines=ln, kind=kind, kind_source=kind_source,
                      meta=meta, smoothing=None, cant_rad=None, text=lines)
