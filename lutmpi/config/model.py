"""The configuration as frozen dataclasses. Lengths carry their unit in the field name (``_mm``) as
in the TOML; the ``*_m`` properties give SI values. Defaults here are THE defaults, documented in
``configs/defaults.toml`` (a test keeps the two in step). Loading and validation: ``load.py``."""

from __future__ import annotations

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
# Per-point quantities a table can hold (``[output] quantities``; "all" = every one). The names are
# the dataset names of ``lutmpi/table/schema.py``. ALWAYS_STORED are written whatever is selected.
QUANTITIES = ("z_g", "roll", "x_g", "pitch", "wheel_point", "rail_point", "normal", "indentation",
              "kc", "rolling_radius", "contact_angle", "wheel_s", "rail_v", "curvatures",
              "n_contacts", "force")
ALWAYS_STORED = ("status", "iterations", "compute_time")


@dataclass(frozen=True)
class WheelConfig:
    """``[wheel]``: a profile file or a generator, and the nominal rolling radius."""

    profile: Path | None = None      # resolved relative to the config file
    generator: str | None = None     # "S1002"
    format: str | None = None        # reader name; None = detect from extension/content
    nominal_radius_mm: float = 460.0

    @property
    def nominal_radius_m(self) -> float:
        return self.nominal_radius_mm * 1e-3


@dataclass(frozen=True)
class RailConfig:
    """``[rail]``: a profile file or a generator, and the inclination to apply."""

    profile: Path | None = None
    generator: str | None = None     # "UIC60"
    format: str | None = None
    inclination: str = "1:20"        # "1:20", "1:40", "1:30", or "none" (file already canted)

    @property
    def inclination_rad(self) -> float:
        return INCLINATIONS[self.inclination]


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
    window_margin_mm: float = 2.0          # extra margin around the window (both directions)


@dataclass(frozen=True)
class ContactConfig:
    method: str = "load_centre"            # one of CONTACT_METHODS or "reference"
    allowed_indentation_mm: float = 0.01   # C_max^amm of eq. (9)
    max_contacts_per_wheel: int = 2        # §4.6 double contact
    extrapolate: bool = True               # report the pose extrapolated to zero indentation


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
    """Flange stiffness model of §4.5 (Table 1 cantilever; linear k_c from base to tip)."""

    enabled: bool = True
    cantilever_b_mm: float = 320.0
    cantilever_h_mm: float = 45.0
    cantilever_l_mm: float = 27.5
    # radius increment (above the tape circle) where the flange base starts
    base_height_mm: float = 2.0


@dataclass(frozen=True)
class WheelWearConfig:
    """``[wear.wheel]``: parametric wheel wear (applied by ``lutmpi/profiles/wear.py``)."""

    flange_thinning_mm: float = 0.0    # material removed from the flange face (Sd decreases)
    tread_hollowing_mm: float = 0.0    # depth of a hollow worn into the tread at the tape circle


@dataclass(frozen=True)
class RailWearConfig:
    """``[wear.rail]``: parametric wear applied to the rail head (``lutmpi/profiles/wear.py``)."""

    vertical_mm: float = 0.0           # head height lost at the rail centre line
    side_mm: float = 0.0               # gauge-face material lost, measured at the gauge depth


@dataclass(frozen=True)
class WearConfig:
    """``[wear]``: parametric wear of the chosen profiles; all zero = the profiles as given."""

    wheel: WheelWearConfig = field(default_factory=WheelWearConfig)
    rail: RailWearConfig = field(default_factory=RailWearConfig)

    @property
    def any(self) -> bool:
        """True when any wear parameter is non-zero."""
        return any(v != 0.0 for v in (self.wheel.flange_thinning_mm, self.wheel.tread_hollowing_mm,
                                      self.rail.vertical_mm, self.rail.side_mm))


@dataclass(frozen=True)
class OutputConfig:
    """``[output]``: which quantities and which methods a table holds (nothing else is computed)."""

    methods: tuple[str, ...] = ("load_centre",)
    quantities: tuple[str, ...] = ("all",)
    refine: bool = True     # refine the pieces between contact jumps (lutmpi/table/jumps.py)


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
