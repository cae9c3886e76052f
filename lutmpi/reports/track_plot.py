"""Both wheels on both rails, to scale (``lutmpi profile plot CONFIG``): the wheelset at its rigid
contact pose for a given (y, yaw = 0), an overview of the cross-section and a close-up of each
wheel-rail pair with the contact points and gauge points marked. Matplotlib Agg only."""

from __future__ import annotations

from pathlib import Path

import numpy as np


def _name(side: float) -> str:
    return "left" if side > 0 else "right"


def _wheel_curve(scene, side: float, z_g: float, y: float, roll: float):
    """Lowest generator of wheel ``side`` in the track's y-z plane (yaw 0), m."""
    w = scene.side(_name(side)).wheel
    s = np.linspace(w.profile.y_min, w.profile.y_max, 1500)
    r = w.radius(s)
    yb, zb = side * (w.d + s), -r
    c, sn = np.cos(roll), np.sin(roll)
    return y + yb * c - zb * sn, z_g + yb * sn + zb * c


def _rail_curve(scene, side: float):
    rail = scene.side(_name(side)).rail
    return side * rail.u, rail.z


def plot_track(scene, out: str | Path, y: float = 0.0, title: str | None = None) -> Path:
    """Write the figure to ``out`` (PNG) and return its path."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lutmpi.pose.solve import solve_pose

    res = solve_pose(scene, y, 0.0, "reference")
    fig = plt.figure(figsize=(12, 7.5))
    ax0 = fig.add_subplot(2, 1, 1)
    axl, axr = fig.add_subplot(2, 2, 4), fig.add_subplot(2, 2, 3)
    for ax, _zoom in ((ax0, False), (axl, True), (axr, True)):
        for side, colour in ((1.0, "C0"), (-1.0, "C1")):
            ry, rz = _rail_curve(scene, side)
            ax.fill_between(ry * 1e3, rz * 1e3, rz.min() * 1e3 - 5, color="0.8", lw=0)
            ax.plot(ry * 1e3, rz * 1e3, color="0.3", lw=1)
            wy, wz = _wheel_curve(scene, side, res.z_g, y, res.roll)
            ax.plot(wy * 1e3, wz * 1e3, color=colour, lw=1.2)
            rail = scene.side(_name(side)).rail
            ax.plot([side * rail.gauge_point[0] * 1e3], [rail.gauge_point[1] * 1e3], "k+", ms=8)
        for name in ("left", "right"):
            for c in res.contacts[name]:
                ax.plot(c.wheel_point[1] * 1e3, c.wheel_point[2] * 1e3, "ro", ms=4)
        ax.set_aspect("equal")
        ax.grid(alpha=0.3)
        ax.set_xlabel("y (mm), to the left")
        ax.set_ylabel("z (mm)")
    ax0.set_ylim(-60, 60)
    ax0.set_xlim(-820, 820)
    ax0.set_title(title or f"y = {y * 1e3:.2f} mm, yaw 0: z_g = {res.z_g * 1e3:.3f} mm, "
                           f"roll = {np.degrees(res.roll):.4f} deg (rigid contact)")
    g = scene.side("left").rail.gauge / 2 * 1e3
    axl.set_xlim(g - 25, g + 80)
    axr.set_xlim(-g - 80, -g + 25)
    for ax, name in ((axl, "left"), (axr, "right")):
        ax.set_ylim(-45, 25)
        cs = res.contacts[name]
        txt = ", ".join(f"s = {c.wheel_s * 1e3:.2f} mm, angle {np.degrees(c.contact_angle):.2f} deg"
                        for c in cs)
        ax.set_title(f"{name}: {txt}", fontsize=9)
    fig.tight_layout()
    out = Path(out)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out
