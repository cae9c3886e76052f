"""The pose pipeline (§4.3): the layer above ``contact/`` and ``equilibrium/``.

``solve.py``: ``solve_pose(scene, y, yaw, method)``, the one entry; ``rigid.py``: the reference
(locus) method's result; ``mesh.py``: the mesh methods' window, k_c iteration and result.
"""
