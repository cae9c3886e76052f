"""The lookup-table schema, declared once: each dataset's name, dtype, shape suffix, units, meaning.

Layout of a table file (HDF5)::

    /                    root attributes: config_toml, lutmpi_version, git_commit, created_utc,
                         ranks, wall_time_s, rank_busy_s, schema_version, complete, methods,
                         quantities, inputs (content hashes, :mod:`lutmpi.table.provenance`)
    /y        (ny,)      m    lateral shift y_g of the wheelset (dimension scale)
    /yaw      (nyaw,)    rad  yaw angle theta_z (dimension scale)
    /<method>/<name>     one group per contact method (``load_centre``, ``reference``, ...),
                         each dataset of shape ``(ny, nyaw) + suffix``

Per-contact datasets have the suffix ``(2, 2)`` (side: 0 = left, 1 = right; slot: 0 = the contact
carrying the largest normal force, 1 = the second contact of a double contact) and vectors a
further ``(3,)`` (x, y, z in the track frame). A missing contact is NaN. ``status`` holds the
codes of :data:`lutmpi.equilibrium.result.STATUS` (attribute ``status_codes``, JSON).

This module is pure: no h5py, no mpi4py.
"""

from __future__ import annotations

import functools
import json
from collections import namedtuple
from collections.abc import Iterable
from dataclasses import dataclass

import numpy as np

from lutmpi.equilibrium.result import NOT_COMPUTED, SIDES, STATUS
from lutmpi.errors import ConfigError

SCHEMA_VERSION = 1
N_SLOTS = 2
CONTACT_SUFFIX = (len(SIDES), N_SLOTS)
#: datasets whose values depend on timing, not on the numerics (excluded from parity checks)
TIMING_FIELDS = ("compute_time",)
#: root attributes that depend on the run, not on the numerics
RUN_ATTRIBUTES = ("created_utc", "ranks", "wall_time_s", "rank_busy_s", "git_commit")


@dataclass(frozen=True)
class Field:
    """One dataset of a method group.

    Attributes
    ----------
    name : str
        Dataset name inside ``/<method>/``.
    dtype : str
        NumPy dtype string.
    suffix : tuple of int
        Shape after ``(ny, nyaw)``.
    units : str
        SI units (``"1"`` dimensionless, ``""`` for codes and counts).
    description : str
        One line, stored as the ``description`` attribute.
    signs : (int, int)
        How a scalar changes under the two reflections of :meth:`reflected`: in the track's
        x-z plane (``(y, yaw) -> (-y, -yaw)``, the wheels swapped) and in its y-z plane
        (``(y, yaw) -> (y, -yaw)``): ``1`` the same, ``-1`` the sign changes (roll in the
        first; x_g and pitch in the second).
    """

    name: str
    dtype: str
    suffix: tuple[int, ...]
    units: str
    description: str
    signs: tuple[int, int] = (1, 1)

    @property
    def fill(self) -> float | int:
        """Value of a point not yet computed (NaN for floats)."""
        if self.name == "status":
            return NOT_COMPUTED
        return float("nan") if np.dtype(self.dtype).kind == "f" else 0

    @property
    def per_contact(self) -> bool:
        return self.suffix[:2] == CONTACT_SUFFIX

    def reflected(self, value: np.ndarray, sides: bool, longitudinal: bool) -> np.ndarray:
        """This field's value at the reflected pose given its ``value`` at ``(y, yaw)``.

        ``sides``: the track frame reflected in its x-z plane, the pose ``(-y, -yaw)`` of a
        symmetric pair (both wheels one profile on one rail profile): the wheels swap (a
        per-wheel axis is reversed) and a vector's y component changes sign. ``longitudinal``:
        reflected in its y-z plane, the pose ``(y, -yaw)`` of any pair (wheels of revolution,
        rails extruded along x): a vector's x component changes sign. Scalars change by their
        :attr:`signs`; profile coordinates, contact angles (> 0 toward each wheel's flange),
        radii, curvatures, forces are each wheel's own. Both: the pose ``(-y, yaw)``. lutmpi's
        solver is symmetric under both (``tests/unit/test_table_mirror.py``): to the bit in
        the first, to rounding (1e-14 relative) in the second."""
        return self._reflect(value, sides, longitudinal, 0)

    def reflected_column(self, column: np.ndarray, sides: bool, longitudinal: bool
                         ) -> np.ndarray:
        """:meth:`reflected` of every value of ``column`` (shape ``(n,) + suffix``: ``n``
        values of this field stacked) at once; the same arithmetic, so the same bits."""
        return self._reflect(column, sides, longitudinal, 1)

    def _reflect(self, value: np.ndarray, sides: bool, longitudinal: bool, wheel_axis: int
                 ) -> np.ndarray:
        swap, comps, negate = _reflection_plan(self.name, sides, longitudinal)
        v = np.array(value, dtype=self.dtype)
        if swap:
            v = np.flip(v, wheel_axis).copy()
        for c in comps:
            v[..., c] = -v[..., c]
        return -v if negate else v

    def empty(self, lead: tuple[int, ...]) -> np.ndarray:
        """An array of shape ``lead + suffix`` filled with :attr:`fill`."""
        return np.full(tuple(lead) + self.suffix, self.fill, dtype=self.dtype)


