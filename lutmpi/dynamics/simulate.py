"""Time integration of the wheelset (solve_ivp with events) and the results as data.

The system is stiff: the lateral creep damping ``2 f22 / (m V)`` (~500 1/s) and the spin mode
``2 f11 r0^2 / (I_yy V)`` (~1000 1/s) are two to three orders faster than hunting (1-5 Hz).
The default is LSODA (switches to BDF when stiff, Jacobian by differences of 5 states); Radau
and BDF work too, an explicit method (RK45) needs ~1 ms steps.

Events (non-terminal, times recorded): ``flange`` -- the largest contact angle crosses
``flange_threshold``; ``double_contact`` -- a wheel gains a second contact; ``nadal`` -- a wheel's
Y/Q crosses the Nadal limit ``(tan g - mu) / (1 + mu tan g)`` for the flange angle ``g``.

On a table (a provider with ``piece`` and ``bounds``, :class:`TableProvider`), three more, terminal:

* ``jump`` -- the wheelset crosses a located contact jump (the table's answer changes side). The
  crossing is located as a state event and the integration restarts there, so no step ever
  spans a jump (the contact forces are discontinuous across it). Times recorded.
* ``left_table`` -- the pose reaches the edge of the table: the run stops there with a non-zero
  status and a message naming the time and the pose (a table is never extrapolated or clipped).
* ``failed_point`` -- the pose reaches a table point whose solve did not converge: same.
"""

from __future__ import annotations

import logging
import math
import time
from dataclasses import dataclass, field
from types import SimpleNamespace
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from lutmpi.dynamics.contact_provider import (
    FAILED_POINT,
    GEOMETRY_OK,
    GEOMETRY_STATUS,
    ContactGeometry,
    ContactProvider,
)
from lutmpi.dynamics.stability import Summary, classify  # noqa: F401 (the one rule)
from lutmpi.dynamics.wheelset import (
    STATE_NAMES,
    ContactForces,
    WheelsetParams,
    accelerations,
    contact_forces,
)

log = logging.getLogger(__name__)


def nadal_limit(flange_angle: float, mu: float) -> float:
    """Nadal's derailment limit Y/Q = (tan g - mu) / (1 + mu tan g) for flange angle g (rad)."""
    t = math.tan(flange_angle)
    return (t - mu) / (1.0 + mu * t)


class _Memo:
    """Remembers the last geometry: solve_ivp's events and rhs often ask for the same pose."""

    def __init__(self, provider: ContactProvider) -> None:
        self.provider = provider
        self.key: tuple[float, float] | None = None
        self.geom: ContactGeometry | None = None

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        key = (float(y), float(yaw))
        if key != self.key:
            self.geom = self.provider.evaluate(*key)
            self.key = key
        return self.geom  # type: ignore[return-value]


@dataclass
class SimulationResult:
    """Time histories of one run (SI, track frame) and how the integration went.

    Arrays have a leading time axis of length n; per-contact arrays are (n, 2 sides, 2 slots).
    """

    t: np.ndarray
    state: np.ndarray                 # (n, 5)  y, yaw, vy, vyaw, spin
    speed: float
    roll: np.ndarray                  # (n,)
    z_g: np.ndarray                   # (n,)
    normal_force: np.ndarray          # (n, 2, 2) N
    tangential: np.ndarray            # (n, 2, 2, 3) N, creep force on the wheels
    contact_point: np.ndarray         # (n, 2, 2, 3) m, NaN where no contact
    contact_angle: np.ndarray         # (n, 2, 2) rad, NaN where no contact
    n_contacts: np.ndarray            # (n, 2)
    y_over_q: np.ndarray              # (n, 2)
    lift: np.ndarray                  # (n,) bool
    success: bool
    status: int
    message: str
    nfev: int
    wall_time: float
    provider_calls: int
    flange_angle: float
    nadal: float
    events: dict[str, np.ndarray] = field(default_factory=dict)
    summary: Summary | None = None
    params: WheelsetParams | None = None

    @property
    def y(self) -> np.ndarray:
        return self.state[:, 0]

    @property
    def yaw(self) -> np.ndarray:
        return self.state[:, 1]

    @property
    def lateral_creep_force(self) -> np.ndarray:
        """Lateral (track y) component of the tangential contact force per wheel, N, (n, 2)."""
        return self.tangential[..., 1].sum(axis=2)

    @property
    def max_y_over_q(self) -> float:
        return float(np.max(self.y_over_q)) if self.y_over_q.size else float("nan")

    @property
    def sim_per_wall(self) -> float:
        """Simulated seconds per wall-clock second."""
        return float((self.t[-1] - self.t[0]) / self.wall_time) if self.wall_time > 0 else math.inf

    def summary_line(self) -> str:
        s = self.summary.line() if self.summary else "no summary"
        return (f"V = {self.speed:.2f} m/s: {s}; max Y/Q {self.max_y_over_q:.3f} "
                f"(Nadal limit {self.nadal:.3f} at {math.degrees(self.flange_angle):.1f} deg, "
                f"mu = {self.params.mu if self.params else float('nan')}); "
                f"flange events {self.events.get('flange', np.empty(0)).size}; "
                + (f"{n} windows sliding along a contact jump; " if (n := self.events.get(
                    "sliding", np.empty(0)).size) else "")
                + f"{self.sim_per_wall:.2f} sim-s per wall-s")


