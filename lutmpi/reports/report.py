"""``lutmpi report OUTDIR -o REPORT``: the convergence (and wear) report of a sweep directory.

Reads ``OUTDIR/index.json`` (written by ``lutmpi sweep``) and the members' tables, and writes
``REPORT/report.md``, ``REPORT/errors.csv`` and PNG figures. The metrics are computed by the pure
:mod:`lutmpi.reports.convergence` and :mod:`lutmpi.reports.conicity`; this module only reads files
(tables through :class:`lutmpi.table.Table`, the one reader) and writes the outputs. A member with
failed poses (status ``partial``) is read and reported with its holes named; members ``not
selected`` by ``sweep --only`` or ``failed`` are listed, not read.
"""

from __future__ import annotations

import csv
import json
import logging
import math
import re
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from lutmpi.errors import TableError
from lutmpi.reports import conicity as con
from lutmpi.reports.convergence import (
    QUANTITIES,
    MemberTable,
    Study,
    convergence_study,
    error_maps,
    mesh_spacing_of,
)
from lutmpi.reports.owned import report_files
from lutmpi.table.schema import Y_AXIS, YAW_AXIS, D

log = logging.getLogger(__name__)
WEAR_KEYS = re.compile(r"^(wheel|rail|wear)\.")
AMPLITUDES = "1:7.5:0.1"


@dataclass
class SweepData:
    """The members of a sweep directory as read from disk."""

    outdir: Path
    index: list[dict[str, Any]]
    tables: list[MemberTable] = field(default_factory=list)
    unreadable: list[tuple[str, str]] = field(default_factory=list)


#: member statuses whose table is complete and read (``partial``: some poses failed)
READABLE = ("ok", "partial")
#: the member-status key of ``index.json`` (a sweep record, not a table dataset)
STATUS_KEY = "status"  # not a dataset


def read_member(path: str | Path) -> dict[str, Any]:
    """A member table as the mapping the metrics take (``y``, ``yaw``, ``attrs``, ``methods``,
    ``meta``), read by :class:`lutmpi.table.Table` with the stored values (failed points keep
    their status; the metrics mask them)."""
    from lutmpi.table import Table

    t = Table.open(path, mask_failed=False)
    return {"y": t.y, "yaw": t.yaw, "attrs": t.attrs, "methods": t.data, "meta": t.meta}


def load_sweep(outdir: str | Path) -> SweepData:
    """Read ``index.json`` and every table of status ``ok``/``partial`` (or every ``*.h5``)."""
    out = Path(outdir)
    if not out.is_dir():
        raise TableError(f"{out}: no such table file or sweep directory (lutmpi report takes "
                         "a table, T.h5, or the folder lutmpi sweep wrote)")
    index_path = out / "index.json"
    if index_path.is_file():
        index = json.loads(index_path.read_text())["members"]
    else:
        index = [{"id": p.stem, STATUS_KEY: "ok", "table": p.name, "params": {}, "message": ""}
                 for p in sorted(out.glob("*.h5"))]
    if not index:
        raise TableError(f"{out}: no index.json and no tables")
    data = SweepData(out, index)
    for entry in index:
        if entry.get(STATUS_KEY) not in READABLE:
            continue
        try:
            table = read_member(out / entry["table"])
        except TableError as exc:
            data.unreadable.append((entry["id"], str(exc)))
            continue
        h = mesh_spacing_of(table["attrs"].get("config_toml", ""))
        methods = list(table["methods"])
        for method in methods:
            mid = entry["id"] if len(methods) == 1 else f"{entry['id']}/{method}"
            data.tables.append(MemberTable(mid, method,
                                           math.nan if method == "reference" else h, table))
    return data


def _fmt(x: float, digits: int = 3) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "–"
    return f"{x:.{digits}g}"


def write_errors_csv(study: Study, path: Path) -> Path:
    """One row per member: cost and max/RMS error per quantity (units in the column names)."""
    cols = ["member", "method", "spacing_mm", "points", "failures", "cpu_s", "cpu_ms_per_point",
            "wall_s", "ranks"]
    for q, (unit, _) in QUANTITIES.items():
        cols += [f"{q}_max_{unit}", f"{q}_rms_{unit}", f"{q}_excluded"]
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(cols)
        for m in study.metrics:
            row = [m.id, m.method, m.spacing * 1e3, m.points, m.failures, m.cpu_total_s,
                   m.cpu_per_point_s * 1e3, m.wall_s, m.ranks]
            for q, (_, scale) in QUANTITIES.items():
                e = m.errors.get(q)
                row += [e.max * scale, e.rms * scale, e.excluded] if e else ["", "", ""]
            w.writerow(row)
    return path