@functools.cache
def _reflection_plan(name: str, sides: bool, longitudinal: bool
                     ) -> tuple[bool, tuple[int, ...], bool]:
    """What :meth:`Field.reflected` does to the values of the field ``name``: reverse the
    per-wheel axis, the vector components whose sign changes, and whether the whole value's sign
    does (decided once per field and reflection, keyed by the name, whose hash Python keeps: a
    mirrored build reflects ~10^5 values)."""
    field = FIELDS_BY_NAME[name]
    vector = field.per_contact and field.suffix[2:] == (3,)
    swap = sides and field.suffix[:1] == (len(SIDES),)
    comps = tuple(c for c, on in ((1, sides), (0, longitudinal)) if on and vector)
    sign = (field.signs[0] if sides else 1) * (field.signs[1] if longitudinal else 1)
    return swap, comps, sign < 0


@dataclass(frozen=True)
class RowReflection:
    """:meth:`Field.reflected` of every field of a structured row at once, on its bytes: the
    destination row's bytes are the source row's taken in the order ``perm`` (the per-wheel
    axis reversed), XOR ``mask`` (the sign bit of every float whose sign changes), with the
    byte ranges ``zero`` cleared (:data:`TIMING_FIELDS`: 0.0, a row not solved). One fancy
    index instead of a numpy call or three per field (issue 14: a mirrored build's grid
    reflects ~3 rows per solved point, which per field cost a twentieth of the solve).

    Attributes
    ----------
    perm : ndarray of intp, shape (itemsize,)
    mask : ndarray of uint8, shape (itemsize,)
    zero : tuple of (int, int)
        Byte ranges ``[start, stop)``.
    """

    perm: np.ndarray
    mask: np.ndarray
    zero: tuple[tuple[int, int], ...]

    def apply(self, rows: np.ndarray, src: int, dst: int) -> None:
        """Row ``dst`` of the structured array ``rows`` (contiguous) set to row ``src``
        reflected."""
        self.apply_bytes(rows.view(np.uint8).reshape(rows.size, rows.dtype.itemsize), src, dst)

    def apply_bytes(self, b: np.ndarray, src: int, dst: int) -> None:
        """:meth:`apply` on the rows' bytes ``b`` (uint8, shape ``(rows, itemsize)``)."""
        np.bitwise_xor(b[src][self.perm], self.mask, out=b[dst])
        for start, stop in self.zero:
            b[dst, start:stop] = 0


