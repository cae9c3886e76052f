"""Standard profiles generated from their published definitions (no file needed).

* :func:`s1002` -- the S1002 wheel (EN 13715 / UIC 510-2), eight analytic sections of ``F(S)``
  (coefficients attributed to H. Netter, DLR; see ``docs/STANDARD_PROFILES.md``).
* :func:`uic60` -- the UIC60 / 60E1 rail head (EN 13674-1): arcs R300, R80, R13 and a 1:20 flank,
  upright, ``v = 0`` on the symmetry axis, crown top ``z = 0``.

Both are sampled by **arc length** (so the steep flange flank and the rail flank get as many points
as the tread) with the exact joint points added, and returned with an interpolating cubic spline
(``smoothing = 0``): the spline then reproduces slope and curvature of every section.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from lutmpi.errors import ProfileError
from lutmpi.profiles.model import Profile

# -- S1002 -------------------------------------------------------------------------------------
# Section boundaries (mm), from the flange back (-70) to the field side (+60).
_S_H, _S_G, _S_F, _S_E = -70.0, -62.764705882, -49.662510381, -39.764473993
_S_D, _S_C, _S_B, _S_A = -38.426669071, -35.0, -26.0, 32.15796
_S_END = 60.0

_B_COEF = (0.0, -3.358537058e-2, 1.565681624e-3, -2.810427944e-5, 5.844240864e-8,
           -1.562379023e-8, 5.309217349e-15, -5.957839843e-12, 2.646656573e-13)
_C_COEF = (-4.320221063e3, -1.038384026e3, -1.065501873e2, -6.051367875, -2.054332446e-1,
           -4.169739389e-3, -4.687195829e-5, -2.252755540e-7)


def _circle(a: float, b: float, c: float, sign: float) -> Callable[[np.ndarray], np.ndarray]:
    """``a + sign * sqrt(b^2 - (S + c)^2)`` (clipped at the tangent points)."""
    return lambda s: a + sign * np.sqrt(np.maximum(b * b - (s + c) ** 2, 0.0))


def _poly(coef: tuple[float, ...]) -> Callable[[np.ndarray], np.ndarray]:
    return lambda s: np.polynomial.polynomial.polyval(s, coef)


#: (S_start, S_end, F) for the sections H, G, F, E, D, C, B, A in increasing S (mm -> mm).
S1002_SECTIONS: tuple[tuple[float, float, Callable[[np.ndarray], np.ndarray]], ...] = (
    (_S_H, _S_G, _circle(9.519259302, 20.5, 49.5, +1.0)),                 # H flange back R20.5
    (_S_G, _S_F, _circle(16.0, 12.0, 55.0, +1.0)),                        # G flange tip R12
    (_S_F, _S_E, _circle(8.834924130, 20.0, 58.558326413, +1.0)),         # F circle R20
    (_S_E, _S_D, lambda s: -93.576667419 - 2.747477419 * s),              # E flange flank line
    (_S_D, _S_C, _circle(16.446, 13.0, 26.210665, -1.0)),                 # D circle R13
    (_S_C, _S_B, _poly(_C_COEF)),                                         # C flange root
    (_S_B, _S_A, _poly(_B_COEF)),                                         # B tread
    (_S_A, _S_END, lambda s: 1.364323640 - 0.066666667 * s),              # A field-side cone 1:15
)


def s1002_radius_mm(s_mm: np.ndarray | float) -> np.ndarray:
    """The S1002 radius increase ``F(S)`` (mm) at ``S`` (mm), piecewise by section.

    Parameters
    ----------
    s_mm : array_like
        Profile coordinate from the tape circle, mm, in [-70, 60]; positive toward the field side.

    Returns
    -------
    ndarray
        Radius increase, mm (flange tip +28 at S = -55).
    """
    s = np.atleast_1d(np.asarray(s_mm, dtype=float))
    if np.any(s < _S_H - 1e-9) or np.any(s > _S_END + 1e-9):
        raise ProfileError(f"S1002 is defined on [-70, 60] mm, got [{s.min():g}, {s.max():g}]")
    out = np.empty_like(s)
    for lo, hi, f in S1002_SECTIONS:
        m = (s >= lo) & (s <= hi)
        out[m] = f(s[m])
    return out


def s1002_joint_jumps() -> np.ndarray:
    """``|F_left - F_right|`` at the seven inner joints of S1002 (mm); ≲ 1e-4 from rounding."""
    jumps = []
    for (_, hi, f_left), (lo, _, f_right) in zip(S1002_SECTIONS[:-1], S1002_SECTIONS[1:],
                                                strict=True):
        jumps.append(abs(float(f_left(np.array(hi))) - float(f_right(np.array(lo)))))
    return np.array(jumps)


def _sample_by_arclength(f: Callable[[np.ndarray], np.ndarray], lo: float, hi: float,
                         step: float) -> np.ndarray:
    """Abscissae on ``[lo, hi]`` spaced about ``step`` along the curve ``(s, f(s))``."""
    fine = np.linspace(lo, hi, max(int(math.ceil((hi - lo) / step)) * 50, 2))
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(fine), np.diff(f(fine))))])
    n = max(int(math.ceil(arc[-1] / step)), 1)
    return np.interp(np.linspace(0.0, arc[-1], n + 1), arc, fine)


def _sample_sections(sections: list[tuple[float, float, Callable[[np.ndarray], np.ndarray]]],
                     step: float) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate arc-length samples of consecutive sections; joints appear once, exactly."""
    ys, zs = [], []
    for k, (lo, hi, f) in enumerate(sections):
        y = _sample_by_arclength(f, lo, hi, step)
        if k > 0:
            y = y[1:]                      # the joint belongs to the previous section
        ys.append(y)
        zs.append(f(y))
    y, z = np.concatenate(ys), np.concatenate(zs)
    keep = np.concatenate([[True], np.diff(y) > 1e-9 * max(step, 1.0)])
    return y[keep], z[keep]


