"""Equivalent conicity by EN 15302 Annex B (integration of the non-linear kinematic equation).

Pure module: arrays in, arrays out (no MPI, no HDF5).

The method
----------
Klingel's kinematic wheelset on tangent track, with ``x`` the distance run, ``y`` the lateral
displacement of the wheelset and ``psi = dy/dx`` its yaw angle. A wheel rolling on the larger radius
runs ahead, so the wheelset turns away from it::

    dy/dx = psi,        dpsi/dx = -dr(y) / (e * r0)                                    (B.1)

where ``dr(y)`` is the rolling-radius difference, positive for ``y > 0`` (the wheel towards which
the wheelset moved rolls on the larger radius: EN 15302 writes ``dr = r_right - r_left`` with ``y``
positive to the right), ``r0`` the nominal rolling radius and ``e`` the distance between the nominal
contact points (about 1.5 m). Multiplying (B.1) by ``psi`` and integrating once gives the energy
equation, with ``S(y) = int_{y0}^{y} dr(u) du`` and ``C = S`` at the turning points::

    psi(y)**2 = (2 / (e * r0)) * (C - S(y))                                            (B.2)

The motion is periodic between the turning points ``y_a < y_b`` where ``psi = 0``; they satisfy
``S(y_a) = S(y_b) = C`` and ``y_b - y_a = 2 * yhat`` (``yhat`` the amplitude; with a diameter offset
the oscillation is not centred on ``y = 0`` but around the minimum of ``S``, where ``dr = 0``). Half
a wavelength is run between them::

    lambda_w / 2 = int_{y_a}^{y_b} dy / psi(y)                                         (B.3)

and the equivalent conicity is the cone angle whose Klingel wavelength
``lambda_w = 2 pi sqrt(e r0 / (2 tan gamma_e))`` is the same::

    tan gamma_e = (2 pi / lambda_w)**2 * e * r0 / 2                                    (B.4)

For a cone, ``dr = 2 lambda y`` gives ``psi**2 = (2 lambda / (e r0)) (yhat**2 - y**2)``, (B.3) is
``pi sqrt(e r0 / (2 lambda))`` and (B.4) returns ``lambda`` exactly. Note that ``e * r0`` cancels
between (B.3) and (B.4): the conicity depends only on ``dr(y)``; ``r0`` and ``e`` only set the
wavelength.

The end points
--------------
``psi -> 0`` at the turning points, so the integrand of (B.3) has inverse-square-root singularities
there (``C - S ~ |dr(y_a)| (y - y_a)``). A plain trapezoid on the data grid is biased and fails the
standard's benchmark cases. Here ``y = y_a + w sin(theta/2)**2`` (``w = y_b - y_a``,
``theta in [0, pi]``) makes ``dy = (w/2) sin(theta) dtheta`` vanish like ``theta`` exactly where
``psi`` does, so the transformed integrand is bounded; ``C - S`` is evaluated as an integral of
``dr`` from the *nearer* end point (exact for the piecewise-linear ``dr``), so it does not lose
digits by cancellation near the ends. The transformed integral is done by adaptive Gauss-Kronrod
(``scipy.integrate.quad``) with the data nodes as break points.

``dr`` between the given samples is linear (``S`` piecewise quadratic and exact).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from scipy import integrate, optimize

from lutmpi.table.schema import JUMPS_GROUP, KNOTS_GROUP, LIMITS_GROUP, Y_AXIS, YAW_AXIS, D, J

__all__ = ["ConicityResult", "equivalent_conicity", "conicity_curve", "parse_amplitudes",
           "dr_from_table", "check_dr", "DrCheck", "HoleError", "failed_poses"]


class _PiecewiseLinear:
    """``dr(y)`` linear between samples, with exact integrals (no cancellation on short spans)."""

    def __init__(self, y: np.ndarray, dr: np.ndarray):
        self.y = y
        self.dr = dr
        seg = 0.5 * np.diff(y) * (dr[1:] + dr[:-1])
        self.cum = np.concatenate(([0.0], np.cumsum(seg)))   # S at the nodes, from y[0]

    def __call__(self, x: float) -> float:
        return float(np.interp(x, self.y, self.dr))

    def integral(self, a: float, b: float, length: float | None = None) -> float:
        """``int_a^b dr(u) du`` for ``a <= b`` (exact for the linear interpolant).

        ``length`` is ``b - a`` when the caller knows it more accurately than the difference
        (an interval shorter than the rounding of ``a``)."""
        ia = int(np.searchsorted(self.y, a, side="right"))   # first node strictly above a
        ib = int(np.searchsorted(self.y, b, side="left"))    # first node at or above b
        if ia >= ib:                                          # no node strictly inside (a, b)
            return 0.5 * (b - a if length is None else length) * (self(a) + self(b))
        inner = self.cum[ib - 1] - self.cum[ia]
        return (0.5 * (self.y[ia] - a) * (self(a) + self.dr[ia]) + inner
                + 0.5 * (b - self.y[ib - 1]) * (self.dr[ib - 1] + self(b)))

    def s(self, x: float) -> float:
        """``S(x) = int_{y[0]}^{x} dr``."""
        return self.integral(float(self.y[0]), x)


class ConicityResult:
    """Equivalent conicity against amplitude (SI).

    Attributes
    ----------
    amplitude : ndarray, shape (n,)
        Amplitude ``yhat``, m (half the distance between the turning points).
    tan_gamma_e : ndarray, shape (n,)
        Equivalent conicity, dimensionless; NaN where the amplitude does not fit in the data.
    wavelength : ndarray, shape (n,)
        Kinematic wavelength ``lambda_w``, m (``inf`` where ``dr = 0`` over the whole motion).
    y_left, y_right : ndarray, shape (n,)
        Turning points ``y_a``, ``y_b``, m.
    """

    def __init__(self, amplitude, tan_gamma_e, wavelength, y_left, y_right):
        self.amplitude = amplitude
        self.tan_gamma_e = tan_gamma_e
        self.wavelength = wavelength
        self.y_left = y_left
        self.y_right = y_right

    def at(self, amplitude: float) -> float:
        """Conicity at one amplitude (m), linear interpolation in the computed curve."""
        return float(np.interp(amplitude, self.amplitude, self.tan_gamma_e))


def _validate(y, dr) -> tuple[np.ndarray, np.ndarray]:
    y = np.asarray(y, dtype=float)
    dr = np.asarray(dr, dtype=float)
    if y.ndim != 1 or y.shape != dr.shape or y.size < 3:
        raise ValueError(f"y and dr must be 1-D of the same length >= 3, got {y.shape}, {dr.shape}")
    if not np.all(np.isfinite(y)) or not np.all(np.isfinite(dr)):
        raise ValueError("y and dr must be finite")
    if np.any(np.diff(y) <= 0):
        raise ValueError("y must be strictly increasing")
    return y, dr


def _centre(f: _PiecewiseLinear) -> float:
    """Where ``S`` is smallest: the centre of small oscillations (``dr`` changes sign there).

    With a flat zone (``dr = 0`` on an interval) the middle of the flat minimum is returned."""
    s_nodes = f.cum
    smin = s_nodes.min()
    scale = max(np.abs(s_nodes).max(), 1e-300)
    idx = np.flatnonzero(s_nodes <= smin + 1e-12 * scale)
    i = int(idx[len(idx) // 2]) if idx[-1] - idx[0] + 1 == len(idx) else int(np.argmin(s_nodes))
    lo, hi = f.y[max(i - 1, 0)], f.y[min(i + 1, len(f.y) - 1)]
    # the exact minimum of the piecewise-quadratic S lies at a zero of dr within the neighbours
    if len(idx) == 1 and f(lo) < 0 < f(hi):
        return float(optimize.brentq(f, lo, hi, xtol=1e-15 * max(1.0, abs(hi)), rtol=1e-15))
    return float(f.y[i]) if len(idx) == 1 else float(0.5 * (f.y[idx[0]] + f.y[idx[-1]]))


#: how far (m) an amplitude may exceed half the data's y span and still be computed at the
#: data's ends: rounding of an amplitude at the edge (3 mm from "2.9:3:0.1" is 3.0000000000000004
#: mm); the same 1 pm as :func:`check_dr`'s "beyond the table"
EDGE_SLACK = 1e-12


def _turning_points(f: _PiecewiseLinear, y0: float, width: float) -> tuple[float, float] | None:
    """``y_a`` with ``int_{y_a}^{y_a + width} dr = 0`` bracketed around the centre ``y0``.

    ``None`` when the motion leaves the data before turning back. A motion that spans the whole
    data (an amplitude at the data's edge: ``lo == hi``) is found despite rounding: a bracket
    value of the wrong sign by no more than the rounding of the integral counts as zero."""
    span = float(f.y[-1] - f.y[0])
    if width > span + 2.0 * EDGE_SLACK:
        return None
    lo = max(y0 - width, float(f.y[0]))
    hi = max(min(y0, float(f.y[-1]) - width), lo)   # lo > hi only by the slack: the data's ends

    def g(ya: float) -> float:
        return f.integral(ya, ya + width)

    # the rounding of g: a few ulps of the largest partial integral of |dr| over the data
    tol = 64.0 * np.finfo(float).eps * span * float(np.abs(f.dr).max())
    glo, ghi = g(lo), g(hi)
    if glo > tol or ghi < -tol:  # the motion leaves the data before turning back
        return None
    if glo >= 0:                 # zero, or above it by rounding only
        return lo, lo + width
    if ghi <= 0:
        return hi, hi + width
    ya = optimize.brentq(g, lo, hi, xtol=1e-15 * max(1.0, abs(y0) + width), rtol=1e-15,
                         maxiter=200)
    return ya, ya + width


def _half_wavelength_scaled(f: _PiecewiseLinear, ya: float, yb: float) -> float:
    """``int_{ya}^{yb} dy / sqrt(C - S(y))`` by the substitution ``y = ya + w sin^2(theta/2)``.

    Returns ``inf`` when ``C - S`` vanishes on the whole interval (``dr = 0`` there) and NaN when
    it is negative somewhere inside (no bounded motion: e.g. ``dr`` of the wrong sign)."""
    w = yb - ya

    def depth(theta: float) -> float:
        # C - S(y), integrated from the nearer end point so it keeps its digits near the ends
        if theta <= 0.5 * math.pi:
            d = w * math.sin(0.5 * theta) ** 2
            return -f.integral(ya, ya + d, d)
        d = w * math.cos(0.5 * theta) ** 2
        return f.integral(yb - d, yb, d)

    def integrand(theta: float) -> float:
        d = depth(theta)
        jac = 0.5 * w * math.sin(theta)
        if d <= 0.0:
            return 0.0 if jac == 0.0 else math.inf
        return jac / math.sqrt(d)

    inner = f.y[(f.y > ya) & (f.y < yb)]
    breaks = 2.0 * np.arcsin(np.sqrt(np.clip((inner - ya) / w, 0.0, 1.0)))
    depths = [depth(t) for t in np.linspace(0.0, math.pi, 65)[1:-1]]
    scale = max(float(np.abs(f.dr).max()) * w, 1e-300)
    if min(depths) < -1e-9 * scale:  # S > C inside: no bounded motion between these points
        return math.nan
    if max(depths) <= 1e-13 * scale:  # dr == 0 over the whole motion: no restoring, infinite λ
        return math.inf
    points = breaks if 0 < breaks.size <= 400 else None
    val, _ = integrate.quad(integrand, 0.0, math.pi, points=points, limit=max(200, 4 * inner.size),
                            epsabs=0.0, epsrel=1e-9)
    return float(val)


def conicity_curve(y, dr, amplitudes, r0: float = 0.46, e: float = 1.5) -> ConicityResult:
    """Equivalent conicity ``tan gamma_e`` against amplitude, EN 15302 Annex B.

    Parameters
    ----------
    y : array_like, shape (n,)
        Lateral displacement of the wheelset, m, strictly increasing.
    dr : array_like, shape (n,)
        Rolling-radius difference at ``y``, m, positive for ``y > 0`` (EN 15302:
        ``r_right - r_left`` with ``y`` positive to the right). May contain a diameter offset.
    amplitudes : array_like, shape (m,)
        Amplitudes ``yhat`` (half the peak-to-peak motion), m.
    r0 : float
        Nominal rolling radius, m (only scales the wavelength).
    e : float
        Distance between the nominal contact points, m (only scales the wavelength).

    Returns
    -------
    ConicityResult
        ``tan_gamma_e`` (NaN where the motion of that amplitude does not fit in ``y`` or is not
        bounded, e.g. ``dr`` of the wrong sign; 0 where ``dr = 0`` over the whole motion), the
        wavelength and the turning points.
    """
    y, dr = _validate(y, dr)
    amps = np.atleast_1d(np.asarray(amplitudes, dtype=float))
    if np.any(amps <= 0):
        raise ValueError("amplitudes must be > 0")
    f = _PiecewiseLinear(y, dr)
    y0 = _centre(f)
    out = np.full((4, amps.size), np.nan)
    for k, a in enumerate(amps):
        tp = _turning_points(f, y0, 2.0 * a)
        if tp is None:
            continue
        half = _half_wavelength_scaled(f, *tp)               # (B.3) times sqrt(2/(e r0))
        if math.isnan(half):
            continue
        wavelength = 2.0 * half * math.sqrt(0.5 * e * r0)     # (B.2)-(B.3)
        tan_g = 0.0 if math.isinf(wavelength) else (2 * math.pi / wavelength) ** 2 * e * r0 / 2
        out[:, k] = (tan_g, wavelength, tp[0], tp[1])          # (B.4)
    return ConicityResult(amps, out[0], out[1], out[2], out[3])


def equivalent_conicity(y, dr, amplitudes, r0: float = 0.46, e: float = 1.5) -> np.ndarray:
    """``tan gamma_e`` at each amplitude (see :func:`conicity_curve`; all lengths in m)."""
    return conicity_curve(y, dr, amplitudes, r0, e).tan_gamma_e


#: most amplitudes one conicity curve takes (each is an integral over the Δr function)
MAX_AMPLITUDES = 10_000


def parse_amplitudes(text: str) -> np.ndarray:
    """``"start:stop:step"`` (stop included) or ``"a,b,c"`` in mm → amplitudes in m (finite,
    > 0, at most :data:`MAX_AMPLITUDES`; ValueError otherwise)."""
    text = text.strip()
    if ":" in text:
        parts = [float(p) for p in text.split(":")]
        if len(parts) != 3 or parts[2] <= 0 or parts[1] < parts[0]:
            raise ValueError(f"amplitudes: expected start:stop:step with step > 0, got {text!r}")
        if not all(math.isfinite(v) for v in parts):
            raise ValueError(f"amplitudes: expected finite numbers, got {text!r}")
        n = int(math.floor((parts[1] - parts[0]) / parts[2] + 1e-9)) + 1
        if n > MAX_AMPLITUDES:
            raise ValueError(f"amplitudes: {text!r} gives {n} amplitudes, more than "
                             f"{MAX_AMPLITUDES}")
        amps = (parts[0] + parts[2] * np.arange(n)) * 1e-3
    else:
        amps = np.array([float(p) for p in text.split(",") if p.strip()]) * 1e-3
    if amps.size == 0 or not (np.all(np.isfinite(amps)) and np.all(amps > 0.0)):
        raise ValueError(f"amplitudes: expected finite amplitudes > 0 mm, got {text!r}")
    if amps.size > MAX_AMPLITUDES:
        raise ValueError(f"amplitudes: {amps.size} amplitudes, more than {MAX_AMPLITUDES}")
    return amps


def dr_from_table(table, method: str | None = None) -> tuple[np.ndarray, np.ndarray]:
    """``(y, dr)`` at yaw = 0 from a lookup table, SI, **with NaN where a pose failed**.

    ``dr = r_left - r_right`` of contact slot 0 (the contact carrying the largest normal force) on
    each wheel: lutmpi's track frame has ``y`` positive to the left, so a positive ``y_g`` puts the
    left wheel on its larger radii and this is EN 15302's ``dr`` (positive for ``y > 0``). A point
    that did not converge (status != 0) is NaN: it is a hole, never integrated across; see
    :func:`check_dr`.

    Where the table holds its contact jumps (``jumps`` of a :class:`~lutmpi.table.Table`, or
    ``jumps`` of the mapping: name -> the ``arrays``, ``knots`` and ``limits`` of
    :mod:`lutmpi.table.jumps`), the yaw-0 column's extra knots and each jump's two one-sided
    limits (5 um apart) are samples too: Δr then steps at its jumps instead of running linearly
    across a grid cell, which moved the conicity of an amplitude whose turning point lies next
    to a flange jump by up to 18 % between a 0.1 and a 0.025 mm grid.

    Parameters
    ----------
    table : lutmpi.table.Table or Mapping
        A :class:`~lutmpi.table.Table`, or a mapping with ``y``, ``yaw``, ``methods``.
    method : str, optional
        Method group; default the table's first method.

    Returns
    -------
    y : ndarray, shape (ny,)
        m.
    dr : ndarray, shape (ny,)
        m; NaN at failed points.

    Raises
    ------
    ValueError
        The grid has no yaw = 0 column, or the table holds no rolling radii.
    """
    if hasattr(table, "get") and hasattr(table, "methods") and not isinstance(table, dict):
        y, yaw = np.asarray(table.y, float), np.asarray(table.yaw, float)
        name = method or table.methods[0]
        group = {k: table.get(k, name, raw=True) for k in table.quantities}
        jumps = table.jumps.get(name)
    else:
        y, yaw = np.asarray(table[Y_AXIS], float), np.asarray(table[YAW_AXIS], float)
        name = method or next(iter(table["methods"]))
        group = table["methods"][name]
        jumps = table.get(JUMPS_GROUP, {}).get(name)
    j = int(np.argmin(np.abs(yaw)))
    if abs(yaw[j]) > 1e-12:
        raise ValueError(f"no yaw = 0 column in the grid (closest {yaw[j]:.3g} rad): "
                         "equivalent conicity needs the wheelset at zero yaw")
    if D.rolling_radius not in group:
        raise ValueError(f"method {name!r}: the table holds no {D.rolling_radius}")
    rr = np.asarray(group[D.rolling_radius], dtype=float)[:, j, :, 0]
    dr = rr[:, 0] - rr[:, 1]
    if D.status in group:
        dr = np.where(np.asarray(group[D.status])[:, j] == 0, dr, np.nan)
    if jumps is None or D.rolling_radius not in jumps[KNOTS_GROUP]:
        return y, dr
    return _with_jump_samples(y, dr, jumps, j)


def _with_jump_samples(y: np.ndarray, dr: np.ndarray, jumps: dict, j: int
                       ) -> tuple[np.ndarray, np.ndarray]:
    """The grid's ``(y, dr)`` with column ``j``'s extra knots and jump limits added (sorted,
    one sample per y, failed ones NaN)."""
    arr, knots, limits = jumps["arrays"], jumps[KNOTS_GROUP], jumps[LIMITS_GROUP]

    def drs(rr: np.ndarray, status: np.ndarray | None) -> np.ndarray:
        d = rr[..., 0, 0] - rr[..., 1, 0]
        return d if status is None else np.where(status == 0, d, np.nan)

    ky = np.asarray(arr[J.knot_y], float)[j]
    kst = np.asarray(knots[D.status])[j] if D.status in knots else None
    kd = drs(np.asarray(knots[D.rolling_radius], float)[j], kst)
    lo, hi = np.asarray(arr[J.jump_y_lo], float)[j], np.asarray(arr[J.jump_y_hi], float)[j]
    lrr = np.asarray(limits[D.rolling_radius], float)[j]          # (K, 2, side, slot)
    lst = np.asarray(limits[D.status])[j] if D.status in limits else None
    ld = drs(lrr, lst)                                             # (K, 2)
    ys = np.concatenate([y, ky, lo, hi])
    ds = np.concatenate([dr, kd, ld[:, 0], ld[:, 1]])
    keep = np.isfinite(ys)
    ys, ds = ys[keep], ds[keep]
    order = np.argsort(ys, kind="stable")
    ys, ds = ys[order], ds[order]
    first = np.concatenate([[True], np.diff(ys) > 0])
    return ys[first], ds[first]


#: EN 15302's benchmark Δr data are given every 0.1 mm: a coarser y grid is flagged
MAX_DY = 1e-4


class HoleError(ValueError):
    """Δr(y) has no value (a failed pose) inside the range an amplitude's motion covers."""


@dataclass
class DrCheck:
    """What :func:`check_dr` found (SI).

    Attributes
    ----------
    y, dr : ndarray
        The finite samples to integrate (ends without a value dropped).
    holes : ndarray
        ``y`` of every missing Δr value of the table, m.
    beyond : ndarray
        Requested amplitudes whose motion does not fit in the table's y range, m.
    dy : float
        Largest y step, m.
    warnings : list of str
        One line per finding (holes outside the amplitude range, beyond, coarse Δy).
    """

    y: np.ndarray
    dr: np.ndarray
    holes: np.ndarray
    beyond: np.ndarray
    dy: float
    warnings: list[str]


def failed_poses(y: np.ndarray) -> str:
    """The holes at ``y`` (m) of a table's Δr: its failed poses (:func:`check_dr`)."""
    return f"y = {_mm_list(y)} mm (failed poses)"


def check_dr(y, dr, amplitudes, *, refuse_holes: bool = True,
             name_holes: Callable[[np.ndarray], str] = failed_poses,
             remedy: str = "rebuild those poses") -> DrCheck:
    """Refuse or flag what would make an equivalent conicity hide a gap in Δr(y).

    * A hole (NaN: a failed pose) at ``|y| < max(amplitudes)`` -- inside the lateral range the
      requested motions cover -- raises :class:`HoleError` naming its y (``refuse_holes``) or, if
      not refused, limits the amplitudes to those that stay clear of it (``beyond`` then lists the
      others and a warning names the hole).
    * Amplitudes whose motion does not fit in the table's y range are listed in ``beyond``.
    * A y step above 0.1 mm (:data:`MAX_DY`) adds a warning.

    Parameters
    ----------
    y, dr : array_like, shape (n,)
        m; ``dr`` NaN where missing.
    amplitudes : array_like
        m.
    refuse_holes : bool
        Raise on a hole inside the amplitude range (the ``conicity`` command) instead of limiting
        the amplitudes (the reports, which show the limit).
    name_holes : callable
        ``name_holes(y)`` names the holes at ``y`` (m) where they come from (default: a table's
        failed poses; a Δr file's rows).
    remedy : str
        What fills a hole, after "use amplitudes below ... or".
    """
    y = np.asarray(y, float)
    dr = np.asarray(dr, float)
    amps = np.atleast_1d(np.asarray(amplitudes, float))
    missing = y[~np.isfinite(dr)]
    warnings: list[str] = []
    amax = float(amps.max()) if amps.size else 0.0
    inside = missing[np.abs(missing) < amax]
    dy = float(np.max(np.diff(y))) if y.size > 1 else math.inf
    if inside.size and refuse_holes:
        raise HoleError(
            f"Δr has no value at {name_holes(inside)} inside the amplitude range "
            f"±{amax * 1e3:g} mm: the conicity would integrate across the hole; use amplitudes "
            f"below {np.abs(inside).min() * 1e3:g} mm or {remedy}")
    reach = min(-float(y[0]), float(y[-1]))
    nearest = float(np.abs(missing).min()) if missing.size else math.inf
    # never join across a hole: integrate only the run of values around y = 0
    keep = np.isfinite(dr) & (np.abs(y) < nearest)
    usable = min(-float(y[keep].min()), float(y[keep].max())) if keep.any() else 0.0
    if inside.size:
        warnings.append(f"Δr missing at {name_holes(inside)}: amplitudes above {usable * 1e3:g} mm "
                        "not computed")
    elif missing.size:
        warnings.append(f"Δr missing at {name_holes(missing)}, outside the amplitudes used")
    beyond = amps[amps > usable + 1e-12]
    off_table = amps[amps > reach + 1e-12]
    if off_table.size:
        warnings.append(f"amplitudes {_mm_list(off_table, span=True)} mm: beyond the table's "
                        f"y range [{y[0] * 1e3:g}, {y[-1] * 1e3:g}] mm, not computed")
    if dy > MAX_DY * (1 + 1e-9):
        warnings.append(f"y step {dy * 1e3:g} mm is coarser than 0.1 mm (EN 15302's benchmark "
                        "data): the conicity of a non-linear Δr(y) carries that discretisation")
    return DrCheck(y[keep], dr[keep], missing, beyond, dy, warnings)


def _mm_list(values: np.ndarray, span: bool = False) -> str:
    v = np.sort(np.asarray(values)) * 1e3
    if span and v.size > 2:
        return f"{v[0]:g}–{v[-1]:g}"
    return ", ".join(f"{x:g}" for x in v)
