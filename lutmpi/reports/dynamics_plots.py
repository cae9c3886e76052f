"""Plots of a wheelset run like the paper's Figs 11-14 (matplotlib, Agg backend)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from lutmpi.dynamics.simulate import SimulationResult  # noqa: E402

_PANELS = (
    ("y", "transverse displacement of the centre of mass (Fig. 11)", "y [mm]", 1e3),
    ("yaw", "yaw angle (Fig. 12)", "yaw [mrad]", 1e3),
    ("roll", "roll angle (Fig. 13)", "roll [mrad]", 1e3),
    ("fy", "lateral tangential force per wheel (Fig. 14)", "F_y [kN]", 1e-3),
)


def _series(run: SimulationResult, key: str):
    if key == "fy":
        return [(run.lateral_creep_force[:, 0], "left"), (run.lateral_creep_force[:, 1], "right")]
    return [({"y": run.y, "yaw": run.yaw, "roll": run.roll}[key], None)]


def plot_run(runs: Sequence[SimulationResult], prefix: str | Path,
             labels: Sequence[str] | None = None) -> list[Path]:
    """One PNG per quantity (``<prefix>_y.png`` ...), every run overlaid.

    Parameters
    ----------
    runs : sequence of SimulationResult
    prefix : path
        Output path without extension.
    labels : sequence of str, optional
        Legend label per run (default ``V = ... m/s``).
    """
    prefix = Path(prefix)
    labels = labels or [f"V = {r.speed:g} m/s" for r in runs]
    out = []
    for key, title, ylabel, scale in _PANELS:
        fig, ax = plt.subplots(figsize=(7, 3.2), constrained_layout=True)
        for run, label in zip(runs, labels, strict=True):
            for data, side in _series(run, key):
                ax.plot(run.t, data * scale, lw=1.0,
                        label=label if side is None else f"{label}, {side}")
        ax.set_xlabel("t [s]")
        ax.set_ylabel(ylabel)
        ax.set_title(title, fontsize=10)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        path = prefix.parent / f"{prefix.name}_{key}.png"
        fig.savefig(path, dpi=110)
        plt.close(fig)
        out.append(path)
    return out
