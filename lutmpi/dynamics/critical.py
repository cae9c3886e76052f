"""Critical speed of the free wheelset: nonlinear bisection and the classical linear model.

Nonlinear: bisection on V with :func:`lutmpi.dynamics.simulate.simulate`; a speed is "hunting"
when the oscillation started by a small lateral velocity persists or grows (see
:func:`lutmpi.dynamics.stability.classify`, the rule simulate uses too).

Linear (the cross-check): the classical free-wheelset model in (y, yaw) (Wickens; Garg &
Dukkipati §8) with its coefficients taken from the same contact provider at the centred pose:

    m y'' = -2 f22 (k_r y'/V - yaw) - f23 (2 yaw'/V + S' y) - k_gy y
    I_zz yaw'' = -2 f11 b (b yaw'/V + lam_e y / r0) + 2 f23 (k_r y'/V - yaw)
                 - f33 (2 yaw'/V + S' y) - k_gyaw yaw - I_yy (V/r0) rho y'

``lam_e`` equivalent conicity at amplitude A (first harmonic of Δr(A sin θ)); ``k_gy`` lateral
gravitational stiffness (first harmonic of the normal forces' lateral resultant, creep off);
``k_gyaw`` the same in yaw; ``kappa`` (:attr:`LinearParameters.transfer`) the load transfer
that a lateral creep force causes through the roll balance (it multiplies the lateral creep
terms; 1.16 for a 1:5 cone, 1.005 for S1002 centred); ``S'`` slope of the summed static spin
creepage of the two contacts (the cone angle seen by the spin); ``k_spin`` the lateral stiffness
of the static spin-creep forces ``-f23 phi`` (it contains ``f23 S'`` and the growth of
f23 ~ N with the load transferred by the offset), which replaces ``f23 S' y`` in the lateral
equation;
``rho = d roll / dy``, ``k_r = 1 + r0 rho`` (the roll rate
moves the contact points laterally); f11 .. f33 Kalker's coefficients times G c^n on the centred
Hertz ellipses under the static loads. The spin degree of freedom is left out (it only carries the
symmetric longitudinal creep).
"""

from __future__ import annotations

import logging
import math
from dataclasses import asdict, dataclass
from types import SimpleNamespace

import numpy as np
from scipy.optimize import brentq, root

from lutmpi.dynamics.contact_provider import (
    GEOMETRY_OK,
    GEOMETRY_STATUS,
    ContactGeometry,
    ContactProvider,
)
from lutmpi.dynamics.simulate import classify, simulate
from lutmpi.dynamics.wheelset import WheelsetParams, contact_forces, kalker_fast, wheelset_rhs
from lutmpi.errors import TableError

log = logging.getLogger(__name__)

#: yaw step of the yaw gravitational stiffness in :func:`linear_parameters`, rad
LINEAR_YAW_STEP = 1e-3
#: yaw step of the Jacobian's yaw column in :func:`rhs_jacobian`, rad
JACOBIAN_YAW_STEP = 1e-5
#: output step of the bisection's runs, s
NONLINEAR_DT_OUT = 0.01
#: |Δr| below this counts as pure rolling, m (:func:`rolling_offset`)
PURE_ROLLING_TOL = 1e-9


def _table_range(provider: object) -> str:
    """`` (table: y in [..] mm, yaw in [..] rad)`` for a provider with ``bounds``, else ``""``."""
    bounds = getattr(provider, "bounds", None)
    if bounds is None:
        return ""
    y0, y1, a0, a1 = bounds
    return (f" (table: y in [{y0 * 1e3:.4f}, {y1 * 1e3:.4f}] mm, yaw in [{a0:.4f}, {a1:.4f}] "
            "rad)")


