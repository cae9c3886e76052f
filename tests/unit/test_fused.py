"""The compiled fused multiply-add and the point transform built on it
(:mod:`lutmpi.geometry.fused`), against exact rational arithmetic: each result must be the
exact value rounded once (to nearest, ties to even), which is what makes the rigid contact
points independent of the BLAS kernel a CPU selects."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from lutmpi.contact.rigid_kernels import rotation
from lutmpi.geometry.fused import body_to_track, fma_py


def exact_fma(a: float, b: float, c: float) -> float:
    """``a * b + c`` rounded once (nonzero results; ``float(Fraction)`` rounds correctly)."""
    return float(Fraction(a) * Fraction(b) + Fraction(c))


def test_fma_rounds_once():
    rng = np.random.default_rng(3)
    a, b = rng.standard_normal((2, 20000))
    # c near -a*b: the cancellation where a rounded product loses what a fused one keeps
    c = -(a * b) * (1.0 + rng.uniform(-1e-12, 1e-12, a.size))
    split = 0
    for ai, bi, ci in zip(a, b, c, strict=True):
        want = exact_fma(ai, bi, ci)
        assert fma_py(ai, bi, ci) == want, (ai, bi, ci)
        split += want != ai * bi + ci
    assert split > 10000  # the cases really tell a fused from an unfused product


def test_fma_signed_zeros_and_specials():
    # IEEE 754: an exact zero sum is +0 unless both addends are -0
    assert math.copysign(1.0, fma_py(-0.0, 1.0, -0.0)) == -1.0
    assert math.copysign(1.0, fma_py(0.0, -1.0, 0.0)) == 1.0
    assert math.copysign(1.0, fma_py(2.0, 3.0, -6.0)) == 1.0
    assert math.isnan(fma_py(math.inf, 0.0, 1.0))
    assert fma_py(1e308, 10.0, -math.inf) == -math.inf


@pytest.mark.parametrize("yaw, roll", [(0.0, 0.0), (-0.0, 0.0), (0.12, -0.03), (-0.3, 0.07)])
def test_body_to_track_is_the_stated_sequence_of_single_roundings(yaw, roll):
    R = rotation(yaw, roll)
    rng = np.random.default_rng(5)
    for _ in range(500):
        c = np.array([rng.standard_normal() * 0.5, rng.standard_normal() * 0.8,
                      -rng.uniform(0.3, 0.6)])
        g = np.array([0.0, rng.standard_normal() * 0.01, rng.uniform(0.4, 0.5)])
        got = body_to_track(R, c[0], c[1], c[2], g[0], g[1], g[2])
        for i in range(3):
            inner = exact_fma(R[i, 0], c[0], R[i, 1] * c[1])
            want = g[i] + exact_fma(R[i, 2], c[2], inner)
            assert got[i] == want
            # and the exact G + R c to a few units in the last place of its largest term
            exact = sum(Fraction(R[i, j]) * Fraction(c[j]) for j in range(3)) + Fraction(g[i])
            scale = max(abs(g[i]), *(abs(R[i, j] * c[j]) for j in range(3)))
            assert abs(got[i] - float(exact)) <= 4 * np.spacing(scale)
