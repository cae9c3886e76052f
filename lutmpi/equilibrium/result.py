"""Result objects of a pose solve. Non-convergence is data: ``success``, ``status``, ``message``."""

from __future__ import annotations

from dataclasses import dataclass, field

# declared next to the code that fills it (one module per stored per-contact quantity); re-exported
from lutmpi.contact.records import ContactResult  # noqa: F401

# status code -> text; stored as an attribute of every table's ``status`` dataset
STATUS = {
    0: "converged",
    1: "max_iterations: the iteration budget (equilibrium.max_iterations) ran out",
    2: "no_contact: no rigid two-wheel contact exists, or a wheel found none in its mesh window",
    3: "kc_limit: k_c reached its upper limit before the indentation was allowed",
    4: "equilibrium_failed: the equilibrium solve did not converge at some k_c",
    5: "window_too_small: the intersecting volume touched the mesh window edge",
    6: "not_computed",
    7: "error: an exception was raised while solving this point",
    8: "time_budget: the pose's wall-time budget (equilibrium.max_pose_time_s) ran out",
    9: "profile_end: a contact lies on or beyond the end of a profile's data",
    10: "rigid_unresolved: the rigid root's two touching heights differ (a gap minimum the "
        "contact locus's samples do not resolve)",
}
(CONVERGED, MAX_ITER, NO_CONTACT, KC_LIMIT, EQ_FAILED, WINDOW, NOT_COMPUTED, ERROR,
 TIME_BUDGET, PROFILE_END, RIGID_UNRESOLVED) = range(11)
SIDES = ("left", "right")


@dataclass
class PoseResult:
    """Solution for one pose (y_g, yaw) of the wheelset."""

    y: float                      # m, imposed lateral shift y_g
    yaw: float                    # rad, imposed yaw theta_z
    method: str
    x_g: float = float("nan")     # m
    z_g: float = float("nan")     # m, height of the centre of mass above rail-top level
    roll: float = float("nan")    # rad, theta_x
    pitch: float = float("nan")   # rad, theta_y
    success: bool = False
    status: int = 6
    message: str = STATUS[6]
    nit: int = 0                  # total equilibrium iterations over all k_c levels
    kc: float = float("nan")      # N/m, final k_c scale
    indentation: float = float("nan")  # m, final max indentation over both wheels
    contacts: dict[str, list[ContactResult]] = field(
        default_factory=lambda: {"left": [], "right": []})
    time: float = 0.0             # s, CPU time of this solve

    @property
    def n_contacts(self) -> dict[str, int]:
        return {s: len(self.contacts[s]) for s in SIDES}
