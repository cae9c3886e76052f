"""The normalized profile: one orientation, SI units, a smooth spline for slope and curvature.

Orientation (documented once, used everywhere)
----------------------------------------------
Both kinds are a function ``z(y)`` sampled at strictly increasing ``y`` (m).

``kind == "wheel"``
    ``y`` is the profile coordinate *s* measured from the tape circle (``s = 0``), positive toward
    the **field side** (so the flange lies at negative ``s``; S1002: flange tip at ``s = -0.055``).
    ``z`` is the **radius increment** ``dr`` (m): the rolling radius at ``s`` is ``r0 + dr(s)``
    (flange tip of S1002 at ``dr = +0.028``).
``kind == "rail"``
    ``y`` is the lateral coordinate *v* in the rail's own frame, positive toward the **field side**
    (gauge face at negative ``v``); ``z`` is the height, positive **up**. For generated rails the
    head centre line is ``v = 0`` and the crown top ``z = 0``. ``cant_rad`` records an inclination
    already contained in the data (e.g. ``atan(1/40)`` for a file that is already canted).

The spline is a cubic interpolating spline for exact (generated) data and a smoothing spline for
measured data; both give slope ``dz/dy`` and curvature.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

import numpy as np
from scipy.interpolate import CubicSpline, make_smoothing_spline

from lutmpi.errors import ProfileError
from lutmpi.profiles.spline import fast, piecewise

Kind = Literal["wheel", "rail"]


@dataclass(frozen=True, eq=False)
class Profile:
    """A wheel or rail profile in the normalized orientation (see module docstring).

    Parameters
    ----------
    kind : {"wheel", "rail"}
    y, z : ndarray, shape (n,)
        Lateral coordinate and height / radius increment, m. ``y`` strictly increasing.
    name : str
        Short label (file stem or generator name).
    source : str or None
        File path or ``"generator:S1002"``.
    cant_rad : float
        Rails only: inclination already present in the data, rad (0 for an upright profile).
    smoothing : float
        0 for an interpolating spline; > 0 for a smoothing spline (``lam`` of
        :func:`scipy.interpolate.make_smoothing_spline`, in m^3).
    meta : dict
        Reader-specific header data (e.g. MiniProf ``Sd``, ``Sh``, ``qR``).
    """

    kind: Kind
    y: np.ndarray
    z: np.ndarray
    name: str = "profile"
    source: str | None = None
    cant_rad: float = 0.0
    smoothing: float = 0.0
    meta: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        y = np.asarray(self.y, dtype=float)
        z = np.asarray(self.z, dtype=float)
        if self.kind not in ("wheel", "rail"):
            raise ProfileError(f"kind must be 'wheel' or 'rail', got {self.kind!r}",
                               path=self.source)
        if y.ndim != 1 or y.shape != z.shape:
            raise ProfileError(f"y and z must be 1-D of equal length, got {y.shape} and {z.shape}",
                               path=self.source)
        if y.size < 4:
            raise ProfileError(f"expected at least 4 points, got {y.size}", path=self.source)
        if not (np.all(np.isfinite(y)) and np.all(np.isfinite(z))):
            raise ProfileError("profile contains NaN or inf", path=self.source)
        dy = np.diff(y)
        if np.any(dy <= 0):
            k = int(np.argmax(dy <= 0))
            raise ProfileError(
                f"y must be strictly increasing (a function of y): point {k + 1} at "
                f"y = {y[k + 1]:.6g} m "
                f"follows y = {y[k]:.6g} m", path=self.source)
        y.setflags(write=False)
        z.setflags(write=False)
        object.__setattr__(self, "y", y)
        object.__setattr__(self, "z", z)
        if self.smoothing > 0:
            spl = piecewise(make_smoothing_spline(y, z, lam=self.smoothing))
        else:
            spl = CubicSpline(y, z, bc_type="not-a-knot")
        # compiled, the same values
        spl, d1, d2 = fast(spl), fast(spl.derivative(1)), fast(spl.derivative(2))
        object.__setattr__(self, "_spl", spl)
        object.__setattr__(self, "_d1", d1)
        object.__setattr__(self, "_d2", d2)

    # -- evaluation ------------------------------------------------------------------------
    @property
    def y_min(self) -> float:
        return float(self.y[0])

    @property
    def y_max(self) -> float:
        return float(self.y[-1])

    def z_at(self, y: np.ndarray | float) -> np.ndarray:
        """Spline value at ``y`` (m); no extrapolation guarantees outside ``[y_min, y_max]``."""
        return self._spl(y)

    def slope(self, y: np.ndarray | float) -> np.ndarray:
        """``dz/dy`` at ``y`` (dimensionless)."""
        return self._d1(y)

    @property
    def ppolys(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Coefficients and breakpoints ``(c, x, c1, x1)`` of the spline and of its slope for
        the compiled kernels (:func:`lutmpi.profiles.spline.ppoly_at`)."""
        return self._spl.c, self._spl.x, self._d1.c, self._d1.x

    def second(self, y: np.ndarray | float) -> np.ndarray:
        """``d2z/dy2`` at ``y`` (1/m)."""
        return self._d2(y)

    def curvature(self, y: np.ndarray | float) -> np.ndarray:
        """Signed curvature ``z'' / (1 + z'^2)^1.5`` (1/m); positive where the curve is convex
        seen from above (concave up)."""
        d1 = self._d1(y)
        return self._d2(y) / (1.0 + d1 * d1) ** 1.5

    def with_points(self, y: np.ndarray, z: np.ndarray, **changes: Any) -> Profile:
        """A copy with other points (and optionally other fields)."""
        kw = dict(kind=self.kind, name=self.name, source=self.source, cant_rad=self.cant_rad,
                  smoothing=self.smoothing, meta=dict(self.meta))
        kw.update(changes)
        return Profile(y=y, z=z, **kw)

    def __repr__(self) -> str:
        return (f"Profile(kind={self.kind!r}, name={self.name!r}, n={self.y.size}, "
                f"y=[{self.y_min * 1e3:.2f}, {self.y_max * 1e3:.2f}] mm)")
