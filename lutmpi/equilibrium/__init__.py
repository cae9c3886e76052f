"""Equilibrium of eq. (1) with the k_c iteration of §4.3; result objects."""

from lutmpi.equilibrium.result import STATUS, ContactResult, PoseResult

__all__ = ["STATUS", "ContactResult", "PoseResult"]