def s1002(s_min_mm: float = -70.0, s_max_mm: float = 60.0, step_mm: float = 0.1) -> Profile:
    """The S1002 wheel profile in the normalized orientation (``s`` from the tape circle, m).

    Parameters
    ----------
    s_min_mm, s_max_mm : float
        Range of ``S`` (mm) within [-70, 60]. At -70 the flange back is vertical (infinite slope);
        start at about -69 when slopes there matter.
    step_mm : float
        Point spacing along the curve, mm (exact joint points are always included).

    Returns
    -------
    Profile
        ``kind="wheel"``, ``smoothing=0``, ``meta`` with the flange parameters.
    """
    if not (-70.0 <= s_min_mm < s_max_mm <= 60.0) or step_mm <= 0:
        raise ProfileError(f"S1002 needs -70 <= s_min < s_max <= 60 mm and step > 0, got "
                           f"s_min={s_min_mm}, s_max={s_max_mm}, step={step_mm}")
    secs = [(max(lo, s_min_mm), min(hi, s_max_mm), f) for lo, hi, f in S1002_SECTIONS
            if hi > s_min_mm and lo < s_max_mm]
    s, F = _sample_sections(secs, step_mm)
    return Profile(kind="wheel", y=s * 1e-3, z=F * 1e-3, name="S1002", source="generator:S1002",
                   smoothing=0.0,
                   meta={"generator": "S1002", "step_mm": step_mm, "units": "mm (generated)",
                         "Sh_mm": 28.0, "flange_back_s_mm": -70.0})


# -- UIC60 / 60E1 --------------------------------------------------------------------------------
_R1, _R2, _R3 = 300.0, 80.0, 13.0
_C1 = (0.0, -300.0)
_C2 = (7.5005, -80.128)
_C3 = (23.0160, -14.9491)
_V12, _V23 = 20.456 / 2, 52.053 / 2
_FLANK = 1.0 / 20.0                        # dv/dw of the flank (widening downward)


def _uic60_tangent_point() -> tuple[float, float]:
    """Where the R13 arc meets the 1:20 flank: the arc point whose outward normal is ⟂ the flank."""
    n = np.array([1.0, _FLANK]) / math.hypot(1.0, _FLANK)
    return _C3[0] + _R3 * n[0], _C3[1] + _R3 * n[1]


def uic60_half_sections(depth_mm: float = 40.0) -> list[tuple[float, float, Callable]]:
    """(v_start, v_end, w(v)) for the field-side half (v >= 0), mm, from the axis to ``-depth``."""
    vt, wt = _uic60_tangent_point()
    v_bottom = vt + (wt + depth_mm) * _FLANK
    return [
        (0.0, _V12, _circle(_C1[1], _R1, -_C1[0], +1.0)),
        (_V12, _V23, _circle(_C2[1], _R2, -_C2[0], +1.0)),
        (_V23, vt, _circle(_C3[1], _R3, -_C3[0], +1.0)),
        (vt, v_bottom, lambda v: wt - (v - vt) / _FLANK),
    ]


def uic60_joint_jumps() -> np.ndarray:
    """``|w_left - w_right|`` at the three joints of the half head (mm)."""
    secs = uic60_half_sections()
    return np.array([abs(float(a[2](np.array(a[1]))) - float(b[2](np.array(b[0]))))
                     for a, b in zip(secs[:-1], secs[1:], strict=True)])


def uic60(depth_mm: float = 40.0, step_mm: float = 0.1) -> Profile:
    """The UIC60 (60E1) rail head, upright, in the normalized rail orientation.

    ``v = 0`` on the symmetry axis, positive toward the field side, ``z = 0`` at the crown top,
    positive up. The head is symmetric, so the gauge side (``v < 0``) is the mirror image.

    Parameters
    ----------
    depth_mm : float
        How far below the top the flanks go, mm (> 14.3 so the gauge point 14 mm down exists).
    step_mm : float
        Point spacing along the curve, mm.

    Returns
    -------
    Profile
        ``kind="rail"``, ``cant_rad=0``, ``smoothing=0``.
    """
    vt, wt = _uic60_tangent_point()
    if depth_mm <= -wt + 0.5 or depth_mm > 60 or step_mm <= 0:
        raise ProfileError(f"UIC60 needs {-wt + 0.5:.1f} < depth <= 60 mm and step > 0, "
                           f"got depth={depth_mm}, step={step_mm}")
    v, w = _sample_sections(uic60_half_sections(depth_mm), step_mm)
    y = np.concatenate([-v[:0:-1], v])
    z = np.concatenate([w[:0:-1], w])
    return Profile(kind="rail", y=y * 1e-3, z=z * 1e-3, name="UIC60", source="generator:UIC60",
                   cant_rad=0.0, smoothing=0.0,
                   meta={"generator": "UIC60", "step_mm": step_mm, "units": "mm (generated)",
                         "head_width_14mm_mm": 2 * 35.981})


#: Generators by name (``[wheel] generator = "S1002"``, ``[rail] generator = "UIC60"``).
GENERATORS: dict[str, Callable[..., Profile]] = {"S1002": s1002, "UIC60": uic60, "60E1": uic60}


def generate(name: str, **kwargs: float) -> Profile:
    """Build a standard profile by name; an unknown name raises and lists the valid ones."""
    key = name.strip().upper()
    if key not in GENERATORS:
        raise ProfileError(f"unknown profile generator {name!r}; valid: {', '.join(GENERATORS)}")
    return GENERATORS[key](**kwargs)