def _convergence_md(study: Study, figs: list[str]) -> list[str]:
    lines = ["## Convergence", "", f"Reference: **{study.reference}**. Errors over the converged "
             "points of both tables (contact quantities: slot 0, both wheels); `excl.` counts the "
             "values left out.", "",
             "| member | method | h [mm] | points | failures | CPU s | CPU ms/pt | wall s "
             "| ranks |",
             "|---|---|---|---|---|---|---|---|---|"]
    for m in study.metrics:
        lines.append(f"| {m.id} | {m.method} | {_fmt(m.spacing * 1e3)} | {m.points} | "
                     f"{m.failures} | {_fmt(m.cpu_total_s)} | {_fmt(m.cpu_per_point_s * 1e3)} | "
                     f"{_fmt(m.wall_s)} | {m.ranks} |")
    lines += ["", "Max / RMS errors:", "",
              "| member | " + " | ".join(f"{q} [{u}]" for q, (u, _) in QUANTITIES.items()) + " |",
              "|---|" + "---|" * len(QUANTITIES)]
    for m in study.metrics:
        cells = []
        for q, (_, s) in QUANTITIES.items():
            e = m.errors.get(q)
            cells.append("–" if e is None else
                         f"{_fmt(e.max * s)} / {_fmt(e.rms * s)}" + (f" ({e.excluded} excl.)"
                                                                     if e.excluded else ""))
        lines.append(f"| {m.id} | " + " | ".join(cells) + " |")
    lines += ["", "Observed order p (fit of max error = C h^p over the mesh levels):", "",
              "| method | " + " | ".join(QUANTITIES) + " | levels |",
              "|---|" + "---|" * (len(QUANTITIES) + 1)]
    for method, per_q in study.orders.items():
        n = max((v[2] for v in per_q.values()), default=0)
        lines.append(f"| {method} | " + " | ".join(_fmt(v[0], 3) for v in per_q.values())
                     + f" | {n} |")
    lines += [""] + [f"![{f}]({f})" for f in figs] + [""]
    return lines


#: the config sections a case (one wheel-rail geometry) is made of: what the rigid reference
#: depends on. Members that differ in any of them are compared each with its own case's
#: reference, never across cases (a 1:40 member against a 1:20 reference measured the cant)
CASE_SECTIONS = ("wheel", "rail", "track", "wheelset", "wear", "grid")


def case_key(member: MemberTable) -> str:
    """The geometry case of a member table (:data:`CASE_SECTIONS` of its stored config)."""
    import tomllib

    cfg = tomllib.loads(member.table["attrs"].get("config_toml", "") or "")
    return json.dumps({k: cfg.get(k) for k in CASE_SECTIONS}, sort_keys=True, default=str)


def _case_labels(keys: list[str]) -> dict[str, str]:
    """A short label per case: the keys whose values differ between the cases."""
    flat = {}
    for key in keys:
        out: dict[str, Any] = {}

        def walk(d: Any, prefix: str, out: dict[str, Any] = out) -> None:
            if isinstance(d, dict):
                for k, v in d.items():
                    walk(v, f"{prefix}{k}.", out)
            else:
                out[prefix.rstrip(".")] = d

        walk(json.loads(key), "")
        flat[key] = out
    names = sorted({n for f in flat.values() for n in f})
    differ = [n for n in names if len({json.dumps(f.get(n), default=str)
                                       for f in flat.values()}) > 1]
    return {key: ", ".join(f"{n} = {flat[key].get(n)!r}" for n in differ) or "one case"
            for key in keys}


