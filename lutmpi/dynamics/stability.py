"""The one classification of a wheelset run: ``stable``, ``hunting`` or ``undetermined``.

``lutmpi simulate`` and ``lutmpi critical-speed`` (its bisection) both call :func:`classify` with
the same rule, so a run is never logged as "hunting" by one and "stable" by the other.

Rule. The peaks of ``|y(t)|`` form the envelope of the lateral oscillation; a straight line is
fitted to ``log(peak)`` over the later half of the peaks, its slope is the growth rate ``sigma``
(1/s; the envelope goes as ``exp(sigma t)``):

* fewer than :data:`MIN_PEAKS` peaks (two full periods in the fit window): ``undetermined`` -- the
  run is too short to tell, and no rate is reported (NaN, said in the line);
* the motion decayed below ``floor`` times its first peak: ``stable``;
* ``sigma > growth_tol`` or an envelope that ends at or above its first peak (a limit cycle reached
  from below): ``hunting``; otherwise ``stable``.

Growth rates are printed in significant digits with their unit (``+3.81e-02 1/s``), never rounded
to ``0.000``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.signal import find_peaks

#: peaks of |y| needed: the fit window (later half) then spans at least two periods
MIN_PEAKS = 8


def format_rate(rate: float) -> str:
    """``+3.81e-02 1/s`` (three significant digits and the unit; ``nan 1/s`` when unknown)."""
    return "nan 1/s" if not math.isfinite(rate) else f"{rate:+.3g} 1/s"


@dataclass
class Summary:
    """Classification of a run (SI).

    Attributes
    ----------
    kind : str
        ``"stable"``, ``"hunting"`` or ``"undetermined"``.
    growth_rate : float
        Growth rate of the peak envelope over the later half of the peaks, 1/s (NaN when
        undetermined).
    amplitude : float
        Mean peak over the last quarter of the run, m.
    first_amplitude : float
        First peak, m.
    n_peaks : int
        Peaks of ``|y|`` found.
    reason : str
        Why this kind, in words.
    """

    kind: str
    growth_rate: float
    amplitude: float
    first_amplitude: float
    n_peaks: int
    reason: str = ""

    def line(self) -> str:
        return (f"{self.kind}: growth rate {format_rate(self.growth_rate)}, final amplitude "
                f"{self.amplitude * 1e3:.3g} mm (first peak {self.first_amplitude * 1e3:.3g} mm, "
                f"{self.n_peaks} peaks){'; ' + self.reason if self.reason else ''}")


def classify(t: np.ndarray, y: np.ndarray, growth_tol: float = 0.0,
             floor: float = 1e-3) -> Summary:
    """Stable, hunting or undetermined from a lateral-displacement history (see module doc).

    Parameters
    ----------
    t, y : ndarray, shape (n,)
        Times (s) and lateral shift (m), evenly sampled.
    growth_tol : float
        Growth rate above which a run hunts, 1/s (default 0).
    floor : float
        Relative amplitude below which a run is stable whatever its fitted rate.
    """
    t = np.asarray(t, float)
    ay = np.abs(np.asarray(y, float))
    pk, _ = find_peaks(ay)
    top = float(ay.max(initial=0.0))
    if pk.size < MIN_PEAKS:
        dur = float(t[-1] - t[0]) if t.size else 0.0
        return Summary("undetermined", math.nan, float(ay[-1]) if ay.size else 0.0, top,
                       int(pk.size), f"{pk.size} peaks in {dur:.3g} s: too short to tell "
                       f"(needs {MIN_PEAKS}, two periods in the fit window)")
    tp, ap = t[pk], ay[pk]
    half = tp >= tp[0] + 0.5 * (tp[-1] - tp[0])
    half[-(MIN_PEAKS // 2):] = True
    slope = float(np.polyfit(tp[half], np.log(np.maximum(ap[half], 1e-300)), 1)[0])
    last = tp >= t[0] + 0.75 * (t[-1] - t[0])
    amp = float(ap[last].mean()) if last.any() else float(ap[-1])
    first = float(ap[0])
    if amp <= floor * first:
        return Summary("stable", slope, amp, first, int(pk.size), "decayed")
    hunting = slope > growth_tol or amp >= first
    return Summary("hunting" if hunting else "stable", slope, amp, first, int(pk.size))