def _events(memo: _Memo, speed: float, params: WheelsetParams, threshold: float,
            nadal: float) -> list[Any]:
    def flange(t: float, x: np.ndarray) -> float:
        g = memo.evaluate(x[0], x[1])
        return float(np.max(np.where(g.active, g.contact_angle, -np.inf))) - threshold

    def double_contact(t: float, x: np.ndarray) -> float:
        return float(np.max(memo.evaluate(x[0], x[1]).n_contacts)) - 1.5

    def nadal_event(t: float, x: np.ndarray) -> float:
        g = memo.evaluate(x[0], x[1])
        return float(np.max(contact_forces(x, speed, params, g).y_over_q)) - nadal

    return [flange, double_contact, nadal_event]


EVENT_NAMES = ("flange", "double_contact", "nadal")

#: solve_ivp's method names (``method=`` of :func:`simulate`)
INTEGRATORS = ("LSODA", "BDF", "Radau", "RK45", "RK23", "DOP853")
#: most output samples one run keeps: the histories take ~0.4 kB per sample (2e6 samples: ~0.8
#: GB, 10 000 s at the default 5 ms output step)
MAX_OUTPUT_SAMPLES = 2_000_000


def output_samples(duration: float, dt_out: float) -> int:
    """Number of output samples of a run of ``duration`` s sampled every ``dt_out`` s."""
    return int(math.floor(duration / dt_out + 0.5)) + 1


def check_run_inputs(provider: ContactProvider, duration: float, dt_out: float,
                     method: str) -> None:
    """Raise before any work where a run cannot be made (called by :func:`simulate`).

    Raises
    ------
    ValueError
        ``duration`` or ``dt_out`` not a finite number > 0, more output samples than
        :data:`MAX_OUTPUT_SAMPLES`, an integrator not in :data:`INTEGRATORS`.
    TableError
        A table provider whose y or yaw axis holds one value (a 1-D table): the wheelset moves
        and yaws from its first step, so the run would leave the table at once.
    """
    from lutmpi.errors import TableError

    if method not in INTEGRATORS:
        raise ValueError(f"integrator: expected one of {', '.join(INTEGRATORS)}, got {method!r}")
    for name, value in (("duration", duration), ("dt_out", dt_out)):
        if not (math.isfinite(value) and value > 0.0):
            raise ValueError(f"{name}: expected a finite number > 0 (s), got {value!r}")
    if (n := output_samples(duration, dt_out)) > MAX_OUTPUT_SAMPLES:
        raise ValueError(f"duration: {duration:g} s at an output step of {dt_out:g} s is {n:.3g} "
                         f"samples, more than the {MAX_OUTPUT_SAMPLES} a run keeps in memory "
                         f"(at most {(MAX_OUTPUT_SAMPLES - 1) * dt_out:g} s)")
    bounds = getattr(provider, "bounds", None)
    if bounds is not None:
        y0, y1, a0, a1 = bounds
        if not (y1 > y0 and a1 > a0):
            raise TableError(
                f"the wheelset dynamics needs a table with a y range and a yaw range (the "
                f"wheelset shifts and yaws from its first step); the table is 1-D: y in "
                f"[{y0 * 1e3:.4f}, {y1 * 1e3:.4f}] mm, yaw in [{a0:.4f}, {a1:.4f}] rad. Build "
                f"it with a range on both axes, e.g. [grid] yaw_rad = [-0.01, 0.01, 5]")