def _convergence(data: SweepData, report: Path, reference: str) -> tuple[list[str], Study | None]:
    """The convergence section: one study per geometry case (:func:`case_key`)."""
    groups: dict[str, list[MemberTable]] = {}
    for t in data.tables:
        groups.setdefault(case_key(t), []).append(t)
    if len(groups) == 1:
        return _convergence_case(data.tables, report, reference, "")
    labels = _case_labels(list(groups))
    lines = ["## Convergence", "", f"The members form {len(groups)} geometry cases; each is "
             "compared with its own case's reference, never across cases.", ""]
    study = None
    for n, (key, tables) in enumerate(sorted(groups.items(), key=lambda kv: labels[kv[0]]), 1):
        section, st = _convergence_case(tables, report, reference, f"_case{n}")
        section[0] = f"### Case {n}: {labels[key]}"
        lines += section
        study = study or st
    return lines, study


def _convergence_case(tables: list[MemberTable], report: Path, reference: str,
                      suffix: str) -> tuple[list[str], Study | None]:
    from lutmpi.reports import plots

    if not any(t.method != "reference" for t in tables):
        return ["## Convergence", "", "Not computed: no mesh-method member in this case.", ""], \
            None
    try:
        study = convergence_study(tables, reference=reference)
    except ValueError as exc:
        return ["## Convergence", "", f"Not computed: {exc}.", ""], None
    if not study.metrics:
        return ["## Convergence", "", "Not computed: no member to compare.", ""], None
    write_errors_csv(study, report / f"errors{suffix}.csv")
    figs = []
    for q in QUANTITIES:
        if any(q in m.errors for m in study.metrics):
            figs.append(plots.error_vs_time(study.metrics, q,
                                            report / f"error_vs_time_{q}{suffix}.png").name)
            figs.append(plots.error_vs_spacing(study.metrics, q, study.orders,
                                               report / f"error_vs_spacing_{q}{suffix}.png").name)
    refs = _references(tables, reference)
    for t in tables:
        ref = refs.get(t.method)
        if ref is None or ref is t:
            continue
        for q, err in error_maps(t.group, ref.group).items():
            if q in (D.z_g, D.contact_angle):
                name = f"map_{_safe(t.id)}_{q}.png"
                plots.error_map(t.table[Y_AXIS], t.table[YAW_AXIS], err, q, f"{t.id} vs {ref.id}",
                                report / name)
                figs.append(name)
    return _convergence_md(study, figs), study


def _references(tables: list[MemberTable], reference: str) -> dict[str, MemberTable]:
    refs = [t for t in tables if t.method == "reference"]
    out: dict[str, MemberTable] = {}
    for t in tables:
        if t.method == "reference":
            continue
        if reference == "reference" and refs:
            out[t.method] = refs[0]
        elif reference == "finest":
            same = [u for u in tables if u.method == t.method]
            out[t.method] = min(same, key=lambda u: u.spacing)
    return out


def _safe(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9._+-]", "_", text)


def _is_wear(data: SweepData) -> bool:
    return any(WEAR_KEYS.match(k) for e in data.index for k in (e.get("params") or {}))