@functools.cache
def row_reflection(dtype: np.dtype, sides: bool, longitudinal: bool) -> RowReflection:
    """The :class:`RowReflection` of a structured ``dtype`` whose fields named ``<any>/<field
    name>`` hold the schema field of that name (a journal row: one per method); any other
    field is copied as it is.

    Raises
    ------
    ValueError
        A field whose sign changes is not a little-endian float (its sign is not one bit).
    """
    n = dtype.itemsize
    perm = np.arange(n, dtype=np.intp)
    mask = np.zeros(n, dtype=np.uint8)
    zero = []
    for key, spec in dtype.fields.items():
        sub, off = spec[0], spec[1]
        name = key.rpartition("/")[2]
        if "/" not in key or name not in FIELDS_BY_NAME:
            continue
        if name in TIMING_FIELDS:
            zero.append((off, off + sub.itemsize))
            continue
        swap, comps, negate = _reflection_plan(name, sides, longitudinal)
        base, shape = sub.base, sub.shape
        size = base.itemsize
        src = np.arange(int(np.prod(shape, dtype=int))).reshape(shape)
        flip = np.full(shape, negate)
        if swap:
            src = src[::-1]
        for c in comps:
            flip[..., c] = ~flip[..., c]
        src, flip = src.ravel(), flip.ravel()
        for e in range(src.size):
            perm[off + e * size: off + (e + 1) * size] = off + src[e] * size + np.arange(size)
        if flip.any():
            little = base.byteorder == "<" or (base.byteorder == "=" and
                                              np.little_endian)
            if base.kind != "f" or not little:
                raise ValueError(f"field {key!r}: a sign change needs a little-endian float, "
                                 f"got {base.str}")
            mask[off + np.flatnonzero(flip) * size + size - 1] = 0x80
    return RowReflection(perm, mask, tuple(zero))


_C = CONTACT_SUFFIX
_V = CONTACT_SUFFIX + (3,)
FIELDS: tuple[Field, ...] = (
    # per point
    Field("x_g", "f8", (), "m", "longitudinal shift of the wheelset centre of mass",
          signs=(1, -1)),
    Field("z_g", "f8", (), "m", "height of the centre of mass above rail-top level"),
    Field("roll", "f8", (), "rad", "roll angle theta_x", signs=(-1, 1)),
    Field("pitch", "f8", (), "rad", "pitch angle theta_y", signs=(1, -1)),
    Field("status", "i1", (), "", "solve status code (see attribute status_codes)"),
    Field("iterations", "i4", (), "", "equilibrium iterations over all k_c levels"),
    Field("compute_time", "f8", (), "s", "CPU time of the solve of this point"),
    Field("kc", "f8", (), "N/m", "final contact stiffness scale k_c"),
    Field("indentation_max", "f8", (), "m", "final maximum indentation over both wheels"),
    Field("n_contacts", "i1", (len(SIDES),), "", "number of contacts per wheel [left, right]"),
    Field("n_roots", "i1", (), "", "rigid two-wheel contact solutions found over the admissible "
          "roll range (0: none; > 1: the stable one of lowest z_g is stored)"),
    # per wheel x contact slot
    Field("wheel_point", "f8", _V, "m", "contact point on the wheel, track frame (x, y, z)"),
    Field("rail_point", "f8", _V, "m", "contact point on the rail, track frame (x, y, z)"),
    Field("normal", "f8", _V, "1", "rail outward unit normal, track frame (x, y, z)"),
    Field("indentation", "f8", _C, "m", "indentation C_max of the contact"),
    Field("kc_contact", "f8", _C, "N/m", "contact stiffness used for the contact"),
    Field("force", "f8", _C, "N", "normal force of the contact"),
    Field("rolling_radius", "f8", _C, "m", "rolling radius at the wheel contact point"),
    Field("contact_angle", "f8", _C, "rad", "normal angle from vertical, > 0 toward the flange"),
    Field("wheel_s", "f8", _C, "m", "wheel profile coordinate s of the contact"),
    Field("rail_v", "f8", _C, "m", "rail profile coordinate v of the contact"),
    Field("curv_wheel_rolling", "f8", _C, "1/m", "wheel principal curvature, rolling direction"),
    Field("curv_wheel_transverse", "f8", _C, "1/m", "wheel profile curvature (convex > 0)"),
    Field("curv_rail_transverse", "f8", _C, "1/m", "rail profile curvature (convex > 0)"),
)
FIELDS_BY_NAME = {f.name: f for f in FIELDS}
#: the selectable quantities of ``[output] quantities`` (:data:`lutmpi.config.model.QUANTITIES`)
#: -> the datasets each one stores; a name not listed here stores the dataset of the same name
QUANTITY_FIELDS: dict[str, tuple[str, ...]] = {
    "indentation": ("indentation", "indentation_max"),
    "kc": ("kc", "kc_contact"),
    "curvatures": ("curv_wheel_rolling", "curv_wheel_transverse", "curv_rail_transverse"),
}
#: stored whatever ``[output] quantities`` says (:data:`lutmpi.config.model.ALWAYS_STORED`)
ALWAYS_STORED = ("status", "iterations", "compute_time")
#: every selectable ``[output] quantities`` name, derived from :data:`FIELDS` in schema order: a
#: field's group of :data:`QUANTITY_FIELDS` or the field itself, the always-stored ones left out
QUANTITIES: tuple[str, ...] = tuple(dict.fromkeys(
    next((q for q, names in QUANTITY_FIELDS.items() if f.name in names), f.name)
    for f in FIELDS if f.name not in ALWAYS_STORED))
