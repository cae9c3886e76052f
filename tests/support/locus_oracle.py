"""Parts of the rigid solve as they ran in Python before they were compiled (issue 14), the
oracles of their compiled forms: the local solve with SciPy's ``brentq`` (equal to the bit),
the bracket list, the contact minima, the contact refinement and the stored contact geometry
(equal to numpy's last-bit rounding of arcsin, arctan and arctan2)."""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from lutmpi.contact.locus import LocusSolver, RigidContact, local_minima
from lutmpi.contact.rigid_kernels import side_gaps


class _State:
    def __init__(self, solver: LocusSolver, y: float, yaw: float):
        self.solver, self.y, self.yaw = solver, y, yaw
        self.last_gap: dict[str, np.ndarray] = {}
        self.nit = 0

    def heights(self, roll: float, sub=None) -> tuple[float, float]:
        from lutmpi.geometry.pose import wheelset_rotation

        R = wheelset_rotation(self.yaw, roll)
        out = []
        for name, sd in self.solver.sides.items():
            idx = sd.samp.all_idx if sub is None else sub[name]
            gap = np.empty(idx.size)
            sp, lim = sd.samp, sd.lim
            h, _ = side_gaps(idx, sd.sign, sp.s, sp.r, sp.dr, sd.wheel.d, R, self.y, lim[0],
                             lim[1], sd.rail.height_table[2], lim[2], lim[3], gap,
                             np.empty(0))
            out.append(h)
            self.last_gap[name] = gap
        return out[0], out[1]

    def h(self, roll: float, sub=None) -> float:
        self.nit += 1
        zl, zr = self.heights(roll, sub)
        return zl - zr if np.isfinite(zl) and np.isfinite(zr) else np.nan

    def candidates(self, band: float = 5e-4, half: int = 30) -> dict[str, np.ndarray]:
        out = {}
        for name, g in self.last_gap.items():
            n = g.size
            mins = local_minima(g)
            if mins.size == 0:
                out[name] = np.arange(n)
                continue
            mins = mins[g[mins] <= np.min(g[mins]) + band]
            i = (mins[:, None] + np.arange(-half, half + 1)[None, :]).ravel()
            out[name] = np.unique(np.clip(i, 0, n - 1))
        return out


def local_root(solver: LocusSolver, y: float, yaw: float, xtol: float = 1e-13,
               max_secant: int = 12) -> tuple[float | None, int]:
    """``(roll or None, evaluations of h)`` by the Python local solve."""
    st = _State(solver, y, yaw)
    if not np.isfinite(st.h(0.0)):
        return None, st.nit
    roll: float | None = 0.0
    for _ in range(3):
        sub = st.candidates()
        roll = _secant(solver, lambda r, sub=sub: st.h(r, sub), roll, xtol, max_secant)
        if roll is None:
            return None, st.nit
        part = st.heights(roll, sub)
        full = st.heights(roll)
        st.nit += 2
        if abs(part[0] - full[0]) <= 1e-12 and abs(part[1] - full[1]) <= 1e-12:
            return roll, st.nit
    return None, st.nit   # no check passed: a root of the candidate samples only


def _secant(solver, h, roll0: float, xtol: float, max_secant: int) -> float | None:
    x0, f0 = roll0, h(roll0)
    if not np.isfinite(f0):
        return None
    x1 = x0 + f0 / (2.0 * solver.lever)
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
    pts = sorted((x, f) for x, f in pts if np.isfinite(f))
    for (xa, fa), (xb, fb) in zip(pts[:-1], pts[1:], strict=True):
        if fa * fb <= 0:
            return float(brentq(h, xa, xb, xtol=xtol, rtol=4 * np.finfo(float).eps))
    return None


def brackets_from_points(x: np.ndarray, h: np.ndarray, extra: list[tuple[float, float]]
                         ) -> list[tuple[float, float, bool]]:
    """The last step of :func:`lutmpi.contact.locus.find_brackets` as it was written with
    Python lists (before it was vectorised): sign changes and exact zeros among the scan points
    ``(x, h)`` and the ``extra`` points, a bracket only within one finite run of the scan."""
    pts = [(float(a), float(b)) for a, b in zip(x, h, strict=True)] + list(extra)
    pts.sort()
    out = []
    fin = [(a, b) for a, b in pts if np.isfinite(b)]
    for i, (xa, fa) in enumerate(fin):
        if fa == 0.0:
            prev = fin[i - 1][1] if i > 0 else np.nan
            nxt = fin[i + 1][1] if i + 1 < len(fin) else np.nan
            out.append((xa, xa, bool(prev > 0 or nxt < 0)))
        elif i + 1 < len(fin) and fa * fin[i + 1][1] < 0:
            xb = fin[i + 1][0]
            inside = (x > xa) & (x < xb)
            if not np.any(~np.isfinite(h[inside])):
                out.append((xa, xb, bool(fa > 0)))
    return out


def contact_minima(gap: np.ndarray, double_tol: float, max_contacts: int = 2) -> list[int]:
    """The contact minima of one wheel's locus gaps as :mod:`lutmpi.contact.locus` chose them in
    numpy before they were compiled (issue 14; the sort made stable: ties by index): the oracle
    of :func:`lutmpi.contact.rigid_kernels.contact_minima`."""
    mins = local_minima(gap)
    if mins.size == 0:
        return []
    order = mins[np.argsort(gap[mins], kind="stable")]
    chosen = [int(order[0])]
    g0 = gap[order[0]]
    for i in order[1:]:
        if len(chosen) >= max_contacts or gap[i] - g0 > double_tol:
            break
        if all(np.max(gap[min(i, j) : max(i, j) + 1]) > gap[i] + 1e-7 for j in chosen):
            chosen.append(int(i))
    return chosen


