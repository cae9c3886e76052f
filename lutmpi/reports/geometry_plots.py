"""The contact-geometry figures of one table (matplotlib Agg): arrays in, PNG files out.

Every figure's title names the case (profile pair, cant, gauge, back-to-back: :mod:`lutmpi.reports.
pair`); lengths are in mm and angles in degrees; curves against y break at contact jumps
(:mod:`lutmpi.reports.breaks`) instead of joining across them.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.colors import BoundaryNorm, ListedColormap  # noqa: E402

from lutmpi.equilibrium.result import SIDES, STATUS  # noqa: E402
from lutmpi.reports.breaks import broken  # noqa: E402

DEG = 180.0 / math.pi
STYLE = {("left", 0): ("C0", "-"), ("right", 0): ("C1", "-"), ("left", 1): ("C0", ":"),
         ("right", 1): ("C1", ":")}


def _save(fig: plt.Figure, path: Path) -> Path:
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _axes(title: str, case: str, xlabel: str, ylabel: str, size=(7.0, 4.2)):
    fig, ax = plt.subplots(figsize=size, constrained_layout=True)
    ax.set_title(f"{title}\n{case}", fontsize=9)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(alpha=0.3)
    return fig, ax


def curve(y: np.ndarray, series: Mapping[str, np.ndarray], mask: np.ndarray, title: str,
          case: str, ylabel: str, path: Path, scale: float = 1.0) -> Path:
    """Functions of y (``series[label] = values``, SI), one line each, broken at ``mask``."""
    fig, ax = _axes(title, case, "lateral shift y [mm] (to the left)", ylabel)
    for k, (label, v) in enumerate(series.items()):
        xs, vs = broken(y * 1e3, np.asarray(v, float) * scale, mask)
        ax.plot(xs, vs, ".-", ms=3, lw=1.1, color=f"C{k}", label=label)
    if mask.any():
        ax.plot([], [], " ", label=f"line broken at {int(mask.sum())} contact jump(s)")
    ax.legend(fontsize=7)
    return _save(fig, path)


def per_contact(y: np.ndarray, values: np.ndarray, mask: np.ndarray, title: str, case: str,
                ylabel: str, path: Path, scale: float = 1.0) -> Path:
    """A per-contact function ``values (n, 2 sides, 2 slots)``: both wheels, both slots."""
    fig, ax = _axes(title, case, "lateral shift y [mm] (to the left)", ylabel)
    for i, side in enumerate(SIDES):
        for slot in (0, 1):
            v = np.asarray(values, float)[:, i, slot] * scale
            if np.all(np.isnan(v)):
                continue
            colour, ls = STYLE[(side, slot)]
            xs, vs = broken(y * 1e3, v, mask)
            ax.plot(xs, vs, ls, marker="o" if slot == 0 else "s", ms=3, color=colour,
                    label=f"{side} wheel, {'main' if slot == 0 else 'second'} contact")
    ax.legend(fontsize=7)
    return _save(fig, path)


def contact_map(y: np.ndarray, profiles: Mapping[str, Mapping[str, tuple[np.ndarray, np.ndarray]]],
                points: Mapping[str, np.ndarray], case: str, path: Path) -> Path:
    """Where the contacts sit on the wheel and on the rail profile, coloured by y.

    ``profiles[side]["wheel"] = (s, dr)``, ``profiles[side]["rail"] = (v, z)`` in m (lutmpi's
    profile coordinates: positive toward the field side); ``points["wheel"]``, ``points["rail"]``
    are the contact coordinates ``(n, 2 sides, 2 slots)``, m. Each side's contacts sit on that
    side's profile (drawn twice when the sides differ)."""
    fig, axes = plt.subplots(2, 1, figsize=(8.0, 7.5), constrained_layout=True)
    norm = plt.Normalize(y.min() * 1e3, y.max() * 1e3)
    sc = None
    for ax, part in zip(axes, ("wheel", "rail"), strict=True):
        same = all(np.array_equal(profiles["left"][part][k], profiles["right"][part][k])
                   for k in (0, 1))
        coord = np.asarray(points[part], float)
        for i, side in enumerate(SIDES):
            px, pz = profiles[side][part]
            if i == 0 or not same:
                ax.plot(px * 1e3, pz * 1e3, color="0.4", lw=1, ls="-" if i == 0 else "--",
                        label=None if same else f"{side} {part} profile")
            for slot in (0, 1):
                c = coord[:, i, slot]
                ok = np.isfinite(c)
                if not ok.any():
                    continue
                zc = np.interp(c[ok], px, pz)
                sc = ax.scatter(c[ok] * 1e3, zc * 1e3, c=y[ok] * 1e3, cmap="viridis", norm=norm,
                                marker=("o" if side == "left" else "^") if slot == 0 else "s",
                                s=22 if slot == 0 else 36, edgecolors="k" if slot else "none",
                                linewidths=0.6,
                                label=f"{side} wheel" + ("" if slot == 0 else ", second contact"))
        origin = "tape circle" if part == "wheel" else "rail profile origin"
        ax.set_xlabel(f"{part} profile coordinate [mm] (0 = {origin}, + toward the field side)")
        ax.set_ylabel("radius increase [mm]" if part == "wheel" else "height [mm]")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, loc="best")
    if sc is not None:
        fig.colorbar(sc, ax=axes, label="lateral shift y [mm]")
    axes[0].set_title(f"Contact points on the wheel and rail profiles, yaw 0\n{case}", fontsize=9)
    return _save(fig, path)


