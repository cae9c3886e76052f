"""Reference solution of the check grid and the classification of poses into regions.

A pose's region comes from the semi-analytic reference (contact-locus) solution, never from the
mesh method under test:

* ``double``      -- a wheel's vertical-gap function along the profile has a second local minimum
                     (separated from the first by a gap maximum) within ``dc_tol`` of the global
                     minimum (both with the dips between samples resampled, as the rigid
                     contacts are chosen): two candidate contact zones, a contact-point jump is
                     near;
* ``flange``      -- otherwise, the largest contact angle of either wheel >= ``FLANGE_ANGLE``;
* ``flange_root`` -- ``ROOT_ANGLE`` <= angle < ``FLANGE_ANGLE`` (the throat, tread to flank);
* ``tread``       -- angle < ``ROOT_ANGLE``.

Pure: no MPI, no files.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lutmpi.contact.locus import contact_minima
from lutmpi.equilibrium.result import SIDES, PoseResult
from lutmpi.pose.solve import solve_pose

ROOT_ANGLE = 0.15  # rad (8.6 deg): S1002/UIC60 tread contacts stay below ~0.05 rad
FLANGE_ANGLE = 1.0  # rad (57 deg): the S1002 flank is at 70 deg = 1.22 rad
REGIONS = ("tread", "flange_root", "flange", "double")


@dataclass
class RefPoint:
    """Reference (rigid, locus) solution of one grid pose and its region."""

    i: int  # index along y
    j: int  # index along yaw
    result: PoseResult
    region: str
    max_angle: float  # rad, largest contact angle over both wheels
    n_zones: int  # candidate contact zones of the worse wheel (1 or 2)
    band: dict = None  # m per wheel: profile band within ``delta`` of the gap minimum


def primary_s(res: PoseResult, side: str) -> float:
    """Wheel-profile coordinate (m) of the first contact of ``side`` (NaN when none)."""
    cs = res.contacts[side]
    return cs[0].wheel_s if cs else float("nan")


def classify(res: PoseResult, n_zones: int) -> tuple[str, float]:
    """Region of a reference result with ``n_zones`` candidate zones; and its largest angle."""
    angles = [c.contact_angle for s in SIDES for c in res.contacts[s]]
    gmax = max(angles) if angles else float("nan")
    if n_zones >= 2:
        return "double", gmax
    if not np.isfinite(gmax) or gmax < ROOT_ANGLE:
        return "tread", gmax
    return ("flange" if gmax >= FLANGE_ANGLE else "flange_root"), gmax


def band_width(s: np.ndarray, gap: np.ndarray, delta: float) -> float:
    """Length (m) of the connected stretch of the profile around the gap minimum where the gap is
    within ``delta`` of it: the width of the patch at interpenetration ``delta``."""
    g = np.where(np.isfinite(gap), gap, np.inf)
    i0 = int(np.argmin(g))
    inside = g - g[i0] <= delta
    lo = hi = i0
    while lo > 0 and inside[lo - 1]:
        lo -= 1
    while hi < g.size - 1 and inside[hi + 1]:
        hi += 1
    return float(s[hi] - s[lo])


def reference_point(scene, ys, yaws, i: int, j: int, dc_tol: float,
                    delta: float = 0.0) -> RefPoint:
    """Solve the reference at grid pose (i, j) and classify it; ``delta`` (m) is the
    interpenetration at which the patch band is measured."""
    y, yaw = float(ys[i]), float(yaws[j])
    res = solve_pose(scene, y, yaw, "reference")
    rigid = scene.locus.solve(y, yaw)
    zones, band = 1, dict.fromkeys(SIDES, 0.0)
    if rigid.success:
        # the gaps with the minima the 0.1 mm samples do not resolve resampled, as the rigid
        # contacts are chosen: a yawed flange's true minimum lies up to tens of um below its
        # sample, and a second zone within dc_tol of the sample may not be within it of the
        # true minimum
        gaps = {s: resolved_gap(rigid.loci[s]) for s in SIDES}
        zones = max(len(contact_minima(gaps[s], dc_tol, 2)) for s in SIDES)
        band = {s: band_width(rigid.loci[s].s, gaps[s], delta) for s in SIDES}
    region, gmax = classify(res, zones)
    return RefPoint(i, j, res, region, gmax, zones, band)


def resolved_gap(loc) -> np.ndarray:
    """A locus's gaps with its unresolved minima resampled (``gap_min``, what the rigid
    contacts are chosen and placed by), else its sample gaps."""
    return loc.gap if loc.gap_min is None else loc.gap_min


class ReferenceGrid:
    """Lazily solved reference over the grid (``ys`` m, ``yaws`` rad)."""

    def __init__(self, scene, ys, yaws, dc_tol: float, delta: float = 0.0):
        self.scene, self.dc_tol, self.delta = scene, dc_tol, delta
        self.ys, self.yaws = np.asarray(ys), np.asarray(yaws)
        self.points: dict[tuple[int, int], RefPoint] = {}

    def __getitem__(self, ij: tuple[int, int]) -> RefPoint:
        if ij not in self.points:
            self.points[ij] = reference_point(self.scene, self.ys, self.yaws, *ij, self.dc_tol,
                                                  self.delta)
        return self.points[ij]

    def survey(self, max_points: int) -> list[RefPoint]:
        """Solve a regular sub-grid of at most ~``max_points`` poses that always holds the
        grid's corners and centre lines; returns the solved points."""
        ny, nw = self.ys.size, self.yaws.size
        stride = max(1, int(np.ceil(np.sqrt(ny * nw / max(max_points, 4)))))
        ii = sorted(set(range(0, ny, stride)) | {ny - 1, ny // 2})
        jj = sorted(set(range(0, nw, stride)) | {nw - 1, nw // 2})
        return [self[i, j] for i in ii for j in jj]


def stratified_sample(points: list[RefPoint], n: int) -> list[RefPoint]:
    """About ``n`` points spread over the regions: an equal share per populated region (what a
    region does not use goes to the others), evenly spaced within each region."""
    by_region = {r: [p for p in points if p.region == r] for r in REGIONS}
    by_region = {r: v for r, v in by_region.items() if v}
    quota = dict.fromkeys(by_region, 0)
    left = min(n, len(points))
    while left > 0:
        open_ = [r for r in by_region if quota[r] < len(by_region[r])]
        if not open_:
            break
        share = max(1, left // len(open_))
        for r in open_:
            take = min(share, len(by_region[r]) - quota[r], left)
            quota[r] += take
            left -= take
    out = []
    for r, pts in by_region.items():
        idx = np.unique(np.round(np.linspace(0, len(pts) - 1, quota[r])).astype(int))
        out += [pts[k] for k in idx]
    return out
