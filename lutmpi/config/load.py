"""TOML → :class:`~lutmpi.config.model.Config`, strict, and back.

Every section and key is checked against the dataclasses of ``model.py``: an unknown section or
key, a wrong type, a missing profile file or an impossible value raises ``ConfigError``
naming the dotted key (``mesh.wheel_lateral_mm``), the file and what was expected vs what was found.
Only ``[wheel]`` and ``[rail]`` are required; everything else takes the defaults of ``model.py``
(documented in ``configs/defaults.toml``).

Types: a float key accepts a TOML integer or float (finite; ``true``/``false`` are rejected although
``bool`` is an ``int`` in Python); an integer key accepts only an integer; a grid axis is the triple
``[start, stop, count]``.

Profile files (``wheel.profile``, ``rail.profile``): an absolute path is used as is; a relative path
is looked up, in this order, (1) relative to the directory of the config file (``base_dir``),
(2) relative to the current directory, (3) relative to the lutmpi source checkout (the directory
holding ``lutmpi/``, so ``profiles/...`` works from anywhere), (4) for a path ``../shared/...``
(any number of ``../``), in the shared folder that :func:`lutmpi.paths.shared_dir` finds. The
first existing file wins and is stored as an absolute, resolved path.

Derived default: when ``[output] methods`` is not given it is ``[contact.method]``, so a config that
only changes the method computes that method. ``contact.method`` must be one of ``output.methods``.
"""

from __future__ import annotations

import dataclasses
import math
import os
import tomllib
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from lutmpi.config.model import (
    ALL_METHODS,
    EQUILIBRIUM_SOLVERS,
    GAUGE_POINTS,
    QUANTITIES,
    RAIL_GENERATORS,
    SIDE_NAMES,
    WHEEL_GENERATORS,
    WHEEL_ORIGINS,
    Config,
)
from lutmpi.errors import ConfigError

__all__ = ["load_config", "config_from_dict", "config_to_toml", "read_toml", "section_fields",
           "leaf_keys", "MIN_FLANGE_THICKNESS_MM"]

# The thinnest flange a wheel may have (S1002-type worn limit ~22 mm): the track gauge must leave
# room for two of them outside the back-to-back distance.
MIN_FLANGE_THICKNESS_MM = 20.0
MAX_GRID_COUNT = 100_000
REQUIRED_SECTIONS = ("wheel", "rail")
_SOURCE_ROOT = Path(__file__).resolve().parents[2]


# --------------------------------------------------------------------------------------- schema

def section_fields(cls: type) -> dict[str, Any]:
    """Field name → resolved type hint of a config dataclass (in declaration order)."""
    hints = typing.get_type_hints(cls)
    return {f.name: hints[f.name] for f in dataclasses.fields(cls) if f.name != "path"}


def leaf_keys(cls: type = Config, prefix: str = "") -> list[str]:
    """Every settable dotted key, e.g. ``["wheel.profile", ..., "wear.rail.side_mm"]``."""
    keys: list[str] = []
    for name, hint in section_fields(cls).items():
        dotted = f"{prefix}{name}"
        if dataclasses.is_dataclass(hint):
            keys.extend(leaf_keys(hint, dotted + "."))
        else:
            keys.append(dotted)
    return keys


def _closed(lo: float, hi: float) -> tuple[typing.Callable[[Any], bool], str]:
    return (lambda v: lo <= v <= hi), f"a number in [{lo:g}, {hi:g}]"


def _open_closed(lo: float, hi: float) -> tuple[typing.Callable[[Any], bool], str]:
    return (lambda v: lo < v <= hi), f"a number in ({lo:g}, {hi:g}]"


def _positive() -> tuple[typing.Callable[[Any], bool], str]:
    return (lambda v: v > 0), "a number > 0"


def _one_of(names: typing.Iterable[str]) -> tuple[typing.Callable[[Any], bool], str]:
    names = tuple(names)
    return (lambda v: v in names), "one of " + ", ".join(repr(n) for n in names)


