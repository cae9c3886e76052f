"""Wheels and rails placed on the track.

Both sides are described in a *side-local* lateral coordinate ``u = side * y`` (``side = +1``
for the left wheel/rail, ``-1`` for the right), positive toward the field side on both sides;
``z`` is the track's vertical. The track is symmetric, so one placed rail profile ``z = zr(u)``
serves both rails, and one wheel geometry serves both wheels (left/right by mirroring).

Rail placement
    The upright rail profile (v, w) is rotated by the inclination ``delta`` so its head faces the
    track centre: ``v' = v cos d - w sin d``, ``w' = v sin d + w cos d``. The top of rail (highest
    point after inclination) is put at ``z = 0``; the gauge point (the point of the gauge face
    nearest the track centre within ``gauge_depth`` below the top) is put at ``u = gauge / 2``.
Wheel placement
    The tape circle of each wheel is ``back_to_back / 2 + tape_offset`` from the wheelset centre
    (0.75 m nominally); profile coordinate ``s`` is positive toward the field side, so a wheel
    point of profile coordinate ``s`` lies at ``u_w = d + s`` in the wheelset frame, at radius
    ``r0 + dr(s)``.
Steep parts (:class:`SteepCut`)
    Each placement keeps the profile around its reference point (the top of rail, the tape
    circle) up to the first stretch steeper than :data:`MAX_SLOPE_DEG` on either side. A steep
    end face dropped whole is silent; usable surface dropped beyond a steep stretch is a
    WARNING naming the profile, the dropped range, the steep stretch and the usable range; a
    wheel's flange tip or a rail's top dropped that way is a :class:`GeometryError`.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from scipy.interpolate import CubicSpline
from scipy.optimize import brentq

from lutmpi.errors import GeometryError
from lutmpi.profiles.model import Profile
from lutmpi.profiles.spline import fast

log = logging.getLogger(__name__)

SIDES = {"left": 1.0, "right": -1.0}
MAX_SLOPE_DEG = 85.0  # profile parts steeper than this are never contact candidates
_SAMPLE = 5e-5  # m, resampling step when rotating a profile


def _arc_length(x: np.ndarray, z: np.ndarray) -> np.ndarray:
    return np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(x), np.diff(z)))])


def _contiguous_slope_range(slope: np.ndarray, i0: int, limit: float,
                            what: str = "profile") -> tuple[int, int]:
    """Largest index range around ``i0`` where |slope| <= limit; ``what`` names the profile and
    its reference point in the error raised when ``i0`` itself is steeper."""
    ok = np.abs(slope) <= limit
    if not ok[i0]:
        raise GeometryError(f"{what} is steeper than the slope limit at its reference point")
    lo = i0
    while lo > 0 and ok[lo - 1]:
        lo -= 1
    hi = i0
    while hi < ok.size - 1 and ok[hi + 1]:
        hi += 1
    return lo, hi


@dataclass(frozen=True, eq=False)
class PlacedRail:
    """One rail on the track in side-local coordinates: ``z = zr(u)`` on ``[u_min, u_max]``.

    Attributes
    ----------
    u, z : ndarray
        Samples of the placed rail (m), ``u`` increasing (toward the field side).
    gauge_point : (float, float)
        (u, z) of the gauge point, m: ``u = gauge / 2`` by construction.
    inclination : float
        Applied inclination, rad.
    """

    profile: Profile
    inclination: float
    gauge: float
    gauge_depth: float
    u: np.ndarray
    z: np.ndarray
    gauge_point: tuple[float, float]
    v_gp: float  # v' of the gauge point before shifting (m)
    w_top: float  # w' of the top of rail before shifting (m)

    @classmethod
    def place(
        cls,
        profile: Profile,
        inclination: float,
        gauge: float,
        gauge_depth: float,
        max_slope_deg: float = MAX_SLOPE_DEG,
        gauge_v: float | None = None,
    ) -> PlacedRail:
        """Incline and place ``profile`` (kind ``rail``) in side-local coordinates.

        ``gauge_v``: the profile's own lateral coordinate (m, before inclination) of an explicit
        gauge point; None finds it ``gauge_depth`` below the top of rail."""
        if profile.kind != "rail":
            raise GeometryError(f"expected a rail profile, got a {profile.kind} ({profile.name})")
        n = max(int((profile.y_max - profile.y_min) / _SAMPLE), 200)
        v = np.linspace(profile.y_min, profile.y_max, n)
        w = profile.z_at(v)
        cd, sd = np.cos(inclination), np.sin(inclination)
        vp, wp = v * cd - w * sd, v * sd + w * cd
        k_top = int(np.argmax(wp))
        w_top = float(wp[k_top])
        if gauge_v is None:
            v_gp = cls._gauge_v(profile, v, vp, wp, inclination, w_top - gauge_depth)
        else:
            if not profile.y_min <= gauge_v <= profile.y_max:
                raise GeometryError(f"rail {profile.name}: gauge point v = {gauge_v * 1e3:.3f} mm "
                                    f"is outside the profile (v = {profile.y_min * 1e3:.3f} .. "
                                    f"{profile.y_max * 1e3:.3f} mm)")
            w_gp = float(profile.z_at(gauge_v))
            v_gp = float(gauge_v * cd - w_gp * sd)
            gauge_depth = w_top - float(gauge_v * sd + w_gp * cd)
            if v_gp >= vp[k_top]:
                raise GeometryError(
                    f"rail {profile.name}: the gauge point v = {gauge_v * 1e3:.3f} mm is on the "
                    f"field side of the top of rail (v = {v[k_top] * 1e3:.3f} mm): it must be on "
                    "the gauge face, toward the track centre; give rail.gauge_point as the other "
                    "end of the file (\"first\" / \"last\") or as a number (mm)")
        u = 0.5 * gauge + (vp - v_gp)
        z = wp - w_top
        # keep the part around the top that is a function of u and not steeper than the limit
        cut = RailCut.of(profile.name, v, u, z, max_slope_deg)
        for text in cut.drop_messages(profile.name):
            log.warning("%s", text)
        u, z = u[cut.lo : cut.hi + 2], z[cut.lo : cut.hi + 2]
        return cls(
            profile=profile,
            inclination=float(inclination),
            gauge=float(gauge),
            gauge_depth=float(gauge_depth),
            u=u,
            z=z,
            gauge_point=(0.5 * gauge, -gauge_depth),
            v_gp=v_gp,
            w_top=w_top,
        )

    @staticmethod
    def _gauge_v(profile: Profile, v: np.ndarray, vp: np.ndarray, wp: np.ndarray,
                 inclination: float, w_line: float) -> float:
        """Smallest v' of the inclined profile where it lies at or above ``w_line``: at a
        crossing of the line, solved on the profile's own curve (between samples, a chord of
        the gauge corner misses it by ~1-2 um where the face is steep); ``v`` the samples'
        profile coordinate, ``(vp, wp)`` the inclined samples."""
        above = wp >= w_line
        top = float(wp.max())
        if above[0]:
            # the gauge side ends above the line: the gauge face there is not in the data
            ends = {k: profile.meta.get(f"file_{k}_point_mm") for k in ("first", "last")}
            gauge_end = [f'"{k}"' for k, p in ends.items()
                         if p is not None and abs(p[0] * 1e-3 - v[0]) < 1e-4]
            raise GeometryError(
                f"rail {profile.name}: no gauge point — the gauge side of the profile ends "
                f"{(top - wp[0]) * 1e3:.2f} mm below the top of rail, above the gauge depth of "
                f"{(top - w_line) * 1e3:.2f} mm; give a smaller rail.gauge_depth_mm, or "
                "rail.gauge_point (" + (f"{gauge_end[0]}: the file's gauge-side end, at "
                if gauge_end else "the file's gauge-side end, at ") +
                f"v = {v[0] * 1e3:.3f} mm, or another v in mm)")
        cd, sd = np.cos(inclination), np.sin(inclination)

        def level(x: float) -> float:
            return float(x * sd + profile.z_at(x) * cd) - w_line

        cands = [vp[above].min()]
        for i in np.nonzero(above[:-1] != above[1:])[0]:
            x = brentq(level, v[i], v[i + 1], xtol=1e-12, rtol=4 * np.finfo(float).eps)
            cands.append(float(x * cd - profile.z_at(x) * sd))
        return float(min(cands))

    def __post_init__(self) -> None:
        spl = fast(CubicSpline(self.u, self.z))  # compiled, the same values
        object.__setattr__(self, "_spl", spl)
        tab_u = np.linspace(self.u[0], self.u[-1], int((self.u[-1] - self.u[0]) / 5e-6) + 2)
        object.__setattr__(self, "_tab_u", tab_u)
        object.__setattr__(self, "_tab_z", spl(tab_u))
        object.__setattr__(self, "_d1", spl.derivative(1))
        object.__setattr__(self, "_d2", spl.derivative(2))

    @property
    def ppolys(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``(c, x, c1, x1)`` of the placed rail's spline and of its slope for the compiled
        kernels (:func:`lutmpi.profiles.spline.ppoly_at`)."""
        return self._spl.c, self._spl.x, self._d1.c, self._d1.x

    @property
    def u_min(self) -> float:
        return float(self.u[0])

    @property
    def u_max(self) -> float:
        return float(self.u[-1])

    def height(self, u: np.ndarray | float) -> np.ndarray:
        """Rail surface height ``zr(u)``, m (the spline)."""
        return self._spl(u)

    @property
    def height_table(self) -> tuple[float, float, np.ndarray]:
        """(first u, step, heights) of the spline tabulated every 5 µm, interpolated linearly by
        the compiled kernels (error below 1e-9 m for curvature radii above 3 mm)."""
        return float(self._tab_u[0]), float(self._tab_u[1] - self._tab_u[0]), self._tab_z

    def slope(self, u: np.ndarray | float) -> np.ndarray:
        return self._d1(u)


