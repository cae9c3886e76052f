"""The damped Newton iteration of the equilibrium at fixed k_c (:meth:`lutmpi.equilibrium.solver.
Equilibrium.newton`) compiled for the mesh methods: each evaluation runs both wheels' contact
kernels, the flange factors of §4.5 (eq. 1 and eq. 8's springs assembled into the residual
and its Jacobian) and the line search without returning to Python (issue 14).

It computes what the Python iteration computes, in its order of operations, and returns the
same pose, residual and contacts to the bit (``tests/unit/test_pose_newton.py`` compares the
two on every mesh method; the Python iteration stays as the oracle and as the path of any other
contact evaluation). Its budgets are the Python iteration's: before every contact evaluation the
evaluation count (``max_iterations``) and the wall-time deadline (read through ``objmode``) are
checked, and the pose evaluated last is kept for the budget's result.

Buffers (preallocated by :class:`CompiledNewton`, filled in place): two states (the current
pose and the trial pose of the line search), each with its pose ``qs[t]``, residual ``Rs[t]``
and per wheel (left, right) the contact rows of the method's kernel (:data:`~lutmpi.contact.
kernels.COLUMNS`, the contacts kept: indentation > 0, largest first, at most ``max_contacts``),
their flange factors and their count.
"""

from __future__ import annotations

import time

import numpy as np
from numba import njit, objmode

from lutmpi.contact.kernels import COLUMNS, Pose
from lutmpi.contact.methods import load_centre, max_distance, max_normal_distance
from lutmpi.contact.methods.base import MeshContact
from lutmpi.contact.rigid_kernels import rotation
from lutmpi.contact.stiffness import check_flange, flange_factor_at
from lutmpi.equilibrium.result import MAX_ITER, TIME_BUDGET
from lutmpi.equilibrium.solver import (
    BudgetExceededError,
    ContactForce,
    assemble,
    noise_tol,
    solve2,
    step_cap,
)

#: the methods whose kernels the compiled iteration calls, by the id it dispatches on (a
#: numba function that takes a kernel as an argument is compiled again in every process)
KERNEL_IDS = {"max_distance": 0, "max_normal_distance": 1, "load_centre": 2}
#: columns of a contact row (:data:`~lutmpi.contact.kernels.COLUMNS`)
NCOL = max(c.stop if isinstance(c, slice) else c + 1 for c in COLUMNS.values())


@njit(cache=True)
def _kernel(kid, win, wheel, rail, pose):
    if kid == 0:
        return max_distance.contacts(win, wheel, rail, pose)
    if kid == 1:
        return max_normal_distance.contacts(win, wheel, rail, pose)
    return load_centre.contacts(win, wheel, rail, pose)


@njit(cache=True)
def _side(kid, win, wheel, rail, pose, max_contacts, flange, fl, rows, facs):
    """One wheel's contacts at ``pose`` into ``rows``/``facs`` (what
    :meth:`~lutmpi.contact.methods.base.MeshMethod.contacts` keeps, and
    :func:`~lutmpi.contact.stiffness.flange_factor_at` of each); returns their count."""
    n, buf = _kernel(kid, win, wheel, rail, pose)
    idx = np.empty(n, dtype=np.int64)
    m = 0
    for i in range(n):
        if buf[i, 9] > 0.0:
            idx[m] = i
            m += 1
    for a in range(1, m):  # stable, largest indentation first (Python's sort on -C)
        v = idx[a]
        b = a - 1
        while b >= 0 and buf[idx[b], 9] < buf[v, 9]:
            idx[b + 1] = idx[b]
            b -= 1
        idx[b + 1] = v
    m = min(m, max_contacts)
    samp_s, samp_r, r_base, r_tip, chi = fl
    for c in range(m):
        rows[c, :] = buf[idx[c], :]
        facs[c] = flange_factor_at(buf[idx[c], 10], flange, samp_s, samp_r, r_base, r_tip, chi)
    return m


