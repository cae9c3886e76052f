"""The configuration as frozen dataclasses. Lengths carry their unit in the field name (``_mm``) as
in the TOML; the ``*_m`` properties give SI values. Defaults here are THE defaults, documented in
``configs/defaults.toml`` (a test keeps the two in step). Loading and validation: ``load.py``."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field
from pathlib import Path

INCLINATIONS = {"1:20": math.atan(1 / 20), "1:40": math.atan(1 / 40), "1:30": math.atan(1 / 30),
                "none": 0.0}
# the contact methods' registry (one module per method) is the only list of their names
from lutmpi.contact.methods import MESH_METHOD_NAMES as CONTACT_METHODS  # noqa: E402, F401
from lutmpi.contact.methods import METHOD_NAMES as ALL_METHODS  # noqa: E402, F401

WHEEL_GENERATORS = ("S1002",)
RAIL_GENERATORS = ("UIC60",)
EQUILIBRIUM_SOLVERS = ("newton", "fixed_point")
# Per-point quantities a table can hold (``[output] quantities``; "all" = every one), derived from
# the schema, the only list of dataset names. ALWAYS_STORED are written whatever is selected.
from lutmpi.table.schema import ALWAYS_STORED, QUANTITIES  # noqa: E402, F401

SIDE_NAMES = ("left", "right")
WHEEL_ORIGINS = ("tape_circle", "flange_back")
GAUGE_POINTS = ("depth", "first", "last")


def cant_rad(value: str | float) -> float:
    """A rail cant as given in a config: ``"1:N"``, ``"none"`` or a number (rad) -> rad."""
    if isinstance(value, str):
        if value == "none":
            return 0.0
        return math.atan(1.0 / float(value.split(":")[1]))
    return float(value)


@dataclass(frozen=True)
class WheelSideConfig:
    """``[wheel.left]`` / ``[wheel.right]``: this wheel's own keys; None = as in ``[wheel]``.
    A side that gives ``profile`` or ``generator`` takes none of ``[wheel]``'s source keys
    (profile, generator, format)."""

    profile: Path | None = None
    generator: str | None = None
    format: str | None = None
    nominal_radius_mm: float | None = None
    flip_y: bool | None = None
    flip_z: bool | None = None
    offset_y_mm: float | None = None
    offset_z_mm: float | None = None
    origin: str | None = None


@dataclass(frozen=True)
class WheelConfig:
    """``[wheel]``: a profile file or a generator, the nominal rolling radius and the reading
    options; both wheels (mirrored) unless ``[wheel.left]`` / ``[wheel.right]`` say otherwise."""

    profile: Path | None = None      # resolved relative to the config file
    generator: str | None = None     # "S1002"
    format: str | None = None        # reader name; None = detect from extension/content
    nominal_radius_mm: float = 460.0
    flip_y: bool = False             # negate the lateral coordinate as read
    flip_z: bool = False             # negate the radius increment as read
    offset_y_mm: float = 0.0         # added to s after the flips and the origin
    offset_z_mm: float = 0.0         # added to the radius increment
    origin: str = "tape_circle"      # "tape_circle" or "flange_back" (s = 0 of the file)
    left: WheelSideConfig = field(default_factory=WheelSideConfig)
    right: WheelSideConfig = field(default_factory=WheelSideConfig)

    @property
    def nominal_radius_m(self) -> float:
        return self.nominal_radius_mm * 1e-3

    @property
    def per_side(self) -> bool:
        """True when either side has a section of its own."""
        return self.left != WheelSideConfig() or self.right != WheelSideConfig()

    def side(self, name: str) -> WheelConfig:
        """The resolved config of wheel ``name`` (no side sections left)."""
        return _resolve(self, getattr(self, name), WheelSideConfig)


@dataclass(frozen=True)
class RailSideConfig:
    """``[rail.left]`` / ``[rail.right]``: this rail's own keys; None = as in ``[rail]``."""

    profile: Path | None = None
    generator: str | None = None
    format: str | None = None
    inclination: str | float | None = None
    flip_y: bool | None = None
    flip_z: bool | None = None
    offset_y_mm: float | None = None
    offset_z_mm: float | None = None
    gauge_point: str | float | None = None
    gauge_depth_mm: float | None = None


