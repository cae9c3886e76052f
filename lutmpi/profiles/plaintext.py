"""Plain two-column text / CSV profiles (``.csv``, ``.txt``, ``.dat``).

One point per line, ``y z`` separated by blanks, a comma or a semicolon. Lines starting with
``#``, ``!`` or ``%`` are comments; one line of column names may precede the data. A file with
more than two numeric columns (``x y z`` from a scanner, an index column, ...) is read only when
that header names its ``y`` and ``z`` columns (``y``, ``y_mm``, ``y [mm]``, ``z``, ...): which
two of three numbers are the profile cannot be guessed, and reading the first two of ``x y z``
would give a wrong profile without an error. The points must already be in lutmpi's **normalized
orientation** (:mod:`lutmpi.profiles.model`): wheels ``s`` from the tape circle positive to the
field side and ``z`` the radius increment; rails ``v`` positive to the field side and ``z`` up.
Two optional comment directives::

    # units: mm        (default; or m)
    # kind: wheel      (or rail; otherwise decided from the shape)

The data are taken as exact (interpolating spline) unless ``smoothing`` is passed.
"""

from __future__ import annotations

import math
import re

from lutmpi.errors import ProfileError
from lutmpi.profiles._raw import (
    RawProfile,
    leading_numbers,
    looks_numeric,
    parse_point,
    points_array,
    tokens,
)

EXTENSIONS = (".csv", ".txt", ".dat")
_DIRECTIVE = re.compile(r"^[#!%]\s*(units|kind)\s*[:=]\s*(\S+)", re.IGNORECASE)
_UNITS = {"mm": 1.0, "m": 1000.0}
# a column name: "y", "Y_mm", "z [mm]", "z(mm)" -> y / z
_COLUMN = re.compile(r"^\s*([a-z]+)\s*(?:[_\[(].*)?$", re.IGNORECASE)


def _header_columns(header: str) -> tuple[tuple[int, int] | None, list[str]]:
    """The column names of a header line, and the indices of its ``y`` and ``z`` columns
    (None unless it names each exactly once). A bracketed token after a name is its unit
    (``y [mm]``), not a column."""
    names: list[str] = []
    for x in tokens(header):
        if x[0] in "[(" and names:
            continue
        m = _COLUMN.match(x)
        names.append(m.group(1).lower() if m else x.lower())
    if names.count("y") == 1 and names.count("z") == 1:
        return (names.index("y"), names.index("z")), names
    return None, names


def _point(t: str, path: str, ln: int, cols: tuple[int, int] | None, names: list[str]
           ) -> tuple[float, float]:
    """The ``(y, z)`` of data line ``t`` (mm, as written): its first two numbers, or the
    columns the header named; more than two numbers without such a header are refused."""
    y, z = parse_point(t, path, ln)      # decimal commas, NaN, a missing number: refused
    nums = leading_numbers(t)
    if cols is not None:
        if len(nums) <= max(cols):
            raise ProfileError(f"{len(nums)} numbers, but the header names column "
                               f"{max(cols) + 1} {'yz'[cols.index(max(cols))]!r}: {t!r}",
                               path=path, line=ln)
        y, z = float(nums[cols[0]]), float(nums[cols[1]])
        if not (math.isfinite(y) and math.isfinite(z)):
            raise ProfileError(f"NaN or inf in point line {t!r}", path=path, line=ln)
        return y, z
    if len(nums) > 2:
        hint = (f"the header line names the columns {names}, which needs exactly one 'y' and "
                "one 'z'" if names else "name the columns in a header line before the data "
                "(not a comment), e.g. 'x y z'")
        raise ProfileError(
            f"{len(nums)} numeric columns in {t!r}, expected two (y z): which two are the "
            f"profile is ambiguous (x y z? an index column?); {hint}, or keep only y and z",
            path=path, line=ln)
    return y, z


def sniff(text: str) -> bool:
    """Anything can be plain text; the registry tries this reader last."""
    return True


def parse(lines: list[str], path: str) -> RawProfile:
    """Read a plain two-column file into a :class:`RawProfile` (mm, normalized)."""
    scale, unit, unit_line, kind, kind_line = 1.0, "mm", None, None, None
    pts: list[tuple[float, float, int]] = []
    header_seen, cols, names = False, None, []   # the header's (y, z) indices, its names
    for ln, text in enumerate(lines, start=1):
        t = text.strip()
        if not t:
            continue
        m = _DIRECTIVE.match(t)
        if m:
            key, val = m.group(1).lower(), m.group(2).lower()
            if key == "units":
                if val not in _UNITS:
                    raise ProfileError(f"units must be one of {list(_UNITS)}, got {val!r}",
                                       path=path, line=ln)
                scale, unit, unit_line = _UNITS[val], val, ln
            else:
                if val not in ("wheel", "rail"):
                    raise ProfileError(f"kind must be wheel or rail, got {val!r}", path=path,
                                       line=ln)
                kind, kind_line = val, ln
            continue
        if t[0] in "#!%":
            continue
        if not looks_numeric(t) and not pts and not header_seen:
            header_seen = True                # one line of column names
            cols, names = _header_columns(t)
            continue
        pts.append((*_point(t, path, ln, cols, names), ln))
    y, z, ln_arr = points_array(pts)
    return RawProfile(y_mm=y * scale, z_mm=z * scale, lines=ln_arr, kind=kind,
                      kind_source=f"'# kind: {kind}' (line {kind_line})" if kind else "",
                      meta={"format": "plain", "units": unit,
                            "unit_factor_to_m": 1e-3 * scale},
                      smoothing=0.0, unit_line=unit_line, text=lines)
