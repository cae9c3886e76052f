"""Compiled evaluation of SciPy's piecewise cubics (``CubicSpline`` and its derivatives): the
contact geometry of a pose evaluates a profile's spline at one or two points a dozen times, and
SciPy's call costs ~7 µs of overhead each time, several times the arithmetic.

:func:`fast` wraps a :class:`scipy.interpolate.PPoly` that extrapolates (a ``CubicSpline``,
``spline.derivative(n)``) in :class:`FastPPoly`, which computes what SciPy's ``_ppoly.evaluate``
computes, in its order of operations: the interval ``x[i] <= t < x[i+1]`` (the last one closed;
the first or last interval beyond the ends), then ``sum_k c[K-1-k, i] s^k`` with the powers
``s^k`` of ``s = t - x[i]`` built by repeated products and the terms added from the lowest
power up. The values are SciPy's to the bit (``tests/unit/test_profiles_spline.py`` checks
them on every kind of point). A smoothing ``BSpline`` is first written as the ``PPoly`` of its
own polynomial pieces (:func:`piecewise`), so that every profile is evaluated by this one code.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from scipy.interpolate import BSpline, PPoly


@njit(cache=True)
def ppoly_at(c, x, tv):
    """SciPy's ``PPoly`` evaluation (``dx = 0``, extrapolating) of coefficients ``c`` (K, m)
    on breakpoints ``x`` (m + 1,) at one point ``tv``; NaN at a NaN point."""
    if np.isnan(tv):
        return np.nan
    K = c.shape[0]
    i = np.searchsorted(x, tv, side="right") - 1
    i = min(max(i, 0), x.size - 2)
    s = tv - x[i]
    res = 0.0
    z = 1.0
    for kp in range(K):
        res = res + c[K - kp - 1, i] * z
        if kp < K - 1:
            z *= s
    return res


@njit(cache=True)
def ppoly_eval(c, x, t, out):
    """:func:`ppoly_at` at each of the points ``t``, into ``out``."""
    for p in range(t.size):
        out[p] = ppoly_at(c, x, t[p])
    return out


class FastPPoly:
    """A 1-D extrapolating :class:`~scipy.interpolate.PPoly`, evaluated compiled; called like
    it (``f(t)``: an array of ``t``'s shape, 0-d for a scalar)."""

    def __init__(self, pp: PPoly):
        self.pp = pp
        self.c = np.ascontiguousarray(pp.c, dtype=float)
        self.x = np.ascontiguousarray(pp.x, dtype=float)

    def __call__(self, t) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        flat = np.ascontiguousarray(t.ravel())
        return ppoly_eval(self.c, self.x, flat, np.empty(flat.size)).reshape(t.shape)

    def derivative(self, nu: int = 1) -> FastPPoly:
        return FastPPoly(self.pp.derivative(nu))


def fast(spline: PPoly) -> FastPPoly:
    """``spline`` evaluated compiled: a 1-D extrapolating ``PPoly`` with increasing
    breakpoints (a ``CubicSpline``, :func:`piecewise`, their derivatives)."""
    if not (isinstance(spline, PPoly) and spline.extrapolate is True and spline.c.ndim == 2
            and spline.x.size >= 2 and np.all(np.diff(spline.x) > 0)
            and np.isrealobj(spline.c)):
        raise TypeError(f"expected a 1-D extrapolating PPoly with increasing breakpoints, got "
                        f"{type(spline).__name__}")
    return FastPPoly(spline)


def piecewise(spline: BSpline) -> PPoly:
    """A ``BSpline`` (a measured profile's smoothing spline) as the ``PPoly`` of the same
    polynomial pieces: SciPy's ``PPoly.from_spline`` without the zero-width intervals of the
    repeated end knots, extrapolating the end pieces as the ``BSpline`` does. Its values are
    the B-spline's to rounding (a few 1e-18 m over a profile's data; ``tests/unit/
    test_profiles_spline.py``)."""
    pp = PPoly.from_spline(spline, extrapolate=True)
    keep = np.diff(pp.x) > 0
    x = np.append(pp.x[:-1][keep], pp.x[1:][keep][-1])
    return PPoly(np.ascontiguousarray(pp.c[:, keep]), x, extrapolate=True)
