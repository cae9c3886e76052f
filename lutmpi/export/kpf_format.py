"""``kpf``: the table's wheel and rail profiles as GENSYS program KPF reads them.

GENSYS builds its wheel-rail contact functions with its preprocessor KPF ("C(K)ontact Point
Function") from a wheel profile file and a rail profile file. This format writes the pair a table
was built from -- as lutmpi used it: generated or read, worn by the ``[wear]`` parameters, the rail
inclined -- so the same case can be run through KPF and its functions compared with the table's.

Source: GENSYS, *Users Manual for Program KPF* (https://gensys.se/doc_html/kpf.html, section "Wheel
profile input data") and *Users Manual for Program KPF_ROT* (https://gensys.se/doc_html/kpf_rot.html,
``ADJUST_ZERO``, ``GAUGE_TO_ORIGO``, ``GAUGE_MEAS_INTERVAL``):

* two columns ``Y Z`` in mm per line, free format, ``#`` starts a comment;
* Y positive toward the centre of the track (for both wheels), Z positive downwards;
* wheel: Y = 0 at the nominal running circle (the tape circle, 70 mm from the inside of the wheel),
  where Z = 0 -- so Z is the radius increase; the manual's example is S1002 and a test checks this
  module reproduces it;
* rail: origin on the rail surface GAUGE_TO_ORIGO = 32.5 mm (standard gauge) laterally from the
  gauge measuring point, which is the point nearest the track centre between the top of rail and
  GAUGE_MEAS_INTERVAL = 14 mm below it; Z(Y = 0) = 0. The origin is the rail's nominal running
  circle, half the distance between the tape circles minus half the gauge from the gauge point.

The file extensions are KPF's: ``.wheel`` and ``.rail``. This is a profile pair, not GENSYS's own
contact-function file (``*.kpfr``), whose layout the public manual excerpts available here do not
give; KPF makes that file from these two.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

NAME = "kpf"
DESCRIPTION = "GENSYS KPF wheel and rail profile files (.wheel, .rail) of the table's pair"


def _forward(y: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The points in profile order with Y increasing, dropping every node that steps back in Y
    (KPF_ROT: "Remove all nodes that make backsteps in the Y-direction")."""
    if y[-1] < y[0]:
        y, z = y[::-1], z[::-1]
    keep = np.concatenate(([True], y[1:] > np.maximum.accumulate(y)[:-1]))
    return y[keep], z[keep]


def wheel_columns(s: np.ndarray, dr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """KPF wheel ``(Y, Z)`` (m) from lutmpi's ``s`` (toward the field side) and ``dr(s)`` (m)."""
    return _forward(-s, dr)


def rail_columns(u: np.ndarray, z: np.ndarray, origin_u: float) -> tuple[np.ndarray, np.ndarray]:
    """KPF rail ``(Y, Z)`` (m) from a placed rail ``z(u)`` (u toward the field, z up).

    ``origin_u`` is the lateral position of the KPF origin (the nominal running circle)."""
    y, zz = _forward(origin_u - u, -z)
    return y, zz - float(np.interp(0.0, y, zz))


def pair_columns(config_toml: str) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """``{"wheel": (Y, Z), "rail": (Y, Z)}`` in m for a table's resolved configuration."""
    import tomllib

    from lutmpi.config.load import config_from_dict
    from lutmpi.geometry.track import PlacedRail
    from lutmpi.scene import load_scene_profiles

    cfg = config_from_dict(tomllib.loads(config_toml))
    wheel, rail = load_scene_profiles(cfg)
    placed = PlacedRail.place(rail, cfg.rail.inclination_rad, cfg.track.gauge_mm * 1e-3,
                              cfg.track.gauge_depth_mm * 1e-3)
    origin_u = cfg.wheelset.tape_half_distance_m
    return {"wheel": wheel_columns(np.asarray(wheel.y), np.asarray(wheel.z)),
            "rail": rail_columns(np.asarray(placed.u), np.asarray(placed.z), origin_u)}


def _write(path: Path, y: np.ndarray, z: np.ndarray, lines: list[str]) -> Path:
    with open(path, "w") as fh:
        for line in lines:
            fh.write(f"# {line}\n")
        for a, b in zip(y * 1e3, z * 1e3, strict=True):
            fh.write(f"{a:12.5f} {b:12.5f}\n")
    return path


def write(table: Any, out: Path, **_: Any) -> list[Path]:
    """Write ``<stem>.wheel`` and ``<stem>.rail`` (``out`` a directory or a stem)."""
    from lutmpi.reports.pair import pair_info

    stem = out / Path(table.path).stem if out.is_dir() else out.with_suffix("")
    cols = pair_columns(table.config_toml)
    head = [f"lutmpi export of {table.path}: {pair_info(table.config_toml).title}",
            "GENSYS KPF profile: Y [mm] toward the track centre, Z [mm] downwards"]
    return [
        _write(stem.with_suffix(".wheel"), *cols["wheel"],
               head + ["origin: nominal running circle (tape circle); Z = radius increase"]),
        _write(stem.with_suffix(".rail"), *cols["rail"],
               head + ["origin: rail surface 32.5 mm (GAUGE_TO_ORIGO) outside the gauge point"]),
    ]
