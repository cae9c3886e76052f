"""``lutmpi check``: the stability suite of a profile pair and grid (issue 7). Pure numerics
(:mod:`lutmpi.check.suite`, :mod:`lutmpi.check.regions`) and a text report
(:mod:`lutmpi.check.report`)."""

from lutmpi.check.report import format_report
from lutmpi.check.suite import CheckOptions, CheckReport, CheckResult, Tolerances, run_checks

__all__ = ["CheckOptions", "CheckReport", "CheckResult", "Tolerances", "format_report",
           "run_checks"]