def check_linear_range(provider: ContactProvider, amplitude: float, centre: float = 0.0,
                       h_yaw: float = LINEAR_YAW_STEP, name: str = "amplitude") -> None:
    """Raise unless every pose the linear analyses evaluate lies inside the provider's table.

    :func:`linear_parameters` and :func:`rhs_jacobian` read the geometry at lateral shifts up to
    ``centre ± amplitude`` and at yaws ``± h_yaw``; a table answers a pose beyond its edge with
    the edge's geometry (status ``OUT_OF_TABLE``), which would make a number from geometry that
    is not there. Providers without ``bounds`` (on-line, coned) pass.

    Parameters
    ----------
    provider : ContactProvider
    amplitude : float
        Linearisation amplitude, m (> 0).
    centre : float
        Pure-rolling offset about which the model is linearised, m.
    h_yaw : float
        Largest yaw step of the analyses, rad.
    name : str
        How the amplitude is named in the message (a command's option).

    Raises
    ------
    TableError
        The table is 1-D in yaw (no yaw derivatives: the yaw stiffness and the Jacobian's yaw
        terms need a yaw range), or ``centre ± amplitude`` or ``± h_yaw`` lies outside it.
    """
    bounds = getattr(provider, "bounds", None)
    if bounds is None:
        return
    y0, y1, a0, a1 = bounds
    if not a1 > a0:
        raise TableError(
            "the linear analysis needs the yaw derivatives of the contact geometry (the yaw "
            f"gravitational stiffness, the yaw terms of the Jacobian) at yaw ±{h_yaw:g} rad; the "
            f"table is 1-D (yaw in [{a0:.4f}, {a1:.4f}] rad): build it with a yaw range, e.g. "
            "[grid] yaw_rad = [-0.01, 0.01, 5]")
    if -h_yaw < a0 or h_yaw > a1:
        raise TableError(f"the linear analysis reads the contact geometry at yaw ±{h_yaw:g} rad, "
                         f"outside the table's yaw range [{a0:.4f}, {a1:.4f}] rad")
    lo, hi = centre - amplitude, centre + amplitude
    if lo < y0 or hi > y1:
        most = min(centre - y0, y1 - centre)
        raise TableError(
            f"{name} {amplitude:g} m ({amplitude * 1e3:g} mm): the linearisation about "
            f"y = {centre * 1e3:.4f} mm reads the contact geometry over y in "
            f"[{lo * 1e3:.4f}, {hi * 1e3:.4f}] mm, beyond "
            f"the table's y range [{y0 * 1e3:.4f}, {y1 * 1e3:.4f}] mm: give an amplitude of at "
            f"most {max(most, 0.0) * 1e3:.4f} mm, or build a table that spans it")


def _why(g: ContactGeometry) -> str:
    """Why a geometry is not the pose's: its status, or no result of the pose solve."""
    if g.status != GEOMETRY_OK:
        return GEOMETRY_STATUS.get(g.status, f"status {g.status}")
    return "no contact geometry (the pose solve failed)"


def _linearisation(provider: ContactProvider, amplitude: float, centre: float | None,
                   h_yaw: float, what: str) -> tuple[float, _Checked]:
    """The common start of the linear analyses: the amplitude checked, the centre (the
    rolling offset unless given, m), every pose they read checked to lie in the table
    (:func:`check_linear_range`), and the provider wrapped so each lookup is checked too."""
    _positive_amplitude(amplitude)
    yc = rolling_offset(provider) if centre is None else float(centre)
    check_linear_range(provider, amplitude, yc, h_yaw)
    return yc, _Checked(provider, f"{what} (amplitude {amplitude * 1e3:g} mm)")


class _Checked:
    """A provider whose every answer must be real geometry: a pose outside the table or on a
    failed point (``status``), or a pose solve without a result (NaN ``z_g``), raises
    :class:`TableError` naming the pose and what needed it, instead of a number made from the
    edge's or the last good point's geometry."""

    def __init__(self, provider: ContactProvider, what: str) -> None:
        self.provider, self.what = provider, what

    def evaluate(self, y: float, yaw: float) -> ContactGeometry:
        g = self.provider.evaluate(y, yaw)
        if g.status != GEOMETRY_OK or not math.isfinite(g.z_g):
            raise TableError(f"{self.what} needs the contact geometry at y = {y * 1e3:.4f} mm, "
                             f"yaw = {yaw:.6f} rad: {_why(g)}{_table_range(self.provider)}")
        return g

    def __getattr__(self, name: str) -> object:
        return getattr(self.provider, name)


