"""Checksums of the tables the production solver builds, for the "bit-identical before/after"
checks of issue 15 (contact methods as units) and issue 14 (compiled pose loop).

A checksum is the SHA-256 of the bytes of one dataset of one method group, exactly as
:func:`lutmpi.table.compute.compute_points` produces it for the table writer (timing datasets
excluded). They are computed in-process on the configs' own profiles and meshes, over the
config's grid or a sub-grid of it, for every contact method.

    PYTHONPATH=. .venv/bin/python -m tests.support.checksums   # prints this CPU class's JSON
    PYTHONPATH=. .venv/bin/python -m tests.support.checksums --dump-values   # the 7 x 7 values

The last bits depend on the machine's instruction set: on an AVX-512 machine they differ from an
AVX2 one (2026-11-28: the same code, on the AMD EPYC VM without AVX-512, differed from the Intel
Xeon VM's checksums in ``roll`` and ``normal`` of the load centre and the max-(normal-)distance
methods, and ``x_g`` of max distance, in 5 of 16 method groups). So the data file holds one set
per CPU class (:func:`cpu_class`), each derived on a machine of its class; the test compares
with its own class's, and the printed JSON replaces that class's entry of the file. The cause is
not OpenBLAS's choice of kernel: ``OPENBLAS_CORETYPE=Prescott`` changed 96 datasets (the rigid
contact points went through numba's ``np.dot``, OpenBLAS ``dgemv``, and on into the mesh
methods' start), but since they are computed by :func:`lutmpi.geometry.fused.body_to_track`
(the same bits as the AVX2 kernel) Prescott, Core2, Nehalem, Sandybridge, Haswell and Zen
kernels give the same full tables to the bit, and a test keeps it so. The 2 x 2 Newton solve
(LAPACK through numba) gave the same bits under all of them on random systems. Left as
suspects for the AVX-512 difference: OpenBLAS's AVX-512 ``dgesv`` path and numpy's AVX-512
float64 ufuncs (SVML), neither of which an AVX2 machine can run.

A deliberate change of the arithmetic re-derives the file in its own commit, with the largest
differences it made. A machine can derive only its own class's set: the commit then removes the
other classes' sets (their machines skip the bit tests, saying why) and writes the 7 x 7
records with ``--dump-values`` (``tests/data/table_values_7x7.npz``), which every machine
compares by value (:func:`value_differences`, to :data:`VALUE_TOL`), so a class without its own
set is still held to the tables until one of its machines derives it. To compare trees:
``--dump FILE.npz`` (in each tree: ``git archive BASE | tar -x -C /tmp/base``,
``PYTHONPATH=/tmp/base``) writes the full-grid records, ``--compare A.npz B.npz`` prints the
largest difference of each dataset and how many poses moved by more than 1e-9.

History: derived before the contact methods were reorganised (issue 15); re-derived when the
rigid locus of the chosen root came to be computed compiled (issue 14: its gaps and angles no
longer go through numpy's BLAS product; reference and max-(normal-)distance tables moved by at
most 1.4e-11 m/rad, the load centre moved in 1 of 1369 paper poses and 7 of 1369 Manchester
poses by up to 13 um / 5e-4 rad, a k_c iteration that ends on another mesh node); re-derived
when the equilibrium's bracketing stopped evaluating a pose twice (issue 14: only the load
centre's ``iterations``, the count of contact evaluations, changed: in 4 paper and 20 Manchester
poses, by up to 43 fewer); re-derived when a widened contact window that finds no further
node in contact keeps the narrower window's pose instead of solving again (issue 14: again only
``iterations`` changed, in 26 paper and 8 Manchester poses of the mesh methods: the solve
again had found the same pose to the bit); re-derived when the rigid contacts of the chosen
root and every method's stored contact geometry came to be computed compiled (issue 14: numba's
arcsin, arctan and arctan2 round differently from numpy's in the last bit; the largest
differences over both full grids: 2.5e-14 rad of contact angle, 2.3e-13 1/m of curvature,
2.2e-15 m of z_g, 2.2e-3 N/m of a k_c of up to 5.5e10 N/m; no pose moved by more than 1e-9 in any
quantity but k_c and force, whose 1e-9 is below their last bits); re-derived when the
whole-profile gaps took the locus angle's sine and cosine by the angle-sum identity, as the
roll scan already did (issue 14: rigid roots moved within the solver's 1e-13 rad tolerance,
the reference's evaluation count by one in 324 paper and 224 Manchester poses; the mesh
methods' k_c by up to 5e-2 N/m of 5e10; the load centre moved in 1 paper pose (y = -5.5 mm,
yaw -0.06 rad, one that brackets), by 13 um / 5e-4 rad as at the first re-derivation, and in 13
Manchester poses by up to 0.6 um / 4e-7 rad: flange contacts whose k_c iteration ends on
another node); re-derived when the rail's gauge point came to be solved on the profile's own
curve instead of between its 0.05 mm samples (2026-11-24, a reviewer's find: the placed rail
moved laterally by 0.40 um on the paper's UIC60 at 1:20 and by 1.93 um on the Manchester rail,
whose gauge face is steeper there; every pose moved, the reference's z_g by a median 5 nm /
0.13 um and a 99th percentile 2.4 / 9.5 um (paper / Manchester: flange contacts, where a lateral
shift is multiplied by the tangent of the contact angle), and near jumps a second contact
appears or goes in a few poses); re-derived when Newton came to accept a step that its line
search shortened below a fifth of the pose's resolution (2026-11-24, issue 14: only the load
centre moved, in 74 paper and 108 Manchester poses, all with fewer contact evaluations (5 742 ->
5 094 and 7 002 -> 5 872 over the grids); z_g by at most 38 nm / 0.15 um, the contact angle by
5e-8 / 5e-4 rad, and in 16 Manchester poses the rolling radius by up to 7.5 um, where the
centroid's nodes changed; every status the same); re-derived when the nested bracketing came
to search the roll of a pose with y < 0 as its mirror pose searches it (2026-11-24: only the
load centre moved, in 2 paper and 2 Manchester poses that bracket, by up to 0.42 um / 6.9 nm of
z_g; both full grids are now mirror-symmetric to 4e-15 in z_g and roll for every method, where 2
pose pairs of each differed by up to 0.57 um / 8.9 nm); re-derived when a locus gap minimum
that its neighbouring samples do not resolve (one more than 1 um above it) came to be resampled
between them instead of taken from the parabola through three 0.1 mm samples (2026-11-24: a
yawed worn flange on a steep gauge face dipped 0.15 mm between samples; every method moved, the
reference in ~580 of each grid's 1369 poses by up to 1.7 um (paper) / 4.2 um (Manchester) of
z_g, the flange wheel that hovered up to 0.99 um above its rail now touching it to 7 nm by a
brute-force check over the wheel surface; the mesh methods through their rigid start and
windows, the load centre by up to 2.4 um of z_g and 45 um of rolling radius in 24 poses);
re-derived when every discrete gap minimum within 5 mm of the smallest came to be resampled
(not only the smallest's), and the rigid contacts to be placed where the resampled locus has its
minimum, not by the parabola through three samples (2026-11-24: the reference's contacts moved
in 580 paper and 612 Manchester poses, by up to 8.5 / 54 um of rolling radius and 0.8 / 6.0 mrad
of contact angle, onto the point a brute-force surface search finds to ~1 um where they lay up
to 21 um of profile from it; its z_g in 4 Manchester poses by 0.72 um; the mesh methods through
their rigid start, the load centre by up to 0.51 / 1.6 um of z_g; every status and contact
count the same; in 4 Manchester double contacts the two slots of the reference swapped, their
gaps now equal to rounding); re-derived when the sub-samples next to such a minimum, where
they too lie more than 1 um above it, came to be resampled once more 1 um apart (2026-11-24:
4 Manchester poses, by 2 nm of z_g and 57 urad of the reference's contact angle; the rest to
rounding: the contacts' coordinates are now computed from the position in sample units);
re-derived when the sample interval beyond each neighbour of an unresolved smallest sample came
to be resampled too (2026-11-27: where two neighbouring samples are equally low, the touching
height jumped by a dip's depth as they swapped, and a root could sit on that jump; on these two
grids only rounding moved: z_g and roll by at most 9e-16, contact angles by 2.6e-12 rad,
curvatures by 9.6e-10 1/m, k_c by 0.40 N/m of ~5e10, and the reference's evaluation count by
one or two in 16 paper and 44 Manchester poses).
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from pathlib import Path

from lutmpi.config import load_config
from lutmpi.config.model import ALL_METHODS
from lutmpi.paths import REPO_ROOT
from lutmpi.scene import Scene
from lutmpi.table.compute import compute_points, default_solver
from lutmpi.table.grid import Grid
from lutmpi.table.schema import FIELDS, TIMING_FIELDS

DATA = Path(__file__).resolve().parents[1] / "data" / "table_checksums.json"
#: the 7 x 7 records themselves (both configs, every method), for a CPU class without its own
#: checksums: compared by value (:func:`value_differences`)
VALUES = DATA.with_name("table_values_7x7.npz")
#: a stored value and a computed one agree when ``|a - b| <= VALUE_TOL * max(1, |b|)`` (SI:
#: 1 nm, 1 nrad; 50 N/m of a k_c of 5e10): last bits of another CPU's rounding, far below any
#: physics a change could move
VALUE_TOL = 1e-9
#: datasets left out of the comparison by value: the count of contact evaluations, a cost that
#: a last-bit difference can move by one without any stored quantity moving
NOT_COMPARED = ("iterations",)
CONFIGS = {"paper": "configs/paper_s1002_uic60_1in20.toml",
           "manchester": "configs/manchester_s1002_uic60_1in40.toml"}
#: 7 x 7 of the configs' 37 x 37 points (every 6th value of each axis: same range, flange and
#: tread poses, both yaw signs); "full" is the whole 37 x 37 grid
GRIDS = {"7x7": ((-9.0, 9.0, 7), (-0.12, 0.12, 7)), "full": None}


def cpu_class() -> str:
    """The class of CPU whose tables' bits the stored checksums are kept per: numpy's
    ``AVX512_SKX`` dispatch (``avx512_skx``), else AVX2 with FMA (``x86_64_v3``), else the
    machine's name."""
    try:
        from numpy._core._multiarray_umath import __cpu_features__ as feats
    except ImportError:   # numpy < 2
        from numpy.core._multiarray_umath import __cpu_features__ as feats
    if feats.get("AVX512_SKX"):
        return "avx512_skx"
    if feats.get("AVX2") and feats.get("FMA3"):
        return "x86_64_v3"
    import platform

    return platform.machine()


