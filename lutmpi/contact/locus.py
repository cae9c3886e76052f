"""Semi-analytic reference solver: the contact-locus method (rigid two-point contact).

For a wheel of revolution on an extruded rail, a contact point must have a wheel normal with no
component along the rail's extrusion direction x. On each circle of the wheel (profile coordinate
``s``) that condition picks one angle ``phi*(s)`` in closed form; the points ``L(s)`` form the
*contact locus*. Because the rail is invariant in x, contact happens where the vertical gap
``g(s) = L_z(s) - zr(L_u(s))`` has its minimum, and the minimum is zero for rigid contact.

The wheelset's vertical position shifts every gap equally, so for a given roll the height that
makes one wheel touch is explicit; the roll that makes both touch is found by Brent's method.
A second local minimum of the gap within ``double_tol`` of the first flags double contact.

Derivation of ``phi*``: with ``(a, b, c)`` the first row of the rotation ``R`` and the wheel normal
in the wheelset frame ``n ∝ e_rho(phi) - r'(y_w) e_y``, ``e_rho = (sin phi, 0, -cos phi)``, the
condition ``(R n)_x = 0`` reads ``a sin phi - c cos phi = b r'``, i.e.
``phi* = atan2(c, a) + arcsin(b r' / sqrt(a^2 + c^2))``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.optimize import brentq

from lutmpi.geometry.pose import wheelset_rotation
from lutmpi.geometry.track import PlacedRail, WheelGeometry


@dataclass(frozen=True, eq=False)
class LocusSampling:
    """Pose-independent samples of a wheel profile for the locus (``ds`` spacing, m)."""

    s: np.ndarray
    r: np.ndarray
    dr: np.ndarray

    @classmethod
    def build(cls, wheel: WheelGeometry, ds: float = 1e-4) -> LocusSampling:
        s = np.arange(np.ceil(wheel.s_min / ds), np.floor(wheel.s_max / ds) + 1) * ds
        return cls(s=s, r=wheel.radius(s), dr=wheel.dr(s))


@dataclass
class Locus:
    """The contact locus of one wheel at one pose (arrays over the samples)."""

    side: float
    s: np.ndarray
    phi: np.ndarray
    points: np.ndarray  # (n, 3) track frame
    u: np.ndarray  # side-local lateral coordinate of the points
    gap: np.ndarray  # vertical gap to the rail, m (+inf outside the rail)


def locus_angles(side: float, dr: np.ndarray, R: np.ndarray) -> np.ndarray:
    """``phi*`` per sample for wheel ``side`` under rotation ``R`` (rad)."""
    a, b, c = R[0]
    amp = np.hypot(a, c)
    rp = side * dr  # d r / d y_w in the wheelset frame
    return np.arctan2(c, a) + np.arcsin(np.clip(b * rp / amp, -1.0, 1.0))


def wheel_points_body(
    side: float, s: np.ndarray, r: np.ndarray, phi: np.ndarray, d: float
) -> np.ndarray:
    """Wheelset-frame points ``(r sin phi, side (d + s), -r cos phi)``, shape (n, 3)."""
    out = np.empty((phi.size, 3))
    out[:, 0] = r * np.sin(phi)
    out[:, 1] = side * (d + s)
    out[:, 2] = -r * np.cos(phi)
    return out


def compute_locus(
    side: float,
    samp: LocusSampling,
    wheel: WheelGeometry,
    rail: PlacedRail,
    centre: np.ndarray,
    R: np.ndarray,
) -> Locus:
    """Locus points and vertical gaps of one wheel at the pose (``centre``, ``R``)."""
    s, r, dr = samp.s, samp.r, samp.dr
    phi = locus_angles(side, dr, R)
    pts = centre + wheel_points_body(side, s, r, phi, wheel.d) @ R.T
    u = side * pts[:, 1]
    inside = (u >= rail.u_min) & (u <= rail.u_max)
    gap = np.full(u.shape, np.inf)
    gap[inside] = pts[inside, 2] - rail.height_fast(u[inside])
    return Locus(side=side, s=s, phi=phi, points=pts, u=u, gap=gap)


def _parabolic_min(g: np.ndarray, i: int) -> tuple[float, float]:
    """Offset (in samples, within ±0.5) and value of the parabola through g[i-1], g[i], g[i+1]."""
    if i <= 0 or i >= g.size - 1 or not np.isfinite(g[i - 1] + g[i + 1]):
        return 0.0, float(g[i])
    gm, g0, gp = g[i - 1], g[i], g[i + 1]
    den = gm - 2.0 * g0 + gp
    if den <= 0:
        return 0.0, float(g0)
    t = float(np.clip(0.5 * (gm - gp) / den, -0.5, 0.5))
    return t, float(g0 - 0.25 * (gm - gp) * t)


def local_minima(gap: np.ndarray) -> np.ndarray:
    """Indices of the discrete local minima of ``gap`` (finite values only)."""
    g = np.where(np.isfinite(gap), gap, np.inf)
    inner = (g[1:-1] < g[:-2]) & (g[1:-1] <= g[2:])
    idx = np.nonzero(inner)[0] + 1
    ends = [
        i
        for i in (0, g.size - 1)
        if np.isfinite(g[i]) and ((i == 0 and g[0] < g[1]) or (i == g.size - 1 and g[-1] < g[-2]))
    ]
    return np.unique(np.concatenate([idx, np.asarray(ends, dtype=int)]))


def contact_minima(gap: np.ndarray, double_tol: float, max_contacts: int = 2) -> list[int]:
    """Sample indices of the contact(s): the global minimum, plus a second local minimum whose
    gap is within ``double_tol`` of it and that is separated from it by a gap maximum."""
    mins = local_minima(gap)
    if mins.size == 0:
        return []
    order = mins[np.argsort(gap[mins])]
    chosen = [int(order[0])]
    g0 = gap[order[0]]
    for i in order[1:]:
        if len(chosen) >= max_contacts or gap[i] - g0 > double_tol:
            break
        if all(np.max(gap[min(i, j) : max(i, j) + 1]) > gap[i] + 1e-7 for j in chosen):
            chosen.append(int(i))
    return chosen


@dataclass
class RigidContact:
    """A rigid contact found by the locus method (track frame, SI)."""

    side: float
    s: float
    phi: float
    point: np.ndarray
    u: float
    gap: float


@dataclass
class RigidSolution:
    """Rigid two-point contact pose from the locus method."""

    y: float
    yaw: float
    z_g: float
    roll: float
    success: bool
    message: str
    nit: int
    contacts: dict[str, list[RigidContact]] = field(default_factory=dict)
    loci: dict[str, Locus] = field(default_factory=dict)


class LocusSolver:
    """Rigid contact of the wheelset for given (y_g, yaw) by the contact-locus method.

    Parameters
    ----------
    wheel, rail : placed geometry (one wheel and one rail; sides by mirroring)
    ds : float
        Sample spacing along the wheel profile, m.
    double_tol : float
        Gap tolerance for a second contact (double contact), m.
    """

    def __init__(
        self,
        wheel: WheelGeometry,
        rail: PlacedRail,
        ds: float = 1e-4,
        double_tol: float = 1e-5,
        max_contacts: int = 2,
    ):
        self.wheel, self.rail = wheel, rail
        self.samp = LocusSampling.build(wheel, ds)
        self.double_tol = double_tol
        self.max_contacts = max_contacts
        s = self.samp
        self._side2 = np.concatenate([np.ones_like(s.s), -np.ones_like(s.s)])
        self._s2 = np.concatenate([s.s, s.s])
        self._r2 = np.concatenate([s.r, s.r])
        self._dr2 = np.concatenate([s.dr, s.dr])
        self._all_idx = np.arange(2 * s.s.size)

    def heights(self, y: float, yaw: float, roll: float,
                sub: np.ndarray | None = None) -> tuple[float, float]:
        """Touching heights (left, right) for this roll, both sides in one compiled pass;
        ``sub`` restricts the samples (sorted indices into the two concatenated sides)."""
        from lutmpi.contact.kernels import locus_heights

        R = wheelset_rotation(yaw, roll)
        idx = self._all_idx if sub is None else sub
        gap = np.empty(idx.size)
        rail = self.rail
        hl, hr = locus_heights(idx, self.samp.s.size, self._side2, self._s2, self._r2,
                               self._dr2, self.wheel.d, R, y, *rail.height_table, rail.u_min,
                               rail.u_max, gap)
        self._last_gap = gap
        return hl, hr

    def _candidates(self, gap: np.ndarray, band: float = 5e-4, half: int = 30) -> np.ndarray:
        """Indices (both sides concatenated) near every local gap minimum within ``band`` of
        its side's smallest: the only samples that can hold the minimum for small roll changes."""
        n = self.samp.s.size
        out = []
        for off in (0, n):
            g = gap[off:off + n]
            mins = local_minima(g)
            if mins.size == 0:
                out.append(off + np.arange(n))
                continue
            mins = mins[g[mins] <= np.min(g[mins]) + band]
            i = (mins[:, None] + np.arange(-half, half + 1)[None, :]).ravel()
            out.append(off + np.unique(np.clip(i, 0, n - 1)))
        return np.concatenate(out)

    def solve(
        self, y: float, yaw: float, xtol: float = 1e-13, max_secant: int = 12
    ) -> RigidSolution:
        """Rigid two-point contact: z_g and roll such that both wheels touch.

        Secant iteration on the height mismatch ``h(roll) = z_left - z_right`` from a lever-arm
        estimate; Brent's method on a bracket whenever the secant stalls (contact-point jumps
        make ``h`` piecewise smooth). The iterations use only the samples near the gap minima
        found on the whole profile; the result is checked on the whole profile and solved again
        if the minimum moved elsewhere (a contact jump)."""
        nit = 0
        sub: list[np.ndarray | None] = [None]

        def h(roll: float) -> float:
            nonlocal nit
            nit += 1
            zl, zr = self.heights(y, yaw, roll, sub[0])
            return zl - zr

        f0 = h(0.0)
        if not np.isfinite(f0):
            return RigidSolution(y, yaw, np.nan, np.nan, False,
                                 "a wheel has no contact candidate on its rail at zero roll", nit)
        roll = 0.0
        for _ in range(3):
            sub[0] = self._candidates(self._last_gap)
            roll = self._solve_roll(h, roll, xtol, max_secant)
            if roll is None:
                return RigidSolution(y, yaw, np.nan, np.nan, False,
                                     "no roll brackets the two-point contact (wheel off the rail?)",
                                     nit)
            part = self.heights(y, yaw, roll, sub[0])
            full = self.heights(y, yaw, roll)
            nit += 2
            if abs(part[0] - full[0]) <= 1e-12 and abs(part[1] - full[1]) <= 1e-12:
                break
        return self.finish(y, yaw, roll, nit)

    def _solve_roll(self, h, roll0: float, xtol: float, max_secant: int) -> float | None:
        x0, f0 = roll0, h(roll0)
        if not np.isfinite(f0):
            return self._bracketed(h, [], xtol)
        x1 = x0 + f0 / (2.0 * self.wheel.d)
        f1 = h(x1)
        pts = [(x0, f0), (x1, f1)]
        for _ in range(max_secant):
            if not np.isfinite(f1) or f1 == f0:
                break
            x2 = x1 - f1 * (x1 - x0) / (f1 - f0)
            x0, f0, x1 = x1, f1, x2
            f1 = h(x1)
            pts.append((x1, f1))
            if abs(x1 - x0) <= xtol or f1 == 0.0:
                return x1
        return self._bracketed(h, pts, xtol)

    @staticmethod
    def _bracketed(h, pts: list[tuple[float, float]], xtol: float) -> float | None:
        """Brent's method from the best sign change among evaluated points (expanding if none)."""
        pts = sorted((x, f) for x, f in pts if np.isfinite(f))
        for (xa, fa), (xb, fb) in zip(pts[:-1], pts[1:], strict=True):
            if fa * fb <= 0:
                return float(brentq(h, xa, xb, xtol=xtol, rtol=4 * np.finfo(float).eps))
        lo, hi = -0.02, 0.02
        for _ in range(5):
            flo, fhi = h(lo), h(hi)
            if np.isfinite(flo) and np.isfinite(fhi) and flo * fhi <= 0:
                return float(brentq(h, lo, hi, xtol=xtol, rtol=4 * np.finfo(float).eps))
            lo, hi = 2 * lo, 2 * hi
        return None

    def finish(self, y: float, yaw: float, roll: float, nit: int = 0) -> RigidSolution:
        """Contact details at the converged roll."""
        R = wheelset_rotation(yaw, roll)
        loci = {name: compute_locus(side, self.samp, self.wheel, self.rail,
                                    np.array([0.0, y, 0.0]), R)
                for name, side in (("left", 1.0), ("right", -1.0))}
        z_side = [-_parabolic_min(lc.gap, int(np.argmin(lc.gap)))[1] for lc in loci.values()]
        z_g = 0.5 * (z_side[0] + z_side[1])
        centre = np.array([0.0, y, z_g])
        out = RigidSolution(y, yaw, z_g, roll, True, "converged", nit)
        for name, loc in loci.items():
            # the loci were computed with G at height 0: lifting G lifts every point and gap
            loc.points[:, 2] += z_g
            loc.gap += z_g
            out.loci[name] = loc
            out.contacts[name] = [
                self._refine(loc, i, centre, R)
                for i in contact_minima(loc.gap, self.double_tol, self.max_contacts)
            ]
        return out

    def _refine(self, loc: Locus, i: int, centre: np.ndarray, R: np.ndarray) -> RigidContact:
        t, g = _parabolic_min(loc.gap, i)
        ds = loc.s[1] - loc.s[0]
        s = float(loc.s[i] + t * ds)
        r = float(self.wheel.radius(s))
        dr = np.asarray([self.wheel.dr(s)])
        phi = float(locus_angles(loc.side, dr, R)[0])
        p = (
            centre
            + wheel_points_body(
                loc.side, np.array([s]), np.array([r]), np.array([phi]), self.wheel.d
            )[0]
            @ R.T
        )
        return RigidContact(side=loc.side, s=s, phi=phi, point=p, u=float(loc.side * p[1]), gap=g)
