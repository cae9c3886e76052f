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

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cached_property, partial

import numpy as np
from scipy.optimize import brentq, minimize_scalar

from lutmpi.contact import local_root as lr
from lutmpi.contact import rigid_kernels as rk
from lutmpi.contact import roll_scan as rs
from lutmpi.geometry.track import SIDES, PlacedRail, WheelGeometry


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

    @property
    def all_idx(self) -> np.ndarray:
        return np.arange(self.s.size, dtype=np.int64)


@dataclass
class Locus:
    """The contact locus of one wheel at one pose (arrays over the samples)."""

    side: float
    s: np.ndarray
    phi: np.ndarray
    gap: np.ndarray  # vertical gap to the rail, m (+inf outside the rail)
    #: ``gap`` with every minimum the samples do not resolve set to its resampled gap (what
    #: the rigid contacts are chosen by: :func:`~lutmpi.contact.rigid_kernels.dip_minima`);
    #: None where not computed
    gap_min: np.ndarray | None = None


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
    gap is within ``double_tol`` of it and that is separated from it by a gap maximum (compiled:
    :func:`lutmpi.contact.rigid_kernels.contact_minima`)."""
    return [int(i) for i in rk.contact_minima(np.asarray(gap, dtype=float), float(double_tol),
                                              int(max_contacts))]


@dataclass
class RigidContact:
    """A rigid contact found by the locus method (track frame, SI). ``at_end``: the gap minimum
    lies on the first or last usable point of the wheel's or the rail's data."""

    side: float
    s: float
    phi: float
    point: np.ndarray
    u: float
    gap: float
    at_end: bool = False


@dataclass(frozen=True)
class RigidRoot:
    """One rigid two-wheel contact solution (a root of ``h(roll) = z_left - z_right``).

    ``stable``: ``h`` falls through zero with increasing roll, so ``max(z_left, z_right)`` — the
    lowest height the wheelset can take at that roll — has a local minimum there (a local minimum
    of the potential energy under the vertical load). ``at_end``: a contact of this root lies on
    the end of a profile's data."""

    roll: float
    z_g: float
    stable: bool
    at_end: bool


@dataclass
class RigidSolution:
    """Rigid two-point contact pose from the locus method.

    ``n_roots`` counts the rigid solutions found over the admissible roll range (0: no rigid
    contact exists); ``roots`` lists them; ``at_end`` is True when the chosen one has a contact
    on the end of a profile's data (its numbers are then not a valid contact)."""

    y: float
    yaw: float
    z_g: float
    roll: float
    success: bool
    message: str
    nit: int
    contacts: dict[str, list[RigidContact]] = field(default_factory=dict)
    loci: dict[str, Locus] = field(default_factory=dict)
    n_roots: int = 0
    roots: tuple[RigidRoot, ...] = ()
    at_end: bool = False
    #: end circles of the wheels' data that reach into the rail off the locus
    #: (:meth:`LocusSolver.rim_check`): ``(side, s, phi, gap)`` each, m, rad, m (gap < 0)
    rim: tuple[tuple[str, float, float, float], ...] = ()
    #: ``|z_left - z_right|`` at the root (m): the two wheels' touching heights of G on their
    #: whole loci, equal at a root to rounding; above :data:`MISMATCH_M` the root lies on a jump
    #: of a sampled height, not on a zero of the height mismatch (0 with the roll held)
    mismatch: float = 0.0


SCAN_DS = 1e-3  # m, wheel sample spacing of the roll scan
SCAN_STEP = 5e-4  # rad, roll step of the scan
SHIFT_STEP = 5e-4  # rad, step by which a coarse bracket moves on the full samples
MAX_SHIFT = 8  # steps a coarse bracket may move (4 mrad: independent of the scan's step)
MEMO_SIZE = 8  # rigid solutions kept per solver
ROLL_MARGIN = 1e-2  # rad, added to the geometric roll bound (locus angles under yaw)
DIP_XTOL = 1e-7  # rad, tolerance of the extremum search between two scan points
#: m: an end circle of a wheel's data whose smallest gap to the rail lies further below zero
#: than this at the chosen root reaches into the rail off the locus (:meth:`LocusSolver.
#: rim_check`); the root is then no contact of the surfaces the data describe
RIM_TOL = 1e-6
#: m: a root whose two touching heights differ by more than this is no root of the whole
#: loci (:attr:`RigidSolution.mismatch`); converged roots agree to ~1e-13 m, and to 3.4 nm on
#: the worn pairs of ``benchmarks/root_consistency.py``
MISMATCH_M = 1e-7