@njit(cache=True)
def _evaluate(t, q, kc, ctx, state, rated):
    """Contacts, residual and Jacobian at ``q`` into state ``t``; returns ``J``."""
    (kid, y, yaw, q0, w0, w1, load, k_el, k_rot, rate, max_contacts, flange,
     left, right, fl_l, fl_r, lever, rtol, fmin, qtol, allowed) = ctx
    qs, Rs, rows, facs, counts = state
    qs[t, 0], qs[t, 1] = q[0], q[1]
    pose = Pose(np.array([0.0, y, q[0]]), rotation(yaw, q[1]))
    counts[t, 0] = _side(kid, left[0], left[1], left[2], pose, max_contacts, flange, fl_l,
                         rows[t, 0], facs[t, 0])
    counts[t, 1] = _side(kid, right[0], right[1], right[2], pose, max_contacts, flange, fl_r,
                         rows[t, 1], facs[t, 1])
    # eq. (1), eq. (8): the contacts of both wheels, left first, into the shared assembly
    n = counts[t, 0] + counts[t, 1]
    pts, nrm = np.empty((n, 3)), np.empty((n, 3))
    ind, fac, rates = np.empty(n), np.empty(n), np.full(n, rate)
    i = 0
    for sd in range(2):
        for c in range(counts[t, sd]):
            row = rows[t, sd, c]
            pts[i, 0], pts[i, 1], pts[i, 2] = row[0], row[1], row[2]
            nrm[i, 0], nrm[i, 1], nrm[i, 2] = -row[6], -row[7], -row[8]
            ind[i], fac[i] = row[9], facs[t, sd, c]
            i += 1
    R, J, _ = assemble(q, kc, y, w0, w1, q0, load, k_el, k_rot, pts, nrm, ind, fac, rates,
                       rated)
    Rs[t, 0], Rs[t, 1] = R[0], R[1]
    return J


@njit(cache=True)
def _budget(nit, max_evals, deadline):
    """The budget status before an evaluation (0: within both)."""
    if nit >= max_evals:
        return MAX_ITER
    with objmode(now="float64"):
        now = time.perf_counter()
    if now > deadline:
        return TIME_BUDGET
    return 0


@njit(cache=True)
def _counted(t, q, kc, ctx, state, nit, max_evals, deadline):
    """:func:`_evaluate` into state ``t`` when the budgets allow one more evaluation (the count
    and the deadline checked first, as :meth:`Equilibrium._residual` does); returns
    ``(status, nit, J)``, ``J`` unset when a budget ran out."""
    status = _budget(nit, max_evals, deadline)
    if status:
        return status, nit, np.empty((2, 2))
    return 0, nit + 1, _evaluate(t, q, kc, ctx, state, False)


@njit(cache=True)
def _f(R, load, lever):
    s0, s1 = R[0] / load, R[1] / (load * lever)
    return s0 * s0 + s1 * s1


@njit(cache=True)
def _small(dq, tol, lever):
    return abs(dq[0]) <= tol and abs(dq[1]) * lever <= tol


@njit(cache=True)
def newton(q, kc, max_iter, ctx, state, nit, max_evals, deadline):
    """:meth:`Equilibrium.newton` (``rated=False``). Returns ``(ok, status, nit, cur,
    last)``: the result's state ``cur`` (its pose, residual and contacts), the state evaluated
    last, and the budget status (0, :data:`MAX_ITER`, :data:`TIME_BUDGET`)."""
    load, lever, rtol, fmin = ctx[6], ctx[16], ctx[17], ctx[18]
    qtol_opt, allowed = ctx[19], ctx[20]
    Rs = state[1]
    cur, last = 0, -1
    status, nit, J = _counted(cur, q, kc, ctx, state, nit, max_evals, deadline)
    if status:
        return False, status, nit, cur, last
    last = cur
    for _ in range(max_iter):
        R = Rs[cur]
        f0 = _f(R, load, lever)
        a0, a1 = abs(R[0] / load), abs(R[1] / (load * lever))
        top = np.nan if (np.isnan(a0) or np.isnan(a1)) else max(a0, a1)
        if top <= rtol:
            return True, 0, nit, cur, last
        solved, dq = solve2(J, R)
        if not solved:
            return False, 0, nit, cur, last
        dq = -dq
        cap = step_cap(kc, load, fmin)
        scale = abs(dq[0]) / cap
        b = abs(dq[1]) * lever / cap
        if b > scale:
            scale = b
        if 1.0 > scale:
            scale = 1.0
        dq = dq / scale
        noise = noise_tol(kc, load, qtol_opt, allowed)
        if _small(dq, 0.2 * noise, lever):
            return True, 0, nit, cur, last
        trial = 1 - cur
        lam = 1.0
        while True:
            qn = q + lam * dq
            status, nit, Jn = _counted(trial, qn, kc, ctx, state, nit, max_evals, deadline)
            if status:
                return False, status, nit, cur, last
            last = trial
            if _f(Rs[trial], load, lever) < f0 or lam < 0.05:
                break
            lam *= 0.5
        if _f(Rs[trial], load, lever) >= f0:
            counts = state[4]
            ok = _small(dq, 4.0 * noise, lever) and counts[cur, 0] > 0 and counts[cur, 1] > 0
            return ok, 0, nit, cur, last
        counts = state[4]
        if (lam < 1.0 and _small(dq, 4.0 * noise, lever) and _small(lam * dq, 0.2 * noise, lever)
                and counts[trial, 0] > 0 and counts[trial, 1] > 0):
            return True, 0, nit, trial, last   # a shortened step below the resolution
        q, J, cur = qn, Jn, trial
    return False, 0, nit, cur, last