@dataclass(frozen=True)
class LinearParameters:
    """Coefficients of the linear free-wheelset model (SI)."""

    r0: float            # m, centred rolling radius
    b: float             # m, half the lateral distance of the contact points
    lam_e: float         # equivalent conicity at ``amplitude``
    amplitude: float     # m
    k_gy: float          # N/m, lateral gravitational stiffness
    k_gyaw: float        # N m/rad, yaw gravitational stiffness
    spin_slope: float    # 1/m^2, d(phi_L + phi_R)/dy (static)
    rho: float           # rad/m, d roll / dy
    f11: float           # N
    f22: float           # N
    f23: float           # N m
    f33: float           # N m^2
    load: float          # N, static wheel load
    delta0: float = 0.0  # rad, centred contact angle
    k_spin: float = 0.0  # N/m, lateral stiffness of the static spin-creep forces (load-dependent)

    @property
    def transfer(self) -> float:
        """Load-transfer factor kappa on the lateral creep force: a lateral creep force F (per
        wheel, along the contact tangent) also rolls the wheelset about x by (b s + r0 c) F, which
        moves Delta Q = that / (2 (b c - r0 s)) of load between the wheels, whose normals lean by
        the contact angle: the net lateral force is kappa F, kappa = c + s (b s + r0 c) /
        (b c - r0 s), with s, c = sin, cos of delta0 (1 for flat contacts)."""
        s, c = math.sin(self.delta0), math.cos(self.delta0)
        return c + s * (self.b * s + self.r0 * c) / (self.b * c - self.r0 * s)


def _harmonic(fun, amplitude: float, n: int = 32) -> float:
    """First sine harmonic c1 of fun(A sin θ), over one period (n samples)."""
    th = (np.arange(n) + 0.5) * 2.0 * math.pi / n
    vals = np.array([fun(amplitude * math.sin(x)) for x in th])
    return float(2.0 / n * np.sum(vals * np.sin(th)))


def rolling_offset(provider: ContactProvider, reach: float = 5e-3) -> float:
    """Lateral offset y_e (m) of pure rolling, where the rolling-radius difference vanishes.

    0 for a wheelset whose two wheels have the same radius at the centred pose; a wheelset with
    two different wheels (diameters or wear) runs offset to where Δr(y_e) = 0, and its linear
    model is about that pose. The root nearest to 0 within ``reach``; 0 when there is none. On a
    table the scan on each side ends at the table's edge or a failed point (the geometry there is
    not the pose's), and the centred pose itself must be real geometry (:class:`TableError`)."""
    checked = _Checked(provider, "the rolling offset (the pose where Δr = 0)")

    def dr(y: float) -> float:
        g = checked.evaluate(y, 0.0)
        return float(g.rolling_radius[0, 0] - g.rolling_radius[1, 0])

    d0 = dr(0.0)
    if abs(d0) < PURE_ROLLING_TOL:
        return 0.0
    step = 1e-4
    prev = {1.0: (0.0, d0), -1.0: (0.0, d0)}
    ends: list[str] = []                    # where the scan met the table's edge or a failed point
    for k in range(1, int(reach / step) + 1):
        for sign in (1.0, -1.0):             # outward on both sides: the nearest root first
            if sign not in prev:
                continue
            y = sign * k * step
            g = provider.evaluate(y, 0.0)
            if g.status != GEOMETRY_OK or not math.isfinite(g.z_g):
                # the scan on this side ends here: beyond, the table answers with the edge's
                # or the last good point's geometry, and a root there would be made up
                ends.append(f"y = {y * 1e3:.1f} mm ({_why(g)})")
                del prev[sign]
                continue
            v = float(g.rolling_radius[0, 0] - g.rolling_radius[1, 0])
            y0, v0 = prev[sign]
            if v == 0.0 or (v > 0.0) != (v0 > 0.0):
                ye = float(brentq(dr, min(y0, y), max(y0, y), xtol=1e-9))
                if abs(dr(ye + 1e-6) - dr(ye - 1e-6)) > 1e-5:
                    log.warning("Δr changes sign at a contact jump (y = %.3f mm): no smooth "
                                "rolling equilibrium, the wheelset runs on the jump (two-point "
                                "contact); the linear models there are only indicative", ye * 1e3)
                return ye
            prev[sign] = (y, v)
        if not prev:
            break
    log.warning("no pure-rolling offset within %.1f mm%s (Δr(0) = %.3f mm): no steady rolling "
                "pose; a linear model taken anyway is about the centred pose, which is none",
                reach * 1e3,
                f" (the scan stopped at {', '.join(ends)})" if ends else "", d0 * 1e3)
    return 0.0