@dataclass(frozen=True, eq=False)
class SteepCut:
    """What a placement keeps of a profile: the elements ``lo..hi`` around a reference point no
    steeper than ``limit_deg``; beyond the first steeper element on either side the profile is no
    contact candidate. A steep end face (a flange back, a rim, a rail's lower gauge face) dropped
    whole is by design; surface no steeper than the limit beyond a steep stretch is lost, and
    :meth:`drop_messages` says so.

    An element is a sample (:class:`WheelCut`) or the interval from one sample to the next
    (:class:`RailCut`, ``SPAN = 1``).

    Attributes
    ----------
    x : ndarray
        The samples' lateral profile coordinate (``s`` or ``v``), m, increasing.
    slope : ndarray
        Slope of each element (dimensionless; inf where the surface overhangs).
    lo, hi : int
        First and last element kept.
    limit_deg : float
        The slope limit, deg.
    """

    x: np.ndarray
    slope: np.ndarray
    lo: int
    hi: int
    limit_deg: float

    KIND: ClassVar[str] = "profile"          # names the profile in messages
    COORD: ClassVar[str] = "y"               # names its lateral coordinate
    SIDES: ClassVar[tuple[str, str]] = ("low", "high")   # the sides at low / high coordinate
    FRAME: ClassVar[str] = ""                # where the slope is measured, if not the profile
    SPAN: ClassVar[int] = 0                  # 1: element i spans samples i .. i + 1

    def span_mm(self, a: int, b: int) -> tuple[float, float]:
        """Coordinate range (mm) covered by the elements ``a .. b``."""
        return float(self.x[a] * 1e3), float(self.x[b + self.SPAN] * 1e3)

    def _steep(self, part: slice) -> tuple[float, float, float]:
        """(first, last coordinate in mm, steepest angle in deg) of the steep stretch next to the
        kept part, within the dropped ``part`` (``slice(None, lo)`` or ``slice(hi + 1, None)``)."""
        bad = np.flatnonzero(np.abs(self.slope[part]) > np.tan(np.radians(self.limit_deg)))
        idx = np.arange(self.slope.size)[part][bad]
        run = idx[-1] if part.start is None else idx[0]    # the element next to the kept part
        k = np.flatnonzero(np.abs(np.diff(idx)) > 1)
        if part.start is None:
            first = idx[k[-1] + 1] if k.size else idx[0]
            a, b = first, run
        else:
            last = idx[k[0]] if k.size else idx[-1]
            a, b = run, last
        deg = np.degrees(np.arctan(np.abs(self.slope[a: b + 1]).max()))
        return (*self.span_mm(a, b), float(deg))

    def drop_messages(self, name: str) -> list[str]:
        """One line per dropped part that holds surface no steeper than the limit."""
        ok = np.abs(self.slope) <= np.tan(np.radians(self.limit_deg))
        c, out = self.COORD, []
        for part, side in ((slice(None, self.lo), self.SIDES[0]),
                           (slice(self.hi + 1, None), self.SIDES[1])):
            if not ok[part].any():
                continue   # empty, or a steep end face only: nothing a contact could use
            a, b, deg = self._steep(part)
            idx = np.arange(self.slope.size)[part]
            ends = self.span_mm(idx[0], idx[-1])
            use = self.span_mm(self.lo, self.hi)
            out.append(f"{self.KIND} {name}: {c} = {ends[0]:.2f} .. {ends[1]:.2f} mm ({side} side) "
                       f"is not used for contact: it lies beyond {c} = {a:.2f} .. {b:.2f} mm, "
                       f"steeper than {self.limit_deg:g} deg{self.FRAME} (up to {deg:.1f} deg); "
                       f"the usable profile is {c} = {use[0]:.2f} .. {use[1]:.2f} mm")
        return out