# dotted key -> (predicate on the converted value, what is expected). Cross-key rules: _check_cross.
_RULES: dict[str, tuple[typing.Callable[[Any], bool], str]] = {
    "wheel.generator": _one_of(WHEEL_GENERATORS),
    "wheel.nominal_radius_mm": _closed(100.0, 1000.0),
    "rail.generator": _one_of(RAIL_GENERATORS),
    "rail.inclination": ((lambda v: v is not None), "see _as_cant"),
    "wheel.origin": _one_of(WHEEL_ORIGINS),
    "wheel.offset_y_mm": _closed(-200.0, 200.0),
    "wheel.offset_z_mm": _closed(-200.0, 200.0),
    "rail.offset_y_mm": _closed(-200.0, 200.0),
    "rail.offset_z_mm": _closed(-200.0, 200.0),
    "rail.gauge_depth_mm": _open_closed(0.0, 30.0),
    "track.gauge_mm": _closed(500.0, 2000.0),
    "track.gauge_depth_mm": _open_closed(0.0, 30.0),
    "wheelset.back_to_back_mm": _open_closed(0.0, 2000.0),
    "wheelset.tape_offset_mm": _open_closed(0.0, 200.0),
    "mesh.wheel_lateral_mm": _open_closed(0.0, 20.0),
    "mesh.wheel_circumferential_mm": _open_closed(0.0, 20.0),
    "mesh.rail_lateral_mm": _open_closed(0.0, 20.0),
    "mesh.rail_longitudinal_mm": _open_closed(0.0, 20.0),
    "mesh.window_gap_mm": _open_closed(0.0, 50.0),
    "contact.method": _one_of(ALL_METHODS),
    "contact.allowed_indentation_mm": _open_closed(0.0, 1.0),
    "contact.max_contacts_per_wheel": ((lambda v: v in (1, 2)), "1 or 2"),
    "contact.roll": _one_of(("solved", "zero")),
    "equilibrium.spring_N_per_m": _positive(),
    "equilibrium.torsion_spring_Nm_per_rad": _positive(),
    "equilibrium.vertical_load_N": _positive(),
    "equilibrium.initial_kc_N_per_m": _positive(),
    "equilibrium.max_kc_N_per_m": _positive(),
    "equilibrium.max_iterations": ((lambda v: 1 <= v <= 100_000), "an integer in [1, 100000]"),
    "equilibrium.max_pose_time_s": ((lambda v: 0 < v <= 1e6), "a number of seconds in (0, 1e6]"),
    "equilibrium.solver": _one_of(EQUILIBRIUM_SOLVERS),
    "material.young_GPa": _open_closed(0.0, 1000.0),
    "material.poisson": ((lambda v: 0.0 < v < 0.5), "a number in (0, 0.5)"),
    "flange.base_height_mm": _closed(0.0, 50.0),
    "output.refine_scale": _closed(0.1, 1000.0),
    "wear.wheel.flange_thinning_mm": _closed(0.0, 15.0),
    "wear.wheel.tread_hollowing_mm": _closed(0.0, 10.0),
    "wear.rail.vertical_mm": _closed(0.0, 30.0),
    "wear.rail.side_mm": _closed(0.0, 30.0),
}
# keys that were accepted once but never changed a result (issue 15): an old config that sets
# one gets an error that says so, not a silent no-op
REMOVED_KEYS = {
    "flange.cantilever_b_mm": "the flange stiffness uses the paper's chi = 0.082 "
                              "(lutmpi/contact/stiffness.py), never the Table 1 cantilever",
    "flange.cantilever_h_mm": "the flange stiffness uses the paper's chi = 0.082 "
                              "(lutmpi/contact/stiffness.py), never the Table 1 cantilever",
    "flange.cantilever_l_mm": "the flange stiffness uses the paper's chi = 0.082 "
                              "(lutmpi/contact/stiffness.py), never the Table 1 cantilever",
    "mesh.window_margin_mm": "the window depth is mesh.window_gap_mm; no lateral margin is used",
}
# grid axes: key -> (largest |value|, unit)
_GRID_LIMITS = {"grid.y_mm": (100.0, "mm"), "grid.yaw_rad": (0.5, "rad")}


# ------------------------------------------------------------------------------------ reading

def read_toml(path: str | os.PathLike) -> dict:
    """Parse a TOML file; every failure is a :class:`ConfigError` naming the file (and line)."""
    try:
        raw = Path(path).read_bytes()
    except FileNotFoundError:
        raise ConfigError("file not found", path=str(path)) from None
    except (OSError, ValueError) as exc:
        raise ConfigError(f"cannot read the file: {exc}", path=str(path)) from None
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        line = raw[: exc.start].count(b"\n") + 1
        raise ConfigError(f"not UTF-8 text (line {line})", path=str(path)) from None
    try:
        return tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:   # its message ends with "(at line L, column C)"
        raise ConfigError(f"TOML syntax error: {exc}", path=str(path)) from None
    except RecursionError:
        raise ConfigError("TOML syntax error: nesting too deep", path=str(path)) from None


