"""Report figures (matplotlib, Agg backend). Arrays in, PNG files out; no HDF5, no MPI."""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import matplotlib.ticker  # noqa: E402
import numpy as np  # noqa: E402

from lutmpi.reports.convergence import QUANTITIES, MemberMetrics  # noqa: E402

__all__ = ["error_vs_time", "error_vs_spacing", "error_map", "lines_vs_y", "conicity_plot",
           "draw_curves"]


def _save(fig: plt.Figure, path: str | Path) -> Path:
    path = Path(path)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _by_method(metrics: Sequence[MemberMetrics]) -> dict[str, list[MemberMetrics]]:
    out: dict[str, list[MemberMetrics]] = {}
    for m in metrics:
        out.setdefault(m.method, []).append(m)
    for rows in out.values():
        rows.sort(key=lambda r: -r.spacing if math.isfinite(r.spacing) else 0.0)
    return out


def error_vs_time(metrics: Sequence[MemberMetrics], quantity: str, path: str | Path) -> Path:
    """Max error of ``quantity`` against total CPU time, log-log, one line per method, points
    labelled by mesh spacing (mm)."""
    unit, scale = QUANTITIES[quantity]
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for method, rows in _by_method(metrics).items():
        pts = [(r.cpu_total_s, r.errors[quantity].max * scale, r.spacing) for r in rows
               if quantity in r.errors and r.errors[quantity].max > 0]
        if not pts:
            continue
        t, e, h = zip(*pts, strict=True)
        ax.loglog(t, e, "o-", label=method)
        for ti, ei, hi in pts:
            ax.annotate(f"h={hi * 1e3:g}", (ti, ei), textcoords="offset points", xytext=(4, 4),
                        fontsize=7)
    ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax.set_xlabel("CPU time, total over the grid [s]")
    ax.set_ylabel(f"max |error| of {quantity} [{unit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return _save(fig, path)


def error_vs_spacing(metrics: Sequence[MemberMetrics], quantity: str,
                     orders: Mapping[str, Mapping[str, tuple[float, float, int]]],
                     path: str | Path) -> Path:
    """Max error against mesh spacing (log-log) with the fitted ``C h^p`` per method."""
    unit, scale = QUANTITIES[quantity]
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for method, rows in _by_method(metrics).items():
        pts = [(r.spacing, r.errors[quantity].max) for r in rows
               if quantity in r.errors and r.errors[quantity].max > 0 and r.spacing > 0]
        if not pts:
            continue
        h, e = (np.array(v) for v in zip(*pts, strict=True))
        p, c, _ = orders.get(method, {}).get(quantity, (math.nan, math.nan, 0))
        label = f"{method} (p = {p:.2f})" if math.isfinite(p) else method
        line, = ax.loglog(h * 1e3, e * scale, "o", label=label)
        if math.isfinite(p):
            hh = np.geomspace(h.min(), h.max(), 20)
            ax.loglog(hh * 1e3, c * hh**p * scale, "--", color=line.get_color(), lw=1)
    ax.set_xlabel("mesh spacing h [mm]")
    ax.set_ylabel(f"max |error| of {quantity} [{unit}]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend()
    return _save(fig, path)


def error_map(y: np.ndarray, yaw: np.ndarray, err: np.ndarray, quantity: str, title: str,
              path: str | Path) -> Path:
    """Map of |error| over (y, yaw); per-contact errors (ny, nyaw, 2) show the larger wheel."""
    unit, scale = QUANTITIES[quantity]
    e = np.asarray(err, float)
    if e.ndim == 3:
        e = np.where(np.all(np.isnan(e), axis=2), np.nan, np.nanmax(np.nan_to_num(e, nan=-1), 2))
    fig, ax = plt.subplots(figsize=(6.0, 4.4))
    mesh = ax.pcolormesh(np.asarray(yaw), np.asarray(y) * 1e3, e * scale, shading="nearest")
    fig.colorbar(mesh, ax=ax, label=f"|error| of {quantity} [{unit}]")
    ax.set_xlabel("yaw [rad]")
    ax.set_ylabel("y [mm]")
    ax.set_title(title, fontsize=9)
    return _save(fig, path)


#: line styles cycled with the colours, so that members whose curves coincide (a wear that
#: changes only the flange leaves the tread's Δr alike) all stay visible, one over the other
_STYLES = ("-", "--", ":", "-.")


def draw_curves(ax: plt.Axes, curves: Mapping[str, tuple[np.ndarray, np.ndarray]],
                xscale: float = 1.0, yscale: float = 1.0) -> list[str]:
    """One line per curve ``curves[name] = (x, value)`` (scaled), NaN a gap, and a legend of
    exactly the lines drawn; returns the names without a finite value, which are not drawn
    (a legend entry would stand for no curve) but named in the axes instead."""
    empty = []
    n = 0
    for name, (x, v) in curves.items():
        x, v = np.asarray(x, float), np.asarray(v, float)
        if not np.isfinite(v).any():
            empty.append(name)
            continue
        # 20 members before a colour and style repeat, each line thinner than the one it is
        # drawn over; points marked: a value between two gaps is no line
        ax.plot(x * xscale, v * yscale, ls=_STYLES[n % len(_STYLES)],
                lw=2.0 - 0.3 * (n % len(_STYLES)), marker=".", ms=3, color=f"C{n % 10}",
                label=name)
        n += 1
    if n:
        ax.legend(fontsize=6)
    if empty:
        ax.text(0.02, 0.02, "no value: " + ", ".join(empty), transform=ax.transAxes,
                fontsize=7, va="bottom", wrap=True)
    return empty


def lines_vs_y(curves: Mapping[str, tuple[np.ndarray, np.ndarray]], ylabel: str,
               path: str | Path, yscale: float = 1.0) -> Path:
    """One line per member: ``curves[id] = (y [m], value)``, NaN a gap; ``yscale`` converts the
    value (:func:`draw_curves`)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    draw_curves(ax, curves, 1e3, yscale)
    ax.set_xlabel("y [mm]")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    return _save(fig, path)


def conicity_plot(curves: Mapping[str, tuple[np.ndarray, np.ndarray]], path: str | Path) -> Path:
    """Equivalent conicity against amplitude: ``curves[name] = (amplitude [m], tan gamma_e)``
    (:func:`draw_curves`)."""
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    draw_curves(ax, curves, 1e3)
    ax.axvline(3.0, color="k", lw=0.6, ls=":")
    ax.set_xlabel("amplitude ŷ [mm]")
    ax.set_ylabel("equivalent conicity tan γe [-]")
    ax.grid(True, alpha=0.3)
    return _save(fig, path)
