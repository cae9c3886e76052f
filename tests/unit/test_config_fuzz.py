"""Fuzzing the config loader and the sweep expansion (issue 7 item 3).

Random mutations of a valid config (dropped keys, wrong types, unknown keys, out-of-range and
mis-unit numbers) and garbage / corrupted TOML text must end in a ``Config`` or a ``ConfigError``
whose message names the offending key (or a key it is checked against) and the file; never another
exception.
"""

from __future__ import annotations

import copy
import datetime
import tempfile
import tomllib
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lutmpi.config import Config, config_from_dict, expand_sweep, load_config
from lutmpi.config.load import leaf_keys
from lutmpi.errors import ConfigError

ROOT = Path(__file__).resolve().parents[2]
DEFAULTS_TEXT = (ROOT / "configs" / "defaults.toml").read_text()
VALID = tomllib.loads(DEFAULTS_TEXT)
PATH = "/fuzz/config.toml"
LEAVES = leaf_keys()
SECTIONS = sorted({k.split(".")[0] for k in LEAVES})
# a key whose value is checked against another key may be reported under that key
CROSS = {"wheelset.back_to_back_mm": {"track.gauge_mm"},
         "equilibrium.initial_kc_N_per_m": {"equilibrium.max_kc_N_per_m"},
         "contact.method": {"output.methods"}}
FUZZ = settings(max_examples=150, deadline=None, derandomize=True,
                suppress_health_check=[HealthCheck.too_slow])

any_value = st.one_of(
    st.none(), st.booleans(), st.integers(), st.floats(allow_nan=True, allow_infinity=True),
    st.text(max_size=8), st.lists(st.one_of(st.integers(), st.floats(), st.text(max_size=3)),
                                  max_size=4),
    st.dictionaries(st.text(max_size=4), st.integers(), max_size=2),
    st.dates(), st.datetimes(), st.times(),
)


def _set(data, dotted, value):
    *parents, leaf = dotted.split(".")
    table = data
    for name in parents:
        nxt = table.get(name)
        if not isinstance(nxt, dict):
            nxt = table[name] = {}
        table = nxt
    table[leaf] = value


def _get(data, dotted):
    for name in dotted.split("."):
        data = data[name]
    return data


def _delete(data, dotted):
    *parents, leaf = dotted.split(".")
    for name in parents:
        data = data[name]
    data.pop(leaf, None)


@st.composite
def mutation(draw):
    """(kind, dotted key, mutated config dict)."""
    data = copy.deepcopy(VALID)
    kind = draw(st.sampled_from(["drop", "type", "unknown", "scale", "number", "section"]))
    key = draw(st.sampled_from(LEAVES))
    if kind == "drop":
        key = draw(st.sampled_from(LEAVES + SECTIONS))
        if "." in key:
            if key.rsplit(".", 1)[1] in ("profile", "generator", "format"):
                key = key.rsplit(".", 1)[0] + ".generator"
            try:
                _delete(data, key)
            except KeyError:
                pass
        else:
            data.pop(key, None)
    elif kind == "type":
        _set(data, key, draw(any_value))
    elif kind == "unknown":
        section = draw(st.sampled_from(SECTIONS + ["wear.wheel", "wear.rail", ""]))
        name = draw(st.text(min_size=1, max_size=10))
        key = f"{section}.{name}" if section else name
        if key in LEAVES or name in SECTIONS:
            key = key + "_x"
        _set(data, key, draw(any_value)) if section else data.__setitem__(key, draw(any_value))
    elif kind in ("scale", "number"):
        numeric = [k for k in LEAVES if isinstance(_safe_get(data, k), (int, float, list))
                   and not isinstance(_safe_get(data, k), bool)]
        key = draw(st.sampled_from(numeric))
        old = _get(data, key)
        factor = draw(st.sampled_from([1e3, 1e-3, -1.0, 0.0, 1e6]))   # mm/m mix-ups, signs
        number = draw(st.floats(allow_nan=True, allow_infinity=True))
        new = _mutate_number(old, factor if kind == "scale" else None, number)
        _set(data, key, new)
    else:
        key = draw(st.sampled_from(SECTIONS))
        data[key] = draw(any_value)
    return kind, key, data


def _safe_get(data, key):
    try:
        return _get(data, key)
    except (KeyError, TypeError):
        return None


def _mutate_number(old, factor, number):
    if isinstance(old, list):   # a grid axis or a list of names
        return [v * factor if isinstance(v, (int, float)) and factor is not None else number
                for v in old]
    if factor is not None:
        return type(old)(old * factor)
    return number


