"""The scene: a wheel profile and a rail profile placed on the track, meshed, with the numbers of
the solve — everything a pose solve needs, built once from a config and shared by all points.
Pure (no MPI, no files after construction) and picklable."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from lutmpi.config.model import Config
from lutmpi.contact.locus import LocusSolver
from lutmpi.contact.mesh import RailMesh, WheelMesh
from lutmpi.contact.stiffness import paper_flange_chi
from lutmpi.equilibrium.solver import EquilibriumOptions
from lutmpi.geometry.track import PlacedRail, WheelGeometry
from lutmpi.profiles.model import Profile


@dataclass(frozen=True)
class SolveSettings:
    """Settings of a pose solve (SI)."""

    method: str = "load_centre"
    max_contacts: int = 2
    window: bool = True
    window_gap: float = 2e-5  # m, rigid gap depth of the window beyond the penetration
    flange: bool = True
    flange_base_radius: float = float("nan")  # m
    flange_tip_radius: float = float("nan")  # m
    chi: float = 1.0


@dataclass(frozen=True, eq=False)
class Scene:
    """Placed wheel and rail, their meshes, the reference solver and the solve settings."""

    wheel: WheelGeometry
    rail: PlacedRail
    wheel_mesh: WheelMesh
    rail_mesh: RailMesh
    locus: LocusSolver
    equilibrium: EquilibriumOptions
    settings: SolveSettings
    config: Config | None = None

    @classmethod
    def from_profiles(
        cls,
        wheel: Profile,
        rail: Profile,
        *,
        r0: float = 0.46,
        tape_half_distance: float = 0.75,
        inclination: float = np.arctan(1 / 20),
        gauge: float = 1.435,
        gauge_depth: float = 0.014,
        spacing: tuple[float, float, float, float] = (2.5e-4, 5e-4, 2.5e-4, 5e-4),
        equilibrium: EquilibriumOptions | None = None,
        settings: SolveSettings | None = None,
        flange_base_height: float = 0.002,
        config: Config | None = None,
        locus_ds: float = 1e-4,
    ) -> Scene:
        """Build a scene from profiles (SI). ``spacing`` = (wheel lateral, wheel circumferential,
        rail lateral, rail longitudinal), m."""
        wg = WheelGeometry.place(wheel, r0, tape_half_distance)
        rg = PlacedRail.place(rail, inclination, gauge, gauge_depth)
        eq = equilibrium or EquilibriumOptions()
        st = settings or SolveSettings()
        if np.isnan(st.flange_base_radius):
            st = SolveSettings(
                **{
                    **st.__dict__,
                    "flange_base_radius": r0 + flange_base_height,
                    "flange_tip_radius": wg.flange_tip_radius(),
                }
            )
        return cls(
            wheel=wg,
            rail=rg,
            wheel_mesh=WheelMesh.build(wg, spacing[0], spacing[1]),
            rail_mesh=RailMesh.build(rg, spacing[2], spacing[3]),
            locus=LocusSolver(
                wg, rg, ds=locus_ds, double_tol=eq.allowed_indentation, max_contacts=st.max_contacts
            ),
            equilibrium=eq,
            settings=st,
            config=config,
        )

    @classmethod
    def from_config(cls, cfg: Config) -> Scene:
        """Load/generate the profiles of ``cfg``, apply its wear, and build the scene."""
        wheel, rail = load_scene_profiles(cfg)
        e, c, m = cfg.equilibrium, cfg.contact, cfg.mesh
        eq = EquilibriumOptions(
            k_el=e.spring_N_per_m,
            k_rot=e.torsion_spring_Nm_per_rad,
            load=e.vertical_load_N,
            kc0=e.initial_kc_N_per_m,
            kc_max=e.max_kc_N_per_m,
            allowed_indentation=c.allowed_indentation_mm * 1e-3,
            max_iterations=e.max_iterations,
            max_pose_time=e.max_pose_time_s,
            solver=e.solver,
            extrapolate=c.extrapolate,
        )
        f = cfg.flange
        chi = paper_flange_chi() if f.enabled else 1.0
        st = SolveSettings(
            method=c.method,
            max_contacts=c.max_contacts_per_wheel,
            window=m.window,
            window_gap=m.window_gap_mm * 1e-3,
            flange=f.enabled,
            chi=chi,
        )
        return cls.from_profiles(
            wheel,
            rail,
            r0=cfg.wheel.nominal_radius_m,
            tape_half_distance=cfg.wheelset.tape_half_distance_m,
            inclination=cfg.rail.inclination_rad,
            gauge=cfg.track.gauge_mm * 1e-3,
            gauge_depth=cfg.track.gauge_depth_mm * 1e-3,
            spacing=(
                m.wheel_lateral_mm * 1e-3,
                m.wheel_circumferential_mm * 1e-3,
                m.rail_lateral_mm * 1e-3,
                m.rail_longitudinal_mm * 1e-3,
            ),
            equilibrium=eq,
            settings=st,
            flange_base_height=f.base_height_mm * 1e-3,
            config=cfg,
        )


def load_scene_profiles(cfg: Config) -> tuple[Profile, Profile]:
    """The wheel and rail profiles of a config (file or generator), with parametric wear."""
    from lutmpi.profiles.readers import read_profile
    from lutmpi.profiles.standard import generate

    w, r = cfg.wheel, cfg.rail
    wheel = (
        generate(w.generator)
        if w.generator
        else read_profile(w.profile, kind="wheel", format=w.format)
    )
    rail = (
        generate(r.generator)
        if r.generator
        else read_profile(r.profile, kind="rail", format=r.format)
    )
    if cfg.wear.any:
        from lutmpi.profiles import wear

        ww, rw = cfg.wear.wheel, cfg.wear.rail
        if ww.flange_thinning_mm:
            wheel = wear.flange_thinning(wheel, ww.flange_thinning_mm)
        if ww.tread_hollowing_mm:
            wheel = wear.tread_hollowing(wheel, ww.tread_hollowing_mm)
        if rw.vertical_mm:
            rail = wear.rail_vertical_wear(rail, rw.vertical_mm)
        if rw.side_mm:
            rail = wear.rail_side_wear(rail, rw.side_mm)
    return wheel, rail
