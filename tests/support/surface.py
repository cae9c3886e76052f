"""A brute-force search over a wheel's surface of revolution for its smallest vertical gap to its
rail at a pose, with no contact locus: the oracle of the rigid solve's touching heights and
contact points (:mod:`lutmpi.contact.locus`), used by ``tests/unit/test_rigid_roots.py`` and
``benchmarks/rigid_surface_check.py``."""

from __future__ import annotations

import numpy as np

from lutmpi.contact import rigid_kernels as rk


def surface_min(scene, name: str, y: float, yaw: float, roll: float, z: float
                ) -> tuple[float, float]:
    """Smallest vertical gap (m) between wheel ``name``'s surface of revolution and its rail at
    the pose (G at ``(0, y, z)``, yaw and roll in rad, pitch 0), and the profile coordinate where
    it lies (m): every 25 um of profile and 1 mrad of wheel angle over +-0.35 rad, then every
    2 um and 20 urad around the smallest. Points not over the rail's data count as +inf."""
    sd = scene.side(name)
    w, rail, side = sd.wheel, sd.rail, sd.sign
    R = rk.rotation(yaw, roll)

    def gaps(s, phi):
        S, PH = np.meshgrid(s, phi, indexing="ij")
        r = np.broadcast_to(w.radius(s)[:, None], S.shape)
        bx, by, bz = r * np.sin(PH), side * (w.d + S), -r * np.cos(PH)
        u = side * (y + R[1, 0] * bx + R[1, 1] * by + R[1, 2] * bz)
        pz = z + R[2, 0] * bx + R[2, 1] * by + R[2, 2] * bz
        ok = (u >= rail.u_min) & (u <= rail.u_max)
        return np.where(ok, pz - rail.height(np.clip(u, rail.u_min, rail.u_max)), np.inf)

    s = np.arange(w.s_min, w.s_max, 25e-6)
    phi = np.linspace(-0.35, 0.35, 701)
    g = gaps(s, phi)
    i, j = np.unravel_index(np.argmin(g), g.shape)
    s2 = np.clip(np.linspace(s[i] - 50e-6, s[i] + 50e-6, 51), w.s_min, w.s_max)
    g2 = gaps(s2, np.linspace(phi[j] - 2e-3, phi[j] + 2e-3, 201))
    k = np.unravel_index(np.argmin(g2), g2.shape)[0]
    return float(g2.min()), float(s2[k])
