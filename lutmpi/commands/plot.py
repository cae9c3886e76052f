"""``lutmpi plot TABLE.h5 QUANTITY -o fig.png``: a 3D surface and a colour map over y x yaw, as in
the paper's Figs 9-10 (e.g. ``wheel_point --side left --component 0`` is Fig. 9's x of the left
wheel's contact point)."""

from __future__ import annotations

import argparse
from typing import Any

import numpy as np

from lutmpi.equilibrium.result import SIDES
from lutmpi.table.schema import D

COMPONENTS = ("x", "y", "z")


def register(subparsers: Any) -> None:
    p = subparsers.add_parser("plot", help="plot one quantity of a table over y x yaw",
                              description="3D surface and colour map of one table quantity over "
                                          "the (y_g, yaw) grid (matplotlib, PNG/PDF/SVG).")
    p.add_argument("table", help="table file (HDF5)")
    p.add_argument("quantity", help="dataset name, e.g. z_g, roll, wheel_point, normal")
    p.add_argument("-o", "--output", required=True, help="figure file (.png, .pdf, .svg)")
    p.add_argument("--method", default=None, help="contact method (default: the first stored)")
    p.add_argument("--side", choices=SIDES, default=None,
                   help="wheel of a per-wheel quantity (default left)")
    p.add_argument("--slot", type=int, choices=(0, 1), default=None,
                   help="contact slot of a per-contact quantity (0 = largest force; default 0)")
    p.add_argument("--component", type=int, choices=(0, 1, 2), default=None,
                   help="vector component 0=x 1=y 2=z (default z for vectors)")
    p.set_defaults(func=run)


def select(table: Any, quantity: str, method: str | None, side: str | None, slot: int | None,
           component: int | None) -> tuple[np.ndarray, str]:
    """The (ny, nyaw) surface of one quantity and its label (``side`` default left, ``slot``
    0, ``component`` z); an option the quantity has no use for is a :class:`ConfigError`."""
    from lutmpi.errors import ConfigError
    from lutmpi.table.schema import FIELDS_BY_NAME

    arr = table.get(quantity, method).astype(float)
    label = quantity
    fld = FIELDS_BY_NAME.get(quantity)
    per_wheel = fld is not None and fld.suffix[:1] == (len(SIDES),)
    per_contact = per_wheel and fld.per_contact
    for given, used, name, what in ((side, per_wheel, "--side", "one value per wheel"),
                                    (slot, per_contact, "--slot", "one value per contact")):
        if given is not None and not used:
            raise ConfigError(f"{quantity} has no {what}: {name} does not apply to it", key=name)
    if per_wheel:
        side = side or "left"
        arr = arr[:, :, SIDES.index(side)]
        label += f", {side} wheel"
        if per_contact:
            slot = 0 if slot is None else slot
            arr = arr[:, :, slot]
            label += f", slot {slot}"
    if arr.ndim == 3:
        c = 2 if component is None else component
        arr = arr[:, :, c]
        label += f", {COMPONENTS[c]}"
    elif component is not None:
        raise ConfigError(f"{quantity} is not a vector: --component does not apply to it",
                          key="--component")
    return arr, f"{label} [{table.units(quantity, method)}]"


def plot(table: Any, quantity: str, output: str, method: str | None = None,
         side: str | None = None, slot: int | None = None, component: int | None = None) -> None:
    """Write the surface + colour-map figure of one quantity (a table with one yaw value: the
    quantity against y)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from lutmpi.reports.pair import pair_info
    from lutmpi.reports.units import edge_unit
    from lutmpi.table.schema import FIELDS_BY_NAME

    z, label = select(table, quantity, method, side, slot, component)
    case = pair_info(table.config_toml).title
    fld = FIELDS_BY_NAME.get(quantity)
    if fld is not None and fld.dtype == "i1":          # codes and counts: categories, not a scale
        _categories(table, quantity, z, label, case, output)
        return
    unit, factor, _ = edge_unit(table.units(quantity, method))
    z = z * factor
    label = label.rsplit(" [", 1)[0] + f" [{unit}]"
    if table.yaw.size == 1:      # a 1-D table: no surface to draw
        _line(table, z[:, 0], label, case, f"{method or table.methods[0]}", output)
        return
    yy, aa = np.meshgrid(table.y * 1e3, np.degrees(table.yaw), indexing="ij")
    fig = plt.figure(figsize=(12, 5.0))
    fig.suptitle(case, fontsize=10)
    ax = fig.add_subplot(1, 2, 1, projection="3d")
    ax.plot_surface(yy, aa, z, cmap="viridis", linewidth=0.2, edgecolor="k")
    ax.set_xlabel("y_g [mm]", labelpad=8)
    ax.set_ylabel("yaw [deg]", labelpad=8)
    ax.set_zlabel(unit, labelpad=10)
    ax.tick_params(labelsize=7, pad=2)
    ax.set_title(label, fontsize=9)
    ax2 = fig.add_subplot(1, 2, 2)
    mesh = ax2.pcolormesh(yy, aa, z, shading="nearest", cmap="viridis")
    fig.colorbar(mesh, ax=ax2, label=label)
    ax2.set_xlabel("y_g [mm]")
    ax2.set_ylabel("yaw [deg]")
    ax2.set_title(f"{method or table.methods[0]} ({np.isnan(z).sum()} NaN points)", fontsize=9)
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    plt.close(fig)


def _line(table: Any, v: np.ndarray, label: str, case: str, method: str, output: str) -> None:
    """One quantity against y (a table of one yaw value), failed points left out."""
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.5))
    fig.suptitle(case, fontsize=10)
    ax.plot(table.y * 1e3, v, ".-", lw=1, ms=3)
    ax.set_xlabel("y_g [mm]")
    ax.set_ylabel(label)
    ax.grid(alpha=0.3)
    ax.set_title(f"{method}, yaw {np.degrees(table.yaw[0]):g} deg ({int(np.isnan(v).sum())} "
                 "NaN points)", fontsize=9)
    fig.tight_layout()
    fig.savefig(output, dpi=120)
    plt.close(fig)


def _categories(table: Any, quantity: str, codes: np.ndarray, label: str, case: str,
                output: str) -> None:
    """Status codes and contact counts as a categorical map (one colour per value, a legend)."""
    from pathlib import Path

    from lutmpi.reports import geometry_plots as gp

    codes = np.asarray(codes).astype(int)
    names = gp.status_names() if quantity == D.status else \
        {int(c): f"{int(c)} contact(s)" for c in np.unique(codes)}
    gp.category_map(table.y, table.yaw, codes, names, label, case, Path(output))


def run(args: argparse.Namespace) -> int:
    from lutmpi.outpath import check_figure_file
    from lutmpi.table import Table

    check_figure_file(args.output, "figure", inputs=(args.table,))
    plot(Table.open(args.table), args.quantity, args.output, args.method, args.side, args.slot,
         args.component)
    return 0