# -- one side ----------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class LocusSide:
    """Pose-independent data of one wheel on its rail: samples, the rail's height table."""

    name: str
    sign: float
    wheel: WheelGeometry
    rail: PlacedRail
    samp: LocusSampling
    coarse: np.ndarray  # sample indices of the roll scan (every SCAN_DS)
    lim: np.ndarray  # (u0, du, u_min, u_max) of the rail's height table
    ends: np.ndarray  # (2, 2): (s, r) of the circles at the ends of the wheel's data, m
    zmax: float  # the rail's highest point over its data, m
    #: (coarse samples, 6): the ranges of their roll-scan refinement windows
    #: (:func:`~lutmpi.contact.rigid_kernels.window_ranges`)
    windows: np.ndarray

    @classmethod
    def build(cls, name: str, wheel: WheelGeometry, rail: PlacedRail, ds: float) -> LocusSide:
        samp = LocusSampling.build(wheel, ds)
        step = max(1, int(round(SCAN_DS / ds)))
        u0, du, _ = rail.height_table
        coarse = np.unique(np.append(np.arange(0, samp.s.size, step),
                                     samp.s.size - 1)).astype(np.int64)
        return cls(name=name, sign=SIDES[name], wheel=wheel, rail=rail, samp=samp,
                   coarse=coarse, windows=rk.window_ranges(coarse, samp.s, samp.r, samp.dr),
                   lim=np.array([u0, du, rail.u_min, rail.u_max]),
                   ends=np.array([[s, float(wheel.radius(s))]
                                  for s in (wheel.s_min, wheel.s_max)]),
                   zmax=float(np.max(rail.height_table[2])))

    @cached_property
    def local_args(self) -> tuple:
        """This side's arguments of the compiled local solve and heights
        (:mod:`lutmpi.contact.rigid_kernels`; made once: the finish of every pose reads
        them)."""
        sp = self.samp
        return (sp.s, sp.r, sp.dr, self.wheel.d, self.rail.height_table[2], self.lim)

    @property
    def scan_args(self) -> tuple:
        """This side's arguments of the compiled roll scan
        (:func:`~lutmpi.contact.roll_scan.scan`): the coarse indices, :attr:`local_args`
        contiguous copies of the coarse samples, the ranges of their refinement windows
        (:func:`~lutmpi.contact.rigid_kernels.window_ranges`) and the rail's range extrema
        (:func:`~lutmpi.contact.rigid_kernels.extreme_tables`)."""
        sp, c = self.samp, self.coarse
        return (c, *self.local_args, sp.s[c].copy(), sp.r[c].copy(), sp.dr[c].copy(),
                self.windows, *rk.extreme_tables(self.rail.height_table[2]))

    def at_end(self, gap: np.ndarray, i: int) -> bool:
        """True when sample ``i`` (the gap minimum) is a first/last usable point of the wheel,
        or next to a point that is not over the rail (the end of the rail's data)."""
        n = gap.size
        if i <= 0 or i >= n - 1:
            return True
        return not (math.isfinite(gap[i - 1]) and math.isfinite(gap[i + 1]))




def _per_side(obj, kind: type) -> dict[str, object]:
    if isinstance(obj, kind):
        return {name: obj for name in SIDES}
    if set(obj) != set(SIDES):
        raise ValueError(f"expected one {kind.__name__} or one per side {list(SIDES)}")
    return dict(obj)


