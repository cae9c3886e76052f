"""The intermediate every reader returns, and the low-level line parsing they share.

A reader turns a file into a :class:`RawProfile`: points in **mm**, already in the normalized
orientation of :mod:`lutmpi.profiles.model` but still in file order (not yet trimmed to a function
of ``y``), each with the 1-based line it came from. :mod:`lutmpi.profiles.validate` does the rest.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lutmpi.errors import ProfileError

_SPLIT = re.compile(r"[\s,;]+")
# "12,5  3,25" or "12,5;3,25": two numbers written with decimal commas (issue 13)
_COMMA_DECIMALS = re.compile(r"^\s*[-+]?\d+,\d+\s*[\s;]\s*[-+]?\d+,\d+(\s|;|$)")


@dataclass
class RawProfile:
    """Points of one file in the normalized orientation, mm, in file order.

    Attributes
    ----------
    y_mm, z_mm : ndarray, shape (n,)
        Normalized lateral coordinate and height / radius increment, mm.
    lines : ndarray of int, shape (n,)
        1-based line of each point in the file.
    kind : {"wheel", "rail"} or None
        The kind the file declares (header, extension); None when it does not say.
    kind_source : str
        Where ``kind`` came from (for messages).
    meta : dict
        Header data and how the file was interpreted.
    smoothing : float or None
        0 for exact data, None to choose a smoothing from the point spacing (measured data).
    cant_rad : float or None
        Inclination contained in the data, when the file says; None = not stated.
    unit_line : int or None
        Line declaring the length unit (cited when the extent is absurd); None when the file
        declares none.
    text : list of str
        The file's lines, to quote one in a message; empty when not read from a file.
    """

    y_mm: np.ndarray
    z_mm: np.ndarray
    lines: np.ndarray
    kind: str | None = None
    kind_source: str = ""
    meta: dict[str, Any] = field(default_factory=dict)
    smoothing: float | None = 0.0
    cant_rad: float | None = None
    unit_line: int | None = None
    text: list[str] = field(default_factory=list, repr=False)

    def quote(self, line: int) -> str:
        """The stripped text of 1-based ``line`` of the file, or ``""`` when unknown."""
        return self.text[line - 1].strip() if 0 < line <= len(self.text) else ""


def strip_quote(text: str) -> str:
    """Remove a leading MiniProf double quote (and the blanks around it)."""
    t = text.strip()
    return t[1:].strip() if t.startswith('"') else t


def is_number(token: str) -> bool:
    try:
        float(token)
    except ValueError:
        return False
    return True


def tokens(text: str) -> list[str]:
    """The tokens of ``text`` split on blanks, commas and semicolons."""
    return [t for t in _SPLIT.split(text.strip()) if t]


def leading_numbers(text: str) -> list[str]:
    """The leading numeric tokens of ``text`` (split on blanks, commas, semicolons)."""
    out = []
    for tok in _SPLIT.split(text.strip()):
        if not tok or not is_number(tok):
            break
        out.append(tok)
    return out


def looks_numeric(text: str) -> bool:
    """True when the first token of ``text`` is a number (a data line, possibly malformed)."""
    toks = _SPLIT.split(text.strip())
    return bool(toks and toks[0] and is_number(toks[0]))


def parse_point(text: str, path: str, line: int) -> tuple[float, float]:
    """The first two numbers of a data line; anything after them is a comment or extra column.

    Raises
    ------
    ProfileError
        Fewer than two leading numbers (non-numeric value), or NaN / inf.
    """
    if _COMMA_DECIMALS.match(text):
        raise ProfileError(f"decimal commas in {text.strip()!r}: lutmpi reads '.' as the decimal "
                           "separator (and ',' or ';' between columns); convert the file, e.g. "
                           "12.5;3.25", path=path, line=line)
    toks = [t for t in _SPLIT.split(text.strip()) if t]
    if len(toks) < 2:
        raise ProfileError(f"expected two numbers 'y z', got {text.strip()!r}", path=path,
                           line=line)
    try:
        y, z = float(toks[0]), float(toks[1])
    except ValueError:
        raise ProfileError(f"non-numeric value in point line {text.strip()!r}",
                           path=path, line=line) from None
    if not (math.isfinite(y) and math.isfinite(z)):
        raise ProfileError(f"NaN or inf in point line {text.strip()!r}", path=path, line=line)
    return y, z


def points_array(pts: list[tuple[float, float, int]]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Split ``[(y, z, line), ...]`` into three arrays (empty arrays for no points)."""
    if not pts:
        return np.empty(0), np.empty(0), np.empty(0, dtype=int)
    a = np.array(pts, dtype=float)
    return a[:, 0], a[:, 1], a[:, 2].astype(int)
