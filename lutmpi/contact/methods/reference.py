"""``reference``: the semi-analytic contact-locus method (:mod:`lutmpi.contact.locus`) as a
contact method. The rigid two-point contact every method starts from is its result: no mesh,
no k_c (stored as NaN), indentation 0."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lutmpi.contact.methods.base import ContactMethod
from lutmpi.contact.records import SIDE_SIGN, contact_records
from lutmpi.equilibrium.result import CONVERGED, STATUS, PoseResult


@dataclass(frozen=True)
class RigidLocusMethod(ContactMethod):
    """The rigid locus solution itself."""

    def solve(self, scene, rigid, full_mesh: bool = False) -> PoseResult:
        res = PoseResult(
            y=rigid.y, yaw=rigid.yaw, method=self.name, x_g=0.0, z_g=rigid.z_g,
            roll=rigid.roll, pitch=0.0, success=True, status=CONVERGED,
            message=STATUS[CONVERGED], nit=rigid.nit, indentation=0.0,
        )
        rows, names = [], []
        for name, side in SIDE_SIGN.items():
            rail = scene.side(name).rail
            for c in rigid.contacts[name]:
                u = float(np.clip(c.u, rail.u_min, rail.u_max))
                sl = float(rail.slope(u))
                n = np.array([0.0, side * -sl, 1.0]) / np.hypot(1.0, sl)
                rp = np.array([c.point[0], side * u, float(rail.height(u))])
                rows.append((side, c.point, rp, n, max(-c.gap, 0.0), c.s, np.nan))
                names.append(name)
        for name, rec in zip(names, contact_records(scene, rows), strict=True):
            res.contacts[name].append(rec)
        return res


METHOD = RigidLocusMethod("reference", "semi-analytic contact locus, rigid two-point contact")
