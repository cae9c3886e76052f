"""Helpers for the table tests: tiny configs, HDF5 comparison, launching ``lutmpi build``."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

from lutmpi.paths import REPO_ROOT
from lutmpi.table.schema import RUN_ATTRIBUTES, TIMING_FIELDS

HOOK = "tests.support.faulty_solver:solve"
LUTMPI = str(Path(sys.executable).with_name("lutmpi"))


#: two different measured wheels (profiles/) on two different rails: the per-side sections of a
#: config (issue 10's asymmetric wheelset)
_P = REPO_ROOT / "profiles"
TWO_MEASURED_WHEELS = f"""
[wheel.left]
profile = "{_P / 'Car7216_0001r.whl'}"
[wheel.right]
profile = "{_P / 'Car7358_0001r.whl'}"
[rail.left]
profile = "{_P / 'MBench_UIC60_v3.prr'}"
inclination = "none"
[rail.right]
profile = "{_P / 'rail_left_iter288.ban'}"
inclination = "none"
"""
#: the same with the right wheel's own nominal radius, 459 mm (the README's asymmetric example,
#: where a hostile tester found a flange step no cell showed, a fold of three rigid roots and
#: an extrapolation that ran off, y = 4.75-5.25 mm)
README_ASYMMETRIC = TWO_MEASURED_WHEELS.replace(
    "[rail.left]", "nominal_radius_mm = 459.0\n[rail.left]", 1)


def write_config(directory: Path, ny: int = 7, nyaw: int = 5, methods: tuple[str, ...] = (
        "load_centre",), quantities: tuple[str, ...] = ("all",), name: str = "t.toml") -> Path:
    """A small config (S1002/UIC60, grid ±9 mm x ±0.12 rad) written to ``directory``."""
    qs = ", ".join(f'"{q}"' for q in quantities)
    ms = ", ".join(f'"{m}"' for m in methods)
    text = (f'[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n'
            f'[grid]\ny_mm = [-9.0, 9.0, {ny}]\nyaw_rad = [-0.12, 0.12, {nyaw}]\n'
            f'[contact]\nmethod = "{methods[0]}"\n'
            f'[output]\nmethods = [{ms}]\nquantities = [{qs}]\n')
    path = directory / name
    path.write_text(text)
    return path


def datasets(path: Path) -> dict[str, np.ndarray]:
    """Every dataset of an HDF5 file by full name."""
    out: dict[str, np.ndarray] = {}
    with h5py.File(path, "r") as f:
        f.visititems(lambda name, obj: out.__setitem__(name, obj[...])
                     if isinstance(obj, h5py.Dataset) else None)
    return out


def root_attrs(path: Path) -> dict:
    with h5py.File(path, "r") as f:
        return dict(f.attrs)


def differences(a: Path, b: Path) -> list[str]:
    """Names of datasets/attributes that differ bit for bit (timing fields excluded)."""
    da, db = datasets(a), datasets(b)
    diff = sorted(set(da) ^ set(db))
    for name in sorted(set(da) & set(db)):
        if name.rsplit("/", 1)[-1] in TIMING_FIELDS:
            continue
        if da[name].dtype != db[name].dtype or da[name].tobytes() != db[name].tobytes():
            diff.append(name)
    aa, ab = root_attrs(a), root_attrs(b)
    for key in sorted(set(aa) | set(ab)):
        if key not in RUN_ATTRIBUTES and str(aa.get(key)) != str(ab.get(key)):
            diff.append("@" + key)
    return diff


def env(**extra: str) -> dict[str, str]:
    from lutmpi.parallel.mpi import mpirun_env

    e = mpirun_env()
    e["PYTHONPATH"] = str(REPO_ROOT) + os.pathsep + e.get("PYTHONPATH", "")
    e.pop("LUTMPI_FAULT", None)
    e.update(extra)
    return e


def build_command(config: Path, out: Path, ranks: int, *args: str) -> list[str]:
    """``[mpirun -n ranks] lutmpi build CONFIG -o OUT --solver HOOK ARGS`` (1 = no mpirun)."""
    cmd = [LUTMPI, "build", str(config), "-o", str(out), "--solver", HOOK, *args]
    return ["mpirun", "-n", str(ranks), *cmd] if ranks > 1 else cmd


def start_build(config: Path, out: Path, ranks: int, *args: str,
                **extra_env: str) -> subprocess.Popen:
    """:func:`build` in the background (text pipes for stdout and stderr)."""
    return subprocess.Popen(build_command(config, out, ranks, *args), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True, env=env(**extra_env),
                            cwd=str(REPO_ROOT), stdin=subprocess.DEVNULL)


def build(config: Path, out: Path, ranks: int, *args: str, timeout: float = 60,
          **extra_env: str) -> subprocess.CompletedProcess:
    """Run ``[mpirun -n ranks] lutmpi build CONFIG -o OUT --solver HOOK ARGS`` (1 = no mpirun)."""
    return subprocess.run(build_command(config, out, ranks, *args), capture_output=True,
                          text=True, timeout=timeout, env=env(**extra_env), cwd=str(REPO_ROOT))
