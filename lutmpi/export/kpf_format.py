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
  circle: the wheel's tape circle (GAUGE_TO_ORIGO = tape-circle distance minus half the gauge).

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


def side_columns(config: Any) -> dict[str, dict[str, tuple[np.ndarray, np.ndarray]]]:
    """``side -> {"wheel": (Y, Z), "rail": (Y, Z)}`` in m for a table's resolved configuration
    (:meth:`~lutmpi.table.Table.built_config`; each side as placed: its own profile, wear,
    inclination and gauge point)."""
    from lutmpi.scene import Scene

    scene = Scene.from_config(config)
    out = {}
    for name, side in scene.sides.items():
        wheel, rail = side.wheel, side.rail
        out[name] = {"wheel": wheel_columns(np.asarray(wheel.profile.y),
                                            np.asarray(wheel.profile.z)),
                     "rail": rail_columns(np.asarray(rail.u), np.asarray(rail.z), wheel.d)}
    return out


#: extensions an output stem may carry that the files' own replace (``-o case.wheel``)
STEM_SUFFIXES = (".wheel", ".rail", ".kpf")


def stem_of(out: Path) -> Path:
    """The stem of the files for the output ``out`` (not a directory): ``out`` itself, less a
    ``.wheel``/``.rail``/``.kpf`` extension; any other dot is part of the name
    (``case.v2`` -> ``case.v2.wheel``, never ``case.wheel``)."""
    return out.with_suffix("") if out.suffix.lower() in STEM_SUFFIXES else out


def with_ext(stem: Path, ext: str) -> Path:
    """``stem`` + ``ext`` (``.wheel``/``.rail``), keeping every dot of the stem."""
    return stem.with_name(stem.name + ext)


def _write(path: Path, y: np.ndarray, z: np.ndarray, lines: list[str]) -> Path:
    with open(path, "w") as fh:
        for line in lines:
            fh.write(f"# {line}\n")
        for a, b in zip(y * 1e3, z * 1e3, strict=True):
            fh.write(f"{a:12.5f} {b:12.5f}\n")
    return path


def write(table: Any, out: Path, **_: Any) -> list[Path]:
    """Write ``<stem>.wheel`` and ``<stem>.rail`` (``out`` a directory or a stem); a pair whose
    sides differ gives ``<stem>_left.wheel``, ``<stem>_right.wheel``, ... (KPF's Y runs toward
    the track centre on both sides, so one file serves both when they are mirror images)."""
    from lutmpi.reports.pair import pair_info

    stem = out / Path(table.path).stem if out.is_dir() else stem_of(out)
    sides = side_columns(table.built_config())   # raises where a profile file changed
    same = all(np.array_equal(sides["left"][k][i], sides["right"][k][i])
               for k in ("wheel", "rail") for i in (0, 1))
    head = [f"lutmpi export of {table.path}: {pair_info(table.config_toml).title}",
            "GENSYS KPF profile: Y [mm] toward the track centre, Z [mm] downwards"]
    paths = []
    for name in (("left",) if same else ("left", "right")):
        base = stem if same else stem.with_name(f"{stem.name}_{name}")
        side = "" if same else f"{name} side; "
        paths.append(_write(with_ext(base, ".wheel"), *sides[name]["wheel"], head + [
            f"{side}origin: nominal running circle (tape circle); Z = radius increase"]))
        paths.append(_write(with_ext(base, ".rail"), *sides[name]["rail"], head + [
            f"{side}origin: rail surface at the nominal running circle (GAUGE_TO_ORIGO "
            "outside the gauge point)"]))
    return paths