@dataclass(frozen=True, eq=False)
class WheelCut(SteepCut):
    """What the wheel placement keeps of a profile: the samples ``s[lo..hi]`` (m) around the tape
    circle no steeper than ``limit_deg`` (:class:`SteepCut`); the flange tip among the dropped
    surface is an error (:attr:`tip_dropped`, :meth:`tip_message`).

    Attributes
    ----------
    z : ndarray
        The radius increment ``dr`` at each sample, m.
    """

    z: np.ndarray

    KIND: ClassVar[str] = "wheel"
    COORD: ClassVar[str] = "s"
    SIDES: ClassVar[tuple[str, str]] = ("flange", "field")

    @classmethod
    def of(cls, profile: Profile, max_slope_deg: float = MAX_SLOPE_DEG) -> WheelCut:
        """The cut of wheel ``profile`` at the slope limit ``max_slope_deg`` (deg)."""
        n = max(int((profile.y_max - profile.y_min) / _SAMPLE), 200)
        s = np.linspace(profile.y_min, profile.y_max, n)
        slope = profile.slope(s)
        lo, hi = _contiguous_slope_range(slope, int(np.argmin(np.abs(s))),
                                         np.tan(np.radians(max_slope_deg)),
                                         f"wheel {profile.name} (at the tape circle s = 0)")
        return cls(x=s, slope=slope, lo=lo, hi=hi, limit_deg=float(max_slope_deg),
                   z=profile.z_at(s))

    @property
    def s(self) -> np.ndarray:
        """The samples' profile coordinate ``s``, m."""
        return self.x

    @property
    def tip_dropped(self) -> bool:
        """True when the flange side's highest point (the tip) lies in the dropped part."""
        i0 = int(np.argmin(np.abs(self.s)))
        return self.lo > 0 and self.z[: self.lo].max() > self.z[self.lo: i0 + 1].max() + 1e-6

    def tip_message(self, name: str) -> str:
        a, b, deg = self._steep(slice(None, self.lo))
        i0 = int(np.argmin(np.abs(self.s)))
        tip = int(np.argmax(self.z[: self.lo]))
        return (f"wheel {name}: the flange face at s = {a:.2f} .. {b:.2f} mm is steeper than the "
                f"{self.limit_deg:g} deg a contact may have (up to {deg:.1f} deg), and the usable "
                f"profile ends there: s = {self.s[0] * 1e3:.2f} .. "
                f"{self.s[self.lo - 1] * 1e3:.2f} mm would be dropped with the flange tip "
                f"(s = {self.s[tip] * 1e3:.2f} mm, "
                f"dr = {self.z[tip] * 1e3:.2f} mm; the kept part reaches dr = "
                f"{self.z[self.lo: i0 + 1].max() * 1e3:.2f} mm), so flange contacts would end "
                "at the profile's end; check the flange of the profile (or its wear)")