def _wear(data: SweepData, report: Path) -> list[str]:
    """Δr, contact angle and roll against y at yaw 0, and equivalent conicity, per member."""
    from lutmpi.reports import plots

    amps = con.parse_amplitudes(AMPLITUDES)
    ang_c, roll_c, conic, full_c = {}, {}, {}, {}
    rows = ["## Wear: rolling-radius difference and equivalent conicity (yaw = 0)", "",
            "EN 15302 Annex B integration; Δr = r_left − r_right of contact slot 0 (positive for "
            "y > 0, to the left). `–` = the amplitude does not fit in the table's y range. "
            "`wear_dr.png` (data: `wear_dr.csv`) shows Δr over each table's whole y range, a "
            "failed pose a gap; the conicity integrates Δr only up to the first gap either "
            "side of y = 0.", "",
            "| member | tan γe at ŷ = 1 mm | 2 mm | 3 mm | 4 mm | 6 mm | max ŷ [mm] |",
            "|---|---|---|---|---|---|---|"]
    notes = []
    for t in data.tables:
        try:
            y_all, dr_all = con.dr_from_table(t.table, t.method)
        except ValueError as exc:
            rows.append(f"| {t.id} | {exc} | | | | | |")
            continue
        found = con.check_dr(y_all, dr_all, amps, refuse_holes=False)
        notes += [f"- `{t.id}`: {w}" for w in found.warnings if "coarser" not in w]
        y, dr = found.y, found.dr
        # drawn over the table's whole y range, a failed pose a gap: the conicity integrates
        # only the run around y = 0 up to the first gap (found.y), the figure shows all
        full_c[t.id] = (y_all, dr_all)
        j = int(np.argmin(np.abs(np.asarray(t.table[YAW_AXIS]))))
        g = t.group
        failed = np.asarray(g[D.status])[:, j] != 0    # the stored values of a failed pose
        if D.contact_angle in g:
            ang_c[t.id] = (np.asarray(t.table[Y_AXIS]), np.where(
                failed, np.nan, np.asarray(g[D.contact_angle])[:, j, 0, 0]))
        if D.roll in g:
            roll_c[t.id] = (np.asarray(t.table[Y_AXIS]),
                            np.where(failed, np.nan, np.asarray(g[D.roll])[:, j]))
        if y.size < 3:   # in every figure all the same: its conicity curve says "no value"
            conic[t.id] = (amps, np.full(amps.shape, math.nan))
            rows.append(f"| {t.id} | fewer than 3 converged points around y = 0 at yaw 0 "
                        "| | | | | |")
            continue
        res = con.conicity_curve(y, dr, amps)
        conic[t.id] = (amps, res.tan_gamma_e)
        at = [res.at(a * 1e-3) if np.isfinite(res.tan_gamma_e[np.argmin(abs(amps - a * 1e-3))])
              else math.nan for a in (1, 2, 3, 4, 6)]
        reach = amps[np.isfinite(res.tan_gamma_e)]
        rows.append(f"| {t.id} | " + " | ".join(_fmt(v) for v in at)
                    + f" | {_fmt(reach.max() * 1e3 if reach.size else math.nan)} |")
    figs = []
    if full_c:
        figs.append(plots.lines_vs_y(full_c, "Δr = r_left − r_right [mm]",
                                     report / "wear_dr.png", 1e3).name)
        with open(report / "wear_dr.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["member", "y_mm", "delta_r_mm"])
            for name, (y, dr) in full_c.items():
                w.writerows([name, f"{a * 1e3:.6g}", "" if math.isnan(b) else f"{b * 1e3:.6g}"]
                            for a, b in zip(y, dr, strict=True))
    if conic:
        figs.append(plots.conicity_plot(conic, report / "wear_conicity.png").name)
    if ang_c:
        figs.append(plots.lines_vs_y(ang_c, "contact angle, left wheel slot 0 [deg]",
                                     report / "wear_contact_angle.png", 180.0 / math.pi).name)
    if roll_c:
        figs.append(plots.lines_vs_y(roll_c, "roll [mrad]", report / "wear_roll.png", 1e3).name)
    with open(report / "conicity.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["amplitude_mm"] + list(conic))
        for k, a in enumerate(amps):
            w.writerow([f"{a * 1e3:.3f}"] + [c[1][k] for c in conic.values()])
    if notes:
        rows += ["", "Δr holes and limits (never integrated across):", ""] + notes
    return rows + [""] + [f"![{f}]({f})" for f in figs] + [""]


def _sweep_axis(data: SweepData, ids: list[str]) -> tuple[str, list[float], list[str] | None]:
    """The member parameter to plot the indices against: the one numeric parameter that varies
    (its values), else the member IDs as categories."""
    params = {e["id"]: (e.get("params") or {}) for e in data.index}
    base = [i.split("/")[0] for i in ids]
    keys = sorted({k for i in base for k in params.get(i, {})})
    varying = [k for k in keys if len({json.dumps(params[i].get(k)) for i in base}) > 1]
    if len(varying) == 1 and all(isinstance(params[i].get(varying[0]), int | float)
                                 for i in base):
        return varying[0], [float(params[i][varying[0]]) for i in base], None
    return "member", list(range(len(ids))), ids


def _sweep_indices(data: SweepData, report: Path) -> list[str]:
    """One CSV (``indices.csv``) and one plot per index against the member's parameter."""
    from lutmpi.reports import geometry_plots as gp
    from lutmpi.reports import indices as ix

    rows, ids = [], []
    for t in data.tables:
        try:
            y, dr = con.dr_from_table(t.table, t.method)
        except ValueError:
            continue
        found = ix.indices(y, dr)
        rows.append(found.row())
        ids.append(t.id)
    if not rows:
        return []
    key, xs, labels = _sweep_axis(data, ids)
    with open(report / "indices.csv", "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(["member", key if key != "member" else "member_number"] + list(rows[0]))
        for i, x, r in zip(ids, xs, rows, strict=True):
            w.writerow([i, x] + [f"{v:.6g}" for v in r.values()])
    groups = {"tan_gamma_e": ("equivalent conicity tan γe [-]", "tan γe (EN 15302 Annex B)"),
              "rolling_radii_coeff": ("rolling-radii coefficient κ [-]", "rolling-radii "
                                      "coefficient (LSQ slope of Δr / 2)"),
              "nonlinearity_parameter": ("NP [1/mm]", "Polach's nonlinearity parameter")}
    figs = []
    for prefix, (ylabel, title) in groups.items():
        cols = [c for c in rows[0] if c.startswith(prefix)]
        series = {c.removeprefix(prefix + "_") or prefix: [r[c] for r in rows] for c in cols}
        figs.append(gp.index_vs_parameter(xs, series, key, ylabel, title,
                                          report / f"index_{prefix}.png", labels).name)
    return ["## Geometry indices per member", "", "`indices.csv`: one row per member; "
            "definitions and sources in `lutmpi/reports/indices.py`.", ""] + [
        f"![{f}]({f})" for f in figs] + [""]


def _status_line(index: list[dict[str, Any]]) -> str:
    """``12 members: 9 ok, 2 partial (failed poses), 1 not selected``."""
    counts: dict[str, int] = {}
    for e in index:
        counts[e.get(STATUS_KEY, "?")] = counts.get(e.get(STATUS_KEY, "?"), 0) + 1
    label = {"partial": "partial (some poses failed)"}
    order = sorted(counts.items(), key=lambda kv: kv[0] != "ok")
    parts = [f"{n} {label.get(k, k)}" for k, n in order]
    line = f"{len(index)} members: " + ", ".join(parts) + "."
    unfinished = counts.get("pending", 0) + counts.get("interrupted", 0)
    if unfinished:
        line += (f" **The sweep is incomplete**: {unfinished} member(s) not built (rerun the "
                 "sweep to continue it); this report covers the others only.")
    return line


def build_report(outdir: str | Path, report_dir: str | Path, reference: str = "reference",
                 wear: bool | None = None) -> Path:
    """Write ``report.md``, ``errors.csv`` and the figures of a sweep directory.

    Parameters
    ----------
    outdir : path
        A ``lutmpi sweep`` output directory.
    report_dir : path
        Where the report goes (created).
    reference : {"reference", "finest"}
        Error reference: the semi-analytic solver's member, or each method's finest mesh.
    wear : bool, optional
        Add the wear section (Δr, contact angle, roll, conicity per member); default: when the
        sweep varies profiles or wear parameters.

    Returns
    -------
    pathlib.Path
        The ``report.md`` written.
    """
    data = load_sweep(outdir)
    report = Path(report_dir)
    report.mkdir(parents=True, exist_ok=True)
    with report_files(report):   # an earlier report's figures go: none of them looks current
        return _write_report(data, report, reference, wear)


def _write_report(data: SweepData, report: Path, reference: str, wear: bool | None) -> Path:
    lines = [f"# Sweep report: {data.outdir}", "", _status_line(data.index), ""]
    listed = [e for e in data.index if e.get(STATUS_KEY) != "ok"] + [
        {"id": i, STATUS_KEY: "unreadable", "message": m} for i, m in data.unreadable]
    if listed:
        lines += ["Members not fully ok:", ""] + [
            f"- `{e['id']}` ({e.get(STATUS_KEY, '?')}): {e.get('message', '')}" for e in listed]
        lines.append("")
    has_mesh_levels = any(t.method != "reference" for t in data.tables)
    if has_mesh_levels and (reference == "finest" or any(t.method == "reference"
                                                         for t in data.tables)):
        section, _ = _convergence(data, report, reference)
        lines += section
    if wear or (wear is None and _is_wear(data)):
        lines += _wear(data, report)
        lines += _sweep_indices(data, report)
    path = report / "report.md"
    path.write_text("\n".join(lines) + "\n")
    log.info("report written to %s", path)
    return path