@dataclass(frozen=True)
class RailConfig:
    """``[rail]``: a profile file or a generator, the cant to apply, reading options and the
    gauge point; both rails (mirrored) unless ``[rail.left]`` / ``[rail.right]`` say otherwise."""

    profile: Path | None = None
    generator: str | None = None     # "UIC60"
    format: str | None = None
    inclination: str | float = "1:20"  # "1:N", "none" (file already canted), or rad
    flip_y: bool = False
    flip_z: bool = False
    offset_y_mm: float = 0.0
    offset_z_mm: float = 0.0
    gauge_point: str | float = "depth"  # "depth", "first", "last", or v in mm
    gauge_depth_mm: float | None = None  # None: track.gauge_depth_mm
    left: RailSideConfig = field(default_factory=RailSideConfig)
    right: RailSideConfig = field(default_factory=RailSideConfig)

    @property
    def inclination_rad(self) -> float:
        return cant_rad(self.inclination)

    @property
    def per_side(self) -> bool:
        return self.left != RailSideConfig() or self.right != RailSideConfig()

    def side(self, name: str) -> RailConfig:
        """The resolved config of rail ``name`` (no side sections left)."""
        return _resolve(self, getattr(self, name), RailSideConfig)


_SOURCE = ("profile", "generator", "format")


def _resolve(base, side, empty_cls):
    """``base`` with the non-None keys of ``side``; a side that names its own profile or
    generator takes none of the base's source keys."""
    own = {f.name: getattr(side, f.name) for f in dataclasses.fields(side)
           if getattr(side, f.name) is not None}
    if "profile" in own or "generator" in own:
        for key in _SOURCE:
            own.setdefault(key, None)
    return dataclasses.replace(base, **own, left=empty_cls(), right=empty_cls())


@dataclass(frozen=True)
class TrackConfig:
    gauge_mm: float = 1435.0
    gauge_depth_mm: float = 14.0     # gauge measured this far below the top of rail


@dataclass(frozen=True)
class WheelsetConfig:
    back_to_back_mm: float = 1360.0
    tape_offset_mm: float = 70.0     # tape circle outboard of the flange back

    @property
    def tape_half_distance_m(self) -> float:
        """Lateral distance of each tape circle from the wheelset centre, m (0.75 m nominal)."""
        return (0.5 * self.back_to_back_mm + self.tape_offset_mm) * 1e-3


@dataclass(frozen=True)
class GridConfig:
    y_mm: tuple[float, float, int] = (-9.0, 9.0, 37)          # start, stop, count
    yaw_rad: tuple[float, float, int] = (-0.12, 0.12, 37)


@dataclass(frozen=True)
class MeshConfig:
    """Node spacings and the contact window (``[mesh]``)."""

    wheel_lateral_mm: float = 0.25         # arc-length spacing along the wheel profile
    wheel_circumferential_mm: float = 0.5  # arc spacing on the nominal radius
    rail_lateral_mm: float = 0.25          # arc-length spacing along the rail profile
    rail_longitudinal_mm: float = 0.5      # spacing along the track
    window: bool = True                    # mesh only where contact can occur
    window_gap_mm: float = 0.02            # window depth beyond the expected penetration


@dataclass(frozen=True)
class ContactConfig:
    method: str = "load_centre"            # one of CONTACT_METHODS or "reference"
    allowed_indentation_mm: float = 0.01   # C_max^amm of eq. (9)
    max_contacts_per_wheel: int = 2        # §4.6 double contact
    extrapolate: bool = True               # report the pose extrapolated to zero indentation
    roll: str = "solved"                   # "solved", or "zero" (reference only: Annex E Δr)


@dataclass(frozen=True)
class EquilibriumConfig:
    """Fictitious springs of eq. (1), the vertical load and the k_c iteration (§4.3)."""

    spring_N_per_m: float = 1.0e7  # noqa: N815 -- k_el on x_g, z_g
    torsion_spring_Nm_per_rad: float = 1.0e7  # noqa: N815 -- k_rot on roll, pitch
    vertical_load_N: float = 1.0e5  # noqa: N815 -- load on the centre of mass (paper §6)
    initial_kc_N_per_m: float = 1.0e10  # noqa: N815 -- k_c at step 2
    max_kc_N_per_m: float = 1.0e16  # noqa: N815 (unit in the name)
    max_iterations: int = 2000             # hard budget of contact evaluations per pose
    max_pose_time_s: float = 60.0          # wall-time budget of one pose's equilibrium, s
    # "newton" (line search + bracketing fallback) or "fixed_point"
    solver: str = "newton"


@dataclass(frozen=True)
class MaterialConfig:
    young_GPa: float = 206.0  # noqa: N815 (unit in the name)
    poisson: float = 0.3

    @property
    def young_Pa(self) -> float:  # noqa: N802
        return self.young_GPa * 1e9

    @property
    def shear_Pa(self) -> float:  # noqa: N802
        return self.young_Pa / (2.0 * (1.0 + self.poisson))


