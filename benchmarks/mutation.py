"""Mutation testing of lutmpi's physics: does the CI tier notice a one-line error? (issue 16)

Each mutation is one meaningful one-line change to the library -- a sign, a dropped term, a wrong
constant, an off-by-one -- with the CI-tier tests that cover its module. For every mutation the
harness copies the checkout to a temporary folder (never touching the working tree), replaces the
exact original snippet by the mutant, runs the selected tests there (``pytest -x``, the copy first
on ``PYTHONPATH``, so subprocesses such as ``lutmpi build`` run the mutant too) and reports:

* ``killed``   -- the selection failed (or timed out: CI's pytest timeout would fail too);
* ``survived`` -- the selection passed: no test noticed the error;
* ``stale``    -- the snippet is not in the file exactly once (the code was rewritten since the
  mutation was written: refresh the snippet, it is not a result).

The score is killed / (killed + survived). Before the mutants, the union of the selections runs
once unmutated: a red baseline makes every "killed" meaningless, so the harness stops there.

Usage (CPU is shared: keep it niced, and run the whole list rarely)::

    nice -n 10 .venv/bin/python benchmarks/mutation.py                 # all mutations
    nice -n 10 .venv/bin/python benchmarks/mutation.py --only chi_0p5  # some, by id
    .venv/bin/python benchmarks/mutation.py --check                    # stale check only, no runs
    .venv/bin/python benchmarks/mutation.py --list                     # print the list

The list and the last score are recorded in docs/MUTATION.md.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

# CI-tier test selections, by module (file paths relative to the repository root)
T_STORED = "tests/unit/test_stored_physics.py"
T_EQ = "tests/unit/test_equilibrium_terms.py"
T_CLOSED = "tests/unit/test_contact_closed_form.py"
T_MESH = "tests/unit/test_contact_mesh.py"
T_REF = "tests/unit/test_contact_reference.py"
T_STIFF = "tests/unit/test_stiffness.py"
T_TRACK = "tests/unit/test_geometry_track.py"
T_CON = "tests/unit/test_conicity.py"
T_CREEP = "tests/unit/test_creep.py"
T_DYN = "tests/unit/test_dynamics.py"
T_API = "tests/unit/test_table_api.py"
T_PARITY = "tests/unit/test_table_parity.py"
T_PART = "tests/unit/test_table_partition.py"
T_SCHEMA = "tests/unit/test_table_schema.py"
T_INTERP = "tests/unit/test_interp_nearest.py"
T_NEWTON = "tests/unit/test_pose_newton.py"
T_JUMPS = "tests/unit/test_table_jumps.py"
T_MIRROR = "tests/unit/test_table_mirror.py"
T_ROOTS = "tests/unit/test_rigid_roots.py"
T_CHECK = "tests/unit/test_check.py::test_zones_count_the_minima_the_samples_do_not_resolve"
T_SUMS = "tests/unit/test_table_checksums.py"
T_FLOOR = "tests/unit/test_scan_window_floor.py"
T_BATCH = ("tests/integration/test_real_solver_parity.py::"
           "test_static_split_with_multi_point_batches_equals_serial")
T_EXPORT = "tests/unit/test_export.py"
T_READERS = "tests/unit/test_profiles_readers.py"
T_DR_CSV = "tests/unit/test_csv_inputs.py"
T_DYN_CF = "tests/unit/test_dynamics_closed_forms.py"
T_PHYS_CF = "tests/unit/test_physics_closed_forms.py"
CONTACT = (T_STORED, T_CLOSED, T_MESH)


@dataclass(frozen=True)
class Mutation:
    """One-line mutation: in ``file`` replace ``original`` (must occur exactly once) by
    ``replacement``; ``tests`` is the CI-tier selection that should notice."""

    id: str
    area: str
    file: str
    original: str
    replacement: str
    tests: tuple[str, ...]
    what: str


M = Mutation
MUTATIONS: tuple[Mutation, ...] = (
    # -- contact-point methods (compiled kernels, eqs. 3-7) ------------------------------------
    M("md_indent_sign", "contact methods", "lutmpi/contact/methods/max_distance.py",
      "c = (P[i, 0] - Pj[i, 0]) * N[i, 0]", "c = (Pj[i, 0] - P[i, 0]) * N[i, 0]", CONTACT,
      "eq. (3): x term of the indentation V.N with the wrong sign"),
    M("md_argmax_min", "contact methods", "lutmpi/contact/methods/max_distance.py",
      "        if c > out.C[g]:\n", "        if c > out.C[g] and out.C[g] < -1e299:\n", CONTACT,
      "eq. (3): C_max = first node of the volume instead of the maximum"),
    M("mnd_newton_step", "contact methods", "lutmpi/contact/methods/max_normal_distance.py",
      "            t = t - f / df", "            t = t - 0.5 * f / df", CONTACT,
      "eq. (4): half Newton steps on the wheel-normal line (rail point off the rail)"),
    M("lc_rail_mean", "contact methods", "lutmpi/contact/methods/load_centre.py",
      "                RP[g, a] /= out.n_rail_nodes[g]\n",
      "                RP[g, a] /= out.n_rail_nodes[g] + 1\n", CONTACT,
      "eq. (6): rail load centre divided by n_r + 1"),
    M("lc_indent_sign", "contact methods", "lutmpi/contact/methods/load_centre.py",
      "            (WP[g, 0] - RP[g, 0]) * nwv[0]", "            (RP[g, 0] - WP[g, 0]) * nwv[0]",
      CONTACT, "eq. (7): x term of the load-centre indentation with the wrong sign"),
    M("lc_reject_inside", "contact methods", "lutmpi/contact/methods/load_centre.py",
      "        if rho * cos_half - r - dr * (x - ws_[k]) > REJECT_M and abs(dr) < REJECT_SLOPE:",
      "        if rho * cos_half - r - dr * (x - ws_[k]) > -2e-6 and abs(dr) < REJECT_SLOPE:",
      (T_MESH,), "eq. (2): the rail nodes' early bound also drops nodes up to 2 um inside the "
      "wheel"),
    M("grid_angle_no_lower_bound", "contact methods", "lutmpi/contact/kernels.py",
      "            if (1 <= i < sin_t.size and tan_b[i - 1] + TAN_MARGIN < t",
      "            if (1 <= i < sin_t.size and -np.inf < t", (T_MESH,),
      "eq. (6): a rail node's wheel angle from the series estimate checked against one of its "
      "two half-way tangents"),
    M("window_limit_quartered", "contact methods", "lutmpi/contact/kernels.py",
      "wheel, rail, pose, np.min(gap) + depth,",
      "wheel, rail, pose, np.min(gap) + 0.25 * depth,", (T_SUMS,),
      "the window's nodes within a quarter of its depth of the smallest rigid gap"),
    M("intersect_ineq", "contact methods", "lutmpi/contact/kernels.py",
      "        if not v1 * nj1 + v2 * nj2 >= 0.0:\n",
      "        if False:\n", CONTACT,
      "eq. (2): the rail-side inequality dropped (a node is in V_int when the wheel-side one "
      "holds)"),
    # -- the k_c iteration and the zero-indentation extrapolation ------------------------------
    M("kc_criterion", "k_c iteration", "lutmpi/equilibrium/solver.py",
      "            if cmax <= o.allowed_indentation:",
      "            if cmax <= 3.0 * o.allowed_indentation:", (T_EQ, T_STORED, T_CLOSED),
      "eq. (9): converged at three times the allowed indentation"),
    M("kc_target", "k_c iteration", "lutmpi/equilibrium/solver.py",
      "    target: float = 0.5  # aim", "    target: float = 5.0  # aim",
      (T_EQ, T_STORED, T_CLOSED),
      "step 8: k_c aimed at 5x the allowed indentation"),
    M("extrap_sign", "extrapolation", "lutmpi/equilibrium/solver.py",
      "        return np.asarray(q) - dq if ok else np.asarray(q)",
      "        return np.asarray(q) + dq if ok else np.asarray(q)", (T_EQ, T_STORED, T_CLOSED),
      "zero-indentation extrapolation in the wrong direction"),
    M("extrap_off", "extrapolation", "lutmpi/pose/mesh.py",
      "    if out.q_extrapolated is not None:", "    if False:", (T_STORED, T_CLOSED),
      "stored pose not extrapolated to zero indentation"),
    # -- flange stiffness (§4.5) ----------------------------------------------------------------
    M("chi_0p5", "flange stiffness", "lutmpi/scene_config.py",
      "chi=paper_flange_chi() if f.enabled else 1.0", "chi=0.5 if f.enabled else 1.0",
      (T_STORED, T_STIFF), "χ = 0.5 instead of the paper's 0.082"),
    M("flange_interp_reversed", "flange stiffness", "lutmpi/contact/stiffness.py",
      "np.array([1.0, chi])", "np.array([chi, 1.0])", (T_STORED, T_STIFF),
      "flange factor χ at the base and 1 at the tip"),
    M("flange_side", "flange stiffness", "lutmpi/contact/stiffness.py",
      "    if not flange or s >= 0.0:", "    if not flange or s >= -0.03:",
      (T_STORED, T_STIFF), "flange factor only beyond s = -30 mm"),
    M("series_sum", "flange stiffness", "lutmpi/contact/stiffness.py",
      "    out = k1 * k2 / (k1 + k2)", "    out = k1 + k2", (T_STORED, T_STIFF),
      "Hertz and cantilever stiffness added instead of in series"),
    # -- equilibrium terms (eq. 1, eq. 8) -------------------------------------------------------
    M("spring_z_dropped", "equilibrium", "lutmpi/equilibrium/solver.py",
      "    rz = -load - k_el * (q[0] - q0[0])", "    rz = -load",
      (T_EQ, T_STORED, T_CLOSED), "the fictitious vertical spring term dropped"),
    M("yaw_lever_dropped", "equilibrium", "lutmpi/equilibrium/solver.py",
      "wx, wy, wz = w1 * pz, -w0 * pz, w0 * py - w1 * px",
      "wx, wy, wz = w1 * pz, -w0 * pz, w0 * py", (T_EQ, T_STORED, T_CLOSED),
      "the yaw term of the roll lever arm dropped"),
    M("roll_uses_lateral", "equilibrium", "lutmpi/equilibrium/solver.py",
      "        a0, a1 = nz, nz * wz ", "        a0, a1 = nz, ny * wz ",
      (T_EQ, T_STORED, T_CLOSED), "roll balance with the lateral instead of the vertical force"),
    M("force_factor_dropped", "equilibrium", "lutmpi/equilibrium/solver.py",
      "        k = kc * fac[i]\n", "        k = kc\n", (T_EQ, T_STORED, T_CLOSED),
      "eq. (8): the flange factor left out of the equilibrium forces"),
    M("newton_keeps_smallest", "equilibrium", "lutmpi/pose/newton.py",
      "        while b >= 0 and buf[idx[b], 9] < buf[v, 9]:",
      "        while b >= 0 and buf[idx[b], 9] > buf[v, 9]:", (T_NEWTON, T_STORED),
      "compiled Newton: the contacts of a wheel kept smallest indentation first"),
    M("x_g_sign", "equilibrium", "lutmpi/pose/mesh.py",
      "res.x_g = float(-F[0] / eq.k_el)", "res.x_g = float(F[0] / eq.k_el)", (T_STORED,),
      "eq. (1): x_g with the wrong sign"),
    M("pitch_axis", "equilibrium", "lutmpi/pose/mesh.py",
      "res.pitch = float(-M[1] / eq.k_rot)", "res.pitch = float(-M[0] / eq.k_rot)",
      (T_STORED,), "eq. (1): pitch from the roll moment"),
    M("stored_force_unscaled", "equilibrium", "lutmpi/pose/mesh.py",
      "c.wheel_point, c.rail_point, cf.normal, c.indentation, c.s, k",
      "c.wheel_point, c.rail_point, cf.normal, c.indentation, c.s, out.kc", (T_STORED,),
      "kc_contact/force stored without the flange factor"),
    # -- rail placement, gauge point ------------------------------------------------------------
    M("incline_sign", "rail placement", "lutmpi/geometry/track.py",
      "        vp, wp = v * cd - w * sd, v * sd + w * cd",
      "        vp, wp = v * cd + w * sd, -v * sd + w * cd", (T_TRACK, T_STORED),
      "rail inclined away from the track centre"),
    M("gauge_half", "rail placement", "lutmpi/geometry/track.py",
      "        u = 0.5 * gauge + (vp - v_gp)", "        u = gauge + (vp - v_gp)",
      (T_TRACK, T_STORED), "gauge point placed at ±gauge instead of ±gauge/2"),
    M("gauge_point_max", "rail placement", "lutmpi/geometry/track.py",
      "        return float(min(cands))", "        return float(max(cands))",
      (T_TRACK, T_STORED), "gauge point: the farthest crossing instead of the nearest"),
    M("rolling_curvature", "geometry", "lutmpi/contact/records.py",
      "        out[i, 3] = 1.0 / (r * np.sqrt(1.0 + d * d))",
      "        out[i, 3] = 1.0 / r", (T_STORED,),
      "rolling curvature without Meusnier's cos(slope)"),
    M("contact_angle_sign", "geometry", "lutmpi/contact/records.py",
      "        out[i, 1] = np.arctan2(-sgn[i] * nrm[i, 1], nrm[i, 2])",
      "        out[i, 1] = np.arctan2(sgn[i] * nrm[i, 1], nrm[i, 2])", (T_STORED,),
      "contact angle positive toward the field side"),
    # -- conicity integration (EN 15302 Annex B) ------------------------------------------------
    M("conicity_jacobian", "conicity", "lutmpi/reports/conicity.py",
      "        jac = 0.5 * w * math.sin(theta)", "        jac = 0.5 * w", (T_CON,),
      "substitution's Jacobian sin(theta) dropped"),
    M("conicity_wavelength", "conicity", "lutmpi/reports/conicity.py",
      "        wavelength = 2.0 * half * math.sqrt(0.5 * e * r0)",
      "        wavelength = 2.0 * half * math.sqrt(e * r0)", (T_CON,),
      "eq. (B.2): wavelength with e r0 instead of e r0 / 2"),
    # -- creep coefficients (Kalker) ------------------------------------------------------------
    M("kalker_c22_asymptote", "creep", "lutmpi/dynamics/creep.py",
      "    c22 = np.pi**2 / 4.0\n", "    c22 = np.pi**2 / 2.0\n", (T_CREEP,),
      "Kalker's C22 asymptote doubled"),
    M("kalker_nu_interp", "creep", "lutmpi/dynamics/creep.py",
      "    return np.array([np.interp(nu, KALKER_NU, row[i]) for i in range(row.shape[0])])",
      "    return np.array([row[i][0] for i in range(row.shape[0])])", (T_CREEP, T_DYN),
      "Kalker table read at ν = 0 whatever ν"),
    M("kalker_table_entry", "creep", "lutmpi/dynamics/creep.py",
      "[1.33, 1.47, 1.63], [1.21, 1.19, 1.16]],\n    ]\n)\nKALKER_TABLE_A_GT_B",
      "[1.33, 1.47, 1.63], [1.21, 1.19, 1.61]],\n    ]\n)\nKALKER_TABLE_A_GT_B", (T_CREEP,),
      "Kalker Table E.3, circle C33 at ν = 0.5 transposed digits (1.16 -> 1.61)"),
    # -- table writer and reader ----------------------------------------------------------------
    M("record_slot_order", "table writer", "lutmpi/table/compute.py",
      "key=lambda c: -float(c.force))", "key=lambda c: float(c.force))",
      (T_API, T_PARITY, T_STORED), "slot 0 holds the smaller contact force"),
    M("record_sides", "table writer", "lutmpi/table/compute.py",
      "out[D.n_contacts][i] = [len(result.contacts.get(s, [])) for s in SIDES]",
      "out[D.n_contacts][i] = [len(result.contacts.get(s, [])) for s in SIDES[::-1]]",
      (T_API, T_PARITY, T_STORED), "n_contacts stored [right, left]"),
    M("writer_row_offset", "table writer", "lutmpi/parallel/writer.py",
      "                        self.blocks[m][k][rows, iyaw] = v",
      "                        self.blocks[m][k][rows, iyaw[::-1]] = v",
      (T_API, T_PARITY, T_STORED, T_BATCH),
      "writer puts the points of a batch in mirrored yaw columns"),
    M("reader_mask", "table reader", "lutmpi/table/api.py",
      "        source = self.data[method] if raw else self._masked[method]",
      "        source = self.data[method]", (T_API,),
      "Table.get returns the unconverged points unmasked"),
    # -- interpolation ---------------------------------------------------------------------------
    M("interp_weight", "interpolation", "lutmpi/table/lookup.py",
      "    t = (y - y0) / h",
      "    t = (y - y0) / (2 * h)", (T_API, T_INTERP),
      "interpolation weight over two knot intervals"),
    M("interp_nearest", "interpolation", "lutmpi/table/lookup.py",
      "    near_first = t < 0.5",
      "    near_first = t < 0.9", (T_API, T_INTERP),
      "nearest knot of integer data rounds at 0.9"),
    # -- the rigid all-roots search (issue 10) -----------------------------------------------
    M("root_highest", "rigid roots", "lutmpi/contact/locus.py",
      "    low = min(r.z_g for r in pool)",
      "    low = max(r.z_g for r in pool)", (T_ROOTS,),
      "the lowest-z_g rule lost: every stable root counts as the lowest"),
    M("root_stability_flipped", "rigid roots", "lutmpi/contact/locus.py",
      "    pool = [r for r in roots if r.stable] or roots",
      "    pool = [r for r in roots if not r.stable] or roots", (T_ROOTS,),
      "the unstable rigid root chosen where there is one (issue 10's wrong root)"),
    M("profile_end_converged", "rigid roots", "lutmpi/pose/solve.py",
      "    if rigid.success and rigid.at_end:", "    if rigid.success and False:", (T_ROOTS,),
      "a contact on the end of a profile's data stored as converged"),
    M("dip_smallest_only", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "DIP_BAND = SCAN_BAND", "DIP_BAND = 0.0", (T_ROOTS,),
      "only the smallest locus sample's neighbourhood resampled (a deeper dip beside a higher "
      "sample missed)"),
    M("dip_no_second_pass", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "    if 0 < ib < nv - 1 and (vals[ib - 1]", "    if False and (vals[ib - 1]", (T_ROOTS,),
      "a dip sharper than the 10 um sub-samples taken from their parabola"),
    M("contact_on_samples", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "        if np.isfinite(s_fix[i]):", "        if False:", (T_ROOTS,),
      "rigid contacts placed by the samples' parabola, not at the resampled minimum"),
    M("scan_bound_no_roll_terms", "rigid roots", "lutmpi/contact/locus.py",
      "            out.append(float(np.max(by + self.scan_sine * r + slope * (r + self.scan_sine"
      " * by))))",
      "            out.append(float(np.max(by + slope * r)))", (T_ROOTS,),
      "the roll scan's bound of dh/droll without its sin(roll) lever arms (too small)"),
    M("scan_ends_banded", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "        if not edge:  # the end of the data (a knife edge) is always refined",
      "        if g > limit or not edge:", (T_ROOTS,),
      "the roll scan refines the ends of the data only within 5 mm of the smallest gap"),
    M("local_bound_no_rail_slope", "rigid roots", "lutmpi/contact/roll_scan.py",
      "    return by + r * sx + r * turn + rate * slope\n",
      "    return by + r * sx + r * turn\n", (T_ROOTS,),
      "the roll scan's local bound of a wheel's height without the rail's slope under its point"),
    M("local_root_unchecked", "rigid roots", "lutmpi/contact/local_root.py",
      "    return roll, calls, LOCAL_NONE, _no_locus()\n",
      "    return roll, calls, LOCAL_OK, full\n", (T_ROOTS,),
      "a local root whose whole-profile check failed three times is returned as a root"),
    M("scan_parabola_start", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "    h = max(-gap[ib], h2)", "    h = max(h, h2)", (T_ROOTS,),
      "the roll scan starts a wheel's height from the parabola through its coarse samples"),
    M("floor_without_dip", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "    return lb - 0.125 * (ub - lb)", "    return lb", (T_FLOOR,),
      "the roll scan's window floor leaves out how far a parabola through its gaps can dip"),
    M("rim_unchecked", "rigid roots", "lutmpi/contact/locus.py",
      "        if not any(g[0] < -RIM_TOL for side in gaps.tolist() for g in side):",
      "        if True:", (T_ROOTS,),
      "the end circles of the wheels' data are not checked against the rail"),
    M("rim_lateral_reach", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "    if uc + reach < u_min or uc - reach > u_max:",
      "    if uc + 0.1 * reach < u_min or uc - 0.1 * reach > u_max:", (T_ROOTS,),
      "an end circle is skipped when a tenth of its arc's lateral reach misses the rail"),
    M("zones_by_samples", "rigid roots", "lutmpi/check/regions.py",
      "        gaps = {s: resolved_gap(rigid.loci[s]) for s in SIDES}",
      "        gaps = {s: rigid.loci[s].gap for s in SIDES}", (T_CHECK,),
      "lutmpi check's contact zones counted on the 0.1 mm samples' gaps, not the resolved ones"),
    # -- jump-aware tables: jumps located, refined between, followed across yaw (issue 11) -----
    M("jump_bracket_wide", "jump-aware tables", "lutmpi/table/jump_search.py",
      "TOL_M = 5e-6", "TOL_M = 5e-4", (T_JUMPS,),
      "jumps bisected to a 0.5 mm bracket instead of 5 µm"),
    M("sudden_ignored", "jump-aware tables", "lutmpi/table/jump_search.py",
      "    return bool(np.any(np.isfinite(m) & (m > CONFIRM_M) & (m > RATE_RATIO * slower)))",
      "    return False", (T_JUMPS,),
      "a cell whose contact point moves suddenly (< 2 mm) is not searched for a jump"),
    M("refine_rr_loose", "jump-aware tables", "lutmpi/table/refine.py",
      "REFINE_TOL = {D.rolling_radius: 1e-6,", "REFINE_TOL = {D.rolling_radius: 1e-4,",
      (T_JUMPS,), "refinement between jumps to 0.1 mm of rolling radius instead of 1 µm"),
    M("neighbour_dip_off", "rigid roots", "lutmpi/contact/rigid_kernels.py",
      "        if g2 < best and g2 < out:\n",
      "        if g2 < best and g2 < out and False:\n", (T_ROOTS,),
      "the intervals beyond an unresolved smallest sample's neighbours are not resampled (a "
      "root on the touching height's jump, the wheels 29 um apart)"),
    M("refine_floor_coarse", "jump-aware tables", "lutmpi/table/refine.py",
      "MIN_WIDTH_M = TOL_M\n", "MIN_WIDTH_M = 40 * TOL_M\n", (T_JUMPS,),
      "refinement stops at 0.2 mm knot spacing instead of a jump's 5 µm bracket"),
    M("cubic_test_secant", "jump-aware tables", "lutmpi/table/refine.py",
      "    if len(x) == 2:\n        d0 = d1 = delta[0]\n",
      "    if True:\n        d0 = d1 = delta[i]\n", (T_JUMPS,),
      "the pose (z_g, roll) refined against the straight line, not the table's cubic (the "
      "pre-2026-11-27 rule)"),
    M("neighbours_across_jump", "jump-aware tables", "lutmpi/table/refine.py",
      "        return 0 <= i < len(knots) and knots[i][2] == piece and discrete_key(knots[i][1])"
      " == disc\n",
      "        return 0 <= i < len(knots) and discrete_key(knots[i][1]) == disc\n", (T_JUMPS,),
      "the cubic of the pose's refinement reaches across a jump for its neighbours"),
    M("search_ignores_known", "jump-aware tables", "lutmpi/table/jump_search.py",
      "        inside = [(y, r) for y, r in known if a < y < b]\n",
      "        inside = []\n", (T_JUMPS,),
      "each jump of a cluster bisected afresh from its whole sub-interval (the pre-2026-11-27 "
      "search: ~30 % more search solves)"),
    M("narrow_not_searched", "jump-aware tables", "lutmpi/table/refine.py",
      "        if found is not None and classify(state_key(r0), state_key(r1), CONFIRM_M)[0]:\n"
      "            return _narrow(",
      "        if False and classify(state_key(r0), state_key(r1), CONFIRM_M)[0]:\n"
      "            return _narrow(", (T_JUMPS,),
      "an interval too narrow to halve whose contact still moves by more than 0.5 mm is left "
      "to the straight line (the pre-2026-11-28 refinement)"),
    M("pair_moves_ignored", "jump-aware tables", "lutmpi/table/interp.py",
      "MOVE_WEIGHT = 0.25\n", "MOVE_WEIGHT = 0.0\n", (T_JUMPS,),
      "jumps of neighbouring yaw columns pair by position and wheel alone, not by how they "
      "move the main contact (the pairing before 2026-11-28, third part)"),
    M("move_amounts_ignored", "jump-aware tables", "lutmpi/table/interp.py",
      "MOVE_RATIO = 3.0\n", "MOVE_RATIO = 1e9\n", (T_JUMPS,),
      "two jumps moving a wheel's main contact the same way pair as alike whatever the amounts "
      "(44 mm with 1.3 mm; the pairing of 2026-11-28, third part, before its last change)"),
    M("unpaired_by_position", "jump-aware tables", "lutmpi/table/lookup.py",
      "        if k < below or (k < above and jy[c, k] <= y):",
      "        if jy[c, k] <= y:", (T_JUMPS,),
      "a column's unpaired jumps count by their own position even across a paired jump the "
      "jump curve puts on the other side of the query (the lookup before 2026-11-28, third "
      "part)"),
    M("roll_even_in_y", "jump-aware tables", "lutmpi/table/schema.py",
      '"roll angle theta_x", signs=(-1, 1)),', '"roll angle theta_x", signs=(1, 1)),',
      (T_MIRROR,), "a symmetric pair's reflection y -> -y keeps the roll's sign (the mirrored "
      "half of a table with its roll the wrong way round)"),
    M("in_part_unreported", "jump-aware tables", "lutmpi/table/jump_search.py",
      "        if len(jps) < MAX_PER_CELL:\n            continue\n",
      "        if len(jps) <= MAX_PER_CELL:\n            continue\n", (T_JUMPS,),
      "a cell whose search used its whole budget with a jump left is not reported"),
    M("image_limits_unswapped", "jump-aware tables", "lutmpi/table/mirror.py",
      "        return Jump(j, self.y(g, jp.hi), self.y(g, jp.lo), g.record(jp.rec_hi),\n"
      "                    g.record(jp.rec_lo), jp.kind, side)\n",
      "        return Jump(j, self.y(g, jp.hi), self.y(g, jp.lo), g.record(jp.rec_lo),\n"
      "                    g.record(jp.rec_hi), jp.kind, side)\n", (T_MIRROR,),
      "a jump reflected in y keeps its one-sided limits on their old sides (each limit "
      "the other side's)"),
    M("pair_by_count", "jump-aware tables", "lutmpi/table/interp.py",
      "    if (na == nb and np.array_equal(sa, sb) and np.array_equal(a_near, np.arange(na))\n"
      "            and np.array_equal(b_near, np.arange(nb))):\n",
      "    if na == nb and np.array_equal(sa, sb):\n", (T_JUMPS,),
      "jumps of two yaw columns paired by index whenever they hold as many (the pre-2026-11-24 "
      "pairing)"),
    M("jump_curve_one_sided", "jump-aware tables", "lutmpi/table/lookup.py",
      "    if lo >= 0:\n        ma = 0.5 * (b - jy[j - 1, lo])",
      "    if lo >= 0 and False:\n        ma = 0.5 * (b - jy[j - 1, lo])", (T_JUMPS,),
      "jump curve between columns: the lower outer column's partner ignored"),
    M("extend_unlimited", "jump-aware tables", "lutmpi/table/lookup.py",
      "EXTEND_STEPS = 0.1", "EXTEND_STEPS = 1e9", (T_JUMPS,),
      "a column answers however far its piece must be extended to the query"),
    M("pose_jumps", "jump-aware tables", "lutmpi/table/interp.py",
      "KINKING = (D.z_g, D.roll)", "KINKING = ()", (T_JUMPS,),
      "the wheelset's pose (z_g, roll) may be taken to jump"),
    # -- wheelset dynamics (paper §6): Euler's equations, creep kinematics, Hertz, Kalker -------
    M("gyro_yaw_sign", "dynamics", "lutmpi/dynamics/wheelset.py",
      'gyro = params.I_yy * kin["omega_axle"] * kin["roll_rate"] if',
      'gyro = -params.I_yy * kin["omega_axle"] * kin["roll_rate"] if', (T_DYN_CF, T_DYN),
      "the gyroscopic yaw moment of the spinning axle under a roll rate with the wrong sign"),
    M("yaw_gravitational_sign", "dynamics", "lutmpi/dynamics/critical.py",
      "    k_gyaw = -(mz(h_yaw) - mz(-h_yaw)) / (2.0 * h_yaw)",
      "    k_gyaw = (mz(h_yaw) - mz(-h_yaw)) / (2.0 * h_yaw)", (T_DYN,),
      "the linear model's yaw gravitational stiffness with the wrong sign (stabilising)"),
    M("gyro_roll_sign", "dynamics", "lutmpi/dynamics/wheelset.py",
      'gyro_roll = -params.I_yy * kin["omega_axle"] * kin["vyaw"] if',
      'gyro_roll = params.I_yy * kin["omega_axle"] * kin["vyaw"] if', (T_DYN_CF, T_DYN),
      "the gyroscopic roll moment of a yawing axle shifts load to the wrong wheel"),
    M("ellipse_no_rail_curvature", "dynamics", "lutmpi/dynamics/wheelset.py",
      "    kt = geom.curv_wheel_transverse[idx][ok] + geom.curv_rail_transverse[idx][ok]",
      "    kt = geom.curv_wheel_transverse[idx][ok]", (T_DYN_CF, T_DYN),
      "the Hertz ellipse of the creep forces without the rail head's transverse curvature"),
    M("shear_modulus_minus", "dynamics", "lutmpi/dynamics/wheelset.py",
      "        return self.young / (2.0 * (1.0 + self.poisson))",
      "        return self.young / (2.0 * (1.0 - self.poisson))", (T_DYN_CF, T_DYN),
      "the creep forces' shear modulus G = E / (2 (1 - nu)) instead of E / (2 (1 + nu))"),
    M("axle_roll_sign", "dynamics", "lutmpi/dynamics/wheelset.py",
      "    return np.array([-sy * cr, cy * cr, sr]), np.array([cy, sy, 0.0])",
      "    return np.array([-sy * cr, cy * cr, -sr]), np.array([cy, sy, 0.0])", (T_DYN_CF, T_DYN),
      "the axle tilted the wrong way by the roll (the spin creepage of the coned contacts "
      "then varies with y)"),
    M("kalker_axes_swapped", "dynamics", "lutmpi/dynamics/wheelset.py",
      "    x = np.log(np.asarray(a, float) / np.asarray(b, float))",
      "    x = np.log(np.asarray(b, float) / np.asarray(a, float))", (T_DYN_CF, T_DYN, T_CREEP),
      "the dynamics' Kalker coefficients read at b/a instead of a/b (rolling and lateral "
      "semi-axes swapped)"),
    # -- the linear free-wheelset model (Wickens; critical.py) ---------------------------------
    M("load_transfer_sign", "dynamics", "lutmpi/dynamics/critical.py",
      "        return c + s * (self.b * s + self.r0 * c) / (self.b * c - self.r0 * s)",
      "        return c - s * (self.b * s + self.r0 * c) / (self.b * c - self.r0 * s)", (T_DYN,),
      "the linear model's load transfer by a lateral creep force taken the wrong way"),
    # -- Hertz (eqs. 10-13) -----------------------------------------------------------------------
    M("hertz_approach_k_e_swapped", "stiffness", "lutmpi/contact/stiffness.py",
      "    delta = b_min**2 * s * k_int / e_int", "    delta = b_min**2 * s * e_int / k_int",
      (T_STIFF,), "Hertz approach with the elliptic integrals K and E swapped (right for a "
      "circle only)"),
    # -- units and conventions at the edges ------------------------------------------------------
    M("conicity_cmd_half_e", "conicity", "lutmpi/commands/conicity.py",
      "e=args.e_mm * 1e-3)", "e=0.5 * args.e_mm * 1e-3)", (T_PHYS_CF, T_CON, T_DR_CSV),
      "lutmpi conicity takes --e-mm as half the contact-point distance (Klingel's wavelength "
      "off by sqrt(2))"),
    M("curvature_per_mm", "export", "lutmpi/reports/units.py",
      '    "1/m": ("1/mm", 1e-3, "per_mm"),', '    "1/m": ("1/mm", 1e3, "per_mm"),',
      (T_PHYS_CF, T_EXPORT),
      "curvatures exported in 1/mm multiplied by 1000 instead of divided"),
    M("flange_back_origin_sign", "profile readers", "lutmpi/profiles/options.py",
      "            y = y - opts.tape_offset_mm", "            y = y + opts.tape_offset_mm",
      (T_PHYS_CF, T_READERS), "origin = 'flange_back': the tape-circle offset added instead of "
                    "subtracted"),
    # -- partitioning -----------------------------------------------------------------------------
    M("block_extra", "partitioning", "lutmpi/parallel/partition.py",
      "    start = rank * base + min(rank, extra)",
      "    start = rank * base + min(rank, extra) + 1",
      (T_PART, T_PARITY), "block split shifted by one"),
    M("cyclic_step", "partitioning", "lutmpi/parallel/partition.py",
      "    return np.arange(rank, n, size, dtype=np.int64)",
      "    return np.arange(rank, n, size + 1, dtype=np.int64)", (T_PART, T_PARITY),
      "cyclic split skips points"),
    M("owner_rows", "partitioning", "lutmpi/parallel/partition.py",
      "        owners[start:start + count] = rank", "        owners[start:start + count] = 0",
      (T_PART, T_PARITY), "every row owned by rank 0 in the write split"),
)


def _copy_tree(dst: Path) -> None:
    """Copy the checkout (no .git, build outputs or caches; the .venv link is kept as a link)."""
    skip = {".git", "out", ".pytest_cache", ".ruff_cache", "__pycache__"}

    def ignore(folder: str, names: list[str]) -> list[str]:
        return [n for n in names if n in skip or n.endswith(".h5")]

    shutil.copytree(REPO, dst, symlinks=True, ignore=ignore, dirs_exist_ok=True)


def _count(path: Path, snippet: str) -> int:
    return path.read_text().count(snippet) if path.is_file() else 0


def _run_tests(root: Path, tests: tuple[str, ...], timeout: float) -> tuple[str, float, str]:
    """Run ``tests`` in the copy at ``root``; (outcome, seconds, last line)."""
    env = dict(os.environ)
    env["PYTHONPATH"] = str(root) + os.pathsep + env.get("PYTHONPATH", "")
    env["NUMBA_CACHE_DIR"] = str(root / ".numba_cache")
    cmd = [sys.executable, "-m", "pytest", "-x", "-q", "-m", "not slow and not mpi",
           "-p", "no:cacheprovider", "--timeout", "300", *tests]
    t0 = time.perf_counter()
    try:
        # the copy's kernels compiled first, as scripts/setup.sh does for CI: a test that
        # solves a pose directly would otherwise pay the compilation inside that pose's
        # time budget (~1.5 min on a slow 2-core VM: a time_budget status, not the mutant)
        subprocess.run([sys.executable, "-m", "lutmpi.warmup"], cwd=root, env=env,
                       capture_output=True, timeout=timeout)
        r = subprocess.run(cmd, cwd=root, env=env, capture_output=True, text=True,
                           timeout=timeout)
    except subprocess.TimeoutExpired:
        return "killed (timeout)", time.perf_counter() - t0, "timeout"
    dt = time.perf_counter() - t0
    last = (r.stdout.strip().splitlines() or [""])[-1]
    if r.returncode == 0:
        return "survived", dt, last
    if r.returncode == 5:
        return "no tests", dt, last
    failed = [ln for ln in r.stdout.splitlines() if ln.startswith(("FAILED", "ERROR"))]
    return "killed", dt, (failed[0] + " -- " if failed else "") + last


def run(selected: list[Mutation], timeout: float, check_only: bool) -> list[dict]:
    results = []
    for mu in selected:
        n = _count(REPO / mu.file, mu.original)
        if n != 1:
            results.append({"id": mu.id, "outcome": "stale", "detail": f"found {n} times"})
    stale = {r["id"] for r in results}
    live = [mu for mu in selected if mu.id not in stale]
    if check_only:
        return results + [{"id": mu.id, "outcome": "ok"} for mu in live]
    with tempfile.TemporaryDirectory(prefix="lutmpi-mutation-") as tmp:
        root = Path(tmp) / "repo"
        _copy_tree(root)
        union = tuple(sorted({t for mu in live for t in mu.tests}))
        base, dt, last = _run_tests(root, union, timeout=4 * timeout)
        print(f"baseline ({len(union)} files): {base} in {dt:.0f} s -- {last}", flush=True)
        if base != "survived":
            raise SystemExit("baseline selection is not green: fix it before mutating")
        for mu in live:
            target = root / mu.file
            text = target.read_text()
            target.write_text(text.replace(mu.original, mu.replacement, 1))
            try:
                outcome, dt, last = _run_tests(root, mu.tests, timeout)
            finally:
                target.write_text(text)
            print(f"{mu.id:24s} {outcome:18s} {dt:6.0f} s  {last}", flush=True)
            results.append({"id": mu.id, "outcome": outcome, "seconds": round(dt, 1),
                            "detail": last})
    return results


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", nargs="*", help="mutation ids to run (default: all)")
    ap.add_argument("--check", action="store_true", help="only check the snippets (stale)")
    ap.add_argument("--list", action="store_true", help="print the mutations as a table")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per mutation")
    ap.add_argument("--json", type=Path, help="write the results here")
    a = ap.parse_args(argv)
    ids = {mu.id for mu in MUTATIONS}
    if len(ids) != len(MUTATIONS):
        raise SystemExit("duplicate mutation ids")
    if a.list:
        print("| id | area | file | mutation | tests |\n|---|---|---|---|---|")
        for mu in MUTATIONS:
            tests = ", ".join(Path(t).stem for t in mu.tests)
            print(f"| `{mu.id}` | {mu.area} | `{mu.file}` | {mu.what} | {tests} |")
        return 0
    unknown = set(a.only or ()) - ids
    if unknown:
        raise SystemExit(f"unknown mutation ids {sorted(unknown)}; valid: {sorted(ids)}")
    selected = [mu for mu in MUTATIONS if not a.only or mu.id in a.only]
    results = run(selected, a.timeout, a.check)
    for r in results:
        if r["outcome"] == "stale":
            print(f"{r['id']:24s} stale ({r['detail']})")
    counts: dict[str, int] = {}
    for r in results:
        key = "killed" if r["outcome"].startswith("killed") else r["outcome"]
        counts[key] = counts.get(key, 0) + 1
    k, s = counts.get("killed", 0), counts.get("survived", 0)
    score = f"{100.0 * k / (k + s):.0f} %" if k + s else "n/a"
    print(f"summary: {counts}; score (killed / (killed + survived)) = {score}")
    if a.json:
        a.json.write_text(json.dumps({"results": results, "counts": counts}, indent=1))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
