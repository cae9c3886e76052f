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
    p.add_argument("--side", choices=SIDES, default="left", help="wheel, per-contact quantities")
    p.add_argument("--slot", type=int, choices=(0, 1), default=0,
                   help="contact slot (0 = largest force)")
    p.add_argument("--component", type=int, choices=(0, 1, 2), default=None,
                   help="vector component 0=x 1=y 2=z (default z for vectors)")
    p.set_defaults(func=run)


def select(table: Any, quantity: str, method: str | None, side: str, slot: int,
           component: int | None) -> tuple[np.ndarray, str]:
    """The (ny, nyaw) surface of one quantity and its label."""
    from lutmpi.table.schema import FIELDS_BY_NAME

    arr = table.get(quantity, method).astype(float)
    label = quantity
    fld = FIELDS_BY_NAME.get(quantity)
    if fld is not None and fld.suffix[:1] == (len(SIDES),):
        arr = arr[:, :, SIDES.index(side)]
        label += f", {side} wheel"
        if fld.per_contact:
            arr = arr[:, :, slot]
            label += f", slot {slot}"
    if arr.ndim == 3:
        c = 2 if component is None else component
        arr = arr[:, :, c]
        label += f", {COMPONENTS[c]}"
    return arr, f"{label} [{table.units(quantity, method)}]"


def plot(table: Any, quantity: str, output: str, method: str | None = None, side: str = "left",
         slot: int = 0, component: int | None = None) -> None:
    """Write the surface + colour-map figure of one quantity."""
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
