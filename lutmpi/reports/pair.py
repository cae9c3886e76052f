"""What a table was built for, in the words of a title: profile pair, cant, gauge, back-to-back.

Read from the resolved configuration every table stores (``config_toml``); pure (no files).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass
from pathlib import Path
from typing import Any


@dataclass(frozen=True)
class PairInfo:
    """The case of a table (mm at the edge)."""

    wheel: str
    rail: str
    cant: str
    gauge_mm: float
    back_to_back_mm: float
    r0_mm: float
    wear: str = ""

    @property
    def title(self) -> str:
        """``S1002 / UIC60 1:40, gauge 1435 mm, b2b 1360 mm`` (+ wear when any)."""
        cant = "as given" if self.cant == "none" else self.cant
        text = (f"{self.wheel} / {self.rail} {cant}, gauge {self.gauge_mm:g} mm, "
                f"b2b {self.back_to_back_mm:g} mm")
        return text + (f", {self.wear}" if self.wear else "")


def _source(section: dict[str, Any]) -> str:
    if section.get("generator"):
        return str(section["generator"])
    if section.get("profile"):
        return Path(str(section["profile"])).stem
    return "?"


def _side(section: dict[str, Any], name: str) -> dict[str, Any]:
    """A ``[wheel]``/``[rail]`` section resolved for one side: ``[wheel.left]`` keys over
    ``[wheel]``'s (a table without side sections gives the same for both)."""
    base = {k: v for k, v in section.items() if not isinstance(v, dict)}
    return {**base, **(section.get(name) or {})}


def _sides(section: dict[str, Any], what=_source) -> str:
    left, right = (what(_side(section, n)) for n in ("left", "right"))
    return left if left == right else f"{left} (left) | {right} (right)"


def pair_info(config_toml: str) -> PairInfo:
    """The :class:`PairInfo` of a table's ``config_toml`` (defaults for keys it leaves out)."""
    from lutmpi.config.model import Config

    cfg = tomllib.loads(config_toml or "")
    d = Config.__dataclass_fields__
    track = cfg.get("track", {})
    ws = cfg.get("wheelset", {})
    wheel, rail = cfg.get("wheel", {}), cfg.get("rail", {})
    dflt_track = d["track"].default_factory()          # type: ignore[misc]
    dflt_ws = d["wheelset"].default_factory()          # type: ignore[misc]
    wear = []
    for part, keys in cfg.get("wear", {}).items():
        for key, value in (keys or {}).items():
            # a side's own wear is a sub-table: [wear.wheel.left] flange_thinning_mm = 1
            for side, k, v in ([(key, kk, vv) for kk, vv in value.items()]
                               if isinstance(value, dict) else [("", key, value)]):
                if v:
                    wear.append(f"{part}{' ' + side if side else ''} "
                                f"{k.removesuffix('_mm').replace('_', ' ')} {v:g} mm")
    radii = [float(_side(wheel, n).get("nominal_radius_mm", 460.0)) for n in ("left", "right")]
    return PairInfo(
        wheel=_sides(wheel), rail=_sides(rail),
        cant=_sides(rail, lambda r: str(r.get("inclination", "1:20"))),
        gauge_mm=float(track.get("gauge_mm", dflt_track.gauge_mm)),
        back_to_back_mm=float(ws.get("back_to_back_mm", dflt_ws.back_to_back_mm)),
        r0_mm=0.5 * (radii[0] + radii[1]),
        wear=", ".join(wear))


#: EN 15302 Annex E cases (EN 15302:2008, Annex E): (right wheel, left wheel, right radius, left
#: radius in mm) -> case, all on reference rail A; wheels are the reference profile file stems
EN15302_CASES = {
    ("RUIC519A", "RUIC519A", 460.0, 460.0): "E1", ("RUIC519B", "RUIC519B", 460.0, 460.0): "E2",
    ("RUIC519H", "RUIC519H", 460.0, 460.0): "E3", ("RUIC519I", "RUIC519I", 460.0, 460.0): "E4",
    ("RUIC519A", "RUIC519A", 460.0, 459.0): "E5", ("RUIC519B", "RUIC519B", 460.0, 459.0): "E6",
    ("RUIC519H", "RUIC519H", 460.0, 459.0): "E7", ("RUIC519I", "RUIC519I", 460.0, 459.0): "E8",
    ("RUIC519A", "RUIC519B", 460.0, 460.0): "E9",
}
EN15302_RAIL = "SUIC519A"


def en15302_case(config_toml: str) -> str | None:
    """The EN 15302 Annex E case a table's configuration is (``E1`` … ``E9``), else None.

    Recognised by the standard's reference profile files (wheels ``RUIC519A/B/H/I`` right and
    left, rail ``SUIC519A`` on both sides) and the wheel diameters (920 mm, or 918 mm on the left
    wheel for E5-E8)."""
    cfg = tomllib.loads(config_toml or "")
    wheel, rail = cfg.get("wheel", {}), cfg.get("rail", {})
    rails = {_stem(_side(rail, n)) for n in ("left", "right")}
    if rails != {EN15302_RAIL}:
        return None
    key = (_stem(_side(wheel, "right")), _stem(_side(wheel, "left")),
           float(_side(wheel, "right").get("nominal_radius_mm", 460.0)),
           float(_side(wheel, "left").get("nominal_radius_mm", 460.0)))
    return EN15302_CASES.get(key)


def _stem(section: dict[str, Any]) -> str:
    return Path(str(section.get("profile", ""))).stem.upper()
