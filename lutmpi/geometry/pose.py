"""Wheelset pose and rotations in the paper's frames.

Track frame SRo: x along the track, y lateral to the left, z up, origin on the track centre line at
rail-top level. Wheelset frame SRG: origin at the centre of mass G, Y_G along the axle.

Rotation order (documented once): the orientation is ``R = Rz(yaw) @ Rx(roll) @ Ry(pitch)``
— yaw about the track's z axis first, then roll about the yawed x axis, then pitch about the axle.
A point ``c`` given in the wheelset frame is at ``G + R @ c`` in the track frame. Positive roll
raises the left (y > 0) wheel.
"""

from __future__ import annotations

import numpy as np


def rot_x(a: float) -> np.ndarray:
    """Rotation about x by ``a`` rad, shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def rot_y(a: float) -> np.ndarray:
    """Rotation about y by ``a`` rad, shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_z(a: float) -> np.ndarray:
    """Rotation about z by ``a`` rad, shape (3, 3)."""
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def wheelset_rotation(yaw: float, roll: float, pitch: float = 0.0) -> np.ndarray:
    """``R = Rz(yaw) Rx(roll) Ry(pitch)``, shape (3, 3)."""
    return rot_z(yaw) @ rot_x(roll) @ rot_y(pitch)


def roll_axis(yaw: float) -> np.ndarray:
    """Unit vector of the roll axis (the yawed x axis) in the track frame, shape (3,)."""
    return np.array([np.cos(yaw), np.sin(yaw), 0.0])


def to_track(points_body: np.ndarray, centre: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Wheelset-frame points (n, 3) to the track frame: ``G + R c``."""
    return centre + points_body @ R.T


def to_body(points_track: np.ndarray, centre: np.ndarray, R: np.ndarray) -> np.ndarray:
    """Track-frame points (n, 3) to the wheelset frame: ``R^T (P - G)``."""
    return (points_track - centre) @ R
