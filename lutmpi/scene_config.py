"""The edge between the configuration and the pure code: :func:`scene_from_config` reads or
generates the profiles a :class:`~lutmpi.config.model.Config` names (per side), applies its wear
and reading options, and builds the typed, frozen :class:`~lutmpi.scene.Scene`. Nothing below
this module sees the config."""

from __future__ import annotations

from lutmpi.config.model import Config
from lutmpi.contact.stiffness import paper_flange_chi
from lutmpi.equilibrium.solver import EquilibriumOptions
from lutmpi.profiles.model import Profile
from lutmpi.scene import Scene, SolveSettings


def equilibrium_options(cfg: Config) -> EquilibriumOptions:
    """The equilibrium numbers of ``cfg`` (SI)."""
    e, c = cfg.equilibrium, cfg.contact
    return EquilibriumOptions(
        k_el=e.spring_N_per_m,
        k_rot=e.torsion_spring_Nm_per_rad,
        load=e.vertical_load_N,
        kc0=e.initial_kc_N_per_m,
        kc_max=e.max_kc_N_per_m,
        allowed_indentation=c.allowed_indentation_mm * 1e-3,
        max_iterations=e.max_iterations,
        solver=e.solver,
        extrapolate=c.extrapolate,
    )


def solve_settings(cfg: Config) -> SolveSettings:
    """The pose-solve settings of ``cfg``."""
    c, m, f = cfg.contact, cfg.mesh, cfg.flange
    return SolveSettings(
        method=c.method,
        max_contacts=c.max_contacts_per_wheel,
        window=m.window,
        window_gap=m.window_gap_mm * 1e-3,
        flange=f.enabled,
        chi=paper_flange_chi() if f.enabled else 1.0,
    )


def scene_from_config(cfg: Config) -> Scene:
    """Load/generate the profiles of ``cfg``, apply its wear, and build the scene."""
    wheel, rail = load_scene_profiles(cfg)
    m = cfg.mesh
    return Scene.from_profiles(
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
        equilibrium=equilibrium_options(cfg),
        settings=solve_settings(cfg),
        flange_base_height=cfg.flange.base_height_mm * 1e-3,
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
