"""Integer datasets (status, n_contacts) are looked up at the nearest grid node (issue 16).

A bilinear blend of status codes or contact counts means nothing, so ``Table.interp`` gives an
integer dataset the value of the node nearest to the query: the lower node below half a cell,
the upper one above it, in y and in yaw independently.
"""

from __future__ import annotations

import numpy as np
import pytest

from lutmpi.table import interp
from lutmpi.table.schema import D

Y_AXIS = np.linspace(-9e-3, 9e-3, 7)       # 3 mm cells
YAW_AXIS = np.linspace(-0.12, 0.12, 5)     # 0.06 rad cells
CODES = (10 * np.arange(7)[:, None] + np.arange(5)[None, :]).astype(np.int8)   # i j as digits


@pytest.mark.parametrize(("fy", "fa", "i", "j"), [
    (0.3, 0.3, 2, 1),    # below half a cell in both: the lower nodes
    (0.7, 0.3, 3, 1),    # above half in y only
    (0.3, 0.7, 2, 2),    # above half in yaw only
    (0.7, 0.7, 3, 2),
    (0.0, 1.0, 2, 2),    # on nodes
])
def test_nearest_node_by_half_cells(fy, fa, i, j):
    y = Y_AXIS[2] + fy * (Y_AXIS[3] - Y_AXIS[2])
    yaw = YAW_AXIS[1] + fa * (YAW_AXIS[2] - YAW_AXIS[1])
    ip = interp.build(Y_AXIS, YAW_AXIS, {D.status: CODES})      # integers: "nearest" mode
    got = ip.evaluate(np.array([y]), np.array([yaw]))[0][0, 0]
    assert int(got) == 10 * i + j