class LocusSolver:
    """Rigid contact of the wheelset for given (y_g, yaw) by the contact-locus method.

    Parameters
    ----------
    wheel, rail : placed geometry, one for both sides (mirrored) or a mapping
        ``{"left": ..., "right": ...}``
    ds : float
        Sample spacing along the wheel profile, m.
    double_tol : float
        Gap tolerance for a second contact (double contact), m.

    Root selection (every pose)
        ``h(roll) = z_left(roll) - z_right(roll)`` (the heights of G at which each wheel touches
        its rail) is scanned over the whole admissible roll range ``|roll| <= roll_max`` (step
        :data:`SCAN_STEP`, wheel samples every :data:`SCAN_DS`); every sign change, every dip of
        ``|h|`` between scan points that crosses zero, and every edge of a range where a wheel
        has no point over its rail (``h`` NaN on one side) is a bracket, refined by Brent's method
        on the full samples. The wheelset under its vertical load can only sit at
        ``z = max(z_left, z_right)``; a root where ``h`` falls through zero is a local minimum of
        that height (stable), one where ``h`` rises through zero a local maximum (unstable).
        **Criterion**: the stable root of lowest ``z_g`` (minimum potential energy under the
        vertical load). When one of its contacts lies on the end of a profile's data it is
        returned with ``at_end = True`` (the data do not reach the contact: not a valid result).
    """

    def __init__(
        self,
        wheel: WheelGeometry | Mapping[str, WheelGeometry],
        rail: PlacedRail | Mapping[str, PlacedRail],
        ds: float = 1e-4,
        double_tol: float = 1e-5,
        max_contacts: int = 2,
        hold_roll: bool = False,
    ):
        wheels, rails = _per_side(wheel, WheelGeometry), _per_side(rail, PlacedRail)
        self.hold_roll = hold_roll
        self.sides = {name: LocusSide.build(name, wheels[name], rails[name], ds) for name in SIDES}
        self.double_tol = double_tol
        self.max_contacts = max_contacts
        self.lever = 0.5 * (wheels["left"].d + wheels["right"].d)
        self.roll_max = self._roll_bound()
        self.side_lipschitz = self._side_lipschitz()
        self.lipschitz = 0.0
        for share in self.side_lipschitz:
            self.lipschitz += share
        n = int(np.ceil(self.roll_max / SCAN_STEP))
        self.scan_rolls = np.linspace(-n * SCAN_STEP, n * SCAN_STEP, 2 * n + 1)
        self._memo: dict[tuple, RigidSolution] = {}
        # the whole loci of the pose being solved, by (y, yaw, roll): rk.full_locus's result
        self._loci: dict[tuple[float, float, float], tuple] = {}
        self._scan_sides = tuple(self.sides[name].scan_args for name in SIDES)
        self._local_sides = tuple(self.sides[name].local_args for name in SIDES)
        # the scan's local bound (:func:`~lutmpi.contact.roll_scan.scan_adaptive`): each
        # wheel's share of the bound, the end roll's sine and each rail's slope table
        self._scan_bound = (*self.side_lipschitz, self.scan_sine,
                            *(rs.slope_table(self.sides[name].rail.height_table[2],
                                             float(self.sides[name].rail.height_table[1]))
                              for name in SIDES))
        self._ends = np.array([[(s, r, self.sides[name].zmax) for s, r in self.sides[name].ends]
                               for name in SIDES])

    def _roll_bound(self) -> float:
        """Admissible roll range. At a root both wheels touch, so
        ``sin(roll) (d_L + s_L + d_R + s_R) = (z_rail,L - z_rail,R) + cos(roll) (r_L cos phi_L -
        r_R cos phi_R)``: ``|roll|`` is at most the span of both rails' heights plus the span of
        both wheels' radii over the smallest lever ``d + s_min`` of the two wheels, plus
        :data:`ROLL_MARGIN` for the locus angles ``phi`` of a yawed wheelset."""
        sd = list(self.sides.values())
        z = np.concatenate([x.rail.z for x in sd])
        r = np.concatenate([x.samp.r for x in sd])
        lever = sum(x.wheel.d + x.samp.s[0] for x in sd)
        return float(min(np.arcsin(min((np.ptp(z) + np.ptp(r)) / lever, 1.0)) + ROLL_MARGIN,
                         0.25))

    def _side_lipschitz(self) -> tuple[float, float]:
        """Each wheel's share (left, right) of a bound of ``|dh/droll|``, 1/rad x m, over the
        scan's roll range (:attr:`lipschitz`, their sum). A touching height is
        an envelope over the wheel points, so its derivative is that of one point's gap ``p_z -
        z_rail(u)`` (the locus point's own motion along its circle adds nothing there: at the
        touching point the wheel's normal is the rail's, and the gap is stationary along the
        circle). With ``R = Rz(yaw) Rx(roll)`` a point ``b`` of the wheelset frame (``|b_y| =
        |d + s|``, ``|b_z| <= r``) moves by ``dp_z = cos(roll) b_y - sin(roll) b_z`` and
        ``|dp_y| <= |sin(roll) b_y + cos(roll) b_z|`` per radian of roll, so its gap's
        derivative is at most ``|d + s| + r sin(x) + slope (r + |d + s| sin(x))``, with ``x``
        the scan's end roll (a whole number of :data:`SCAN_STEP` at or beyond ``roll_max``) and
        ``slope`` the steepest slope of the rail's height table, which the gaps interpolate
        (steeper than its data's chords: 13.3 against 11.3 on the UIC60 ``.prr``): the sum of
        both sides' largest over the samples. The bound ``hypot(d + s, r) (1 + slope)`` it
        replaces is ~1.7 times larger. The steepest smooth ``|dh/droll|`` measured, on the
        paper's pair, a thinned flange and a worn wheel on measured rails, is ~1.5: at a contact
        on smooth profiles the rail's slope is the wheel's, so a tangency argument would bound
        it far lower, but not at a corner of the data, where the slope of the rail under the
        wheel can be any it has."""
        out = []
        for sd in self.sides.values():
            by, r = np.abs(sd.wheel.d + sd.samp.s), sd.samp.r
            _, du, tab = sd.rail.height_table
            slope = float(np.max(np.abs(np.diff(tab)))) / du
            out.append(float(np.max(by + self.scan_sine * r + slope * (r + self.scan_sine * by))))
        return out[0], out[1]

    @property
    def scan_sine(self) -> float:
        """The sine of the scan's end roll (a whole number of :data:`SCAN_STEP` at or beyond
        ``roll_max``), which the bounds of ``|dh/droll|`` take for ``|sin(roll)|``."""
        return float(np.sin(np.ceil(self.roll_max / SCAN_STEP) * SCAN_STEP))

    # -- heights ---------------------------------------------------------------------------
    def heights(self, y: float, yaw: float, roll: float,
                sub: Mapping[str, np.ndarray] | None = None) -> tuple[float, float]:
        """Touching heights (left, right) of G at this roll; ``sub`` restricts each side's
        samples (sorted indices)."""
        idx = [sd.samp.all_idx if sub is None else sub[name] for name, sd in self.sides.items()]
        zl, zr, _, _ = lr.heights(float(y), float(yaw), float(roll), *self._local_sides,
                                  idx[0], idx[1], np.empty(idx[0].size), np.empty(idx[1].size))
        return zl, zr

    def _h(self, y: float, yaw: float, roll: float, sub=None) -> float:
        zl, zr = self.heights(y, yaw, roll, sub)
        return zl - zr if np.isfinite(zl) and np.isfinite(zr) else np.nan

    # -- the local solve (a start near roll 0) -----------------------------------------------
    def _local(self, y: float, yaw: float, xtol: float, max_secant: int) -> tuple[float | None,
                                                                                   int]:
        """Secant iteration on ``h`` from roll 0 on the samples near the gap minima, checked on
        the whole profile (solved again if the minimum moved: a contact jump); compiled
        (:func:`lutmpi.contact.local_root.local_root`). Returns the roll (None when the
        iteration finds no root) and the number of ``h`` evaluations."""
        roll, calls, status, full = lr.local_root(float(y), float(yaw), float(xtol),
                                                  int(max_secant), float(self.lever),
                                                  *self._local_sides)
        if status == lr.LOCAL_OK:
            self._loci[(float(y), float(yaw), float(roll))] = full
        if status == lr.LOCAL_NOCONV:  # SciPy's brentq raised these
            raise RuntimeError(f"Failed to converge after {lr.BRENTQ_ITER} iterations, value "
                               f"is {roll}.")
        if status == lr.LOCAL_NAN:
            raise ValueError(f"The function value at x={roll} is NaN; solver cannot continue.")
        return (float(roll) if status == lr.LOCAL_OK else None), int(calls)

    # -- the scan over the admissible roll range ---------------------------------------------
    def scan(self, y: float, yaw: float, rolls: np.ndarray | None = None) -> np.ndarray:
        """``h`` on the scan grid (coarse wheel samples); NaN where a wheel misses its rail."""
        rolls = self.scan_rolls if rolls is None else np.asarray(rolls, dtype=float)
        return rs.scan(rolls, float(yaw), float(y), *self._scan_sides)

    def brackets(self, y: float, yaw: float) -> list[tuple[float, float, bool]]:
        """Roll intervals holding one root each, with its stability: ``(a, b, stable)``. The
        scan steps by at least ``max(SCAN_STEP, |h| / lipschitz)`` and, where both ends
        certify it root-free, by up to twice that (:func:`~lutmpi.contact.roll_scan.
        scan_adaptive`): no root is skipped, and far from the roots the scan takes long steps.
        The bisections and extremum searches of :func:`find_brackets` run compiled."""
        y, yaw, sides = float(y), float(yaw), self._scan_sides
        x, h = rs.scan_adaptive(float(self.scan_rolls[0]), float(self.scan_rolls[-1]), SCAN_STEP,
                                self.lipschitz, yaw, y, *sides, self._scan_bound)
        return find_brackets(
            x, lambda r: self.scan(y, yaw, r), h=h, lip=self.lipschitz,
            edge=lambda a, b, n: rs.edge_bisect(a, b, n, yaw, y, sides),
            extremum=lambda lo, hi, sgn, n: rs.bounded_min(lo, hi, sgn, DIP_XTOL, n, yaw, y, sides))

    def warm(self) -> None:
        """Load (or compile) the compiled searches a pose may not reach (the extremum search
        and the NaN-edge bisection of :meth:`brackets`)."""
        rs.bounded_min(-SCAN_STEP, SCAN_STEP, 1.0, DIP_XTOL, 3, 0.0, 0.0, self._scan_sides)
        rs.edge_bisect(0.0, SCAN_STEP, 2, 0.0, 0.0, self._scan_sides)

    # -- the solve ---------------------------------------------------------------------------
    def solve(self, y: float, yaw: float, xtol: float = 1e-13,
              max_secant: int = 12) -> RigidSolution:
        """Every rigid two-point contact at (y, yaw), and the stable one (class docstring).

        A local secant solve from roll 0 gives the usual root cheaply; the scan says whether
        other roots exist and which one is the stable one; the chosen bracket is solved by
        Brent's method on the full samples unless the local root already lies in it. The last
        few solutions are kept (every method of a pose starts from the same rigid solution):
        treat the result as read-only."""
        key = (float(y), float(yaw), xtol, max_secant)
        hit = self._memo.get(key)
        if hit is None:
            hit = self._solve(*key)
            if len(self._memo) >= MEMO_SIZE:
                self._memo.pop(next(iter(self._memo)))
            self._memo[key] = hit
        return hit

    def _solve(self, y: float, yaw: float, xtol: float, max_secant: int) -> RigidSolution:
        self._loci.clear()
        if self.hold_roll:
            return self._held(y, yaw)
        local, nit = self._local(y, yaw, xtol, max_secant)
        roots: list[RigidRoot] = []
        for a, b, stable in self.brackets(y, yaw):
            roll = self._root_in(y, yaw, a, b, stable, local, xtol)
            if roll is not None and all(abs(roll - q.roll) > 1e-9 for q in roots):
                roots.append(self._describe(y, yaw, roll, stable))
        if not roots and local is not None:  # the scan's resolution missed the local root
            roots.append(self._describe(y, yaw, local, True))
        if not roots:  # no bracket, or none whose root the full samples confirm
            return RigidSolution(y, yaw, np.nan, np.nan, False,
                                 "no rigid two-wheel contact over the admissible roll range "
                                 f"|roll| <= {self.roll_max:.3g} rad (a wheel misses its rail)",
                                 nit)
        chosen = _choose(roots, -1.0 if y < 0.0 or (y == 0.0 and yaw < 0.0) else 1.0)
        if (local is not None and _same(local, chosen.roll, self.scan_rolls)
                and min(roots, key=lambda q: abs(q.roll - local)) is chosen):
            roll = local  # (not where a root nearer to it is another: three within a step)
        else:
            roll = chosen.roll
        out = self.finish(y, yaw, roll, nit)
        out.n_roots = len(roots)
        out.roots = tuple(roots)
        return self._mark_ends(out)

    def _root_in(self, y, yaw, a, b, stable, local, xtol) -> float | None:
        """The root of a coarse bracket on the full samples. The coarse samples can misplace a
        sign change by up to ~1 mrad on a narrow flange contact: when the full-sample ``h`` has
        no sign change on ``[a, b]`` the bracket is moved by :data:`SHIFT_STEP` at a time
        toward the root (the side ``h``'s sign and the root's direction of crossing point
        to), at most :data:`MAX_SHIFT` times."""
        if a == b:
            return a
        if local is not None and a <= local <= b:
            return local
        h = lambda r: self._h(y, yaw, r)  # noqa: E731
        fa, fb = h(a), h(b)
        for _ in range(MAX_SHIFT):
            if np.isfinite(fa) and np.isfinite(fb) and fa * fb <= 0:
                return float(brentq(h, a, b, xtol=xtol, rtol=4 * np.finfo(float).eps))
            ref = fa if np.isfinite(fa) else fb
            if not np.isfinite(ref):
                return None
            # a falling root (stable) lies to the right where h > 0, a rising one to the left
            if (ref > 0) == stable:
                a, fa, b = b, fb, b + SHIFT_STEP
                fb = h(b)
            else:
                b, fb, a = a, fa, a - SHIFT_STEP
                fa = h(a)
            if local is not None and a <= local <= b:
                return local
        return None

    def _full(self, y: float, yaw: float, roll: float) -> tuple:
        """:func:`~lutmpi.contact.rigid_kernels.full_locus` at this roll: both wheels' whole
        loci, computed once per roll of the pose being solved (the local solve's check has
        usually computed them at its root already)."""
        key = (float(y), float(yaw), float(roll))
        if key not in self._loci:
            self._loci[key] = rk.full_locus(*key, *self._local_sides)
        return self._loci[key]

    def _describe(self, y: float, yaw: float, roll: float, stable: bool) -> RigidRoot:
        _, gl, zl, il, _, gr, zr, ir = self._full(y, yaw, roll)
        end = any(sd.at_end(g, i) for sd, g, i in zip(self.sides.values(), (gl, gr), (il, ir),
                                                       strict=True))
        return RigidRoot(roll=float(roll), z_g=0.5 * (zl + zr), stable=stable, at_end=end)

    def _held(self, y: float, yaw: float) -> RigidSolution:
        """Roll held at zero (EN 15302 Annex E's Δr): each wheel's contact is the minimum of its
        own gap with the wheelset level; G sits at the higher of the two touching heights (the
        other wheel clears its rail by the difference, stored as its contact's gap)."""
        zl, zr = self._full(y, yaw, 0.0)[2::4]
        if not (np.isfinite(zl) and np.isfinite(zr)):
            return RigidSolution(y, yaw, np.nan, np.nan, False,
                                 "a wheel has no point over its rail at zero roll", 1)
        out = self.finish(y, yaw, 0.0, 1, z_g=max(zl, zr))
        out.n_roots = 1
        out.roots = (RigidRoot(roll=0.0, z_g=out.z_g, stable=True, at_end=False),)
        return self._mark_ends(out)

    def rim_check(self, y: float, yaw: float, roll: float, z_g: float
                  ) -> tuple[tuple[str, float, float, float], ...]:
        """The end circles of the wheels' data (the surfaces' edges) that reach more than
        :data:`RIM_TOL` into the rail at this pose: ``(side, s, phi, gap)`` each (m, rad, m).
        The locus holds only the points where a wheel's surface can touch an extruded rail
        (its normal across x); an edge can touch it anywhere on its circle: at a yaw far beyond
        running the field-side rim passes through the rail while the locus sees a contact
        (:func:`~lutmpi.contact.rigid_kernels.end_circle_gap`)."""
        gaps = rk.rim_gaps(float(y), float(yaw), float(roll), float(z_g), *self._local_sides,
                           self._ends)
        if not any(g[0] < -RIM_TOL for side in gaps.tolist() for g in side):
            return ()
        return tuple((name, float(self._ends[k, e, 0]), float(gaps[k, e, 1]),
                      float(gaps[k, e, 0]))
                     for k, name in enumerate(self.sides) for e in range(2)
                     if gaps[k, e, 0] < -RIM_TOL)

    def _mark_ends(self, out: RigidSolution) -> RigidSolution:
        """``at_end`` and the message of a chosen root: a contact on the end of a profile's
        data, or an end circle through the rail (:meth:`rim_check`)."""
        out.rim = self.rim_check(out.y, out.yaw, out.roll, out.z_g)
        out.at_end = bool(out.rim) or any(c.at_end for cs in out.contacts.values() for c in cs)
        if out.at_end:
            out.message = "a contact lies on the end of a profile's data"
        return out

    def finish(self, y: float, yaw: float, roll: float, nit: int = 0,
               z_g: float | None = None) -> RigidSolution:
        """Contact details at the converged roll (``z_g``: given, else the mean of the two
        touching heights, which are equal at a root)."""
        full = self._full(y, yaw, roll)
        self._loci.clear()  # the gaps are lifted below, in place
        loci, z_side = {}, []
        for k, (name, sd) in enumerate(self.sides.items()):
            phi, gap, height = full[4 * k: 4 * k + 3]  # G at height 0
            loci[name] = Locus(side=sd.sign, s=sd.samp.s, phi=phi, gap=gap)
            z_side.append(height)
        mismatch = 0.0
        if z_g is None:
            z_g = 0.5 * (z_side[0] + z_side[1])
            mismatch = abs(z_side[0] - z_side[1])
        out = RigidSolution(y, yaw, z_g, roll, True, "converged", nit, mismatch=mismatch)
        # held roll: one contact per wheel, the minimum of its own gap
        mc = 1 if self.hold_roll else self.max_contacts
        R = rk.rotation(float(yaw), float(roll))
        for name, loc in loci.items():
            sd = self.sides[name]
            s, r, dr, d, tab, lim = sd.local_args
            # the minima the samples do not resolve, resampled (as the touching heights were)
            gap, s_fix = rk.dip_minima(loc.gap, sd.sign, s, r, dr, d, R, float(y), lim[0],
                                       lim[1], tab, lim[2], lim[3])
            loc.gap += z_g  # lifting G lifts every gap
            gap += z_g
            loc.gap_min = gap
            out.loci[name] = loc
            rows = rk.rigid_contacts(gap, loc.s, sd.sign, sd.wheel.d, sd.wheel.r0,
                                     sd.wheel.profile.ppolys, float(y), float(yaw),
                                     float(roll), float(z_g), float(self.double_tol), int(mc),
                                     s_fix)
            out.contacts[name] = [
                RigidContact(side=sd.sign, s=t[0], phi=t[1], point=r[2:5], u=t[5], gap=t[6],
                             at_end=bool(t[7]))
                for r, t in zip(rows, rows.tolist(), strict=True)]
        return out