def load_config(path: str | os.PathLike) -> Config:
    """Read and validate a config file.

    Parameters
    ----------
    path : str or path-like
        The TOML file. Relative profile paths are resolved against its directory first.

    Returns
    -------
    Config
        The validated configuration, ``path`` set to the absolute file path.

    Raises
    ------
    ConfigError
        Syntax error (with line), unknown section/key, wrong type, missing profile, bad value.
    """
    path = Path(path)
    data = read_toml(path)
    return config_from_dict(data, path=path.absolute(), base_dir=path.absolute().parent)


# --------------------------------------------------------------------------------- validation

@dataclasses.dataclass(frozen=True)
class _Where:
    path: str | None
    base_dir: Path

    def error(self, key: str | None, message: str) -> ConfigError:
        return ConfigError(message, path=self.path, key=key)


def _show(value: Any) -> str:
    text = repr(value)
    if len(text) > 80:
        text = text[:77] + "..."
    return f"{type(value).__name__} {text}"


def _expect(where: _Where, key: str, expected: str, value: Any) -> ConfigError:
    return where.error(key, f"expected {expected}, got {_show(value)}")


def _as_float(value: Any, key: str, where: _Where) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise _expect(where, key, "a number", value)
    try:
        out = float(value)
    except OverflowError:
        raise _expect(where, key, "a finite number", value) from None
    if not math.isfinite(out):
        raise _expect(where, key, "a finite number", value)
    return out


def _as_int(value: Any, key: str, where: _Where) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise _expect(where, key, "an integer", value)
    return int(value)


def _as_str(value: Any, key: str, where: _Where) -> str:
    if not isinstance(value, str) or not value.strip():
        raise _expect(where, key, "a non-empty string", value)
    return value


def _as_bool(value: Any, key: str, where: _Where) -> bool:
    if not isinstance(value, bool):
        raise _expect(where, key, "true or false", value)
    return value


def _as_axis(value: Any, key: str, where: _Where) -> tuple[float, float, int]:
    """``[start, stop, count]`` with start < stop and 2 <= count, or one value (start == stop,
    count 1: a 1-D table), inside the axis limits."""
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise _expect(where, key, "[start, stop, count]", value)
    start = _as_float(value[0], key, where)
    stop = _as_float(value[1], key, where)
    count = _as_int(value[2], key, where)
    limit, unit = _GRID_LIMITS[key]
    if count == 1 and start == stop:
        pass   # a single value: the table is 1-D along this axis
    elif not start < stop:
        raise where.error(key, f"expected start < stop (or start == stop with count 1), got "
                               f"start={start:g}, stop={stop:g}")
    elif not 2 <= count <= MAX_GRID_COUNT:
        raise where.error(key, f"expected a count in [2, {MAX_GRID_COUNT}] (or 1 with start == "
                               f"stop), got {count}")
    if max(abs(start), abs(stop)) > limit:
        raise where.error(key, f"expected values within ±{limit:g} {unit}, "
                               f"got [{start:g}, {stop:g}]")
    return (start, stop, count)


def _as_names(value: Any, key: str, where: _Where) -> tuple[str, ...]:
    if not isinstance(value, (list, tuple)) or not value:
        raise _expect(where, key, "a non-empty list of strings", value)
    names = tuple(_as_str(v, key, where) for v in value)
    if len(set(names)) != len(names):
        raise where.error(key, f"expected distinct names, got {list(names)!r}")
    return names


def _as_cant(value: Any, key: str, where: _Where) -> str | float:
    """A rail cant: ``"1:N"`` (N >= 5), ``"none"``, or a number in rad within [-0.2, 0.2]."""
    expected = 'a cant "1:N" (N >= 5), "none", or a number in rad within [-0.2, 0.2]'
    if isinstance(value, str):
        text = value.strip()
        if text == "none":
            return "none"
        head, _, tail = text.partition(":")
        try:
            n = float(tail)
        except ValueError:
            raise _expect(where, key, expected, value) from None
        if head.strip() != "1" or not math.isfinite(n) or n < 5:
            raise _expect(where, key, expected, value)
        return f"1:{tail.strip()}"
    out = _as_float(value, key, where)
    if abs(out) > 0.2:
        raise _expect(where, key, expected, value)
    return out


