"""What a contact method is: a name, its properties and its stage of the pose solve.

:class:`ContactMethod` is the base of every method; a plain one (the reference) takes the rigid
contact of the pose (the locus solution, the start of every method) as its result.
:class:`MeshMethod` is the base of the methods of §4.2 that search the meshes: its ``kernel`` is
the method's compiled stage (the contacts of one wheel at a pose, from the shared eq. (2) search
and §4.6 split of :mod:`lutmpi.contact.kernels`). The pose pipeline above this layer
(:mod:`lutmpi.pose.solve`) runs a method: the rigid result (:mod:`lutmpi.pose.rigid`) or the
shared mesh pipeline, window, k_c iteration and result (:mod:`lutmpi.pose.mesh`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from lutmpi.contact.kernels import Contacts, Pose, WindowArrays


@dataclass
class MeshContact:
    """One contact of one wheel found on the meshes (track frame, SI)."""

    wheel_point: np.ndarray
    rail_point: np.ndarray
    n_wheel: np.ndarray  # wheel outward normal at the contact (unit)
    indentation: float
    s: float  # wheel profile coordinate of the wheel point
    u_rail: float  # side-local lateral coordinate of the rail point
    n_wheel_nodes: int
    n_rail_nodes: int

    @classmethod
    def from_row(cls, row: np.ndarray, side: float) -> MeshContact:
        """The contact of one row of a kernel's buffer (:data:`~lutmpi.contact.kernels.
        COLUMNS`) on the wheel of ``side`` (its fields are views of ``row``)."""
        return cls(wheel_point=row[0:3], rail_point=row[3:6], n_wheel=row[6:9],
                   indentation=float(row[9]), s=float(row[10]), u_rail=float(side * row[4]),
                   n_wheel_nodes=int(row[11]), n_rail_nodes=int(row[12]))


@dataclass(frozen=True)
class ContactMethod:
    """A contact method.

    Attributes
    ----------
    name : str
        The name a config selects it by (``contact.method``, ``output.methods``).
    description : str
        One line, with the paper's equations.
    """

    name: str
    description: str

    @property
    def uses_mesh(self) -> bool:
        """Whether the method searches the meshes (a window, k_c, an indentation rate)."""
        return False


@dataclass(frozen=True)
class MeshMethod(ContactMethod):
    """A contact-point method of §4.2 on the wheel and rail meshes.

    Attributes
    ----------
    kernel : callable
        Compiled ``kernel(win: WindowArrays, wheel: WheelArrays, rail: RailArrays, pose: Pose)
        -> (n, buf)``: the contacts of one wheel, :func:`~lutmpi.contact.kernels.packed` from
        their :class:`~lutmpi.contact.kernels.Contacts`.
    indentation_rate : float
        d(indentation)/d(approach) of the method's C (1 for a point indentation; 1/2 for the
        load centre, the mean separation of two paraboloidal caps).
    rail_nodes : bool
        Whether the stage needs the window's rail nodes.
    centroid : bool
        Whether the contact point is a weighted mean over the nodes in contact (it then moves in
        steps of about a node spacing over the nodes across the patch, not of a whole node).
    """

    kernel: Callable[..., Contacts] | None = None
    indentation_rate: float = 1.0
    rail_nodes: bool = False
    centroid: bool = False

    @property
    def uses_mesh(self) -> bool:
        return True

    def contacts(self, win, wmesh, rmesh, centre: np.ndarray, R: np.ndarray,
                 max_contacts: int = 2) -> list[MeshContact]:
        """Contacts of the window's wheel at the pose (``centre``, ``R``), largest indentation
        first, at most ``max_contacts``."""
        n, buf = self.kernel(win.arrays, wmesh.arrays, rmesh.arrays, Pose(centre, R))
        found = [
            MeshContact.from_row(row, win.side)
            for row in buf[:n]
            if row[9] > 0.0
        ]
        found.sort(key=lambda c: -c.indentation)
        return found[:max_contacts]


__all__ = ["ContactMethod", "Contacts", "MeshContact", "MeshMethod", "WindowArrays"]