def contact_force(c: MeshContact, factor: float, rate: float) -> ContactForce:
    """What the equilibrium needs of mesh contact ``c``: its wheel point, the rail normal into
    the wheel, its indentation, flange factor and indentation rate (``c`` passed through)."""
    return ContactForce(point=c.wheel_point, normal=-c.n_wheel, indentation=c.indentation,
                        factor=factor, data=c, nodes=c.n_wheel_nodes, rate=rate)


class CompiledNewton:
    """:meth:`Equilibrium.newton` of a mesh method on its windows, compiled.

    Parameters
    ----------
    scene, wins, method, rigid :
        As :func:`lutmpi.pose.mesh._evaluator` takes them.
    """

    def __init__(self, scene, wins, method, rigid):
        st, eq = scene.settings, scene.equilibrium
        self.wins, self.rate = wins, method.indentation_rate
        self.mc = st.max_contacts
        sides, fls = [], []
        for name, win in wins.items():
            sd = scene.side(name)
            sides.append((win.arrays, sd.wheel_mesh.arrays, sd.rail_mesh.arrays))
            fls.append((sd.samp.s, sd.samp.r, float(sd.flange_base_radius),
                        float(sd.flange_tip_radius), float(st.chi)))
        self._sides, self._fls, self._rigid = sides, fls, rigid
        self._kid, self._eq = KERNEL_IDS[method.name], eq
        self._flange = bool(st.flange)
        self.state = (np.zeros((2, 2)), np.zeros((2, 2)), np.zeros((2, 2, self.mc, NCOL)),
                      np.zeros((2, 2, self.mc)), np.zeros((2, 2), dtype=np.int64))

    @staticmethod
    def supports(scene, method) -> bool:
        """Whether the compiled iteration runs ``method`` on ``scene``: a kernel it knows, and
        flange parameters the Python factor accepts (else that path raises its error)."""
        if method.name not in KERNEL_IDS:
            return False
        try:
            for name in ("left", "right"):
                sd = scene.side(name)
                check_flange(sd.flange_base_radius, sd.flange_tip_radius, scene.settings.chi)
        except ValueError:
            return False
        return True

    def _ctx(self, solver) -> tuple:
        """The compiled evaluation's context (:func:`_evaluate`) for ``solver``."""
        eq, rigid = self._eq, self._rigid
        return (self._kid, float(rigid.y), float(rigid.yaw), solver.q0, float(solver.axis[0]),
                float(solver.axis[1]), float(eq.load), float(eq.k_el), float(eq.k_rot),
                float(self.rate), int(self.mc), self._flange, self._sides[0], self._sides[1],
                self._fls[0], self._fls[1], float(solver.lever), float(eq.rtol),
                float(solver.fmin), float(eq.qtol), float(eq.allowed_indentation))

    def newton(self, solver, q: np.ndarray, kc: float, max_iter: int):
        """:meth:`Equilibrium.newton` of ``solver`` (its counts, budgets and last evaluation
        kept on it); returns ``(q, ok, R, contacts)``."""
        eq = self._eq
        ok, status, nit, cur, last = newton(np.asarray(q, dtype=float), float(kc), int(max_iter),
                                            self._ctx(solver), self.state, int(solver.nit),
                                            int(eq.max_iterations), float(solver.deadline))
        solver.nit = nit
        qs, Rs = self.state[0], self.state[1]
        if last >= 0:
            solver._last = (qs[last].copy(), Rs[last].copy(), self.forces(last))
        if status:
            raise BudgetExceededError(status)
        cs = solver._last[2] if cur == last else self.forces(cur)
        return qs[cur].copy(), bool(ok), Rs[cur].copy(), cs

    def residual(self, solver, q: np.ndarray, kc: float):
        """:meth:`Equilibrium.residual` of ``solver`` (the bracketing's evaluations) by the
        compiled evaluation: its budgets checked first, its count and last evaluation kept;
        returns ``(R, J, contacts)``."""
        status, solver.nit, J = _counted(0, np.asarray(q, dtype=float), float(kc),
                                         self._ctx(solver), self.state, int(solver.nit),
                                         int(self._eq.max_iterations), float(solver.deadline))
        if status:
            raise BudgetExceededError(status)
        R, cs = self.state[1][0].copy(), self.forces(0)
        solver._last = (q, R, cs)
        return R, J, cs

    def forces(self, t: int) -> dict[str, list[ContactForce]]:
        """The contacts of state ``t`` as the Python evaluation returns them."""
        rows, facs, counts = self.state[2], self.state[3], self.state[4]
        out = {}
        for sd, (name, win) in enumerate(self.wins.items()):
            out[name] = []
            for c in range(counts[t, sd]):
                mc = MeshContact.from_row(rows[t, sd, c].copy(), win.side)
                out[name].append(contact_force(mc, float(facs[t, sd, c]), self.rate))
        return out