def _related(err_key: str, key: str) -> bool:
    return (err_key == key or err_key.startswith(key + ".") or key.startswith(err_key + ".")
            or err_key in CROSS.get(key, ()))


@FUZZ
@given(mutation())
def test_mutated_config_gives_config_or_named_error(case):
    kind, key, data = case
    try:
        cfg = config_from_dict(data, path=PATH)
    except ConfigError as err:
        msg = str(err)
        assert PATH in msg, msg
        assert err.key is not None and f"[{err.key}]" in msg, msg
        if kind != "drop":   # a dropped key takes its default; errors then come from elsewhere
            assert _related(err.key, key), (key, msg)
        return
    assert isinstance(cfg, Config)


@pytest.fixture(scope="module")
def scratch():
    with tempfile.TemporaryDirectory() as tmp:
        yield Path(tmp)


def _check_file(path: Path) -> None:
    try:
        cfg = load_config(path)
    except ConfigError as err:
        assert str(path) in str(err), str(err)
        return
    assert isinstance(cfg, Config)


@FUZZ
@given(st.text(max_size=300))
def test_garbage_text(scratch, text):
    path = scratch / "garbage.toml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    _check_file(path)


@FUZZ
@given(st.binary(max_size=200))
def test_garbage_bytes(scratch, blob):
    path = scratch / "bytes.toml"
    path.write_bytes(blob)
    _check_file(path)


@st.composite
def corrupted(draw):
    """The defaults file truncated, with lines reordered/dropped/duplicated or bytes flipped."""
    lines = DEFAULTS_TEXT.splitlines(keepends=True)
    how = draw(st.sampled_from(["truncate", "shuffle", "drop", "duplicate", "flip"]))
    if how == "truncate":
        text = DEFAULTS_TEXT[: draw(st.integers(0, len(DEFAULTS_TEXT)))]
    elif how == "shuffle":
        text = "".join(draw(st.permutations(lines)))
    elif how == "drop":
        i = draw(st.integers(0, len(lines) - 1))
        text = "".join(lines[:i] + lines[i + 1:])
    elif how == "duplicate":
        i = draw(st.integers(0, len(lines) - 1))
        text = "".join(lines[: i + 1] + lines[i:])
    else:
        i = draw(st.integers(0, len(DEFAULTS_TEXT) - 1))
        ch = draw(st.characters(codec="utf-8"))
        text = DEFAULTS_TEXT[:i] + ch + DEFAULTS_TEXT[i + 1:]
    return text


@FUZZ
@given(corrupted())
def test_corrupted_defaults_file(scratch, text):
    path = scratch / "corrupt.toml"
    path.write_text(text, encoding="utf-8", errors="surrogatepass")
    _check_file(path)


def test_deep_nesting_is_a_config_error(scratch):
    path = scratch / "deep.toml"
    path.write_text("a = " + "[" * 100_000)
    _check_file(path)


sweep_keys = st.sampled_from(["contact.method", "mesh.spacing_mm", "grid.y_mm", "rail.inclination",
                              "wear.rail.side_mm", "mesh.wheel_lateral_mm", "bogus.key"])


@FUZZ
@given(st.dictionaries(sweep_keys, st.lists(any_value, max_size=3), max_size=3),
       st.dictionaries(sweep_keys, st.lists(any_value, max_size=3), max_size=2))
def test_random_sweeps_give_specs_or_named_error(product, zipped):
    doc = {"base": {"wheel": {"generator": "S1002"}, "rail": {"generator": "UIC60"},
                    "grid": {"y_mm": [-1.0, 1.0, 2], "yaw_rad": [-0.01, 0.01, 2]}},
           "sweep": {"product": product, "zip": zipped}}
    try:
        specs = expand_sweep(doc)
    except ConfigError as err:
        assert err.key is not None and f"[{err.key}]" in str(err), str(err)
        return
    assert len({s.id for s in specs}) == len(specs) > 0
    assert [s.id for s in specs] == [s.id for s in expand_sweep(doc)]


def test_mutation_strategy_reaches_errors_and_configs():
    """Guard against a fuzz test that never fails: known mutations are rejected / accepted."""
    data = copy.deepcopy(VALID)
    _set(data, "track.gauge_mm", 1.435)       # metres written into an _mm key
    with pytest.raises(ConfigError, match=r"\[track\.gauge_mm\]"):
        config_from_dict(data, path=PATH)
    data = copy.deepcopy(VALID)
    _set(data, "grid.y_mm", [-9, 9, datetime.date(2020, 1, 1)])
    with pytest.raises(ConfigError, match=r"\[grid\.y_mm\] expected an integer, got date"):
        config_from_dict(data, path=PATH)
    assert isinstance(config_from_dict(VALID, path=PATH), Config)
