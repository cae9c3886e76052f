"""Shared builders for the contact-core tests (imported, not a conftest: tests/conftest.py belongs
to someone else).

Everything here is *oracle-side*: synthetic profiles whose contact problem has a closed form, and
an independent 2-D rigid-contact solver for yaw = 0 that uses only the placed geometry
(``WheelGeometry.radius`` / ``PlacedRail.height``), never the locus or mesh code.
"""

from __future__ import annotations

from functools import cache

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from lutmpi.equilibrium.solver import EquilibriumOptions
from lutmpi.profiles.model import Profile
from lutmpi.profiles.standard import s1002, uic60
from lutmpi.scene import Scene, SolveSettings

MM = 1e-3
R0 = 0.46
D_TAPE = 0.75
MESH_METHODS = ("max_distance", "max_normal_distance", "load_centre")
INC_20 = float(np.arctan(1 / 20))
INC_40 = float(np.arctan(1 / 40))


# -- synthetic profiles with closed-form contact ------------------------------------------------
def cone_wheel(lam: float, half_width: float = 0.060, n: int = 601) -> Profile:
    """A pure cone ``dr(s) = -lam s`` on ``s in [-half_width, half_width]`` (no flange)."""
    s = np.linspace(-half_width, half_width, n)
    return Profile("wheel", s, -lam * s, name=f"cone{lam}")


def crown_rail(radius: float, half_width: float = 0.030, n: int = 601) -> Profile:
    """Upright circular crown of radius ``radius``: ``z = sqrt(R^2 - v^2) - R``."""
    v = np.linspace(-half_width, half_width, n)
    return Profile("rail", v, np.sqrt(radius**2 - v**2) - radius, name=f"crown{radius}")


def crown_gauge(radius: float, gauge_depth: float, u_crown: float = D_TAPE) -> float:
    """Track gauge that puts the crown's top (v = 0) at side-local ``u = u_crown``.

    The gauge point of an upright crown is where it is ``gauge_depth`` below its top:
    ``v_gp = -sqrt(R^2 - (R - gauge_depth)^2)``; it is placed at ``u = gauge / 2``."""
    return 2.0 * (u_crown - np.sqrt(radius**2 - (radius - gauge_depth) ** 2))


def synthetic_scene(wheel: Profile, rail: Profile, *, spacing=None, gauge_depth=1e-3,
                    allowed=1e-5, **eq) -> Scene:
    """Scene with the crown centred at u = 0.75 m, inclination 0, no flange stiffness factor."""
    radius = _crown_radius(rail)
    kw = {} if spacing is None else {"spacing": spacing}
    return Scene.from_profiles(
        wheel, rail, r0=R0, tape_half_distance=D_TAPE, inclination=0.0,
        gauge=crown_gauge(radius, gauge_depth), gauge_depth=gauge_depth,
        equilibrium=EquilibriumOptions(allowed_indentation=allowed, **eq),
        settings=SolveSettings(flange=False), **kw)


def _crown_radius(rail: Profile) -> float:
    """Radius of a crown built by :func:`crown_rail` (from its edge drop)."""
    v, z = rail.y_max, -float(rail.z[-1])
    return (v * v + z * z) / (2.0 * z)


# -- the standard pair ----------------------------------------------------------------------
@cache
def standard_scene(inclination: float = INC_20, spacing: tuple | None = None,
                   allowed: float = 1e-5, kc0: float = 1e10, k_el: float = 1e7,
                   solver: str = "newton",
                   extrapolate: bool = True) -> Scene:
    """S1002 on UIC60 (generated), gauge 1435, r0 0.46, d 0.75; cached per argument set."""
    kw = {} if spacing is None else {"spacing": spacing}
    return Scene.from_profiles(
        _s1002(), _uic60(), inclination=inclination,
        equilibrium=EquilibriumOptions(k_el=k_el, k_rot=k_el, kc0=kc0, allowed_indentation=allowed,
                                       solver=solver, extrapolate=extrapolate),
        settings=SolveSettings(), **kw)


@cache
def _s1002() -> Profile:
    return s1002()


@cache
def _uic60() -> Profile:
    return uic60()


# -- independent 2-D rigid contact at yaw = 0 -------------------------------------------------
def _min_gap_2d(scene: Scene, side: float, y: float, z_g: float, roll: float,
                ds: float = 2e-4) -> tuple[float, float]:
    """Minimum vertical wheel-above-rail distance of wheel ``side`` in the plane x = 0
    (the lowest generator: at yaw 0 the problem is planar), and the profile coordinate s there.

    The wheel generator in the wheelset frame is ``(Y, Z) = (side (d + s), -r(s))``; the roll
    ``R_x`` maps it to ``y = y_g + c Y - s Z``, ``z = z_g + s Y + c Z``."""
    w, rail = scene.wheel, scene.rail
    c, sn = np.cos(roll), np.sin(roll)

    def gap(s):
        Y, Z = side * (w.d + s), -w.radius(s)
        u = side * (y + c * Y - sn * Z)
        return z_g + sn * Y + c * Z - rail.height(u)

    def usable(s):
        Y, Z = side * (w.d + s), -w.radius(s)
        u = side * (y + c * Y - sn * Z)
        return (u >= rail.u_min) & (u <= rail.u_max)

    s = np.arange(w.s_min, w.s_max, ds)
    ok = usable(s)
    g = np.where(ok, gap(s), np.inf)
    i = int(np.argmin(g))
    lo, hi = s[max(i - 1, 0)], s[min(i + 1, s.size - 1)]
    r = minimize_scalar(gap, bounds=(lo, hi), method="bounded",
                        options={"xatol": 1e-10})
    return float(r.fun), float(r.x)


def rigid_2d(scene: Scene, y: float) -> dict:
    """Rigid two-point contact at yaw 0 by direct minimisation of the planar gaps: the roll that
    makes both wheels touch (Brent on the height mismatch), then z_g. Returns z_g, roll, s."""
    def heights(roll):
        gl, _ = _min_gap_2d(scene, 1.0, y, 0.0, roll)
        gr, _ = _min_gap_2d(scene, -1.0, y, 0.0, roll)
        return -gl, -gr

    def mismatch(roll):
        zl, zr = heights(roll)
        return zl - zr

    roll = brentq(mismatch, -0.03, 0.03, xtol=1e-14)
    zl, zr = heights(roll)
    z_g = 0.5 * (zl + zr)
    _, sl = _min_gap_2d(scene, 1.0, y, z_g, roll)
    _, sr = _min_gap_2d(scene, -1.0, y, z_g, roll)
    return {"z_g": z_g, "roll": roll, "s_left": sl, "s_right": sr}