def linear_parameters(provider: ContactProvider, params: WheelsetParams,
                      amplitude: float = 1e-3, h_yaw: float = LINEAR_YAW_STEP,
                      centre: float | None = None) -> LinearParameters:
    """Coefficients of the linear model from a contact provider (table, on-line, coned), about
    the pure-rolling pose ``centre`` (m; None: :func:`rolling_offset`, 0 for a symmetric
    wheelset).

    Parameters
    ----------
    provider : ContactProvider
    params : WheelsetParams
    amplitude : float
        Amplitude A of the harmonic linearisation of Δr(y) and the gravitational force, m.
    h_yaw : float
        Yaw step for the yaw gravitational stiffness, rad.

    Raises
    ------
    TableError
        A pose the model needs lies outside the table or on a failed point
        (:func:`check_linear_range`).
    """
    yc, provider = _linearisation(provider, amplitude, centre, h_yaw, "the linear model")
    g0 = provider.evaluate(yc, 0.0)
    r0 = float(np.mean(g0.rolling_radius[:, 0]))
    b = 0.5 * float(g0.wheel_point[0, 0, 1] - g0.wheel_point[1, 0, 1])
    no_creep = params.with_(mu=0.0, saturation="cutoff")
    speed = 10.0

    def dr(y: float) -> float:
        g = provider.evaluate(yc + y, 0.0)
        return float(g.rolling_radius[0, 0] - g.rolling_radius[1, 0])

    def fy(y: float) -> float:
        g = provider.evaluate(yc + y, 0.0)
        x = np.array([yc + y, 0, 0, 0, 0.0])
        return float(contact_forces(x, speed, no_creep, g).force[1])

    def spin(y: float) -> float:
        g = provider.evaluate(yc + y, 0.0)
        c = contact_forces(np.array([yc + y, 0, 0, 0, 0.0]), speed, no_creep, g).creepage
        return float(np.sum(np.where(g.active, c[..., 2], 0.0)))

    def mz(yaw: float) -> float:
        g = provider.evaluate(yc, yaw)
        x = np.array([yc, yaw, 0, 0, 0.0])
        return float(contact_forces(x, speed, no_creep, g).moment[2])

    lam_e = _harmonic(dr, amplitude) / (2.0 * amplitude)
    k_gy = -_harmonic(fy, amplitude) / amplitude
    s_slope = _harmonic(spin, amplitude) / amplitude
    k_gyaw = -(mz(h_yaw) - mz(-h_yaw)) / (2.0 * h_yaw)

    def fy_creep(y: float) -> float:
        # static creep forces at rest rates: the spin creep of the inclined contacts, whose
        # coefficient f23 ~ N grows with the load transferred by the offset
        g = provider.evaluate(yc + y, 0.0)
        x = np.array([yc + y, 0, 0, 0, 0.0])
        # the same creep law as the nonlinear model: the saturation already bends the static
        # spin force (Shen-Hedrick-Elkins: slope 1 - 2 beta/3), which is 2.5 % of k_spin here
        return float(contact_forces(x, speed, params, g).force[1]) - fy(y)

    k_spin = -_harmonic(fy_creep, amplitude) / amplitude
    f0 = contact_forces(np.array([yc, 0, 0, 0, 0.0]), speed, no_creep, g0)
    load = float(f0.normal_force[0, 0])
    a_, b_ = (np.array([f0.semi_axes[0, 0, i]]) for i in (0, 1))
    C11, C22, C23, C33 = (float(c[0]) for c in kalker_fast(a_, b_, params.poisson))
    c2 = float(a_[0] * b_[0])
    G = params.shear
    return LinearParameters(r0=r0, b=b, lam_e=lam_e, amplitude=amplitude, k_gy=k_gy,
                            k_gyaw=k_gyaw, spin_slope=s_slope, rho=g0.droll_dy,
                            f11=G * c2 * C11, f22=G * c2 * C22, f23=G * c2**1.5 * C23,
                            f33=G * c2**2 * C33, load=load,
                            delta0=float(g0.contact_angle[0, 0]), k_spin=k_spin)


def _positive_amplitude(amplitude: float) -> None:
    if not (math.isfinite(amplitude) and amplitude > 0.0):
        raise ValueError(f"amplitude: expected a finite number > 0 (m), got {amplitude!r}")