def refine_contact(sd, loc, i: int, centre: np.ndarray, R: np.ndarray,
                   s_fix: np.ndarray | None = None) -> RigidContact:
    """The rigid contact of gap minimum ``i`` of locus ``loc`` (side ``sd`` of a
    :class:`~lutmpi.contact.locus.LocusSolver`) as :meth:`LocusSolver.finish` computed it in
    numpy before it was compiled (issue 14): the parabola's offset through the minimum and its
    neighbours, the wheel's radius and slope there, the locus angle, the point ``G + R c``. The
    oracle of :func:`lutmpi.contact.rigid_kernels.rigid_contacts`. Where ``s_fix[i]`` is finite
    (a minimum the samples do not resolve, resampled by
    :func:`~lutmpi.contact.rigid_kernels.dip_minima`) the contact lies there, with the gap
    ``loc.gap[i]``."""
    g = loc.gap
    t, gmin = 0.0, float(g[i])
    if 0 < i < g.size - 1 and np.isfinite(g[i - 1] + g[i + 1]):
        gm, g0, gp = g[i - 1], g[i], g[i + 1]
        den = gm - 2.0 * g0 + gp
        if den > 0:
            t = min(max(float(0.5 * (gm - gp) / den), -0.5), 0.5)
            gmin = float(g0 - 0.25 * (gm - gp) * t)
    s = float(loc.s[i] + t * (loc.s[1] - loc.s[0]))
    if s_fix is not None and np.isfinite(s_fix[i]):
        s, gmin = float(s_fix[i]), float(g[i])
    r, dr = float(sd.wheel.radius(s)), float(sd.wheel.dr(s))
    a, b, c = R[0]
    phi = float(np.arctan2(c, a) + np.arcsin(np.clip(b * (loc.side * dr) / np.hypot(a, c),
                                                     -1.0, 1.0)))
    body = np.array([r * np.sin(phi), loc.side * (sd.wheel.d + s), -r * np.cos(phi)])
    p = centre + body @ R.T
    return RigidContact(side=loc.side, s=s, phi=phi, point=p, u=float(loc.side * p[1]),
                        gap=gmin, at_end=sd.at_end(g, i))


def _chord_curvature(lo: np.ndarray, hi: np.ndarray, z: np.ndarray, dz: np.ndarray
                     ) -> np.ndarray:
    """Change of the normal's angle from ``lo`` to ``hi`` over the chord, 1/m; ``z``, ``dz``:
    the curve and its slope at ``[lo, hi]``."""
    n = lo.size
    a = np.arctan(dz[n:]) - np.arctan(dz[:n])
    span = np.hypot(hi - lo, z[n:] - z[:n])
    return -a / np.where(span > 0, span, np.inf)


def record_geometry(sd, side: np.ndarray, rp: np.ndarray, s: np.ndarray,
                    normals: np.ndarray, h: float) -> np.ndarray:
    """The stored geometry of contacts in numpy, as :mod:`lutmpi.contact.records` computed it
    (through the geometry's former methods ``contact_geometry``, ``profile_coordinate`` and
    ``convex_curvature``) before it was compiled (issue 14): the oracle of
    :func:`lutmpi.contact.records.record_geometry` (its columns; ``h``: the curvature's half
    base, m)."""
    wheel, rail = sd.wheel, sd.rail
    # the wheel: radius, slope and chord curvature over s +- h (clipped to the wheel)
    lo = np.minimum(np.maximum(s - h, wheel.s_min), wheel.s_max)
    hi = np.minimum(np.maximum(s + h, wheel.s_min), wheel.s_max)
    at = np.concatenate([s, lo, hi])
    z, dz = wheel.profile.z_at(at), wheel.profile.slope(at)
    n = s.size
    rad, dr, cw = wheel.r0 + z[:n], dz[:n], _chord_curvature(lo, hi, z[n:], dz[n:])
    # the rail: v through the placement, chord curvature at the point clipped to the rail
    u_r = side * rp[:, 1]
    v = ((u_r - 0.5 * rail.gauge + rail.v_gp) * np.cos(rail.inclination)
         + (rp[:, 2] + rail.w_top) * np.sin(rail.inclination))
    uc = np.minimum(np.maximum(u_r, rail.u_min), rail.u_max)
    lo = np.minimum(np.maximum(uc - h, rail.u_min), rail.u_max)
    hi = np.minimum(np.maximum(uc + h, rail.u_min), rail.u_max)
    at = np.concatenate([lo, hi])
    cr = _chord_curvature(lo, hi, rail.height(at), rail.slope(at))
    out = np.empty((s.size, 6))
    for i in range(s.size):
        sg, nv, r, d = side[i], normals[i], float(rad[i]), float(dr[i])
        out[i] = (r, float(np.arctan2(-sg * nv[1], nv[2])), float(v[i]),
                  1.0 / (r * np.sqrt(1.0 + d * d)), float(cw[i]), float(cr[i]))
    return out
