"""Tables bit-identical before and after a redesign of the solver (issues 14, 15).

The stored checksums (``tests/data/table_checksums.json``) were computed by
``python -m tests.support.checksums`` with the solver of an earlier commit (an independent
computation: the code of that commit, not the code under test; the history of re-derivations
is in ``tests/support/checksums.py``), one set per CPU class (an AVX-512 machine rounds a few
poses differently from an AVX2 one: :func:`~tests.support.checksums.cpu_class`). Any change of
a stored bit -- in any dataset, any method, on the paper or the Manchester config -- fails
here; a deliberate change re-derives the file in its own commit, saying why and by how much the
tables moved. The 7 x 7 records themselves (``tests/data/table_values_7x7.npz``) are compared
by value on every machine, to 1e-9 relative: a machine of a class without checksums of its own
(a change of the arithmetic re-derives only the class of the machine it was made on, and
removes the others' sets) is then still held to the tables.
"""

from __future__ import annotations

import json
import os
import platform
import subprocess
import sys

import pytest

from lutmpi.paths import REPO_ROOT
from tests.support.checksums import (
    CONFIGS,
    DATA,
    VALUES,
    cpu_class,
    table_checksums,
    value_differences,
)

CLASSES = json.loads(DATA.read_text())

#: this machine's class's checksums; a class without any fails every test here (derive them on
#: a machine of that class, from a commit whose tables are known to be right)
STORED = CLASSES.get(cpu_class(), {})


def _has_avx2_fma() -> bool:
    """The CPU can run OpenBLAS's Haswell kernels (AVX2 and FMA)."""
    try:
        from numpy._core._multiarray_umath import __cpu_features__ as feats
    except ImportError:   # numpy < 2
        from numpy.core._multiarray_umath import __cpu_features__ as feats
    return bool(feats.get("AVX2") and feats.get("FMA3"))


def _differences(key: str) -> list[str]:
    config, grid = key.split("/")
    got = table_checksums(config, grid)
    want = STORED[key]
    return [f"{key} {m}/{name}" for m in want for name in want[m]
            if got.get(m, {}).get(name) != want[m][name]]


#: why a machine of a class without stored checksums compares by value only
NO_CLASS_SET = (f"no checksums stored for CPU class {cpu_class()!r} (stored: {sorted(CLASSES)}):"
                " its 7 x 7 tables are compared by value (test_subgrid_tables_agree_with_the_"
                "stored_values); derive its checksums on a machine of the class")


@pytest.mark.skipif(not STORED, reason=NO_CLASS_SET)
@pytest.mark.parametrize("config", sorted(CONFIGS))
def test_subgrid_tables_bit_identical(config):
    # 7 x 7 of the 37 x 37 grid, 4 methods: ~2 s per config
    assert _differences(f"{config}/7x7") == []


@pytest.mark.slow
@pytest.mark.skipif(not STORED, reason=NO_CLASS_SET)
@pytest.mark.parametrize("config", sorted(CONFIGS))
def test_full_tables_bit_identical(config):
    # the whole 37 x 37 grid, 4 methods: ~12 s per config on a quiet core
    assert _differences(f"{config}/full") == []


@pytest.mark.parametrize("config", sorted(CONFIGS))
def test_subgrid_tables_agree_with_the_stored_values(config):
    # on every CPU class: the stored 7 x 7 records (tests/data/table_values_7x7.npz) to
    # VALUE_TOL; the one comparison where a class has no checksums of its own, and the check
    # that the values file was re-derived with the checksums
    assert value_differences(config) == []


def test_the_comparison_by_value_tells_physics_from_last_bits():
    import numpy as np

    with np.load(VALUES) as f:
        stored = {k: f[k] for k in f.files if k.startswith("paper/")}
    assert value_differences("paper", stored) == []
    ulps = dict(stored)                            # another CPU's last bits pass
    for key in ("paper/load_centre/roll", "paper/reference/z_g", "paper/load_centre/kc"):
        ulps[key] = np.nextafter(stored[key], np.inf)
    assert value_differences("paper", ulps) == []
    for key, scale in (("paper/reference/z_g", 1 + 1e-8),          # 4.6 nm of z_g
                       ("paper/load_centre/kc", 1 + 1e-6)):       # a changed stiffness
        moved = dict(stored)
        moved[key] = stored[key] * scale
        assert [d.split(":")[0] for d in value_differences("paper", moved)] == [key]
    flipped = dict(stored)
    flipped["paper/load_centre/status"] = stored["paper/load_centre/status"].copy()
    flipped["paper/load_centre/status"][0] = 7              # a pose stored as failed
    assert [d.split(":")[0] for d in value_differences("paper", flipped)] == \
        ["paper/load_centre/status"]


def _checksums_under(coretype: str) -> dict:
    """The 7 x 7 checksums of every config, computed in a fresh process whose OpenBLAS uses the
    kernels of ``coretype``."""
    code = ("import json; from tests.support.checksums import CONFIGS, table_checksums; "
            "print(json.dumps({c: table_checksums(c, '7x7') for c in sorted(CONFIGS)}))")
    env = dict(os.environ, OPENBLAS_CORETYPE=coretype,
               PYTHONPATH=os.pathsep.join(filter(None, [str(REPO_ROOT),
                                                        os.environ.get("PYTHONPATH")])))
    run = subprocess.run([sys.executable, "-c", code], cwd=REPO_ROOT, env=env,
                         capture_output=True, text=True, timeout=600, check=False)
    assert run.returncode == 0, run.stderr[-2000:]
    return json.loads(run.stdout.strip().splitlines()[-1])


@pytest.mark.slow
@pytest.mark.skipif(platform.machine() not in ("x86_64", "AMD64") or not _has_avx2_fma(),
                    reason="needs an x86-64 CPU with AVX2 and FMA")
def test_tables_do_not_depend_on_the_blas_kernel_the_cpu_selects():
    # OpenBLAS picks its kernels by CPU: the SSE3-only Prescott kernels round differently from
    # the AVX2/FMA (Haswell) ones, on any machine that can run both. The rigid contact points
    # went through numba's np.dot (OpenBLAS dgemv) until 2026-11-28: under Prescott the
    # paper's 7 x 7 reference points and 26 Manchester datasets moved in their last bits.
    # (AVX-512 kernels are not compared: an AVX2 machine cannot run them.)
    haswell, prescott = _checksums_under("Haswell"), _checksums_under("Prescott")
    for config in sorted(CONFIGS):
        a, b = haswell[config], prescott[config]
        moved = [f"{m}/{name}" for m in a for name in a[m] if b[m][name] != a[m][name]]
        assert moved == [], f"{config}: datasets that change with OpenBLAS's kernel: {moved}"