def table_checksums(config: str, grid: str, methods=ALL_METHODS) -> dict[str, dict[str, str]]:
    """``method -> dataset -> sha256 hex`` of the records of ``config`` on grid ``grid``."""
    return {m: {name: hashlib.sha256(arr.tobytes()).hexdigest() for name, arr in recs.items()}
            for m, recs in _records(config, grid, methods).items()}


def _records(config: str, grid: str, methods) -> dict[str, dict]:
    """``method -> dataset -> array`` of ``config`` on grid ``grid`` (timing datasets left
    out)."""
    import numpy as np

    cfg = load_config(REPO_ROOT / CONFIGS[config])
    if GRIDS[grid] is not None:
        y, yaw = GRIDS[grid]
        cfg = dataclasses.replace(cfg, grid=dataclasses.replace(cfg.grid, y_mm=y, yaw_rad=yaw))
    g = Grid.from_config(cfg.grid)
    recs, _ = compute_points(Scene.from_config(cfg), g, np.arange(g.n_points), list(methods),
                             default_solver(), FIELDS)
    return {m: {name: arr for name, arr in recs[m].items() if name not in TIMING_FIELDS}
            for m in methods}


def dump_values(path: str | Path = VALUES) -> None:
    """The 7 x 7 records of both configs, every method, into ``path`` (``.npz``), with the CPU
    class that computed them (``__cpu_class__``)."""
    import numpy as np

    out = {"__cpu_class__": np.array(cpu_class())}
    for config in CONFIGS:
        for m, recs in _records(config, "7x7", ALL_METHODS).items():
            out.update({f"{config}/{m}/{name}": arr for name, arr in recs.items()})
    np.savez_compressed(path, **out)