#: :attr:`SimulationResult.status` values beyond solve_ivp's (0 done, -1 integration failed)
LEFT_TABLE, ON_FAILED_POINT = 2, 3
STOP_MESSAGES = {LEFT_TABLE: "left the table", ON_FAILED_POINT: "reached a failed table point"}


def simulate(provider: ContactProvider, params: WheelsetParams, speed: float, duration: float,
             *, y0: float = 0.0, yaw0: float = 0.0, vy0: float = 0.1, vyaw0: float = 0.0,
             method: str = "LSODA", rtol: float = 1e-6, atol: np.ndarray | None = None,
             max_step: float = 0.01, dt_out: float = 0.005, flange_threshold: float = 0.35,
             events: bool = True) -> SimulationResult:
    """Integrate the wheelset from the paper's initial condition (lateral velocity ``vy0``).

    Parameters
    ----------
    provider : ContactProvider
    params : WheelsetParams
    speed : float
        Forward speed V, m/s.
    duration : float
        s.
    y0, yaw0, vy0, vyaw0 : float
        Initial state (m, rad, m/s, rad/s); spin starts at pure rolling, V/r0.
    method : str
        solve_ivp method name, one of :data:`INTEGRATORS`.
    rtol, atol, max_step : float
        Integrator tolerances; ``max_step`` (s) keeps the step below a hunting period.
    dt_out : float
        Output sampling, s. Forces are recomputed at the output times.
    flange_threshold : float
        Contact angle marking flange contact, rad.
    events : bool
        Track the flange / double-contact / Nadal events (the table's jump, edge and failed-point
        events are always on).

    Returns
    -------
    SimulationResult
        ``status`` 0 (done), -1 (solve_ivp failed), :data:`LEFT_TABLE` or
        :data:`ON_FAILED_POINT` (stopped; ``message`` names the time and pose). A failed run is
        data.

    Raises
    ------
    ValueError, TableError
        What :func:`check_run_inputs` refuses (no run could be made).
    """
    check_run_inputs(provider, duration, dt_out, method)
    memo = _Memo(provider)
    calls0 = getattr(provider, "calls", 0)
    nadal = nadal_limit(provider.flange_angle, params.mu)
    if atol is None:
        atol = np.array([1e-8, 1e-8, 1e-6, 1e-6, 1e-4])

    def rhs(t: float, x: np.ndarray) -> np.ndarray:
        g = memo.evaluate(x[0], x[1])
        return accelerations(x, speed, params, g, contact_forces(x, speed, params, g))

    t_eval = np.arange(0.0, duration + 0.5 * dt_out, dt_out)
    t_eval = t_eval[t_eval <= duration]
    monitors = _events(memo, speed, params, flange_threshold, nadal) if events else []
    x0 = np.array([y0, yaw0, vy0, vyaw0, 0.0])
    t0 = time.perf_counter()
    sol, stop, crossings = _integrate(rhs, provider, memo, duration, x0, t_eval, monitors,
                                      dict(method=method, rtol=rtol, atol=atol,
                                           max_step=max_step))
    wall = time.perf_counter() - t0
    res = _post(sol, memo, speed, params, wall, provider, calls0, nadal)
    if stop is not None:
        res.success, res.status, res.message = False, stop[0], stop[1]
    if monitors:
        res.events = {name: np.asarray(tt) for name, tt in zip(EVENT_NAMES, sol.t_events,
                                                                 strict=True)}
    if hasattr(provider, "piece"):
        res.events["jump"] = np.asarray(crossings, float)
        res.events["sliding"] = np.asarray([w[0] for w in sol.slides], float)
    res.summary = classify(res.t, res.y) if res.t.size else None
    log.info("%s", res.summary_line())
    return res