@dataclass(frozen=True)
class FlangeConfig:
    """Flange stiffness model of §4.5 (linear k_c factor from base to tip, the paper's
    chi = 0.082: ``lutmpi/contact/stiffness.py``)."""

    enabled: bool = True
    # radius increment (above the tape circle) where the flange base starts
    base_height_mm: float = 2.0


@dataclass(frozen=True)
class WheelWearSideConfig:
    """``[wear.wheel.left]`` / ``[wear.wheel.right]``: one wheel's own wear; None = as
    ``[wear.wheel]``."""

    flange_thinning_mm: float | None = None
    tread_hollowing_mm: float | None = None


@dataclass(frozen=True)
class WheelWearConfig:
    """``[wear.wheel]``: parametric wheel wear (applied by ``lutmpi/profiles/wear.py``), both
    wheels unless ``[wear.wheel.left]`` / ``[wear.wheel.right]`` say otherwise."""

    flange_thinning_mm: float = 0.0    # material removed from the flange face (Sd decreases)
    tread_hollowing_mm: float = 0.0    # depth of a hollow worn into the tread at the tape circle
    left: WheelWearSideConfig = field(default_factory=WheelWearSideConfig)
    right: WheelWearSideConfig = field(default_factory=WheelWearSideConfig)

    def side(self, name: str) -> WheelWearConfig:
        return _resolve(self, getattr(self, name), WheelWearSideConfig)


@dataclass(frozen=True)
class RailWearSideConfig:
    """``[wear.rail.left]`` / ``[wear.rail.right]``: one rail's own wear; None = as
    ``[wear.rail]``."""

    vertical_mm: float | None = None
    side_mm: float | None = None


@dataclass(frozen=True)
class RailWearConfig:
    """``[wear.rail]``: parametric wear applied to the rail head (``lutmpi/profiles/wear.py``),
    both rails unless ``[wear.rail.left]`` / ``[wear.rail.right]`` say otherwise."""

    vertical_mm: float = 0.0           # head height lost at the rail centre line
    side_mm: float = 0.0               # gauge-face material lost, measured at the gauge depth
    left: RailWearSideConfig = field(default_factory=RailWearSideConfig)
    right: RailWearSideConfig = field(default_factory=RailWearSideConfig)

    def side(self, name: str) -> RailWearConfig:
        return _resolve(self, getattr(self, name), RailWearSideConfig)


@dataclass(frozen=True)
class WearConfig:
    """``[wear]``: parametric wear of the chosen profiles; all zero = the profiles as given."""

    wheel: WheelWearConfig = field(default_factory=WheelWearConfig)
    rail: RailWearConfig = field(default_factory=RailWearConfig)

    @property
    def any(self) -> bool:
        """True when any wear parameter is non-zero."""
        vals = []
        for s in SIDE_NAMES:
            w, r = self.wheel.side(s), self.rail.side(s)
            vals += [w.flange_thinning_mm, w.tread_hollowing_mm, r.vertical_mm, r.side_mm]
        return any(v != 0.0 for v in vals)


@dataclass(frozen=True)
class OutputConfig:
    """``[output]``: which quantities and which methods a table holds (nothing else is computed)."""

    methods: tuple[str, ...] = ("load_centre",)
    quantities: tuple[str, ...] = ("all",)
    jumps: bool = True      # locate the contact jumps after the grid (lutmpi/table/jump_search.py)
    refine: bool = True     # refine the pieces between contact jumps (lutmpi/table/refine.py)
    refine_scale: float = 1.0  # factor on the refinement's tolerances (> 1: coarser, cheaper)
    mirror: bool = True     # a symmetric pair's jump step mirrors half its solves (jumps.Mirror)


@dataclass(frozen=True)
class Config:
    """A whole run configuration; ``text`` is the resolved TOML stored in every table."""

    wheel: WheelConfig
    rail: RailConfig
    track: TrackConfig = field(default_factory=TrackConfig)
    wheelset: WheelsetConfig = field(default_factory=WheelsetConfig)
    grid: GridConfig = field(default_factory=GridConfig)
    mesh: MeshConfig = field(default_factory=MeshConfig)
    contact: ContactConfig = field(default_factory=ContactConfig)
    equilibrium: EquilibriumConfig = field(default_factory=EquilibriumConfig)
    material: MaterialConfig = field(default_factory=MaterialConfig)
    flange: FlangeConfig = field(default_factory=FlangeConfig)
    output: OutputConfig = field(default_factory=OutputConfig)
    wear: WearConfig = field(default_factory=WearConfig)
    path: Path | None = None

    @property
    def text(self) -> str:
        """The fully resolved configuration as TOML (what every table stores)."""
        from lutmpi.config.load import config_to_toml

        return config_to_toml(self)