def value_differences(config: str, stored: dict | None = None) -> list[str]:
    """The datasets of ``config``'s 7 x 7 records that differ from the stored values
    (:data:`VALUES`) beyond :data:`VALUE_TOL` (NaN where the other is NaN, integers exactly;
    :data:`NOT_COMPARED` left out), each with its largest difference."""
    import numpy as np

    if stored is None:
        with np.load(VALUES) as f:
            stored = {k: f[k] for k in f.files}
    got = _records(config, "7x7", ALL_METHODS)
    out = []
    for key in sorted(k for k in stored if k.startswith(f"{config}/")):
        _, m, name = key.split("/")
        if name in NOT_COMPARED:
            continue
        a = np.asarray(got[m][name])
        b = np.asarray(stored[key])
        if a.shape != b.shape or a.dtype.kind != b.dtype.kind:
            out.append(f"{key}: shape/dtype {a.shape}/{a.dtype} vs stored {b.shape}/{b.dtype}")
        elif a.dtype.kind != "f":
            if not np.array_equal(a, b):
                out.append(f"{key}: {int((a != b).sum())} values differ")
        else:
            nan_a, nan_b = np.isnan(a), np.isnan(b)
            d = np.where(nan_a | nan_b, 0.0, np.abs(a - b))
            bad = (nan_a != nan_b) | (d > VALUE_TOL * np.maximum(1.0, np.abs(np.nan_to_num(b))))
            if bad.any():
                out.append(f"{key}: {int(bad.sum())} values beyond the tolerance (largest "
                           f"difference {float(d.max()):.3g}; NaN patterns "
                           f"{'differ' if (nan_a != nan_b).any() else 'agree'})")
    return out