class _Joined:
    """The pieces of an integration restarted at events, joined (what _post reads)."""

    def __init__(self, n_monitors: int) -> None:
        self.t: list[np.ndarray] = []
        self.y: list[np.ndarray] = []
        self.t_events: list[list[float]] = [[] for _ in range(n_monitors)]
        # (start, end, length in max_step) of each window sliding along a jump
        self.slides: list[tuple[float, float, float]] = []
        self.nfev = 0
        self.success, self.status, self.message = True, 0, "The solver successfully reached " \
                                                             "the end of the integration interval."

    def add(self, sol: Any, n_monitors: int) -> None:
        self.t.append(np.asarray(sol.t, float).ravel())
        self.y.append(np.asarray(sol.y, float).reshape(len(sol.y) or 5, -1))
        self.nfev += sol.nfev
        for k in range(n_monitors):
            self.t_events[k] += list(sol.t_events[k])
        if sol.status == -1:
            self.success, self.status, self.message = False, -1, sol.message

    def done(self) -> _Joined:
        self.t = np.concatenate(self.t) if self.t else np.empty(0)
        self.y = np.concatenate(self.y, axis=1) if self.y else np.empty((5, 0))
        return self


def _table_events(provider: Any, piece: int) -> list[Any]:
    """Terminal events of a table run: leaving the current side of the jumps (``piece``),
    reaching the table's edge, reaching a failed point."""
    def jump(t: float, x: np.ndarray) -> float:
        # outside the table (piece -1) is the edge event's, not a jump: located at the same
        # crossing, the jump came first in the list and the run restarted "over" it, out of
        # the table, and stopped 0.7 um beyond its edge (an AMD EPYC VM's rounding, 2026-11-28)
        now = provider.piece(x[0], x[1])
        return -0.5 if now < 0 else abs(now - piece) - 0.5

    def edge(t: float, x: np.ndarray) -> float:
        return provider.inside(x[0], x[1])

    def failed(t: float, x: np.ndarray) -> float:
        return -1.0 if provider.status(x[0], x[1]) == FAILED_POINT else 1.0

    for fn, direction in ((jump, 1.0), (edge, -1.0), (failed, -1.0)):
        fn.terminal, fn.direction = True, direction
    return [jump, edge, failed]


def _stop_message(code: int, t: float, x: np.ndarray, provider: Any) -> tuple[int, str]:
    y0, y1, a0, a1 = getattr(provider, "bounds", (np.nan,) * 4)
    return code, (f"{STOP_MESSAGES[code]} at t = {t:.5f} s, pose y = {x[0] * 1e3:.4f} mm, "
                  f"yaw = {x[1]:.6f} rad (table: y in [{y0 * 1e3:.3f}, {y1 * 1e3:.3f}] mm, "
                  f"yaw in [{a0:.4f}, {a1:.4f}] rad)")


def _integrate(rhs: Any, provider: Any, memo: _Memo, duration: float, x0: np.ndarray,
               t_eval: np.ndarray, monitors: list[Any], kw: dict[str, Any]
               ) -> tuple[_Joined, tuple[int, str] | None, list[float]]:
    """solve_ivp, restarted at every jump crossing; stopped at the table's edge or a failed
    point."""
    out = _Joined(len(monitors))
    table = hasattr(provider, "piece")
    t, x, crossings = 0.0, np.asarray(x0, float), []
    while True:
        if table:
            status = provider.status(x[0], x[1])
            if status != GEOMETRY_OK:
                code = ON_FAILED_POINT if status == FAILED_POINT else LEFT_TABLE
                out.t.append(np.array([t]))
                out.y.append(np.asarray(x, float)[:, None])
                return out.done(), _stop_message(code, t, x, provider), crossings
        te = t_eval[(t_eval > t) | ((t_eval == t) & (t == 0.0))]
        if t >= duration:
            return out.done(), None, crossings
        evs = monitors + (_table_events(provider, _piece_ahead(provider, x)) if table
                          else [])
        sol = solve_ivp(rhs, (t, duration), x, t_eval=te, events=evs or None, **kw)
        out.add(sol, len(monitors))
        if sol.status != 1:
            return out.done(), None, crossings
        fired = [k for k in range(len(monitors), len(evs)) if len(sol.t_events[k])]
        k = fired[0]
        t, x = float(sol.t_events[k][-1]), np.asarray(sol.y_events[k][-1], float)
        if k == len(monitors):                       # a jump: restart on its far side
            stalled = bool(crossings) and t <= crossings[-1] + 1e-12
            crossings.append(t)
            x = _over_jump(provider, x)
            if stalled:                  # no progress between two crossings: one step over it
                sol = solve_ivp(rhs, (t, min(t + kw["max_step"] * 1e-3, duration)), x, **kw)
                t, x = float(sol.t[-1]), sol.y[:, -1].copy()
            elif _sliding(crossings):
                # the forces on both sides push the pose onto the jump (a two-point contact
                # holding the wheelset there): restarting at every crossing would take
                # thousands of microsecond pieces. A window without the jump events, the force
                # blended across the jump (_slide): max_step long, twice as long each time the
                # sliding resumes right after a window (a steady state on the jump), at most
                # SLIDE_MAX windows of max_step.
                recent = bool(out.slides) and t - out.slides[-1][1] < SLIDE_RESUME
                n = min(2.0 * out.slides[-1][2], SLIDE_MAX) if recent else 1.0
                start = t
                stops = _table_events(provider, -1)[1:] if table else []
                t, x, code = _slide(rhs, out, t, x, min(t + n * kw["max_step"], duration),
                                    t_eval, monitors, stops, kw)
                out.slides.append((start, t, n))
                if code == -1:
                    return out.done(), None, crossings
                if code:
                    out.t.append(np.array([t]))
                    out.y.append(x[:, None])
                    return out.done(), _stop_message(code, t, x, provider), crossings
            continue
        code = LEFT_TABLE if k == len(monitors) + 1 else ON_FAILED_POINT
        out.t.append(np.array([t]))                  # the run ends at the located stop
        out.y.append(x[:, None])
        return out.done(), _stop_message(code, t, x, provider), crossings