def state_matrix(lp: LinearParameters, params: WheelsetParams, speed: float) -> np.ndarray:
    """First-order matrix A of ``d/dt (y, yaw, y', yaw') = A (y, yaw, y', yaw')``."""
    V, m, I = speed, params.mass, params.I_zz  # noqa: E741
    kr = 1.0 + lp.r0 * lp.rho
    kap = lp.transfer
    omega = V / lp.r0
    gyro = params.I_yy * omega * lp.rho if params.gyroscopic else 0.0
    # the gyroscopic roll moment -I_yy Omega yaw' shifts load too (see ``transfer``)
    s, c = math.sin(lp.delta0), math.cos(lp.delta0)
    gyro_lat = (s * params.I_yy * omega / (lp.b * c - lp.r0 * s)) if params.gyroscopic else 0.0
    # rows: forces (lateral) and moments (yaw) on [y, yaw, y', yaw']
    Fy = np.array([-kap * lp.k_spin - lp.k_gy, 2 * kap * lp.f22,
                   -2 * kap * lp.f22 * kr / V, -2 * kap * lp.f23 / V + gyro_lat])
    Mz = np.array([-2 * lp.f11 * lp.b * lp.lam_e / lp.r0 - lp.f33 * lp.spin_slope,
                   -2 * lp.f23 - lp.k_gyaw,
                   2 * lp.f23 * kr / V - gyro,
                   -2 * lp.f11 * lp.b**2 / V - 2 * lp.f33 / V])
    A = np.zeros((4, 4))
    A[0, 2] = A[1, 3] = 1.0
    A[2], A[3] = Fy / m, Mz / I
    return A


def max_real_part(lp: LinearParameters, params: WheelsetParams, speed: float) -> float:
    """Largest real part of the eigenvalues at speed V (1/s)."""
    return float(np.max(np.linalg.eigvals(state_matrix(lp, params, speed)).real))


@dataclass(frozen=True)
class LinearCritical:
    """Linear critical speed (m/s; 0 = unstable at every speed scanned, inf = never unstable),
    the hunting frequency there (Hz) and the coefficients used."""

    speed: float
    frequency: float
    parameters: LinearParameters

    def as_dict(self) -> dict:
        return {"speed": self.speed, "frequency": self.frequency, **asdict(self.parameters)}


def linear_critical_speed(lp: LinearParameters, params: WheelsetParams, v_min: float = 0.5,
                          v_max: float = 200.0, n_scan: int = 200) -> LinearCritical:
    """Lowest V in [v_min, v_max] where an eigenvalue crosses into the right half-plane."""
    vs = np.geomspace(v_min, v_max, n_scan)
    re = np.array([max_real_part(lp, params, v) for v in vs])
    if re[0] > 0:
        return LinearCritical(0.0, float("nan"), lp)
    up = np.nonzero(re > 0)[0]
    if up.size == 0:
        return LinearCritical(math.inf, float("nan"), lp)
    k = up[0]
    vc = brentq(lambda v: max_real_part(lp, params, v), vs[k - 1], vs[k], xtol=1e-6)
    ev = np.linalg.eigvals(state_matrix(lp, params, vc))
    freq = float(abs(ev[np.argmax(ev.real)].imag) / (2 * math.pi))
    return LinearCritical(float(vc), freq, lp)


_NO_STEADY: set[float] = set()   # rolling offsets already warned about by rhs_jacobian


