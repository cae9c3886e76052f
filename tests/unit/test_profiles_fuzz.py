"""Fuzzing the profile readers (issue 7 item 3).

Corrupted, truncated, reordered and mis-unit variants of every real file must end either in a valid
:class:`Profile` that keeps the invariants (strictly increasing finite y, finite z, a plausible
extent) or in a :class:`ProfileError` naming the file -- never another exception.
"""

from __future__ import annotations

import re
import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lutmpi.errors import ProfileError
from lutmpi.paths import REPO_ROOT
from lutmpi.profiles import read_profile
from lutmpi.profiles.validate import EXTENT_MM

# the repository's copies of shared/profiles (byte-identical; issue 16: no skip without ../shared)
_DIR = REPO_ROOT / "profiles"
FILES = sorted(p.name for p in _DIR.iterdir() if p.suffix in (".prw", ".prr", ".whl", ".ban")) \
    if _DIR and _DIR.is_dir() else []
pytestmark = pytest.mark.skipif(not FILES, reason="profiles/ not found")

SETTINGS = settings(max_examples=25, deadline=None, derandomize=True,
                    suppress_health_check=[HealthCheck.too_slow])
_NUM = re.compile(r"[-+]?\d+\.?\d*(?:[eE][-+]?\d+)?")
_TEXT: dict[str, list[str]] = {}


def _lines(name: str) -> list[str]:
    if name not in _TEXT:
        _TEXT[name] = (_DIR / name).read_text(encoding="latin-1").splitlines()
    return _TEXT[name]


def _check(name: str, lines: list[str], **kw: object) -> None:
    """Write the variant, read it, and check the contract."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / name
        path.write_text("\n".join(lines) + "\n", encoding="latin-1")
        try:
            p = read_profile(path, **kw)
        except ProfileError as exc:
            assert str(path) in str(exc), f"error does not name the file: {exc}"
            return
    assert np.all(np.isfinite(p.y)) and np.all(np.isfinite(p.z))
    assert np.all(np.diff(p.y) > 0)
    w_lo, w_hi, h_lo, h_hi = EXTENT_MM[p.kind]
    assert (p.y_max - p.y_min) * 1e3 <= w_hi and np.ptp(p.z) * 1e3 <= h_hi
    assert p.kind == ("wheel" if name.endswith((".prw", ".whl")) else "rail")
    s = np.linspace(p.y_min, p.y_max, 50)
    assert np.all(np.isfinite(p.z_at(s))) and np.all(np.isfinite(p.curvature(s)))


files = st.sampled_from(FILES or ["none"])
junk = st.text(alphabet="0123456789.-+eE nNaAiIfF\",;!#xX\t", min_size=0, max_size=6)


@SETTINGS
@given(name=files, data=st.data(), new=junk)
def test_corrupted_characters(name: str, data: st.DataObject, new: str):
    lines = list(_lines(name))
    i = data.draw(st.integers(0, len(lines) - 1))
    j = data.draw(st.integers(0, len(lines[i])))
    k = data.draw(st.integers(j, min(len(lines[i]), j + 4)))
    lines[i] = lines[i][:j] + new + lines[i][k:]
    _check(name, lines)


@SETTINGS
@given(name=files, data=st.data())
def test_truncated(name: str, data: st.DataObject):
    lines = _lines(name)
    n = data.draw(st.integers(0, len(lines)))
    cut = list(lines[:n])
    if cut and data.draw(st.booleans()):
        cut[-1] = cut[-1][: data.draw(st.integers(0, len(cut[-1])))]   # mid-line
    _check(name, cut)


@SETTINGS
@given(name=files, data=st.data())
def test_reordered_deleted_duplicated_lines(name: str, data: st.DataObject):
    lines = list(_lines(name))
    i = data.draw(st.integers(0, len(lines) - 1))
    j = data.draw(st.integers(0, len(lines) - 1))
    op = data.draw(st.sampled_from(["swap", "delete", "duplicate", "reverse_block"]))
    if op == "swap":
        lines[i], lines[j] = lines[j], lines[i]
    elif op == "delete":
        del lines[i]
    elif op == "duplicate":
        lines.insert(i, lines[i])
    else:
        a, b = sorted((i, j))
        lines[a:b] = lines[a:b][::-1]
    _check(name, lines)


def _scale_numbers(line: str, factor: float) -> str:
    return _NUM.sub(lambda m: repr(float(m.group(0)) * factor), line)


@SETTINGS
@given(name=files, factor=st.sampled_from([1e-6, 1e-3, 0.1, 0.5, 2.0, 10.0, 1e3, 1e6]))
def test_mis_unit(name: str, factor: float):
    lines = _lines(name)
    if name.endswith((".prw", ".prr")):      # a wrong unit factor in the header
        out = [ln.replace("+1.000000000000000e+03", f"{1000 / factor:+.15e}", 1)
               if "units.len.f" in ln and not ln.lstrip().startswith("!") else ln
               for ln in lines]
    else:                                    # MiniProf is always mm: the numbers were scaled
        start = next(i for i, ln in enumerate(lines) if i > 5 and _NUM.match(ln.strip(' "')))
        out = lines[:start] + [_scale_numbers(ln, factor) for ln in lines[start:]]
    if factor in (1e-6, 1e-3, 1e3, 1e6):     # far outside any plausible extent
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / name
            path.write_text("\n".join(out) + "\n", encoding="latin-1")
            with pytest.raises(ProfileError, match="implausible|wrong length unit|look like"):
                read_profile(path)
    else:
        _check(name, out)


@SETTINGS
@given(name=files, kind=st.sampled_from(["wheel", "rail"]),
       fmt=st.sampled_from([None, "simpack", "miniprof", "plain"]))
def test_forced_kind_and_format(name: str, kind: str, fmt: str | None):
    lines = _lines(name)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / name
        path.write_text("\n".join(lines) + "\n", encoding="latin-1")
        try:
            p = read_profile(path, kind=kind, format=fmt)
        except ProfileError as exc:
            assert str(path) in str(exc)
            return
    assert p.kind == kind == ("wheel" if name.endswith((".prw", ".whl")) else "rail")