CONTACT_DIMS = "y, yaw, side [0=left, 1=right], slot [0=largest force, 1=second contact]"


def fields_of_quantity(quantity: str) -> tuple[str, ...]:
    """Dataset names stored for one ``[output] quantities`` entry."""
    return QUANTITY_FIELDS.get(quantity, (quantity,))


def select_fields(quantities: Iterable[str]) -> tuple[Field, ...]:
    """The fields a table stores for ``output.quantities`` (``"all"`` or a list of names).

    Parameters
    ----------
    quantities : iterable of str
        ``("all",)`` or names from :data:`QUANTITIES` (or dataset names);
        :data:`ALWAYS_STORED` are always added.

    Returns
    -------
    tuple of Field
        In schema order.

    Raises
    ------
    ConfigError
        On an unknown name (the message lists the valid ones).
    """
    wanted = set(quantities)
    if "all" in wanted:
        return FIELDS
    names = set(ALWAYS_STORED)
    for q in sorted(wanted):
        stored = fields_of_quantity(q)
        if not set(stored) <= set(FIELDS_BY_NAME):
            raise ConfigError(f"unknown quantity {q!r}; valid: 'all' or any of "
                              f"{', '.join(QUANTITIES)}", key="output.quantities")
        names.update(stored)
    return tuple(f for f in FIELDS if f.name in names)


def status_codes_json() -> str:
    """The ``status_codes`` attribute of every ``status`` dataset: JSON ``{"code": "text"}``."""
    return json.dumps({str(k): v for k, v in STATUS.items()})


def dataset_attributes(field: Field) -> dict[str, str]:
    """Attributes stored on a dataset: ``units``, ``description`` and dims/codes when relevant."""
    attrs = {"units": field.units, "description": field.description}
    if field.per_contact:
        attrs["dims"] = CONTACT_DIMS + (", xyz" if field.suffix[-1:] == (3,) else "")
    elif field.suffix:
        attrs["dims"] = "y, yaw, side [0=left, 1=right]"
    else:
        attrs["dims"] = "y, yaw"
    if field.name == "status":
        attrs["status_codes"] = status_codes_json()
    return attrs


# -- dataset names as attributes (issue 15: no module spells a dataset name) ------------------
#: ``D.rolling_radius == "rolling_radius"``: code outside this module names datasets through ``D``,
#: so a renamed or removed field fails where it is used instead of reading a missing key
D = namedtuple("DatasetNames", [f.name for f in FIELDS])(*(f.name for f in FIELDS))
#: the root datasets: the table's axes and dimension scales, ``/y`` (m) and ``/yaw`` (rad)
Y_AXIS, YAW_AXIS = "y", "yaw"
AXES = (Y_AXIS, YAW_AXIS)