def rhs_jacobian(provider: ContactProvider, params: WheelsetParams, speed: float,
                 amplitude: float = 3.5e-4, centre: float | None = None) -> np.ndarray:
    """Jacobian (5 x 5) of :func:`lutmpi.dynamics.wheelset.wheelset_rhs` at centred rolling.

    The linearisation of the nonlinear model itself (same contact forces, creep law with its
    saturation, spin degree of freedom, gyroscopic terms), by central differences: the y step
    is ``amplitude`` (a secant over the oscillation, as the harmonic linearisation; the table is
    piecewise linear in y), the others small. The linearisation is about the steady rolling
    state: the spin perturbation at its equilibrium (the rolling radius differs from the
    nominal r0) and, for a wheelset with two different wheels, the lateral offset where Δr
    vanishes (``centre``, m; None: :func:`rolling_offset`, 0 for a symmetric wheelset).

    Raises
    ------
    TableError
        A pose the differences need lies outside the table or on a failed point
        (:func:`check_linear_range`).
    """
    yc, checked = _linearisation(provider, amplitude, centre, JACOBIAN_YAW_STEP, "the Jacobian")

    def f(x: np.ndarray) -> np.ndarray:
        return wheelset_rhs(0.0, x, speed, params, checked)

    spin_eq = brentq(lambda s: f(np.array([yc, 0.0, 0.0, 0.0, s]))[4], -5.0, 5.0, xtol=1e-12)
    x0 = np.array([yc, 0.0, 0.0, 0.0, spin_eq])
    if yc != 0.0:   # two different wheels: the steady state also has a small yaw (the lateral
        # gravitational force at the offset is balanced by creep); a symmetric one is centred
        scale = np.array([1e-3, 1e-3, 1.0])
        try:
            sol = root(lambda q: f(np.array([*(q[:2] * scale[:2]), 0.0, 0.0, q[2]]))[2:],
                       np.array([yc / scale[0], 0.0, spin_eq]), method="hybr")
        except TableError as exc:          # the search wandered off the table: no steady state
            sol = SimpleNamespace(success=False, message=str(exc))
        if sol.success:
            q = sol.x * scale
            x0 = np.array([q[0], q[1], 0.0, 0.0, q[2]])
        elif yc not in _NO_STEADY:   # once per offset, not once per speed of a scan
            _NO_STEADY.add(yc)
            log.warning("no steady rolling state near y = %.3f mm (%s): Jacobian about the "
                        "pure-rolling offset", yc * 1e3, sol.message)
    steps = np.array([amplitude, JACOBIAN_YAW_STEP, 1e-4, 1e-5, 1e-3])
    J = np.zeros((5, 5))
    for k, h in enumerate(steps):
        e = np.zeros(5)
        e[k] = h
        J[:, k] = (f(x0 + e) - f(x0 - e)) / (2.0 * h)
    return J


def jacobian_critical_speed(provider: ContactProvider, params: WheelsetParams,
                            amplitude: float = 3.5e-4, v_min: float = 1.0,
                            v_max: float = 100.0, n_scan: int = 25,
                            centre: float | None = None) -> tuple[float, float]:
    """Lowest V where an eigenvalue of :func:`rhs_jacobian` crosses into the right half-plane;
    returns (V m/s, frequency Hz); (0, nan) unstable everywhere, (inf, nan) never. The rolling
    offset (``centre``, m; None: :func:`rolling_offset`) is found once for every speed."""
    yc = rolling_offset(provider) if centre is None else float(centre)

    def sigma(v: float) -> complex:
        ev = np.linalg.eigvals(rhs_jacobian(provider, params, v, amplitude, centre=yc))
        return ev[np.argmax(ev.real)]

    vs = np.geomspace(v_min, v_max, n_scan)
    re = np.array([sigma(v).real for v in vs])
    if re[0] > 0:
        return 0.0, float("nan")
    up = np.nonzero(re > 0)[0]
    if up.size == 0:
        return math.inf, float("nan")
    vc = brentq(lambda v: sigma(v).real, vs[up[0] - 1], vs[up[0]], xtol=1e-4)
    return float(vc), float(abs(sigma(vc).imag) / (2 * math.pi))


@dataclass(frozen=True)
class NonlinearCritical:
    """Bisection result: the critical speed (m/s) bracketed by [stable, hunting] speeds."""

    speed: float
    stable_below: float
    hunting_above: float
    runs: tuple[tuple[float, str, float], ...]   # (V, kind, growth rate) of every run
    converged: bool
    message: str = ""                            # why not converged ("" when converged)