def _as_gauge_point(value: Any, key: str, where: _Where) -> str | float:
    """``"depth"``, ``"first"``, ``"last"`` (a point of the file) or a lateral coordinate, mm."""
    if isinstance(value, str):
        if value not in GAUGE_POINTS:
            raise _expect(where, key, "one of " + ", ".join(repr(g) for g in GAUGE_POINTS)
                          + " or a lateral coordinate in mm", value)
        return value
    out = _as_float(value, key, where)
    if abs(out) > 200.0:
        raise _expect(where, key, "a lateral coordinate within ±200 mm", value)
    return out


def _shared_candidate(rel: Path) -> Path | None:
    """``../shared/x`` also in the shared folder :func:`lutmpi.paths.shared_dir` finds
    (``LUTMPI_SHARED``, beside the checkout, ``/work/shared``): validation data that must not be
    copied into the repository, read from wherever the checkout is."""
    from lutmpi.paths import shared_dir

    parts = rel.parts
    if rel.is_absolute() or "shared" not in parts:
        return None
    k = parts.index("shared")
    if any(p != ".." for p in parts[:k]):
        return None
    base = shared_dir()
    return None if base is None else base.joinpath(*parts[k + 1:])


def _as_profile(value: Any, key: str, where: _Where) -> Path:
    """Resolve a profile path (config directory, current directory, source checkout)."""
    if isinstance(value, os.PathLike):
        value = os.fspath(value)
    text = _as_str(value, key, where)
    tried: list[Path] = []
    try:
        rel = Path(text).expanduser()
        roots = [] if rel.is_absolute() else [where.base_dir, Path.cwd(), _SOURCE_ROOT]
        candidates = [rel] if rel.is_absolute() else [root / rel for root in roots]
        shared = _shared_candidate(rel)
        if shared is not None:
            candidates.append(shared)
        for cand in candidates:
            if cand in tried:
                continue
            tried.append(cand)
            if cand.is_file():
                return cand.resolve()
    except (OSError, ValueError, RuntimeError) as exc:   # NUL byte, name too long, bad ~user
        raise where.error(key, f"invalid profile path {text!r}: {exc}") from None
    looked = ", ".join(str(c) for c in tried)
    folders = [str(c) for c in tried if c.is_dir()]
    if folders:
        raise where.error(key, f"profile path {text!r} is a folder ({folders[0]}), not a "
                               "profile file")
    raise where.error(key, f"profile file not found: {text!r} (looked for {looked})")


_CONVERTERS: dict[Any, typing.Callable[[Any, str, _Where], Any]] = {
    float: _as_float,
    int: _as_int,
    bool: _as_bool,
    str: _as_str,
    str | None: _as_str,
    Path | None: _as_profile,
    tuple[float, float, int]: _as_axis,
    tuple[str, ...]: _as_names,
    float | None: _as_float,
    bool | None: _as_bool,
    str | float: _as_cant,
    str | float | None: _as_cant,
}
_GAUGE_POINT_KEYS = {"rail.gauge_point", "rail.left.gauge_point", "rail.right.gauge_point"}


def _rule_key(key: str) -> str:
    """``wheel.left.nominal_radius_mm`` -> ``wheel.nominal_radius_mm`` (side keys share rules)."""
    parts = key.split(".")
    if len(parts) == 3 and parts[0] in ("wheel", "rail") and parts[1] in SIDE_NAMES:
        return f"{parts[0]}.{parts[2]}"
    if len(parts) == 4 and parts[0] == "wear" and parts[2] in SIDE_NAMES:
        return f"wear.{parts[1]}.{parts[3]}"
    return key


def _build(cls: type, table: Any, prefix: str, where: _Where) -> Any:
    """One (possibly nested) section: reject unknown keys, convert and check the given ones."""
    if not isinstance(table, Mapping):
        raise _expect(where, prefix, f"a table [{prefix}]", table)
    fields = section_fields(cls)
    for key in table:
        if f"{prefix}.{key}" in REMOVED_KEYS:
            raise where.error(f"{prefix}.{key}", "this key was removed: "
                              + REMOVED_KEYS[f"{prefix}.{key}"] + "; delete it from the config")
        if key not in fields:
            valid = ", ".join(fields)
            raise where.error(f"{prefix}.{key}", f"unknown key in [{prefix}]; valid keys: {valid}")
    kwargs = {}
    for name, hint in fields.items():
        dotted = f"{prefix}.{name}"
        if dataclasses.is_dataclass(hint):
            kwargs[name] = _build(hint, table.get(name, {}), dotted, where)
        elif name in table:
            kwargs[name] = _convert(hint, table[name], dotted, where)
    return cls(**kwargs)