# -- contact jumps (issue 11): /<method>/jumps/ -----------------------------------------------
#: group of a method holding its located jumps (``/<method>/jumps``)
JUMPS_GROUP = "jumps"
#: sub-group of :data:`JUMPS_GROUP` holding the one-sided limits of every stored field
LIMITS_GROUP = "limits"
#: bits of ``jump_kind``
JUMP_KIND_BITS = {1: "a contact point moves by more than the threshold",
                  2: "a contact appears or disappears (contact count changes)",
                  4: "the solve status changes"}
#: bits of ``jump_side``
JUMP_SIDE_BITS = {1: "left wheel", 2: "right wheel"}


@dataclass(frozen=True)
class JumpField:
    """One dataset of ``/<method>/jumps/``, shape ``(nyaw, K)`` (K = most jumps at one yaw;
    jumps sorted by y, unused entries NaN / 0)."""

    name: str
    dtype: str
    units: str
    description: str


JUMP_FIELDS: tuple[JumpField, ...] = (
    JumpField("jump_y", "f8", "m", "jump position y_j(yaw): middle of its bracket [lo, hi]"),
    JumpField("jump_y_lo", "f8", "m", "last solved pose below the jump (lower-side limit)"),
    JumpField("jump_y_hi", "f8", "m", "first solved pose above the jump (upper-side limit)"),
    JumpField("jump_kind", "i1", "", "bit mask: " + "; ".join(
        f"{k} = {v}" for k, v in JUMP_KIND_BITS.items())),
    JumpField("jump_side", "i1", "", "bit mask: " + "; ".join(
        f"{k} = {v}" for k, v in JUMP_SIDE_BITS.items())),
)
JUMP_FIELDS_BY_NAME = {f.name: f for f in JUMP_FIELDS}
#: extra knots: every direct solve of the post-build step (bisection samples, refinement
#: midpoints), ``/<method>/jumps/knot_y`` (nyaw, E) and ``/<method>/jumps/knots/<field>``
#: (nyaw, E, *suffix), sorted by y, NaN padded
KNOT_FIELD = JumpField("knot_y", "f8", "m", "extra knot position: a pose solved after the build "
                       "(jump bisection or refinement), sorted per yaw, NaN padded")
KNOTS_GROUP = "knots"
#: ``J.jump_y == "jump_y"``: the datasets of ``/<method>/jumps/`` by name, as :data:`D`
J = namedtuple("JumpDatasetNames", [f.name for f in JUMP_FIELDS + (KNOT_FIELD,)])(
    *(f.name for f in JUMP_FIELDS + (KNOT_FIELD,)))
#: dims of every limit dataset ``/<method>/jumps/limits/<field>``: shape (nyaw, K, 2) + suffix
LIMIT_DIMS = "yaw, jump, side of the jump [0 = at jump_y_lo, 1 = at jump_y_hi], field dims"


def limit_fields(fields: Iterable[Field]) -> tuple[Field, ...]:
    """The fields whose one-sided limits are stored at each jump (every stored field but the
    timing ones, which would break the table's independence of the run)."""
    return tuple(f for f in fields if f.name not in TIMING_FIELDS)


def jump_attributes(field: JumpField | Field, limit: bool = False) -> dict[str, str]:
    """Attributes of a jump dataset (``limit``: a one-sided limit of a table field)."""
    if limit:
        return {"units": field.units, "description": f"one-sided limits of {field.name}: "
                                                     f"{field.description}", "dims": LIMIT_DIMS}
    return {"units": field.units, "description": field.description, "dims": "yaw, jump"}


# -- what the dynamics reads from a table (issue 15): root attributes written at build time ----
#: root attribute -> units; written by :func:`lutmpi.table.jumps.dynamics_attributes`
DYNAMICS_ATTRIBUTES = {
    "wheel_flange_angle": "rad",   # steepest flange flank of the wheel profile (Nadal's limit)
    "young_modulus": "Pa",
    "poisson_ratio": "1",
    "nominal_radius": "m",
    "vertical_load": "N",
}
