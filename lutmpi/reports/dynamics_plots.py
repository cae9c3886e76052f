"""Plots of a wheelset run like the paper's Figs 11-14 (matplotlib, Agg backend)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from lutmpi.dynamics.simulate import SimulationResult  # noqa: E402

#: (key, title, axis name, unit, scale from SI to the unit)
_PANELS = (
    ("y", "transverse displacement of the centre of mass (Fig. 11)", "y", "mm", 1e3),
    ("yaw", "yaw angle (Fig. 12)", "yaw", "mrad", 1e3),
    ("roll", "roll angle (Fig. 13)", "roll", "mrad", 1e3),  # not a dataset: a run's series
    ("fy", "lateral tangential force per wheel (Fig. 14)", "F_y", "kN", 1e-3),
)


def _series(run: SimulationResult, key: str):
    if key == "fy":
        return [(run.lateral_creep_force[:, 0], "left"), (run.lateral_creep_force[:, 1], "right")]
    return [(getattr(run, key), None)]


#: the start-up transient left out of the axis scaling: this fraction of the run, at least 0.2 s
STARTUP_FRACTION, STARTUP_MIN_S = 0.05, 0.2


def steady_limits(t: np.ndarray, series: Sequence[np.ndarray]) -> tuple[float, float] | None:
    """y-axis limits that show the oscillation after the start-up transient.

    The first :data:`STARTUP_FRACTION` of the run (at least :data:`STARTUP_MIN_S`) is left out of
    the scaling, so a spike at t = 0 (the initial creep forces) does not squash the rest; None when
    nothing is left to scale on."""
    t = np.asarray(t, float)
    if t.size < 2:
        return None
    t0 = t[0] + max(STARTUP_FRACTION * (t[-1] - t[0]), STARTUP_MIN_S)
    keep = t >= t0
    vals = np.concatenate([np.asarray(v, float)[keep] for v in series]) if keep.any() else []
    vals = np.asarray(vals)[np.isfinite(vals)] if len(vals) else np.asarray([])
    if vals.size == 0:
        return None
    lo, hi = float(vals.min()), float(vals.max())
    pad = 0.08 * (hi - lo) or 0.08 * max(abs(hi), 1e-12)
    return lo - pad, hi + pad


def panel(runs: Sequence[SimulationResult], key: str,
          labels: Sequence[str] | None = None) -> plt.Figure:
    """The figure of one quantity of :data:`_PANELS` (``key``), every run overlaid; a start-up
    peak beyond the axis is named in the title with its unit."""
    _, title, name, unit, scale = next(p for p in _PANELS if p[0] == key)
    labels = labels or [f"V = {r.speed:g} m/s" for r in runs]
    fig, ax = plt.subplots(figsize=(7, 3.2), constrained_layout=True)
    limits, extreme = [], 0.0
    for run, label in zip(runs, labels, strict=True):
        series = [data * scale for data, _ in _series(run, key)]
        for data, (_, side) in zip(series, _series(run, key), strict=True):
            ax.plot(run.t, data, lw=1.0, label=label if side is None else f"{label}, {side}")
        extreme = max([extreme] + [float(np.nanmax(np.abs(d))) for d in series if d.size])
        lim = steady_limits(run.t, series)
        if lim is not None:
            limits.append(lim)
    if limits:
        lo, hi = min(a for a, _ in limits), max(b for _, b in limits)
        ax.set_ylim(lo, hi)
        if extreme > max(abs(lo), abs(hi)):
            title += f"; start-up peak {extreme:.3g} {unit} off the axis"
    ax.set_xlabel("t [s]")
    ax.set_ylabel(f"{name} [{unit}]")
    ax.set_title(title, fontsize=10)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return fig


def plot_run(runs: Sequence[SimulationResult], prefix: str | Path,
             labels: Sequence[str] | None = None) -> list[Path]:
    """One PNG per quantity (``<prefix>_y.png`` ...), every run overlaid (:func:`panel`).

    Parameters
    ----------
    runs : sequence of SimulationResult
    prefix : path
        Output path without extension.
    labels : sequence of str, optional
        Legend label per run (default ``V = ... m/s``).
    """
    prefix = Path(prefix)
    out = []
    for key, *_ in _PANELS:
        fig = panel(runs, key, labels)
        path = prefix.parent / f"{prefix.name}_{key}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        out.append(path)
    return out