# -- roots of the height mismatch -------------------------------------------------------------
def find_brackets(x: np.ndarray, hfun, n_bisect: int = 30, n_golden: int = 30,
                  h: np.ndarray | None = None, lip: float = np.inf, edge=None,
                  extremum=None) -> list[tuple[float, float, bool]]:
    """Intervals of roll holding one root of ``h`` each, and whether the root is stable.

    Parameters
    ----------
    x : ndarray
        Increasing scan grid of roll, rad.
    hfun : callable
        ``hfun(rolls) -> h`` (m), NaN where a wheel misses its rail.
    h : ndarray, optional
        ``hfun(x)`` when already known.
    lip : float
        A bound of ``|dh/droll|``: a NaN range whose finite neighbour has ``|h| > lip`` times
        the step to it cannot hold a root before it and is not bisected.
    edge, extremum : callable, optional
        ``edge(a, b, n) -> (x, h)``: the last finite point between ``a`` (finite) and ``b``
        (NaN) after ``n`` bisections; ``extremum(lo, hi, sgn, n) -> (x, sgn * h)``: the minimum
        of ``sgn * h`` on ``[lo, hi]`` by SciPy's bounded method in at most ``n`` evaluations.
        Default: both by ``hfun``.

    Returns
    -------
    list of (a, b, stable)
        ``a <= b``; ``a == b`` for an exact zero. ``stable``: ``h`` falls through zero.
        Besides the sign changes between scan points, the last finite point before every NaN
        range is found by bisection (a root can sit between a scan point and a NaN range, on
        either side of roll 0), and every dip of ``|h|`` toward zero between scan points is
        searched for its extremum (two close roots can hide between two scan points); where
        ``h`` folds beside a sign change (:func:`~lutmpi.contact.roll_scan.
        bracket_searches`: three roots within a scan step) the two steps next to the fold are
        scanned at a quarter step first (``hfun`` at six more rolls).
    """
    x = np.ascontiguousarray(x, dtype=float)
    h = np.ascontiguousarray(hfun(x) if h is None else h, dtype=float)
    if edge is None:
        edge = partial(_edge_by, hfun)
    if extremum is None:
        extremum = partial(_extremum_by, hfun)
    # compiled: which NaN edges and dips need a search, and the brackets of all the points
    edges, dips, folds = rs.bracket_searches(x, h, float(lip))
    if folds.size and hfun is not None:
        # a fold beside a sign change: both steps next to it scanned at a quarter step, and
        # the searches then run on the finer scan (its sign changes and dips)
        xs = np.unique(np.array([x[i] + f * (x[i + d] - x[i]) for i in folds.tolist()
                                 for d in (-1, 1) for f in (0.25, 0.5, 0.75)]))
        xs = xs[np.searchsorted(x, xs) == np.searchsorted(x, xs, "right")]  # new rolls only
        x2 = np.concatenate([x, xs])
        h2 = np.concatenate([h, np.asarray(hfun(xs), dtype=float)])
        order = np.argsort(x2, kind="stable")
        x, h = np.ascontiguousarray(x2[order]), np.ascontiguousarray(h2[order])
        edges, dips, _ = rs.bracket_searches(x, h, float(lip))
    extra = [edge(a, b, n_bisect) for a, b in edges.tolist()]
    for i in dips.tolist():
        sgn = 1.0 if h[i] > 0 else -1.0
        xm, fm = extremum(float(x[i - 1]), float(x[i + 1]), sgn, n_golden)
        extra.append((xm, sgn * fm))
    X, H = x, h
    if extra:
        X = np.concatenate([x, [float(p[0]) for p in extra]])
        H = np.concatenate([h, [float(p[1]) for p in extra]])
    a, b, stable = rs.bracket_ends(x, h, X, H)
    return list(zip(a.tolist(), b.tolist(), stable.tolist(), strict=True))


