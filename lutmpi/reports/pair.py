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
            if value:
                wear.append(f"{part} {key.removesuffix('_mm').replace('_', ' ')} {value:g} mm")
    return PairInfo(
        wheel=_source(wheel), rail=_source(rail),
        cant=str(rail.get("inclination", "1:20")),
        gauge_mm=float(track.get("gauge_mm", dflt_track.gauge_mm)),
        back_to_back_mm=float(ws.get("back_to_back_mm", dflt_ws.back_to_back_mm)),
        r0_mm=float(wheel.get("nominal_radius_mm", 460.0)),
        wear=", ".join(wear))


#: EN 15302 Annex E cases with equal wheels (right / left wheel profile, rail, diameters 920 mm):
#: reference wheel profile file stem -> case
EN15302_SYMMETRIC = {"RUIC519A": "E1", "RUIC519B": "E2", "RUIC519H": "E3", "RUIC519I": "E4"}
EN15302_RAIL = "SUIC519A"


def en15302_case(config_toml: str) -> str | None:
    """The EN 15302 Annex E case a table's configuration is (``E1`` … ``E4``), else None.

    Recognised by the standard's reference profile files (wheel ``RUIC519A/B/H/I``, rail
    ``SUIC519A``) with equal wheels of 920 mm diameter; the cases with unequal diameters or
    profiles (E5 … E9) need per-side wheels and are not matched here."""
    cfg = tomllib.loads(config_toml or "")
    wheel, rail = cfg.get("wheel", {}), cfg.get("rail", {})
    if not wheel.get("profile") or not rail.get("profile"):
        return None
    if Path(str(rail["profile"])).stem.upper() != EN15302_RAIL:
        return None
    if abs(float(wheel.get("nominal_radius_mm", 460.0)) - 460.0) > 1e-9:
        return None
    return EN15302_SYMMETRIC.get(Path(str(wheel["profile"])).stem.upper())
