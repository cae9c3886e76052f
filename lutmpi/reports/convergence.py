"""Convergence metrics: error of each sweep member against a reference table, and its cost.

Pure module: tables come in as the mappings of :func:`lutmpi.table.h5io.read_table` (``attrs``,
``y``, ``yaw``, ``methods`` → field → array); no file, no MPI here.

Errors are taken over the grid points where both the member and the reference converged
(``status == 0``); per-contact quantities use contact slot 0 (the contact carrying the largest
normal force) of both wheels, where both tables have a contact. The number of excluded points is
reported with every error.
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from lutmpi.table.schema import D

__all__ = ["QUANTITIES", "MemberTable", "MemberMetrics", "ErrorStat", "error_maps",
           "compare", "observed_order", "mesh_spacing_of", "convergence_study"]

#: quantity -> (unit shown in reports, scale from SI to that unit)
QUANTITIES: dict[str, tuple[str, float]] = {
    D.z_g: ("mm", 1e3),
    D.roll: ("mrad", 1e3),
    D.wheel_s: ("mm", 1e3),
    D.rail_v: ("mm", 1e3),
    D.contact_angle: ("mrad", 1e3),
    D.normal: ("mrad", 1e3),
}
_PER_POINT = (D.z_g, D.roll)
CONVERGED = 0


@dataclass
class MemberTable:
    """One table of a sweep with what the report needs to know about it.

    Attributes
    ----------
    id : str
        Member ID.
    method : str
        Contact method (the method group compared).
    spacing : float
        Mesh spacing h, m (NaN for the mesh-free reference).
    table : Mapping
        ``read_table`` mapping.
    """

    id: str
    method: str
    spacing: float
    table: Mapping[str, Any]

    @property
    def group(self) -> Mapping[str, np.ndarray]:
        return self.table["methods"][self.method]


@dataclass
class ErrorStat:
    """Max and RMS of an absolute error over the included values (SI), and how many counted."""

    max: float
    rms: float
    n: int
    excluded: int


@dataclass
class MemberMetrics:
    """Errors and cost of one member (SI: m, rad, s)."""

    id: str
    method: str
    spacing: float
    points: int
    failures: int                     # points with status != 0
    cpu_total_s: float                # sum of compute_time over all points
    cpu_per_point_s: float
    wall_s: float                     # root attribute wall_time_s
    ranks: int
    errors: dict[str, ErrorStat] = field(default_factory=dict)


def mesh_spacing_of(config_toml: str) -> float:
    """Mesh spacing h of a table, m: the largest of its four ``[mesh]`` spacings.

    Parameters
    ----------
    config_toml : str
        The resolved configuration stored in the table (root attribute ``config_toml``).
    """
    mesh = tomllib.loads(config_toml).get("mesh", {})
    keys = ("wheel_lateral_mm", "wheel_circumferential_mm", "rail_lateral_mm",
            "rail_longitudinal_mm")
    values = [float(mesh[k]) for k in keys if k in mesh]
    return max(values) * 1e-3 if values else math.nan


def _normal_angle(n1: np.ndarray, n2: np.ndarray) -> np.ndarray:
    """Angle between unit vectors along the last axis, rad (atan2 form: exact near 0)."""
    cross = np.linalg.norm(np.cross(n1, n2), axis=-1)
    return np.arctan2(cross, np.sum(n1 * n2, axis=-1))


def error_maps(member: Mapping[str, np.ndarray], ref: Mapping[str, np.ndarray]
               ) -> dict[str, np.ndarray]:
    """Absolute error of every quantity of :data:`QUANTITIES` on the grid, SI units.

    Parameters
    ----------
    member, ref : Mapping
        Method groups (field name → array) on the same ``(ny, nyaw)`` grid.

    Returns
    -------
    dict
        Quantity → array ``(ny, nyaw)`` for per-point quantities, ``(ny, nyaw, 2)`` (left, right;
        slot 0) for per-contact ones; NaN where a point is excluded (not converged in either
        table, or no contact in either).
    """
    ok = (np.asarray(member[D.status]) == CONVERGED) & (np.asarray(ref[D.status]) == CONVERGED)
    out: dict[str, np.ndarray] = {}
    for q in QUANTITIES:
        if q == D.normal:
            if D.normal not in member or D.normal not in ref:
                continue
            err = _normal_angle(member[D.normal][:, :, :, 0, :], ref[D.normal][:, :, :, 0, :])
        elif q in member and q in ref:
            a, b = np.asarray(member[q], float), np.asarray(ref[q], float)
            if q not in _PER_POINT:
                a, b = a[:, :, :, 0], b[:, :, :, 0]
            err = np.abs(a - b)
        else:
            continue
        mask = ok if err.ndim == 2 else ok[:, :, None]
        out[q] = np.where(mask, err, np.nan)
    return out


def _stat(err: np.ndarray) -> ErrorStat:
    good = np.isfinite(err)
    n = int(good.sum())
    if n == 0:
        return ErrorStat(math.nan, math.nan, 0, int(err.size))
    vals = err[good]
    return ErrorStat(float(vals.max()), float(np.sqrt(np.mean(vals**2))), n, int(err.size - n))


def compare(member: MemberTable, ref: MemberTable) -> MemberMetrics:
    """Errors of ``member`` against ``ref`` and the member's cost.

    Raises
    ------
    ValueError
        When the two tables are not on the same (y, yaw) grid.
    """
    for axis in ("y", "yaw"):
        a, b = np.asarray(member.table[axis]), np.asarray(ref.table[axis])
        if a.shape != b.shape or not np.allclose(a, b, rtol=0, atol=1e-12):
            raise ValueError(f"{member.id} and reference {ref.id} are not on the same {axis} grid")
    g = member.group
    status = np.asarray(g[D.status])
    cpu = float(np.nansum(g[D.compute_time])) if D.compute_time in g else math.nan
    attrs = member.table.get("attrs", {})
    metrics = MemberMetrics(
        id=member.id, method=member.method, spacing=member.spacing, points=int(status.size),
        failures=int(np.count_nonzero(status != CONVERGED)), cpu_total_s=cpu,
        cpu_per_point_s=cpu / status.size if status.size else math.nan,
        wall_s=float(attrs.get("wall_time_s", math.nan)), ranks=int(attrs.get("ranks", 0)))
    for q, err in error_maps(g, ref.group).items():
        metrics.errors[q] = _stat(err)
    return metrics


def observed_order(spacing: Sequence[float], error: Sequence[float]) -> tuple[float, float, int]:
    """Least-squares fit of ``log error = log C + p log h``.

    Parameters
    ----------
    spacing : sequence of float
        Mesh spacings h, m.
    error : sequence of float
        Errors at those spacings (any unit).

    Returns
    -------
    p : float
        Observed order (NaN with fewer than two usable points).
    C : float
        The constant, in the error's unit per m**p.
    n : int
        Points used (finite, h > 0, error > 0).
    """
    h = np.asarray(spacing, float)
    e = np.asarray(error, float)
    use = np.isfinite(h) & np.isfinite(e) & (h > 0) & (e > 0)
    n = int(use.sum())
    if n < 2 or np.ptp(np.log(h[use])) == 0:
        return math.nan, math.nan, n
    p, logc = np.polyfit(np.log(h[use]), np.log(e[use]), 1)
    return float(p), float(math.exp(logc)), n


@dataclass
class Study:
    """All member metrics and the observed order per method and quantity (max error)."""

    reference: str
    metrics: list[MemberMetrics]
    orders: dict[str, dict[str, tuple[float, float, int]]]


def convergence_study(members: Sequence[MemberTable], reference: str = "reference") -> Study:
    """Compare every member with its reference and fit the observed orders.

    Parameters
    ----------
    members : sequence of MemberTable
        All tables of the sweep (including the reference member when there is one).
    reference : {"reference", "finest"}
        ``"reference"``: the member whose method is ``reference`` (the semi-analytic solver);
        ``"finest"``: for each method its finest-mesh member (which is then left out of the fit).

    Returns
    -------
    Study

    Raises
    ------
    ValueError
        No reference member found, or an unknown ``reference`` choice.
    """
    by_method: dict[str, list[MemberTable]] = {}
    for m in members:
        by_method.setdefault(m.method, []).append(m)
    refs: dict[str, MemberTable] = {}
    if reference == "reference":
        if "reference" not in by_method:
            raise ValueError("no member computed with method 'reference'; use reference='finest'")
        refs = {meth: by_method["reference"][0] for meth in by_method if meth != "reference"}
        label = by_method["reference"][0].id
    elif reference == "finest":
        for meth, group in by_method.items():
            if meth != "reference":
                refs[meth] = min(group, key=lambda m: m.spacing)
        label = "finest mesh of each method"
    else:
        raise ValueError(f"reference must be 'reference' or 'finest', got {reference!r}")
    metrics = [compare(m, refs[m.method]) for m in members
               if m.method in refs and m is not refs[m.method]]
    orders: dict[str, dict[str, tuple[float, float, int]]] = {}
    for meth in refs:
        rows = [r for r in metrics if r.method == meth]
        orders[meth] = {q: observed_order([r.spacing for r in rows],
                                          [r.errors[q].max if q in r.errors else math.nan
                                           for r in rows])
                        for q in QUANTITIES}
    return Study(reference=label, metrics=metrics, orders=orders)
