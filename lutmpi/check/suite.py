"""The stability suite behind ``lutmpi check``: runs a user's profile pair and grid through the
checks of issue 7 and returns the verdicts as data (a list of :class:`CheckResult`).

Checks (each on a sample of the grid; regions from :mod:`lutmpi.check.regions`):

* ``convergence`` per region -- every sampled pose converges, no NaN in a converged result;
  the contact evaluations (``nit``) per region are reported;
* ``accuracy`` per region -- the mesh method against the semi-analytic reference (not in the
  double-contact region, where the two may sit on different sides of a contact-point jump);
* ``sensitivity k_c`` / ``sensitivity k_el`` -- initial k_c and allowed indentation x10 and /10,
  fictitious springs (k_el and k_rot) x10 and /10: z_g, roll and the contact points must not move
  (the eq. (9) discussion of the paper: the stiffnesses do not move the contact points);
* ``continuity`` -- along grid lines, changes of z_g, roll and contact position between
  neighbouring grid points that the reference does not show (a real contact-point jump, i.e. a
  jump of the reference's contact point or a double-contact end point, explains a jump);
* ``window`` -- windowed against ``full_mesh=True`` solves at yawed flange poses, and no pose
  with the ``window_too_small`` status;
* ``spacing`` -- the contact patch at the allowed indentation spans >= 3 nodes in each mesh
  direction.

Tolerances (:class:`Tolerances`) derive from the lateral mesh spacing ``h`` (the larger of the
wheel and rail lateral spacings): z_g 0.08 h (0.02 mm at the default 0.25 mm mesh, the accuracy
issue 3 demands there), roll 0.08 h / d (d = half the tape-circle distance), contact position 2 h
(a node entering the volume moves a load centre by less than one node spacing; two meshes). The
accuracy against the reference uses the fixed limits of issue 3 (0.02 mm, 2e-5 rad, 0.5 mm).

Pure: no MPI, no files, no printing.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field, replace

import numpy as np

from lutmpi.check.regions import (
    REGIONS,
    ReferenceGrid,
    RefPoint,
    primary_s,
    resolved_gap,
    stratified_sample,
)
from lutmpi.contact.methods import get_method
from lutmpi.equilibrium.result import (
    CONVERGED,
    EQ_FAILED,
    ERROR,
    KC_LIMIT,
    MAX_ITER,
    NO_CONTACT,
    PROFILE_END,
    RIGID_UNRESOLVED,
    SIDES,
    STATUS,
    WINDOW,
    PoseResult,
)
from lutmpi.pose.solve import solve_pose, warm

MM = 1e-3


@dataclass(frozen=True)
class CheckResult:
    """One verdict: ``value`` against ``limit`` (pass when within); ``message`` says what was
    measured and, on failure, what to change."""

    name: str
    region: str
    passed: bool
    value: float
    limit: float
    message: str
    #: False where nothing was measured (no mesh, no window, no pose of the kind, the reference
    #: against itself): shown as ``n/a``, never as a PASS
    measured: bool = True


@dataclass(frozen=True)
class Tolerances:
    """Tolerances of the checks (SI), see the module docstring."""

    z: float
    roll: float
    s: float
    dc: float  # m, gap tolerance of a second contact zone (double-contact region)
    acc_z: float = 0.02 * MM
    acc_roll: float = 2e-5
    acc_s: float = 0.5 * MM
    min_nodes: float = 3.0  # nodes across the contact patch, each mesh direction
    jump_s: float = 4.0 * MM  # smallest reference contact-point change counted as a jump

    @classmethod
    def from_scene(cls, scene) -> Tolerances:
        sd = scene.side("left")  # the mesh spacings are the same on both sides
        h = max(sd.wheel_mesh.h_lat, sd.rail_mesh.h_lat)
        return cls(
            z=0.08 * h,
            roll=0.08 * h / scene.lever,
            s=2.0 * h,
            dc=5.0 * scene.equilibrium.allowed_indentation,
        )


@dataclass(frozen=True)
class CheckOptions:
    """Sizes of the samples. ``fast`` shrinks every sample (for CI)."""

    points: int = 60  # poses of the convergence/accuracy sample
    fast: bool = False
    method: str | None = None  # default: the scene's

    @property
    def survey(self) -> int:
        return 300 if self.fast else 1500

    @property
    def sens_per_region(self) -> int:
        return 1 if self.fast else 2

    @property
    def window_poses(self) -> int:
        return 1 if self.fast else 3


@dataclass
class CheckReport:
    """What ``run_checks`` returns."""

    results: list[CheckResult]
    tolerances: Tolerances
    method: str
    regions: dict[str, int]  # surveyed reference poses per region
    n_solves: int
    elapsed: float  # s, wall time
    notes: list[str] = field(default_factory=list)

    @property
    def passed(self) -> bool:
        return all(r.passed for r in self.results)


# -- helpers -------------------------------------------------------------------------------------
def safe_solve(scene, y: float, yaw: float, method: str, full_mesh: bool = False) -> PoseResult:
    """``solve_pose`` that turns an exception into a result with the ``error`` status."""
    try:
        return solve_pose(scene, y, yaw, method, full_mesh=full_mesh)
    except Exception as exc:  # noqa: BLE001 - the check reports, the solver must not raise
        return PoseResult(y=y, yaw=yaw, method=method, status=ERROR,
                          message=f"{STATUS[ERROR]}: {type(exc).__name__}: {exc}")


def finite_result(res: PoseResult) -> bool:
    """All numbers of a result finite (z_g, roll, every contact's points and angles)."""
    vals = [res.z_g, res.roll]
    for cs in res.contacts.values():
        for c in cs:
            vals += [*c.wheel_point, *c.rail_point, c.wheel_s, c.rail_v, c.contact_angle]
    return all(math.isfinite(v) for v in vals)


def ok(res: PoseResult) -> bool:
    return res.success and res.status == CONVERGED and finite_result(res)


def primary(res: PoseResult, side: str):
    """The contact of ``side`` carrying the largest force (the reference: its first)."""
    cs = res.contacts[side]
    if not cs:
        return None
    if res.method == "reference":
        return cs[0]
    return max(cs, key=lambda c: c.force if math.isfinite(c.force) else -1.0)


def deviation(a: PoseResult, b: PoseResult, tz: float, tr: float, ts: float | None) -> float:
    """max(|dz_g|/tz, |droll|/tr, |d contact position|/ts) of the primary contacts (positions
    on the wheel and the rail profile; skipped when ``ts`` is None). inf when a contact is
    missing."""
    d = max(abs(a.z_g - b.z_g) / tz, abs(a.roll - b.roll) / tr)
    if ts is not None:
        for side in SIDES:
            ca, cb = primary(a, side), primary(b, side)
            if ca is None or cb is None:
                return math.inf
            d = max(d, abs(ca.wheel_s - cb.wheel_s) / ts, abs(ca.rail_v - cb.rail_v) / ts)
    return d if math.isfinite(d) else math.inf


def pose_text(res: PoseResult) -> str:
    return f"y={res.y / MM:+.2f} mm yaw={res.yaw:+.4f} rad"


def advice(status: int, scene, message: str = "") -> str:
    """What to change for a pose that ended with ``status`` (``message``: the pose's message,
    which tells a missing rigid contact from a mesh that sees none)."""
    eq, sd = scene.equilibrium, scene.side("left")
    wm, rm = sd.wheel_mesh, sd.rail_mesh
    if status == NO_CONTACT and "rigid" in message:
        return ("no rigid two-wheel contact exists at this pose: a wheel misses its rail (the "
                "profiles' data do not reach each other). Check the placement with "
                "`lutmpi profile plot` (track.gauge_mm, wheelset.back_to_back_mm, the gauge "
                "point) and that grid.y_mm stays within the profiles' lateral extent")
    return {
        NO_CONTACT: (f"a rigid contact exists but the mesh sees none: refine "
                     f"mesh.wheel_lateral_mm / rail_lateral_mm (now {wm.h_lat / MM:g} / "
                     f"{rm.h_lat / MM:g}) or lower equilibrium.initial_kc_N_per_m "
                     f"(now {eq.kc0:.3g})"),
        PROFILE_END: ("the contact lies on the end of a profile's data: give a profile file that "
                      "extends further (gauge face / flange), or limit grid.y_mm to where the "
                      "data reach"),
        RIGID_UNRESOLVED: ("the profiles meet in a gap minimum narrower than the contact "
                           "locus's 0.1 mm samples resolve (a worn flange on a steep gauge "
                           "face): check the profiles' data there; a mesh method's pose is not "
                           "affected"),
        KC_LIMIT: (f"raise equilibrium.max_kc_N_per_m (now {eq.kc_max:.3g}) or "
                   f"contact.allowed_indentation_mm (now {eq.allowed_indentation / MM:g})"),
        MAX_ITER: f"raise equilibrium.max_iterations (now {eq.max_iterations})",
        EQ_FAILED: (f"the equilibrium did not converge at some k_c: refine the lateral mesh "
                    f"(mesh.wheel_lateral_mm now {wm.h_lat / MM:g})"),
        WINDOW: (f"window too narrow: increase mesh.window_gap_mm "
                 f"(now {scene.settings.window_gap / MM:g})"),
        ERROR: "the solver raised an exception: a bug, please report the pose",
    }.get(status, "")


def _failure_text(res: PoseResult, scene) -> str:
    if res.success and not finite_result(res):
        return f"{pose_text(res)}: NaN in a converged result (a bug, please report the pose)"
    return f"{pose_text(res)}: {res.message}; {advice(res.status, scene, res.message)}"


# -- the suite ----------------------------------------------------------------------------------
class Suite:
    """State of one check run: the scene, the reference grid, the cache of mesh solves."""

    def __init__(self, scene, ys, yaws, opts: CheckOptions):
        self.scene, self.opts = scene, opts
        self.method = opts.method or scene.settings.method
        self.tol = Tolerances.from_scene(scene)
        rate = getattr(get_method(self.method), "indentation_rate", 1.0)
        # peak interpenetration at the allowed indentation: the patch the solver may use
        self.delta = scene.equilibrium.allowed_indentation / rate
        self.ref = ReferenceGrid(scene, ys, yaws, self.tol.dc, self.delta)
        self.ys, self.yaws = self.ref.ys, self.ref.yaws
        self.cache: dict[tuple[int, int], PoseResult] = {}
        self.n_solves = 0
        self.notes: list[str] = []
        self._lopsided: dict[tuple[int, int], float] = {}

    def mesh(self, i: int, j: int, scene=None, full: bool = False) -> PoseResult:
        """Mesh-method solve of grid pose (i, j) (cached for the user's own scene)."""
        self.n_solves += 1
        if scene is None and not full:
            if (i, j) not in self.cache:
                self.cache[i, j] = safe_solve(self.scene, self.ys[i], self.yaws[j], self.method)
            else:
                self.n_solves -= 1
            return self.cache[i, j]
        return safe_solve(scene or self.scene, self.ys[i], self.yaws[j], self.method, full)

    # -- convergence and accuracy per region ----------------------------------------------------
    def convergence(self, sample: list[RefPoint]) -> list[CheckResult]:
        out = []
        for region in REGIONS:
            pts = [p for p in sample if p.region == region]
            if not pts:
                continue
            res = [self.mesh(p.i, p.j) for p in pts]
            bad = [r for r in res if not ok(r)]
            nit = np.array([r.nit for r in res])
            msg = (f"{len(res) - len(bad)}/{len(res)} converged; contact evaluations median "
                   f"{int(np.median(nit))}, max {int(nit.max())}")
            if bad:
                msg += "; " + "; ".join(_failure_text(r, self.scene) for r in bad[:2])
                if len(bad) > 2:
                    msg += f"; ... {len(bad) - 2} more"
            rate = 1.0 - len(bad) / len(res)
            out.append(CheckResult("convergence", region, not bad, rate, 1.0, msg))
        return out

    def accuracy(self, sample: list[RefPoint]) -> list[CheckResult]:
        t = self.tol
        if self.method == "reference":
            return [CheckResult("accuracy vs reference", "all", True, math.nan, 1.0,
                                "the reference method is the reference: nothing to compare",
                                measured=False)]
        out = []
        for region in REGIONS[:3]:
            pts = [p for p in sample if p.region == region and ok(self.mesh(p.i, p.j))]
            if not pts:
                continue
            devs = [deviation(self.mesh(p.i, p.j), p.result, t.acc_z, t.acc_roll,
                              self.position_tol(p, t.acc_s)) for p in pts]
            k = int(np.argmax(devs))
            m, r = self.mesh(pts[k].i, pts[k].j), pts[k].result
            msg = (f"worst {pose_text(m)}: dz_g {(m.z_g - r.z_g) / MM:+.4f} mm, droll "
                   f"{m.roll - r.roll:+.2e} rad, dwheel_s {_ds(m, r) / MM:+.3f} mm (limits "
                   f"{t.acc_z / MM:g} mm, {t.acc_roll:g} rad, {t.acc_s / MM:g} mm"
                   f"{' + patch lopsidedness' if self.method == 'load_centre' else ''})")
            if devs[k] > 1.0:
                sd = self.scene.side("left")  # same spacings on both sides
                wm, rm = sd.wheel_mesh, sd.rail_mesh
                msg += (f"; refine mesh.wheel_lateral_mm / rail_lateral_mm (now "
                        f"{wm.h_lat / MM:g} / {rm.h_lat / MM:g}) or lower "
                        f"contact.allowed_indentation_mm")
            out.append(CheckResult("accuracy vs reference", region, devs[k] <= 1.0, devs[k], 1.0,
                                   msg))
        return out

    def position_tol(self, p: RefPoint, base: float) -> float:
        """Contact-position tolerance at reference pose ``p``. The load centre is the centroid of
        the penetration patch, not its deepest point: where the patch is lopsided (a nearly
        conformal tread contact next to the flange root) the centroid lies between the rigid
        contact point and the middle of the patch, whatever the mesh. For that method the
        tolerance is ``base`` plus the distance from the rigid contact point to the middle of
        the patch (the wheel-profile span whose rigid gap is within twice the allowed
        indentation of the minimum, from the reference locus); for the others ``base``."""
        if self.method != "load_centre":
            return base
        key = (p.i, p.j)
        if key not in self._lopsided:
            rig = self.scene.locus.solve(self.ys[p.i], self.yaws[p.j])
            off = 0.0
            if rig.success:
                for side in SIDES:
                    loc, cs = rig.loci[side], rig.contacts[side]
                    if not cs:
                        continue
                    s0 = cs[0].s
                    near = np.abs(loc.s - s0) <= 0.02   # the patch around this contact only
                    gap = resolved_gap(loc)             # as the rigid contact was placed
                    sel = near & (gap <= np.min(gap[near]) + 2.0 * self.delta)
                    if sel.any():
                        off = max(off, abs(0.5 * (loc.s[sel].min() + loc.s[sel].max()) - s0))
            self._lopsided[key] = off
        return base + self._lopsided[key]

    # -- sensitivity to the stiffnesses ---------------------------------------------------------
    def sensitivity(self, sample: list[RefPoint]) -> list[CheckResult]:
        eq = self.scene.equilibrium
        pts = []
        for region in REGIONS:
            rp = [p for p in sample if p.region == region and ok(self.mesh(p.i, p.j))]
            idx = np.unique(np.round(np.linspace(0, len(rp) - 1, self.opts.sens_per_region)))
            pts += [rp[int(k)] for k in idx] if rp else []
        groups = {
            "sensitivity k_c": [
                ("initial k_c x10", replace(eq, kc0=eq.kc0 * 10)),
                ("initial k_c /10", replace(eq, kc0=eq.kc0 / 10)),
                ("allowed indentation x10",
                 replace(eq, allowed_indentation=eq.allowed_indentation * 10)),
                ("allowed indentation /10",
                 replace(eq, allowed_indentation=eq.allowed_indentation / 10)),
            ],
            "sensitivity k_el": [
                ("k_el, k_rot x10", replace(eq, k_el=eq.k_el * 10, k_rot=eq.k_rot * 10)),
                ("k_el, k_rot /10", replace(eq, k_el=eq.k_el / 10, k_rot=eq.k_rot / 10)),
            ],
        }
        return [self._sensitivity_group(name, variants, pts) for name, variants in groups.items()]

    def _sensitivity_group(self, name: str, variants, pts: list[RefPoint]) -> CheckResult:
        t = self.tol
        worst, failed = (0.0, ""), []
        for label, eqv in variants:
            scene = replace(self.scene, equilibrium=eqv)
            for p in pts:
                base, var = self.mesh(p.i, p.j), self.mesh(p.i, p.j, scene=scene)
                if not ok(var):
                    failed.append(f"{label}: {pose_text(var)}: {var.message}")
                    continue
                ts = None if p.region == "double" else self.position_tol(p, t.s)
                d = deviation(var, base, t.z, t.roll, ts)
                if d > worst[0]:
                    worst = (d, f"{label} at {pose_text(var)} ({p.region}): dz_g "
                                f"{(var.z_g - base.z_g) / MM:+.4f} mm, droll "
                                f"{var.roll - base.roll:+.2e} rad, dwheel_s "
                                f"{_ds(var, base) / MM:+.3f} mm")
        msg = (f"{len(pts)} poses x {len(variants)} variants; worst: {worst[1] or 'none'} "
               f"(tolerances {t.z / MM:.3g} mm, {t.roll:.2g} rad, {t.s / MM:.3g} mm)")
        passed = not failed and worst[0] <= 1.0
        if failed:
            msg = f"{len(failed)} variant solves failed: {'; '.join(failed[:2])}; " + msg
        if not passed:
            msg += ("; the results depend on the stiffness: lower contact.allowed_indentation_mm "
                    "or refine the mesh" if "k_c" in name else
                    "; the results depend on the fictitious springs: keep "
                    "equilibrium.spring_N_per_m well below k_c and refine the mesh")
        value = math.inf if failed else worst[0]
        return CheckResult(name, "all", passed, value, 1.0, msg)

    # -- continuity along grid lines ------------------------------------------------------------
    def lines(self, survey: list[RefPoint]) -> list[tuple[str, list[tuple[int, int]]]]:
        """y-lines at yaw 0 (and at the largest |yaw|); yaw-lines at the largest |y| (and at the
        y next to the first contact-point jump of the yaw-0 line)."""
        ny, nw = self.ys.size, self.yaws.size
        j0, jm = int(np.argmin(np.abs(self.yaws))), int(np.argmax(np.abs(self.yaws)))
        im = int(np.argmax(np.abs(self.ys)))
        out = [(f"y-line at yaw {self.yaws[j0]:+.3f}", [(i, j0) for i in range(ny)]),
               (f"yaw-line at y {self.ys[im] / MM:+.2f} mm", [(im, j) for j in range(nw)])]
        if not self.opts.fast:
            out.append((f"y-line at yaw {self.yaws[jm]:+.3f}", [(i, jm) for i in range(ny)]))
            regions = [self.ref[i, j0].region for i in range(ny)]
            change = [i for i in range(1, ny) if regions[i] != regions[i - 1]]
            ij = change[-1] if change else ny // 2
            if ij != im:
                out.append((f"yaw-line at y {self.ys[ij] / MM:+.2f} mm",
                            [(ij, j) for j in range(nw)]))
        return out

    def continuity(self, survey: list[RefPoint]) -> CheckResult:
        t = self.tol
        n_pairs, real, n_pos, flagged = 0, 0, 0, []
        lines = self.lines(survey)
        for label, line in lines:
            refs = [self.ref[ij] for ij in line]
            mesh = [self.mesh(*ij) for ij in line]
            dsr = [_max_abs_ds(refs[k + 1].result, refs[k].result) for k in range(len(line) - 1)]
            thr = max(t.jump_s, 5.0 * float(np.nanmedian(dsr)) if dsr else 0.0)
            for k in range(len(line) - 1):
                a, b, ra, rb = mesh[k], mesh[k + 1], refs[k], refs[k + 1]
                if not (ok(a) and ok(b)):
                    continue  # reported by the convergence check
                n_pairs += 1
                # a real contact-point jump: the contact position may jump, z_g and roll may
                # not; a wheel whose patch is wider than a jump has no point-like contact (its
                # load centre migrates across the patch): its position is not compared
                jump = (dsr[k] > thr or "double" in (ra.region, rb.region)
                        or any(len(ra.result.contacts[s]) != len(rb.result.contacts[s])
                               for s in SIDES))
                sides = () if jump else tuple(
                    s for s in SIDES if max(ra.band[s], rb.band[s]) <= t.jump_s)
                real += jump
                n_pos += len(sides)
                d = _jump_deviation(a, b, ra.result, rb.result, t, sides)
                if d > 1.0:
                    flagged.append((d, label, a, b, ra.result, rb.result))
        msg = (f"{n_pairs} neighbour pairs on {len(lines)} grid lines, {real} at a "
               f"real "
               f"contact-point jump; contact positions compared on {n_pos} wheel-steps (not at "
               f"jumps nor where the patch is wider than {t.jump_s / MM:g} mm); {len(flagged)} "
               f"unexplained jumps (tolerance 2x "
               f"{t.z / MM:.3g} mm, {t.roll:.2g} rad, {t.s / MM:.3g} mm per step)")
        value = max((f[0] for f in flagged), default=0.0)
        if flagged:
            d, label, a, b, ra, rb = max(flagged, key=lambda f: f[0])
            msg += (f"; worst on the {label} between {pose_text(a)} and {pose_text(b)}: "
                    f"step of z_g {(b.z_g - a.z_g) / MM:+.4f} mm (reference "
                    f"{(rb.z_g - ra.z_g) / MM:+.4f}), roll {b.roll - a.roll:+.2e} rad (reference "
                    f"{rb.roll - ra.roll:+.2e}); refine mesh.wheel_lateral_mm / rail_lateral_mm "
                    f"or lower contact.allowed_indentation_mm")
        return CheckResult("continuity", "all", not flagged, value, 1.0, msg)

    # -- mesh adequacy ----------------------------------------------------------------------------
    def window(self, survey: list[RefPoint]) -> CheckResult:
        t, st = self.tol, self.scene.settings
        if not st.window or self.method == "reference":
            return CheckResult("mesh window", "all", True, math.nan, 1.0,
                               "no window (whole mesh or reference method)", measured=False)
        flange = sorted((p for p in survey if p.region in ("flange", "flange_root")),
                        key=lambda p: (-abs(self.yaws[p.j]), -abs(self.ys[p.i])))
        pos = [p for p in flange if self.ys[p.i] >= 0]
        neg = [p for p in flange if self.ys[p.i] < 0]
        # the most yawed flange poses, alternating the sign of y
        chosen = [p for pair in zip(pos, neg, strict=False) for p in pair]
        chosen += pos[len(neg):] + neg[len(pos):]
        chosen = chosen[: self.opts.window_poses]
        if not chosen:
            return CheckResult("mesh window", "flange", True, math.nan, 1.0,
                               "no flange pose in the surveyed grid: the window was not "
                               "compared with the full mesh", measured=False)
        worst, bad = (0.0, ""), []
        for p in chosen:
            w, f = self.mesh(p.i, p.j), self.mesh(p.i, p.j, full=True)
            if ok(w) != ok(f):
                bad.append(f"{pose_text(w)}: windowed {w.message}, full mesh {f.message}")
                continue
            if ok(w):
                d = deviation(w, f, t.z, t.roll, t.s)
                if d > worst[0]:
                    worst = (d, f"{pose_text(w)}: dz_g {(w.z_g - f.z_g) / MM:+.2e} mm, droll "
                                f"{w.roll - f.roll:+.2e} rad, dwheel_s {_ds(w, f) / MM:+.3f} mm")
        hit = [r for r in self.cache.values() if r.status == WINDOW]
        bad += [f"{pose_text(r)}: {r.message}" for r in hit[:2]]
        passed = not bad and worst[0] <= 1.0
        msg = (f"windowed vs full mesh at {len(chosen)} yawed flange poses; worst "
               f"{worst[1] or 'identical'}; {len(hit)} poses with status window_too_small")
        if bad:
            msg = "; ".join(bad) + "; " + msg
        if not passed:
            msg += (f"; window too narrow: increase mesh.window_gap_mm (now "
                    f"{st.window_gap / MM:g})")
        return CheckResult("mesh window", "flange", passed,
                           math.inf if bad else worst[0], 1.0, msg)

    def spacing(self, sample: list[RefPoint]) -> CheckResult:
        """Patch half-widths at the allowed indentation from the reference curvatures:
        ``a = sqrt(2 R delta)``, ``R = 1 / (k_wheel + k_rail)`` across the profile and the
        wheel's rolling radius of curvature along it; ``delta`` the peak interpenetration at the
        allowed indentation (C / rate of the method: 2 C for the load centre's mean)."""
        if self.method == "reference":
            return CheckResult("mesh spacing", "all", True, math.nan, self.tol.min_nodes,
                               "reference method: no mesh", measured=False)
        eq, sd = self.scene.equilibrium, self.scene.side("left")  # same spacings both sides
        wm, rm = sd.wheel_mesh, sd.rail_mesh
        delta = eq.allowed_indentation / get_method(self.method).indentation_rate
        lat, lon = (math.inf, None), (math.inf, None)
        for p in sample:
            for side in SIDES:
                for c in p.result.contacts[side]:
                    at = _half_width(c.wheel_curv_transverse + c.rail_curv_transverse, delta)
                    ax = _half_width(c.wheel_curv_rolling, delta)
                    lat = min(lat, (at, p), key=lambda v: v[0])
                    lon = min(lon, (ax, p), key=lambda v: v[0])
        keys = [("mesh.wheel_lateral_mm", wm.h_lat, lat), ("mesh.rail_lateral_mm", rm.h_lat, lat),
                ("mesh.wheel_circumferential_mm", wm.h_circ, lon),
                ("mesh.rail_longitudinal_mm", rm.h_x, lon)]
        nodes = [(2.0 * a / h, key, h, a, p) for key, h, (a, p) in keys]
        n_min, key, h, a, p = min(nodes, key=lambda v: v[0])
        coarse = [v for v in nodes if v[0] < self.tol.min_nodes]
        msg = (f"contact patch at the allowed indentation spans >= {n_min:.1f} nodes "
               f"({key}, half-width {a / MM:.3g} mm at "
               f"{pose_text(p.result) if p else 'no contact'})")
        if coarse:
            msg = "; ".join(
                f"{k} = {hh / MM:g} too coarse for contact.allowed_indentation_mm = "
                f"{eq.allowed_indentation / MM:g} (patch half-width {aa / MM:.3g} mm at "
                f"{pose_text(pp.result)}, {pp.region}); use <= "
                f"{2.0 * aa / self.tol.min_nodes / MM:.3g}" for _, k, hh, aa, pp in coarse)
        return CheckResult("mesh spacing", "all", not coarse, n_min, self.tol.min_nodes, msg)


def _half_width(curvature: float, delta: float) -> float:
    """Half-width sqrt(2 R delta) of the patch for the combined curvature (1/m); inf when the
    surfaces are flat or conformal (the patch is then not bounded by curvature)."""
    if not math.isfinite(curvature) or curvature <= 1e-3:
        return math.inf
    return math.sqrt(2.0 * delta / curvature)


def _ds(a: PoseResult, b: PoseResult) -> float:
    """Signed largest change of the primary contact's wheel coordinate (m) over both wheels."""
    out = 0.0
    for side in SIDES:
        ca, cb = primary(a, side), primary(b, side)
        if ca is None or cb is None:
            return math.nan
        d = ca.wheel_s - cb.wheel_s
        out = d if abs(d) > abs(out) else out
    return out


def _max_abs_ds(a: PoseResult, b: PoseResult) -> float:
    return max(abs(primary_s(a, s) - primary_s(b, s)) for s in SIDES)


def _jump_deviation(a, b, ra, rb, t: Tolerances, sides=SIDES) -> float:
    """Step of the mesh result between neighbours minus the reference's step, normalized by
    twice the tolerances (each end point may be off by one tolerance)."""
    d = max(abs((b.z_g - a.z_g) - (rb.z_g - ra.z_g)) / (2 * t.z),
            abs((b.roll - a.roll) - (rb.roll - ra.roll)) / (2 * t.roll))
    for side in sides:
        ca, cb, fa, fb = primary(a, side), primary(b, side), primary(ra, side), primary(rb, side)
        if None in (ca, cb, fa, fb):
            return math.inf
        d = max(d, abs((cb.wheel_s - ca.wheel_s) - (fb.wheel_s - fa.wheel_s)) / (2 * t.s))
    return d if math.isfinite(d) else math.inf


def run_checks(scene, ys, yaws, opts: CheckOptions | None = None) -> CheckReport:
    """Run the stability suite on ``scene`` over the grid ``ys`` (m) x ``yaws`` (rad)."""
    opts = opts or CheckOptions()
    t0 = time.perf_counter()
    suite = Suite(scene, ys, yaws, opts)
    warm(scene, suite.method)   # kernels loaded outside the first pose's time budget
    survey = suite.ref.survey(opts.survey)
    sample = stratified_sample(survey, opts.points)
    results = suite.convergence(sample)
    results += suite.accuracy(sample)
    results += suite.sensitivity(sample)
    results.append(suite.continuity(survey))
    results.append(suite.window(survey))
    results.append(suite.spacing(sample))
    regions = {r: sum(p.region == r for p in survey) for r in REGIONS}
    return CheckReport(results, suite.tol, suite.method, regions, suite.n_solves,
                       time.perf_counter() - t0, suite.notes)
