"""The compiled piecewise-cubic evaluation (:mod:`lutmpi.profiles.spline`, issue 14) gives
SciPy's values to the bit, so that every table stays what SciPy's call would have made it; a
measured profile's smoothing spline, evaluated as its pieces, its values to rounding."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline, make_smoothing_spline

from lutmpi.profiles.spline import FastPPoly, fast, piecewise
from lutmpi.profiles.standard import s1002, uic60


def _points(x: np.ndarray, rng) -> np.ndarray:
    """Every kind of point: random inside and beyond the ends, the breakpoints and their
    neighbours (the interval search's edges), the ends exactly, NaN."""
    return np.concatenate([rng.uniform(2 * x[0] - x[-1], 2 * x[-1] - x[0], 3000), x,
                           np.nextafter(x, np.inf), np.nextafter(x, -np.inf),
                           [x[0], x[-1], np.nan, -np.inf + 0 * x[0]]])


@pytest.mark.parametrize("seed", range(6))
def test_random_cubics_and_their_derivatives_to_the_bit(seed):
    rng = np.random.default_rng(seed)
    x = np.unique(rng.uniform(-0.07, 0.07, rng.integers(4, 600)))
    spl = CubicSpline(x, rng.normal(0, 0.01, x.size))
    for f in (spl, spl.derivative(1), spl.derivative(2), spl.derivative(3)):
        g = fast(f)
        assert isinstance(g, FastPPoly)
        t = _points(x, rng)
        assert np.array_equal(g(t), f(t), equal_nan=True)
        for s in (float(x[1]), 0.5 * (x[0] + x[1]), -1.0, 1.0):
            assert g(s).shape == f(s).shape == () and g(s) == f(s)
        t2 = t[: 2 * (t.size // 2)].reshape(2, -1)
        assert np.array_equal(g(t2), f(t2), equal_nan=True)
    assert np.array_equal(fast(spl).derivative(2)(x), spl.derivative(2)(x))


def test_profiles_and_rails_evaluate_as_scipy():
    rng = np.random.default_rng(7)
    for prof in (s1002(), uic60()):
        spl = CubicSpline(prof.y, prof.z, bc_type="not-a-knot")
        t = _points(prof.y, rng)
        assert np.array_equal(prof.z_at(t), spl(t), equal_nan=True)
        assert np.array_equal(prof.slope(t), spl.derivative(1)(t), equal_nan=True)
        assert np.array_equal(prof.second(t), spl.derivative(2)(t), equal_nan=True)


def test_smoothing_splines_as_their_pieces():
    # a measured profile's smoothing B-spline is evaluated as the PPoly of its pieces
    # (spline.piecewise): the B-spline's values to rounding inside the data, its end pieces
    # beyond them; value, slope and curvature
    from lutmpi.profiles.model import Profile

    rng = np.random.default_rng(11)
    x = np.sort(rng.uniform(-0.07, 0.06, 400))
    z = 0.01 * np.sin(40 * x) + 1e-5 * rng.normal(size=x.size)
    smooth = make_smoothing_spline(x, z, lam=1e-9)
    g = fast(piecewise(smooth))
    inside = np.linspace(x[0], x[-1], 20001)
    beyond = np.concatenate([np.linspace(x[0] - 0.01, x[0], 500),
                             np.linspace(x[-1], x[-1] + 0.01, 500)])
    for nu, (tol_in, tol_out) in enumerate([(1e-16, 1e-12), (1e-14, 1e-11), (1e-11, 1e-9)]):
        f = smooth.derivative(nu) if nu else smooth
        gg = g.derivative(nu) if nu else g
        assert np.max(np.abs(gg(inside) - f(inside))) <= tol_in
        assert np.max(np.abs(gg(beyond) - f(beyond))) <= tol_out
    prof = Profile("wheel", x, z, smoothing=1e-9)
    assert np.max(np.abs(prof.z_at(inside) - smooth(inside))) <= 1e-16
    assert np.max(np.abs(prof.slope(inside) - smooth.derivative(1)(inside))) <= 1e-14


def test_other_splines_are_refused():
    x = np.linspace(0.0, 1.0, 50)
    smooth = make_smoothing_spline(x, np.sin(6 * x), lam=1e-4)
    bounded = CubicSpline(x, np.sin(6 * x), extrapolate=False)
    for spl in (smooth, bounded):
        with pytest.raises(TypeError, match="extrapolating PPoly"):
            fast(spl)