#: the rail head's top: the surface within this depth (m) below the top of rail. A placement
#: that keeps nothing deeper is a sliver of it (or of a spline's overshoot beside a step), and
#: the head's top is dropped. A rail read from a file falls by at least 5 mm on both sides
#: (:func:`lutmpi.profiles.validate.looks_like_rail`, whose crown is the same 1 mm)
RAIL_TOP_DEPTH = 1e-3


@dataclass(frozen=True, eq=False)
class RailCut(SteepCut):
    """What the rail placement keeps of a profile: the intervals ``lo..hi`` between the samples
    around the top of rail whose slope, as placed (inclined), is within ``limit_deg``
    (:class:`SteepCut`); ``x`` is the profile's own ``v`` (m), gauge side first. Dropping the
    head's top is an error: a top of rail steeper than the limit on both sides, or a kept part
    that stays within :data:`RAIL_TOP_DEPTH` of it."""

    KIND: ClassVar[str] = "rail"
    COORD: ClassVar[str] = "v"
    SIDES: ClassVar[tuple[str, str]] = ("gauge", "field")
    FRAME: ClassVar[str] = " as placed"
    SPAN: ClassVar[int] = 1

    @classmethod
    def of(cls, name: str, v: np.ndarray, u: np.ndarray, z: np.ndarray,
           max_slope_deg: float = MAX_SLOPE_DEG) -> RailCut:
        """The cut of the rail ``name`` sampled at profile ``v`` and placed at ``(u, z)`` (m, all
        shape (n,)); an interval where ``u`` does not increase (an overhang) is steep.

        Raises
        ------
        GeometryError
            The cut would drop the head's top (class docstring).
        """
        du, dz = np.diff(u), np.diff(z)
        with np.errstate(divide="ignore", invalid="ignore"):
            slope = np.where(du > 0, dz / du, np.inf)
        limit = np.tan(np.radians(max_slope_deg))
        k = int(np.argmax(z))
        # the interval on the field side of the top, else the one on its gauge side
        ref = [i for i in (min(k, slope.size - 1), k - 1)
               if 0 <= i < slope.size and abs(slope[i]) <= limit]
        if not ref:
            near = np.abs(slope[max(k - 1, 0): k + 1])
            raise GeometryError(
                f"rail {name}: the top of rail (its highest point as placed, v = "
                f"{v[k] * 1e3:.2f} mm) lies between stretches steeper than the "
                f"{max_slope_deg:g} deg a contact may have (up to "
                f"{np.degrees(np.arctan(near.max())):.1f} deg): the placement would drop the "
                "head's top; check the crown of the profile (a spike or a step?)")
        lo, hi = _contiguous_slope_range(slope, ref[0], limit)
        cut = cls(x=v, slope=slope, lo=lo, hi=hi, limit_deg=float(max_slope_deg))
        depth = float(z[k] - z[lo: hi + 2].min())
        if depth < RAIL_TOP_DEPTH:
            raise GeometryError(cut._sliver_message(name, v[k], depth))
        return cut

    def _sliver_message(self, name: str, v_top: float, depth: float) -> str:
        use = self.span_mm(self.lo, self.hi)
        beyond = []
        for part, side in ((slice(None, self.lo), self.SIDES[0]),
                           (slice(self.hi + 1, None), self.SIDES[1])):
            if np.arange(self.slope.size)[part].size:
                a, b, deg = self._steep(part)
                beyond.append(f"v = {a:.2f} .. {b:.2f} mm on the {side} side (up to {deg:.1f} deg)")
        return (f"rail {name}: the placement would keep only v = {use[0]:.2f} .. {use[1]:.2f} mm "
                f"around the top of rail (v = {v_top * 1e3:.2f} mm), nowhere more than "
                f"{depth * 1e3:.3f} mm below it (a rail head falls away by more than "
                f"{RAIL_TOP_DEPTH * 1e3:g} mm): beyond it, {' and '.join(beyond)} are steeper than "
                f"the {self.limit_deg:g} deg a contact may have as placed, so the head's top would "
                "be dropped; check the crown of the profile (a step in it? an interpolating "
                "spline overshoots beside a step)")