#: crossings closer than this (s) in a row of :data:`SLIDE_COUNT` mean the pose slides along a jump
SLIDE_WINDOW = 2e-3
SLIDE_COUNT = 4
#: sliding that resumes within this (s) of a window's end doubles the next window, up to
#: SLIDE_MAX times max_step
SLIDE_RESUME = 5e-3
SLIDE_MAX = 8.0
#: half width (m) in y of the band over which a pose sliding along a jump blends its two sides
SLIDE_HALF_WIDTH = 5e-5


def _sliding(crossings: list[float]) -> bool:
    """True when the last :data:`SLIDE_COUNT` jump crossings came within :data:`SLIDE_WINDOW`."""
    return len(crossings) >= SLIDE_COUNT and \
        crossings[-1] - crossings[-SLIDE_COUNT] < SLIDE_WINDOW


def _slide(rhs: Any, out: _Joined, t: float, x: np.ndarray, end: float, t_eval: np.ndarray,
           monitors: list[Any], stops: list[Any], kw: dict[str, Any]
           ) -> tuple[float, np.ndarray, int]:
    """Integrate ``[t, end]`` without the jump events (a pose sliding along a jump); the output
    samples in the window go to ``out``. ``stops``: the table's edge and failed-point events.
    Returns the end time and state and 0, -1 (solve_ivp failed) or the stop code of the event
    that ended the window (:data:`LEFT_TABLE`, :data:`ON_FAILED_POINT`).

    On a rigid table the contact geometry, hence the force, jumps at a contact jump; when the
    forces on both sides push the wheelset onto the jump it slides along it (Filippov), and an
    integrator on the discontinuous right-hand side crawls (measured: 0.005 simulated s per wall
    s on two measured wheels). In the window, within ``SLIDE_HALF_WIDTH`` of the jump's ``y``
    (the crossing's), the right-hand side blends linearly the two sides' values at the band's
    edges: continuous, it takes the load from one contact to the other over 0.1 mm of lateral
    motion, the scale over which an elastic two-point contact does; outside the band it is the
    exact one."""
    if end <= t:
        return t, x, 0
    y_j, eps = float(x[0]), SLIDE_HALF_WIDTH

    def smooth(tt: float, xx: np.ndarray) -> np.ndarray:
        d = float(xx[0]) - y_j
        if abs(d) >= eps:
            return rhs(tt, xx)
        lo, hi = np.array(xx, float), np.array(xx, float)
        lo[0], hi[0] = y_j - eps, y_j + eps
        w = 0.5 * (d + eps) / eps
        return (1.0 - w) * rhs(tt, lo) + w * rhs(tt, hi)

    evs = monitors + stops
    win = solve_ivp(smooth, (t, end), x, events=evs or None, dense_output=True, **kw)
    te = t_eval[(t_eval > t) & (t_eval <= float(win.t[-1]))]
    out.add(SimpleNamespace(t=te, y=win.sol(te) if te.size else np.empty((x.size, 0)),
                            nfev=win.nfev, t_events=(win.t_events or [])[:len(monitors)],
                            status=win.status, message=win.message), len(monitors))
    if win.status == -1:
        return float(win.t[-1]), win.y[:, -1].copy(), -1
    if win.status == 1:
        k = next(k for k in range(len(monitors), len(evs)) if len(win.t_events[k]))
        code = LEFT_TABLE if k == len(monitors) else ON_FAILED_POINT
        return float(win.t_events[k][-1]), np.asarray(win.y_events[k][-1], float), code
    return float(win.t[-1]), win.y[:, -1].copy(), 0


