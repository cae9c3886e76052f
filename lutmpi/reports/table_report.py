"""``lutmpi report T.h5 -o DIR``: the contact-geometry report of one table (report.md + PNGs).

The report is a list of sections (:data:`SECTIONS`); a section is a function ``(ctx) -> list of
markdown lines`` that may write figures into ``ctx.outdir``. A new section is one function plus one
line in :data:`SECTIONS` (the table-error section of issue 11 goes there).
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lutmpi.errors import MissingQuantityError
from lutmpi.reports import breaks, indices
from lutmpi.reports import conicity as con
from lutmpi.reports.owned import report_files
from lutmpi.reports.pair import PairInfo, en15302_case, pair_info
from lutmpi.table.schema import D

log = logging.getLogger(__name__)
AMPLITUDES = "1:7.5:0.1"


@dataclass
class ReportContext:
    """What every section sees."""

    table: Any
    method: str
    outdir: Path
    pair: PairInfo
    j0: int                          # index of yaw 0 (or the yaw nearest to it)
    mask: np.ndarray                 # intervals of y not to join at yaw j0
    at_y: tuple[float, ...] = ()     # m: poses drawn to scale
    band_case: str | None = None     # EN 15302 Annex E case (E1..E9) for the conicity band
    figures: list[str] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)

    @property
    def case(self) -> str:
        return self.pair.title

    def at0(self, name: str) -> np.ndarray:
        """A dataset at yaw j0, failed points NaN (raw codes for integer datasets)."""
        arr = self.table.get(name, self.method)
        return arr[:, self.j0] if arr.dtype.kind == "f" else \
            self.table.get(name, self.method, raw=True)[:, self.j0]

    def fig(self, path: Path) -> str:
        self.figures.append(path.name)
        return f"![{path.name}]({path.name})"


def _header(ctx: ReportContext) -> list[str]:
    t = ctx.table
    counts = t.status_counts(ctx.method)
    bad = sum(n for k, n in counts.items() if k != "converged")
    yaw0 = t.yaw[ctx.j0]
    lines = [f"# Contact geometry: {ctx.case}", "",
             f"Table `{t.path}`, method `{ctx.method}`, r0 {ctx.pair.r0_mm:g} mm; grid y "
             f"{t.y[0] * 1e3:g} … {t.y[-1] * 1e3:g} mm ({t.y.size}), yaw {t.yaw[0]:g} … "
             f"{t.yaw[-1]:g} rad ({t.yaw.size}). Functions of y at yaw {yaw0:g} rad.", "",
             "Status: " + ", ".join(f"{k} {n}" for k, n in counts.items()) + ".", ""]
    if abs(yaw0) > 1e-12:
        ctx.warnings.append(f"no yaw = 0 column: the functions of y are at yaw {yaw0:g} rad and "
                            "the conicity is not computed")
    if bad:
        ctx.warnings.append(f"{bad} poses did not converge: they are holes in every curve "
                            "(never interpolated across)")
    return lines


def _functions(ctx: ReportContext) -> list[str]:
    from lutmpi.reports import geometry_plots as gp

    y, out, m = ctx.table.y, ctx.outdir, ctx.mask
    rr = lambda: ctx.at0(D.rolling_radius)   # noqa: E731
    ang = lambda: ctx.at0(D.contact_angle)   # noqa: E731
    # (what a figure shows, the figure); a table of a subset of the quantities draws the rest
    plots = [
        ((D.rolling_radius,), lambda: gp.curve(
            y, {"Δr = r_left − r_right (main contacts)": rr()[:, 0, 0] - rr()[:, 1, 0]}, m,
            "Rolling-radius difference Δr(y)", ctx.case, "Δr [mm]", out / "delta_r.png", 1e3)),
        ((D.rolling_radius,), lambda: gp.per_contact(
            y, rr() - ctx.pair.r0_mm * 1e-3, m, "Rolling radii (minus r0)", ctx.case,
            f"r − {ctx.pair.r0_mm:g} mm [mm]", out / "rolling_radii.png", 1e3)),
        ((D.contact_angle,), lambda: gp.per_contact(
            y, ang(), m, "Contact angles (+ toward the flange)", ctx.case,
            "contact angle [deg]", out / "contact_angles.png", gp.DEG)),
        ((D.contact_angle,), lambda: gp.curve(
            y, {"tan γ_left − tan γ_right (main contacts)": indices.delta_tan_gamma(ang())}, m,
            "Δtanγ function", ctx.case, "Δtanγ [-]", out / "delta_tan_gamma.png")),
        ((D.roll,), lambda: gp.curve(
            y, {"roll (+ raises the left wheel)": ctx.at0(D.roll)}, m, "Roll angle",
            ctx.case, "roll [deg]", out / "roll.png", gp.DEG)),
        ((D.z_g,), lambda: gp.curve(
            y, {D.z_g: ctx.at0(D.z_g)}, m, "Height of the wheelset centre above rail top",
            ctx.case, "z_g [mm]", out / "z_g.png", 1e3)),
    ]
    stored = set(ctx.table.quantities)
    figs = [make() for names, make in plots if stored.issuperset(names)]
    missing = sorted({n for names, _ in plots for n in names} - stored)
    if missing:
        ctx.warnings.append(f"functions of y not drawn for {', '.join(missing)}: the table does "
                            "not store them")
    return ["## Functions of y", "", "Lines break where a contact jumps (moves more than "
            f"{breaks.JUMP_THRESHOLD * 1e3:g} mm on the wheel between neighbouring poses, appears "
            "or disappears) or the status changes.", ""] + [ctx.fig(f) for f in figs] + [""]


def _contact_map(ctx: ReportContext) -> list[str]:
    from lutmpi.reports import geometry_plots as gp
    from lutmpi.reports.profiles_of import table_profiles

    profiles = table_profiles(ctx.table)
    points = {"wheel": ctx.at0(D.wheel_s), "rail": ctx.at0(D.rail_v)}
    path = gp.contact_map(ctx.table.y, profiles, points, ctx.case, ctx.outdir / "contact_map.png")
    lines = ["## Contact points on the profiles", "", ctx.fig(path), ""]
    for y in ctx.at_y:
        lines.append(ctx.fig(_track(ctx, y)))
    return lines + [""]


def _track(ctx: ReportContext, y: float) -> Path:
    from lutmpi.reports.track_plot import plot_track
    from lutmpi.scene import Scene

    scene = Scene.from_config(ctx.table.built_config())
    path = ctx.outdir / f"pair_y{y * 1e3:+.1f}mm.png"
    return plot_track(scene, path, y, title=f"{ctx.case}\nto scale at y = {y * 1e3:g} mm, yaw 0 "
                                            "(rigid contact, reference solver)")


def _indices(ctx: ReportContext) -> list[str]:
    from lutmpi.reports import geometry_plots as gp

    if abs(ctx.table.yaw[ctx.j0]) > 1e-12:
        return ["## Equivalent conicity and indices", "", "Not computed: no yaw = 0 column.", ""]
    y, dr = con.dr_from_table(ctx.table, ctx.method)
    amps = con.parse_amplitudes(AMPLITUDES)
    found = con.check_dr(y, dr, amps, refuse_holes=False)
    ctx.warnings += found.warnings
    idx = indices.indices(y, dr)
    lam = con.conicity_curve(found.y, found.dr, amps).tan_gamma_e if found.y.size >= 3 else \
        np.full(amps.size, np.nan)
    band = _band(ctx.band_case)
    path = gp.conicity(amps, lam, ctx.case, ctx.outdir / "conicity.png", band,
                       f"EN 15302 case {ctx.band_case} tolerance band" if band else "")
    head = "| index | source | " + " | ".join(f"ŷ = {a * 1e3:g} mm" for a in idx.amplitudes)
    lines = ["## Equivalent conicity and indices", "",
             "Definitions and sources: `lutmpi/reports/indices.py`.", "",
             head + " |", "|---|---|" + "---|" * idx.amplitudes.size,
             "| tan γe | EN 15302 Annex B | " + " | ".join(_f(v) for v in idx.conicity) + " |",
             "| rolling-radii coefficient κ | LSQ slope of Δr / 2 | "
             + " | ".join(_f(v) for v in idx.rolling_radii) + " |",
             "| Δtanγ at y = ŷ | tan γ_left − tan γ_right | "
             + " | ".join(_f(v) for v in _dtan_at(ctx, idx.amplitudes)) + " |", "",
             f"Nonlinearity parameter NP (Polach 2010) = {_f(idx.nonlinearity * 1e-3)} 1/mm.", ""]
    if band is None and ctx.band_case:
        lines.append(f"No EN 15302 band: case {ctx.band_case} data not found (shared/).")
    elif band is not None:
        inside = _inside_band(amps, lam, band)
        lines.append(f"EN 15302 Annex E case {ctx.band_case}: tolerance band drawn; "
                     f"{inside[0]} of {inside[1]} computed amplitudes inside it.")
    return lines + [ctx.fig(path), ""]


def _dtan_at(ctx: ReportContext, ys: np.ndarray) -> np.ndarray:
    """Δtanγ at the lateral shifts ``ys`` (m), NaN where a neighbouring pose failed or the two
    neighbours straddle a contact jump (a jump is not interpolated)."""
    y = ctx.table.y
    d = indices.delta_tan_gamma(ctx.at0(D.contact_angle))
    out = np.full(np.size(ys), np.nan)
    for k, v in enumerate(np.atleast_1d(ys)):
        i = int(np.searchsorted(y, v)) - 1
        if 0 <= i < y.size - 1 and not ctx.mask[i]:
            out[k] = float(np.interp(v, y[i:i + 2], d[i:i + 2]))
        elif i + 1 < y.size and abs(y[i + 1] - v) < 1e-12:
            out[k] = float(d[i + 1])
    return out


def _band(case: str | None) -> dict[str, np.ndarray] | None:
    if not case:
        return None
    from lutmpi.paths import shared_dir

    root = shared_dir()
    path = None if root is None else root / "validation" / "en15302" / "csv" / \
        f"reference_conicity_{case}.csv"
    if path is None or not path.is_file():
        return None
    d = np.genfromtxt(path, delimiter=",", names=True)
    return {"amplitude": d["amplitude_mm"] * 1e-3, "reference": d["tan_gamma_e_ref"],
            "lower": d["tol_lower"], "upper": d["tol_upper"]}


def _inside_band(amps: np.ndarray, lam: np.ndarray, band: dict[str, np.ndarray]
                 ) -> tuple[int, int]:
    """(inside, compared): amplitudes where both the conicity and the band have a value."""
    lo = np.interp(amps, band["amplitude"], band["lower"], left=np.nan, right=np.nan)
    hi = np.interp(amps, band["amplitude"], band["upper"], left=np.nan, right=np.nan)
    ok = np.isfinite(lam) & np.isfinite(lo)
    return int(np.count_nonzero(ok & (lam >= lo) & (lam <= hi))), int(ok.sum())


def _lead(ctx: ReportContext) -> list[str]:
    from lutmpi.reports import geometry_plots as gp

    t = ctx.table
    wp = t.get(D.wheel_point, ctx.method)[:, :, :, 0, 0]          # (ny, nyaw, side) x
    picks = sorted({0, t.y.size // 4, t.y.size // 2, 3 * t.y.size // 4, t.y.size - 1})
    leads = {f"y = {t.y[i] * 1e3:g} mm": wp[i] for i in picks}
    raw = {n: t.get(n, ctx.method, raw=True) for n in (D.wheel_s, D.n_contacts, D.status)
           if n in t.quantities}
    masks = {f"y = {t.y[i] * 1e3:g} mm": breaks.detect(
        raw[D.wheel_s][i], raw[D.n_contacts][i] if D.n_contacts in raw else None,
        raw[D.status][i]) for i in picks} if D.wheel_s in raw else None
    path = gp.lead_vs_yaw(t.yaw, leads, ctx.case, ctx.outdir / "contact_lead.png", masks)
    return ["## Contact lead against yaw", "", ctx.fig(path), ""]


def _status(ctx: ReportContext) -> list[str]:
    from lutmpi.reports import geometry_plots as gp

    t = ctx.table
    st = t.get(D.status, ctx.method, raw=True)
    figs = [gp.category_map(t.y, t.yaw, st, gp.status_names(), "Solve status", ctx.case,
                            ctx.outdir / "status_map.png")]
    if D.n_contacts in t.quantities:
        nc = t.get(D.n_contacts, ctx.method, raw=True)
        code = 10 * nc[:, :, 0] + nc[:, :, 1]
        names = {int(c): f"left {c // 10}, right {c % 10}" for c in np.unique(code)}
        figs.append(gp.category_map(t.y, t.yaw, code, names, "Contacts per wheel", ctx.case,
                                    ctx.outdir / "contacts_map.png"))
    return ["## Status and contact count maps", ""] + [ctx.fig(f) for f in figs] + [""]


def _warnings(ctx: ReportContext) -> list[str]:
    if not ctx.warnings:
        return []
    return ["## Warnings", ""] + [f"- {w}" for w in ctx.warnings] + [""]


def _f(v: float) -> str:
    return "–" if not math.isfinite(v) else f"{v:.4g}"


Section = Callable[[ReportContext], list[str]]
#: the report's sections, in order (the warnings gathered by all of them come last)
SECTIONS: list[Section] = [_header, _indices, _functions, _contact_map, _lead, _status]


def build_table_report(table_path: str | Path, report_dir: str | Path, *,
                       method: str | None = None, at_y_mm: tuple[float, ...] | None = None,
                       band_case: str | None = None) -> Path:
    """Write ``report.md`` and the figures of one table into ``report_dir``.

    Parameters
    ----------
    table_path : path
        A complete lookup table.
    report_dir : path
        Created if needed.
    method : str, optional
        Contact method (default: the table's first).
    at_y_mm : tuple of float, optional
        Lateral shifts (mm) at which the pair is drawn to scale; default 0 and the grid's last y.
    band_case : str, optional
        EN 15302 Annex E case (``E1`` … ``E9``) whose tolerance band is drawn with the conicity;
        default: the case the table's profiles are, if any (:func:`lutmpi.reports.pair.
        en15302_case`).
    """
    from lutmpi.table import Table

    table = Table.open(table_path)
    table.built_config()   # before any figure: the profile files still the table's (or raise)
    out = Path(report_dir)
    out.mkdir(parents=True, exist_ok=True)
    method = method or table.methods[0]
    j0 = int(np.argmin(np.abs(table.yaw)))
    at = tuple(a * 1e-3 for a in at_y_mm) if at_y_mm is not None else (0.0, float(table.y[-1]))
    band_case = band_case or en15302_case(table.config_toml)
    ctx = ReportContext(table, method, out, pair_info(table.config_toml), j0,
                        breaks.break_mask(table, method, j0), at, band_case)
    lines: list[str] = []
    path = out / "report.md"
    with report_files(out):   # an earlier report's figures go: none of them looks current
        for section in SECTIONS:
            try:
                lines += section(ctx)
            except MissingQuantityError as exc:   # a table of a subset of the quantities
                note = (f"section `{section.__name__.lstrip('_')}` left out: the table does "
                        f"not store what it shows ({exc})")
                log.warning("%s", note)
                ctx.warnings.append(note)
        lines += _warnings(ctx)
        path.write_text("\n".join(lines) + "\n")
    log.info("report written to %s (%d figures)", path, len(ctx.figures))
    return path