def all_checksums(grids=("7x7", "full")) -> dict:
    return {f"{c}/{g}": table_checksums(c, g) for g in grids for c in CONFIGS}


def dump(path: str) -> None:
    """The full-grid records of both configs, every method, into one ``.npz``."""
    import numpy as np

    out = {}
    for config in CONFIGS:
        for m, recs in _records(config, "full", ALL_METHODS).items():
            out.update({f"{config}/{m}/{name}": arr for name, arr in recs.items()})
    np.savez(path, **out)


def compare(a_path: str, b_path: str) -> None:
    """Largest difference per dataset between two :func:`dump` files, and the poses that moved
    by more than 1e-9."""
    import numpy as np

    a, b = np.load(a_path), np.load(b_path)
    for key in a.files:
        x, y = a[key].astype(float), b[key].astype(float)
        if x.tobytes() == y.tobytes():
            continue
        d = np.where(np.isnan(x) & np.isnan(y), 0.0, np.abs(x - y))
        per_pose = np.nan_to_num(d.reshape(d.shape[0], -1), nan=np.inf).max(axis=1)
        print(f"{key:55s} max {np.nanmax(d):.3e}  poses > 1e-9: {int((per_pose > 1e-9).sum())}")


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] == ["--dump"]:
        dump(sys.argv[2])
    elif sys.argv[1:2] == ["--dump-values"]:
        dump_values()
    elif sys.argv[1:2] == ["--compare"]:
        compare(sys.argv[2], sys.argv[3])
    else:
        print(json.dumps(all_checksums(), indent=1, sort_keys=True))