def _convert(hint: Any, value: Any, key: str, where: _Where) -> Any:
    converter = _as_gauge_point if key in _GAUGE_POINT_KEYS else _CONVERTERS.get(hint)
    if converter is None:   # a field type added to model.py without a converter: programming error
        raise TypeError(f"no TOML converter for {key} of type {hint!r}")
    if value is None and hint in (str | None, Path | None, float | None, bool | None):
        return None
    out = converter(value, key, where)
    rule = _RULES.get(_rule_key(key))
    if rule is not None and not rule[0](out):
        raise _expect(where, key, rule[1], value)
    return out


def _check_source(section: Any, name: str, where: _Where) -> None:
    """One section's own source keys: not both profile and generator, no format for a
    generator."""
    if section.profile is not None and section.generator is not None:
        raise where.error(name, "give either 'profile' (a file) or 'generator', not both")
    if section.generator is not None and section.format is not None:
        raise where.error(f"{name}.format", "'format' applies to a profile file, not a generator")


def _check_sides(base: Any, name: str, where: _Where) -> None:
    """``[wheel]`` / ``[rail]`` and their side sections: each side must end up with exactly one
    source (its own or the base's)."""
    _check_source(base, name, where)
    for side in SIDE_NAMES:
        _check_source(getattr(base, side), f"{name}.{side}", where)
    for side in SIDE_NAMES:
        res = base.side(side)
        if res.profile is None and res.generator is None:
            if not base.per_side:
                raise where.error(name, "expected 'profile = \"path\"' or "
                                        "'generator = \"...\"', got neither")
            other = SIDE_NAMES[1 - SIDE_NAMES.index(side)]
            raise where.error(f"{name}.{side}", f"the {side} {name} has no profile: [{name}] "
                              f"gives none and [{name}.{side}] is missing or gives none "
                              f"(while [{name}.{other}] is given)")
        if res.generator is not None and res.format is not None:
            raise where.error(f"{name}.{side}.format",
                              "'format' applies to a profile file, not a generator")
    _check_reading_options(base, name, where)


# the keys of ReadOptions (lutmpi/profiles/options.py) a config gives: they act on a file's points
_READING_OPTIONS = ("flip_y", "flip_z", "origin", "offset_y_mm", "offset_z_mm")


def _check_reading_options(base: Any, name: str, where: _Where) -> None:
    """The reading options (flip, origin, offsets) act on a file's points only: one that only a
    generator takes is an error naming its key, not a silent no-op. A ``[wheel]`` / ``[rail]``
    option is fine while some side reads a file with it; an option at its default (as a
    written-back config gives it) is never an error."""
    defaults = type(base)()
    for opt in _READING_OPTIONS:
        if not hasattr(base, opt):   # origin: wheels only
            continue
        default = getattr(defaults, opt)
        takers = []   # the sides that take [name]'s value of opt
        for side in SIDE_NAMES:
            res, own = base.side(side), getattr(getattr(base, side), opt)
            if own is None:
                takers.append((side, res))
            elif res.generator is not None and own != default:
                raise _generator_option(where, f"{name}.{side}.{opt}", name, side, res.generator)
        if getattr(base, opt) != default and takers and all(
                res.generator is not None for _, res in takers):
            side, res = takers[0]
            raise _generator_option(where, f"{name}.{opt}", name,
                                    side if len(takers) < len(SIDE_NAMES) else None,
                                    res.generator)


def _generator_option(where: _Where, key: str, name: str, side: str | None,
                      generator: str | None) -> ConfigError:
    opt = key.rsplit(".", 1)[1]
    what = f"the {side} {name}" if side else f"the {name}"
    return where.error(key, f"'{opt}' is a reading option and applies to a profile file only; "
                            f"{what} is the built-in generator {generator!r}: delete the key "
                            "or give a profile file")


def _check_output(cfg: Config, where: _Where) -> None:
    for method in cfg.output.methods:
        if method not in ALL_METHODS:
            raise _expect(where, "output.methods", "names from " + ", ".join(ALL_METHODS), method)
    quantities = cfg.output.quantities
    if quantities != ("all",):
        for q in quantities:
            if q not in QUANTITIES:
                raise _expect(where, "output.quantities",
                              '["all"] or names from ' + ", ".join(QUANTITIES), q)
    if cfg.contact.roll == "zero" and set(cfg.output.methods) != {"reference"}:
        raise where.error("contact.roll", "roll = 'zero' (wheelset held level) applies to the "
                          "rigid reference only: expected output.methods = ['reference'], got "
                          f"{list(cfg.output.methods)!r}")
    if cfg.contact.method not in cfg.output.methods:
        raise where.error("output.methods", f"contact.method {cfg.contact.method!r} must be one of "
                                            f"output.methods, got {list(cfg.output.methods)!r}")


