"""Plain two-column text / CSV profiles (``.csv``, ``.txt``, ``.dat``).

One point per line, ``y z`` separated by blanks, a comma or a semicolon; further columns are
ignored. Lines starting with ``#``, ``!`` or ``%`` are comments; one line of column names may
precede the data. The points must already be in lutmpi's **normalized orientation**
(:mod:`lutmpi.profiles.model`): wheels ``s`` from the tape circle positive to the field side and
``z`` the radius increment; rails ``v`` positive to the field side and ``z`` up. Two optional
comment directives::

    # units: mm        (default; or m)
    # kind: wheel      (or rail; otherwise decided from the shape)

The data are taken as exact (interpolating spline) unless ``smoothing`` is passed.
"""

from __future__ import annotations

import re

from lutmpi.errors import ProfileError
from lutmpi.profiles._raw import RawProfile, looks_numeric, parse_point, points_array

EXTENSIONS = (".csv", ".txt", ".dat")
_DIRECTIVE = re.compile(r"^[#!%]\s*(units|kind)\s*[:=]\s*(\S+)", re.IGNORECASE)
_UNITS = {"mm": 1.0, "m": 1000.0}


def sniff(text: str) -> bool:
    """Anything can be plain text; the registry tries this reader last."""
    return True


def parse(lines: list[str], path: str) -> RawProfile:
    """Read a plain two-column file into a :class:`RawProfile` (mm, normalized)."""
    scale, unit, unit_line, kind, kind_line = 1.0, "mm", None, None, None
    pts: list[tuple[float, float, int]] = []
    header_seen = False
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
            continue
        pts.append((*parse_point(t, path, ln), ln))
    y, z, ln_arr = points_array(pts)
    return RawProfile(y_mm=y * scale, z_mm=z * scale, lines=ln_arr, kind=kind,
                      kind_source=f"'# kind: {kind}' (line {kind_line})" if kind else "",
                      meta={"format": "plain", "units": unit,
                            "unit_factor_to_m": 1e-3 * scale},
                      smoothing=0.0, unit_line=unit_line)