@dataclass(frozen=True, eq=False)
class WheelGeometry:
    """A wheel: profile ``dr(s)``, nominal radius ``r0``, tape-circle distance ``d``.

    In the wheelset frame, the point of profile coordinate ``s`` at angle ``phi`` on the wheel of
    side ``side`` is ``(r sin phi, side (d + s), -r cos phi)`` with ``r = r0 + dr(s)``; ``phi = 0``
    is the lowest point.
    """

    profile: Profile
    r0: float
    d: float
    s_min: float
    s_max: float

    @classmethod
    def place(
        cls, profile: Profile, r0: float, d: float, max_slope_deg: float = MAX_SLOPE_DEG
    ) -> WheelGeometry:
        if profile.kind != "wheel":
            raise GeometryError(f"expected a wheel profile, got a {profile.kind} ({profile.name})")
        if not profile.y_min < 0.0 < profile.y_max:
            raise GeometryError(
                f"wheel {profile.name}: the tape circle s = 0 is outside the profile"
            )
        cut = WheelCut.of(profile, max_slope_deg)
        if cut.tip_dropped:
            raise GeometryError(cut.tip_message(profile.name))
        for text in cut.drop_messages(profile.name):
            log.warning("%s", text)
        return cls(profile=profile, r0=float(r0), d=float(d), s_min=float(cut.s[cut.lo]),
                   s_max=float(cut.s[cut.hi]))

    def radius(self, s: np.ndarray | float) -> np.ndarray:
        return self.r0 + self.profile.z_at(s)

    def dr(self, s: np.ndarray | float) -> np.ndarray:
        return self.profile.slope(s)

    def flange_tip_radius(self) -> float:
        s = np.linspace(self.s_min, 0.0, 4000)
        return float(self.radius(s).max())