def _check_cross(cfg: Config, where: _Where) -> None:
    """Rules that involve more than one key."""
    _check_sides(cfg.wheel, "wheel", where)
    _check_sides(cfg.rail, "rail", where)
    need = cfg.wheelset.back_to_back_mm + 2.0 * MIN_FLANGE_THICKNESS_MM
    if cfg.track.gauge_mm <= need:
        raise where.error("track.gauge_mm", f"expected gauge > back_to_back_mm + 2 x "
                          f"{MIN_FLANGE_THICKNESS_MM:g} mm flange = {need:g} mm, "
                          f"got {cfg.track.gauge_mm:g} mm")
    eq = cfg.equilibrium
    if eq.max_kc_N_per_m < eq.initial_kc_N_per_m:
        raise where.error("equilibrium.max_kc_N_per_m", f"expected >= initial_kc_N_per_m = "
                          f"{eq.initial_kc_N_per_m:g}, got {eq.max_kc_N_per_m:g}")
    _check_output(cfg, where)


def config_from_dict(data: Mapping, path: str | os.PathLike | None = None,
                     base_dir: str | os.PathLike | None = None) -> Config:
    """Validate a parsed TOML mapping and build the :class:`Config`.

    Parameters
    ----------
    data : Mapping
        ``{"wheel": {...}, "rail": {...}, ...}`` as ``tomllib`` returns it.
    path : path-like, optional
        The file the data came from: named in every error and stored as ``Config.path``.
    base_dir : path-like, optional
        Directory for relative profile paths; default: the directory of ``path``, else the cwd.

    Raises
    ------
    ConfigError
        See the module docstring.
    """
    where = _Where(None if path is None else str(path),
                   Path(base_dir) if base_dir is not None
                   else (Path(path).parent if path is not None else Path.cwd()))
    if not isinstance(data, Mapping):
        raise _expect(where, None, "a TOML document (a table of sections)", data)
    sections = section_fields(Config)
    for name in data:
        if name not in sections:
            raise where.error(str(name), "unknown section; valid sections: " + ", ".join(sections))
    for name in REQUIRED_SECTIONS:
        if name not in data:
            raise where.error(name, f"missing required section [{name}]")
    built = {name: _build(cls, data.get(name, {}), name, where) for name, cls in sections.items()}
    if "methods" not in data.get("output", {}):
        built["output"] = dataclasses.replace(built["output"], methods=(built["contact"].method,))
    cfg = Config(**built, path=None if path is None else Path(path))
    _check_cross(cfg, where)
    return cfg


# ------------------------------------------------------------------------------------ writing

def _toml_string(text: str) -> str:
    out = []
    for ch in text:
        if ch in '"\\':
            out.append("\\" + ch)
        elif ord(ch) < 0x20 or ord(ch) == 0x7F:
            out.append(f"\\u{ord(ch):04x}")
        else:
            out.append(ch)
    return '"' + "".join(out) + '"'


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)   # shortest repr that reads back to the same float
    if isinstance(value, (str, Path)):
        return _toml_string(str(value))
    if isinstance(value, (tuple, list)):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    raise TypeError(f"cannot write {value!r} as TOML")


def _emit(obj: Any, name: str, lines: list[str]) -> None:
    nested, own = [], []
    for field_name in section_fields(type(obj)):
        value = getattr(obj, field_name)
        if dataclasses.is_dataclass(value):
            nested.append((field_name, value))
        elif value is not None:   # None (no generator / no format) is written as an absent key
            own.append(f"{field_name} = {_toml_value(value)}")
    if own:
        lines.extend([f"[{name}]", *own, ""])
    for field_name, value in nested:
        _emit(value, f"{name}.{field_name}", lines)


def config_to_toml(cfg: Config) -> str:
    """The fully resolved configuration as TOML: every key with its value, profile paths absolute.

    ``config_from_dict(tomllib.loads(config_to_toml(cfg)), path=cfg.path) == cfg``.
    """
    lines = ["# lutmpi resolved configuration"
             + (f" (from {cfg.path})" if cfg.path is not None else ""), ""]
    for name in section_fields(Config):
        _emit(getattr(cfg, name), name, lines)
    return "\n".join(lines)