def _edge_by(hfun, a: float, b: float, n: int) -> tuple[float, float]:
    for _ in range(n):
        m = 0.5 * (a + b)
        if np.isfinite(hfun(np.array([m]))[0]):
            a = m
        else:
            b = m
    return a, float(hfun(np.array([a]))[0])


def _extremum_by(hfun, lo: float, hi: float, sgn: float, n: int) -> tuple[float, float]:
    res = minimize_scalar(lambda r: sgn * hfun(np.array([r]))[0], bounds=(lo, hi),
                          method="bounded", options={"xatol": DIP_XTOL, "maxiter": n})
    return float(res.x), float(res.fun)


#: two roots whose heights differ by less than this (m) are equally low: a symmetric wheelset
#: at y = 0 has mirror-image roots (roll r and -r) whose heights differ only by rounding
TIE_M = 1e-12


def _choose(roots: list[RigidRoot], sgn: float = 1.0) -> RigidRoot:
    """The stable root of lowest z_g (minimum potential energy); with no stable root, the
    lowest root. A chosen root with a contact on a profile's end keeps ``at_end``.

    Among roots within :data:`TIE_M` of the lowest, the one of largest ``sgn * roll``:
    ``sgn = -1`` for a pose that is the mirror image of one with ``sgn = 1`` (y < 0, or y = 0
    and yaw < 0), so a symmetric wheelset's pose and its mirror choose mirror-image roots
    (a worn, hollow wheel at y = 0 and a large yaw has two equally low ones)."""
    pool = [r for r in roots if r.stable] or roots
    low = min(r.z_g for r in pool)
    return max((r for r in pool if r.z_g <= low + TIE_M), key=lambda r: sgn * r.roll)


def _same(a: float, b: float, grid: np.ndarray) -> bool:
    """True when two roots are the same root (closer than one scan step)."""
    return abs(a - b) < 0.5 * (grid[1] - grid[0])