def _over_jump(provider: Any, x: np.ndarray) -> np.ndarray:
    """The located crossing moved a nanometre on along its velocity, onto the far side.

    The located state sits within round-off of the jump: the restarted integration would see the
    near side's geometry in its first event values and the far side's in its dense output, and a
    discontinuous monitor (the contact angle) would then give solve_ivp's root bracket the same
    sign at both ends (``brentq``: "f(a) and f(b) must have different signs", seen on an
    asymmetric measured wheelset). 1 nm (or 1 nrad of yaw) is far below the tolerances."""
    rate = max(abs(x[2]), abs(x[3]))
    if rate == 0.0:
        return x
    dt = 1e-9 / rate
    ahead = x.copy()
    ahead[0] += x[2] * dt
    ahead[1] += x[3] * dt
    return ahead if provider.piece(ahead[0], ahead[1]) >= 0 else x


def _piece_ahead(provider: Any, x: np.ndarray) -> int:
    """The side of the jumps the state is heading into: at a located crossing the pose is within
    round-off of the jump, so look a nanometre ahead along the lateral velocity."""
    step = math.copysign(1e-9, x[2]) if x[2] != 0.0 else 0.0
    piece = provider.piece(x[0] + step, x[1])
    return piece if piece >= 0 else provider.piece(x[0], x[1])


def _post(sol: Any, memo: _Memo, speed: float, params: WheelsetParams, wall: float,
          provider: ContactProvider, calls0: int, nadal: float) -> SimulationResult:
    """Forces and geometry at the output times (one evaluation per sample)."""
    t, X = np.asarray(sol.t), np.asarray(sol.y).T
    n = t.size
    roll, zg, lift = np.zeros(n), np.zeros(n), np.zeros(n, bool)
    nf, ca = np.zeros((n, 2, 2)), np.full((n, 2, 2), np.nan)
    tg, cp = np.zeros((n, 2, 2, 3)), np.full((n, 2, 2, 3), np.nan)
    nc, yq = np.zeros((n, 2), int), np.zeros((n, 2))
    calls = getattr(provider, "calls", 0) - calls0
    for i in range(n):
        g = memo.evaluate(X[i, 0], X[i, 1])
        f: ContactForces = contact_forces(X[i], speed, params, g)
        roll[i], zg[i], lift[i] = g.roll, g.z_g, f.lift
        nf[i], tg[i] = f.normal_force, f.tangential
        ca[i] = np.where(g.active, g.contact_angle, np.nan)
        cp[i] = np.where(g.active[..., None], g.wheel_point, np.nan)
        nc[i], yq[i] = g.n_contacts, f.y_over_q
    return SimulationResult(
        t=t, state=X, speed=speed, roll=roll, z_g=zg, normal_force=nf, tangential=tg,
        contact_point=cp, contact_angle=ca, n_contacts=nc, y_over_q=yq, lift=lift,
        success=bool(sol.success), status=int(sol.status), message=str(sol.message),
        nfev=int(sol.nfev), wall_time=wall, provider_calls=int(calls),
        flange_angle=float(provider.flange_angle), nadal=nadal, params=params)


__all__ = ["simulate", "SimulationResult", "Summary", "classify", "nadal_limit", "STATE_NAMES",
           "EVENT_NAMES", "LEFT_TABLE", "ON_FAILED_POINT", "GEOMETRY_STATUS", "INTEGRATORS",
           "MAX_OUTPUT_SAMPLES", "output_samples", "check_run_inputs"]