def conicity(amplitude: np.ndarray, tan_ge: np.ndarray, case: str, path: Path,
             band: Mapping[str, np.ndarray] | None = None, band_label: str = "") -> Path:
    """Equivalent conicity function; ``band`` (amplitude [m], lower, upper) from EN 15302."""
    fig, ax = _axes("Equivalent conicity function (EN 15302 Annex B)", case,
                    "amplitude ŷ [mm]", "tan γe [-]")
    if band is not None:
        ax.fill_between(band["amplitude"] * 1e3, band["lower"], band["upper"], color="0.85",
                        label=band_label or "EN 15302 tolerance band")
        ax.plot(band["amplitude"] * 1e3, band["reference"], "k--", lw=0.8, label="reference")
    ax.plot(amplitude * 1e3, tan_ge, "C0.-", ms=3, label="this table")
    ax.axvline(3.0, color="k", lw=0.6, ls=":")
    ax.legend(fontsize=7)
    return _save(fig, path)


def lead_vs_yaw(yaw: np.ndarray, leads: Mapping[str, np.ndarray], case: str, path: Path,
                masks: Mapping[str, np.ndarray] | None = None) -> Path:
    """Longitudinal position of the main contact (the contact lead) against yaw, both wheels,
    one line per chosen y: ``leads[label] = x (nyaw, 2 sides)``, m; ``masks[label]`` marks the
    yaw intervals with a contact jump, where the line breaks."""
    fig, ax = _axes("Contact lead (x of the main contact) against yaw", case, "yaw [deg]",
                    "contact x [mm] (+ ahead of the axle)")
    for k, (label, x) in enumerate(leads.items()):
        mask = (masks or {}).get(label, np.zeros(max(yaw.size - 1, 0), bool))
        for i, side in enumerate(SIDES):
            xs, vs = broken(yaw * DEG, np.asarray(x)[:, i] * 1e3, mask)
            ax.plot(xs, vs, "-" if side == "left" else "--", color=f"C{k}", lw=1.1,
                    label=f"{label}, {side}")
    ax.legend(fontsize=6, ncol=2)
    return _save(fig, path)


def category_map(y: np.ndarray, yaw: np.ndarray, codes: np.ndarray, names: Mapping[int, str],
                 title: str, case: str, path: Path) -> Path:
    """A categorical map over (y, yaw): one colour per code present, a legend, no colour bar."""
    present = sorted(int(c) for c in np.unique(codes))
    index = {c: k for k, c in enumerate(present)}
    grid = np.vectorize(index.get)(codes)
    cmap = ListedColormap([f"C{k % 10}" for k in range(len(present))])
    fig, ax = _axes(title, case, "yaw [deg]", "lateral shift y [mm]")
    ax.pcolormesh(yaw * DEG, y * 1e3, grid, cmap=cmap,
                  norm=BoundaryNorm(np.arange(len(present) + 1) - 0.5, len(present)),
                  shading="nearest")
    for k, c in enumerate(present):
        n = int(np.count_nonzero(codes == c))
        ax.fill_between([], [], color=f"C{k % 10}", label=f"{c}: {names.get(c, c)} ({n})")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))
    return _save(fig, path)


def status_names() -> dict[int, str]:
    """Status code -> short text."""
    return {k: v.split(":")[0] for k, v in STATUS.items()}


def index_vs_parameter(values: Sequence[float], series: Mapping[str, Sequence[float]],
                       xlabel: str, ylabel: str, title: str, path: Path,
                       labels: Sequence[str] | None = None) -> Path:
    """One index against a sweep parameter (numbers on a line, or labels as categories)."""
    fig, ax = _axes(title, "", xlabel, ylabel, size=(6.4, 4.0))
    x = np.arange(len(values)) if labels is not None else np.asarray(values, float)
    for k, (name, v) in enumerate(series.items()):
        ax.plot(x, np.asarray(v, float), "o-", color=f"C{k}", label=name)
    if labels is not None:
        ax.set_xticks(x, labels, rotation=30, ha="right", fontsize=7)
    ax.legend(fontsize=7)
    return _save(fig, path)
