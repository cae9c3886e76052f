"""Contact methods as a registry of units (issue 15): names from one registry, unknown names
refused with the valid ones listed, the config's lists derived from it, and the closed-form
rotation of the pose loop equal bit for bit to the geometry's matrix product."""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.config.model import ALL_METHODS, CONTACT_METHODS
from lutmpi.contact.methods import METHODS, get_method
from lutmpi.contact.methods.base import MeshMethod
from lutmpi.geometry.pose import wheelset_rotation
from lutmpi.pose.mesh import rotation
from lutmpi.pose.solve import solve_pose


def test_config_lists_come_from_the_registry():
    assert ALL_METHODS == tuple(METHODS)
    assert CONTACT_METHODS == tuple(n for n, m in METHODS.items() if isinstance(m, MeshMethod))
    assert {"max_distance", "max_normal_distance", "load_centre", "reference"} <= set(METHODS)


def test_unknown_method_lists_the_valid_ones():
    with pytest.raises(ValueError, match="load_centre") as err:
        get_method("centre_of_load")
    assert "centre_of_load" in str(err.value)
    with pytest.raises(ValueError, match="valid"):
        solve_pose(None, 0.0, 0.0, "nope")


@pytest.mark.parametrize("name", sorted(METHODS))
def test_every_method_owns_its_properties(name):
    m = get_method(name)
    assert m.name == name and m.description
    if m.uses_mesh:
        assert m.kernel is not None and 0.0 < m.indentation_rate <= 1.0


def test_rotation_is_the_geometry_rotation_bit_for_bit():
    # the closed form must give the same bits (signed zeros included) as Rz(yaw) Rx(roll) Ry(0)
    # by matrix products, or the tables would change
    rng = np.random.default_rng(7)
    yaws = np.concatenate([rng.uniform(-0.5, 0.5, 3000), [0.0, -0.0, 0.12, -0.12]])
    rolls = np.concatenate([rng.uniform(-0.05, 0.05, 3000), [0.0, -0.0, 0.0, -0.0]])
    for yaw, roll in zip(yaws, rolls, strict=True):
        want = wheelset_rotation(yaw, roll).tobytes()
        assert rotation(yaw, roll).tobytes() == want, (yaw, roll)
    for yaw in (0.0, -0.0, 0.05):
        for roll in (0.0, -0.0, 1e-3):
            want = wheelset_rotation(yaw, roll).tobytes()
            assert rotation(yaw, roll).tobytes() == want