def nonlinear_critical_speed(provider: ContactProvider, params: WheelsetParams, v_lo: float,
                             v_hi: float, *, rel_tol: float = 0.01, vy0: float = 0.1,
                             duration: float = 30.0, rtol: float = 1e-9,
                             **sim_kw) -> NonlinearCritical:
    """Bisection on V between a stable ``v_lo`` and a hunting ``v_hi``.

    A run is "hunting" when the fitted growth rate of its peak envelope is positive (no
    tolerance band: near the boundary of a free wheelset the rates are ~1e-4 1/s). The
    absolute tolerances scale with ``vy0`` and ``rtol`` is tight, because an integrator's
    error damps or excites the motion at that level (with solve_ivp's defaults a 4 um
    oscillation came out 1e-3 1/s more damped). The paper's 0.1 m/s gives a ~0.35 mm
    oscillation, still inside the tread region where the geometry is nearly linear.

    A run that stops (leaves the table, reaches a failed point, the integrator fails) has no
    verdict (kind ``"stopped"``): the bisection ends there, not converged, and ``message`` says
    why, as it does for a first bracket that is not [stable, hunting] and an undetermined run.

    Raises
    ------
    ValueError
        ``v_lo``/``v_hi`` not finite with 0 < v_lo < v_hi, ``rel_tol`` not in (0, 1), ``vy0``
        zero or not finite (nothing would start the oscillation), and what
        :func:`lutmpi.dynamics.simulate.check_run_inputs` refuses.
    """
    if not (math.isfinite(v_lo) and math.isfinite(v_hi) and 0.0 < v_lo < v_hi):
        raise ValueError(f"bracket: expected finite speeds 0 < v_lo < v_hi, got {v_lo!r}, "
                         f"{v_hi!r}")
    if not (math.isfinite(rel_tol) and 0.0 < rel_tol < 1.0):
        raise ValueError(f"rel_tol: expected a number in (0, 1), got {rel_tol!r}")
    if not (math.isfinite(vy0) and vy0 != 0.0):
        raise ValueError(f"vy0: expected a finite, non-zero lateral velocity (m/s), got {vy0!r}")
    runs: list[tuple[float, str, float]] = []
    atol = (abs(vy0) / 0.1) * np.array([1e-11, 1e-11, 1e-10, 1e-10, 1e-8])
    stops: list[str] = []

    def kind(v: float) -> str:
        r = simulate(provider, params, v, duration, vy0=vy0, events=False, rtol=rtol,
                     atol=atol, dt_out=NONLINEAR_DT_OUT, **sim_kw)
        if not r.success:         # a truncated record has no verdict of its own
            runs.append((v, "stopped", float("nan")))
            stops.append(f"the run at {v:.4g} m/s stopped: {r.message}")
            log.info("V = %.4g m/s: stopped: %s", v, r.message)
            return "stopped"
        s = r.summary if r.summary is not None else classify(r.t, r.y)   # the run's own verdict
        runs.append((v, s.kind, s.growth_rate))
        log.info("V = %.4g m/s: %s", v, s.line())
        return s.kind

    def failed(lo: float, hi: float, why: str) -> NonlinearCritical:
        return NonlinearCritical(float("nan"), lo, hi, tuple(runs), False,
                                 "; ".join([why, *stops]))

    lo_kind, hi_kind = kind(v_lo), kind(v_hi)
    if lo_kind != "stable" or hi_kind != "hunting":
        return failed(v_lo, v_hi, f"the bracket needs a stable run at {v_lo:.4g} m/s and a "
                                  f"hunting one at {v_hi:.4g} m/s; got {lo_kind} and {hi_kind}"
                                  + _too_short((lo_kind, hi_kind), duration))
    lo, hi = v_lo, v_hi
    while (hi - lo) > rel_tol * hi:
        mid = 0.5 * (lo + hi)
        verdict = kind(mid)
        if verdict in ("undetermined", "stopped"):   # no verdict: stop with the bracket so far
            return failed(lo, hi, f"the run at {mid:.4g} m/s is {verdict}"
                                  + _too_short((verdict,), duration))
        if verdict == "stable":
            lo = mid
        else:
            hi = mid
    return NonlinearCritical(0.5 * (lo + hi), lo, hi, tuple(runs), True)


def _too_short(kinds: tuple[str, ...], duration: float) -> str:
    """A hint where a run was undetermined (too few peaks in ``duration`` s)."""
    if "undetermined" in kinds:
        return (f" (undetermined: too few oscillation peaks in {duration:g} s to tell stable "
                "from hunting; run longer)")
    return ""


__all__ = ["LinearParameters", "linear_parameters", "check_linear_range", "LINEAR_YAW_STEP",
           "JACOBIAN_YAW_STEP", "NONLINEAR_DT_OUT", "state_matrix", "max_real_part",
           "LinearCritical", "linear_critical_speed", "NonlinearCritical",
           "nonlinear_critical_speed", "rhs_jacobian", "jacobian_critical_speed"]
