"""Text rendering of a :class:`~lutmpi.check.suite.CheckReport`: a verdict table, then the
messages (what was measured; on failure, what to change)."""

from __future__ import annotations

import math

from lutmpi.check.suite import CheckReport

MM = 1e-3


def _num(v: float) -> str:
    if math.isinf(v):
        return "inf"
    return f"{v:.3g}"


def format_report(report: CheckReport, title: str = "") -> str:
    """The verdict table and the messages, as one string."""
    t = report.tolerances
    rows = [("check", "region", "verdict", "value", "limit")]
    for r in report.results:
        rows.append((r.name, r.region,
                     "n/a" if not r.measured else "PASS" if r.passed else "FAIL",
                     "-" if not r.measured else _num(r.value),
                     ("<=" if r.name != "convergence" and r.name != "mesh spacing" else ">=")
                     + " " + _num(r.limit)))
    widths = [max(len(row[k]) for row in rows) for k in range(5)]
    line = "  ".join("-" * w for w in widths)
    out = []
    if title:
        out.append(title)
    out.append(f"method {report.method}; surveyed reference poses per region: "
               + ", ".join(f"{k} {v}" for k, v in report.regions.items()))
    out.append(f"tolerances: z_g {t.z / MM:.3g} mm, roll {t.roll:.3g} rad, contact position "
               f"{t.s / MM:.3g} mm (from the mesh spacing); accuracy vs reference "
               f"{t.acc_z / MM:g} mm, {t.acc_roll:g} rad, {t.acc_s / MM:g} mm; double contact: "
               f"second gap minimum within {t.dc / MM:.3g} mm")
    out.append("regions by the reference contact angle: tread < 0.15 rad <= flange root < 1.0 "
               "rad <= flange")
    out.append(line)
    for k, row in enumerate(rows):
        out.append("  ".join(c.ljust(w) for c, w in zip(row, widths, strict=True)).rstrip())
        if k == 0:
            out.append(line)
    out.append(line)
    for k, r in enumerate(report.results, 1):
        out.append(f"[{k}] {r.name} ({r.region}): {r.message}")
    verdict = "PASS" if report.passed else "FAIL"
    n_fail = sum(not r.passed for r in report.results)
    n_na = sum(not r.measured for r in report.results)
    n = len(report.results) - n_na
    out.append(f"{verdict}: {n - n_fail}/{n} checks passed"
               + (f" ({n_na} not applicable, listed n/a)" if n_na else "")
               + f"; {report.n_solves} mesh solves in {report.elapsed:.1f} s")
    return "\n".join(out)
