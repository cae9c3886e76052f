"""The edge between the configuration and the pure code: :func:`scene_from_config` reads or
generates the profiles a :class:`~lutmpi.config.model.Config` names (per side), applies its wear
and reading options, and builds the typed, frozen :class:`~lutmpi.scene.Scene`. Nothing below
this module sees the config."""

from __future__ import annotations

from lutmpi.config.model import SIDE_NAMES, Config
from lutmpi.contact.stiffness import paper_flange_chi
from lutmpi.equilibrium.solver import EquilibriumOptions
from lutmpi.errors import ConfigError, GeometryError, ProfileError
from lutmpi.profiles.model import Profile
from lutmpi.profiles.options import ReadOptions
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
        max_pose_time=e.max_pose_time_s,
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
        hold_roll=c.roll == "zero",
    )


def scene_from_config(cfg: Config) -> Scene:
    """Load/generate the profiles of ``cfg`` for each side, apply its wear and reading options,
    and build the scene. Sides whose resolved keys are equal share one profile (mirrored)."""
    wheels, rails = side_profiles(cfg)
    r0, d, inc, depth, gv = {}, {}, {}, {}, {}
    for name in SIDE_NAMES:
        wc, rc = cfg.wheel.side(name), cfg.rail.side(name)
        r0[name] = wc.nominal_radius_m
        d[name] = cfg.wheelset.tape_half_distance_m
        inc[name] = rc.inclination_rad
        depth[name] = (rc.gauge_depth_mm if rc.gauge_depth_mm is not None
                       else cfg.track.gauge_depth_mm) * 1e-3
        gv[name] = _gauge_v(rc.gauge_point, rails[name],
                            f"rail.{name}.gauge_point"
                            if getattr(cfg.rail, name).gauge_point is not None
                            else "rail.gauge_point",
                            None if cfg.path is None else str(cfg.path))
    try:
        return _scene(cfg, wheels, rails, r0, d, inc, depth, gv)
    except GeometryError as exc:   # a placement the config's keys cannot give: name the key
        raise ConfigError(str(exc), key=_placement_key(cfg, wheels, rails, str(exc),
                                                       getattr(exc, "side", None)),
                          path=None if cfg.path is None else str(cfg.path)) from None


def _placement_key(cfg: Config, wheels: dict, rails: dict, message: str,
                   side: str | None = None) -> str | None:
    """The config key that set what a placement error (``rail NAME: ...`` / ``wheel NAME:
    ...``) is about: a rail's gauge point or gauge depth, or the wheel's profile; ``side``:
    the side whose placement raised it, when known (two sides can read one file)."""
    for name in (side,) if side in SIDE_NAMES else SIDE_NAMES:
        own_rail, rc = getattr(cfg.rail, name), cfg.rail.side(name)
        if message.startswith(f"rail {rails[name].name}:"):
            if rc.gauge_point != "depth":
                return f"rail.{name}.gauge_point" if own_rail.gauge_point is not None \
                    else "rail.gauge_point"
            if own_rail.gauge_depth_mm is not None:
                return f"rail.{name}.gauge_depth_mm"
            return "rail.gauge_depth_mm" if rc.gauge_depth_mm is not None \
                else "track.gauge_depth_mm"
        if message.startswith(f"wheel {wheels[name].name}:"):
            return _source_key(cfg.wheel, "wheel", name)
    return None


def _scene(cfg: Config, wheels, rails, r0, d, inc, depth, gv) -> Scene:
    m = cfg.mesh
    return Scene.from_profiles(
        wheels, rails, r0=r0, tape_half_distance=d, inclination=inc,
        gauge=cfg.track.gauge_mm * 1e-3, gauge_depth=depth, gauge_v=gv,
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


#: how far (m) the file's first or last point may lie beyond the profile's ends and still name
#: that end (reading drops the points a steep face shadows: a file extending its gauge face
#: straight down, as avg_low2.ban does by 1 um, ends at the point above)
END_TOL_M = 1e-5


def _gauge_v(point: str | float, rail: Profile, key: str = "rail.gauge_point",
             path: str | None = None) -> float | None:
    """The rail profile's lateral coordinate of an explicit gauge point (m), or None.

    ``key`` names the config key in errors (``rail.gauge_point`` or ``rail.<side>.gauge_point``),
    ``path`` the config file.
    """
    if point == "depth":
        return None
    if point in ("first", "last"):
        if f"file_{point}_point_mm" not in rail.meta:
            raise ConfigError(f"gauge_point = {point!r} names a point of a rail profile file; "
                              f"the rail {rail.name} is not read from a file (a generator): give "
                              "a depth below the rail top (gauge_depth_mm) or a lateral "
                              "coordinate in mm", key=key, path=path)
        v = rail.meta[f"file_{point}_point_mm"][0] * 1e-3
        if rail.y_min - END_TOL_M <= v <= rail.y_max + END_TOL_M:
            v = min(max(v, rail.y_min), rail.y_max)
        return v
    v = float(point) * 1e-3
    if rail.y_min - END_TOL_M <= v <= rail.y_max + END_TOL_M:   # an end point copied, rounded
        return min(max(v, rail.y_min), rail.y_max)
    raise ConfigError(f"gauge_point = {point!r} mm is outside the rail profile {rail.name} "
                      f"(v = {rail.y_min * 1e3:.3f} .. {rail.y_max * 1e3:.3f} mm)", key=key,
                      path=path)


def side_profiles(cfg: Config) -> tuple[dict[str, Profile], dict[str, Profile]]:
    """The wheel and rail profile of each side (file or generator, reading options, wear);
    equal resolved sections give the same object."""
    cache: dict = {}
    wheels, rails = {}, {}
    for name in SIDE_NAMES:
        for kind, sec, out in (("wheel", cfg.wheel, wheels), ("rail", cfg.rail, rails)):
            res = sec.side(name)
            wear = getattr(cfg.wear, kind).side(name)
            key = (kind, res, wear)
            if key not in cache:
                cache[key] = _load(cfg, kind, res, wear, _source_key(sec, kind, name),
                                   _thinning_key(cfg, kind, name))
            out[name] = cache[key]
    return wheels, rails


def _source_key(sec, kind: str, side: str) -> str:
    own = getattr(sec, side)
    return f"{kind}.{side}.profile" if own.profile is not None else f"{kind}.profile"


def _thinning_key(cfg: Config, kind: str, side: str) -> str:
    own = kind == "wheel" and getattr(cfg.wear.wheel, side).flange_thinning_mm is not None
    return f"wear.wheel.{side}.flange_thinning_mm" if own else "wear.wheel.flange_thinning_mm"


def _load(cfg: Config, kind: str, sec, wear_cfg, key: str,
          thinning_key: str = "wear.wheel.flange_thinning_mm") -> Profile:
    """One profile: generated, or read with the section's reading options; then the wear."""
    from lutmpi.profiles import wear
    from lutmpi.profiles.readers import read_profile
    from lutmpi.profiles.standard import generate

    if sec.generator:
        prof = generate(sec.generator)
    else:
        opts = ReadOptions(flip_y=sec.flip_y, flip_z=sec.flip_z, offset_y_mm=sec.offset_y_mm,
                           offset_z_mm=sec.offset_z_mm,
                           origin=getattr(sec, "origin", "tape_circle"),
                           tape_offset_mm=cfg.wheelset.tape_offset_mm)
        try:
            prof = read_profile(sec.profile, kind=kind, format=sec.format, options=opts)
        except ProfileError as exc:
            raise ConfigError(f"cannot read the {kind} profile: {exc}", key=key,
                              path=None if cfg.path is None else str(cfg.path)) from None
    if kind == "wheel":
        if wear_cfg.flange_thinning_mm:
            prof = _thinned(prof, wear_cfg.flange_thinning_mm, thinning_key,
                            None if cfg.path is None else str(cfg.path))
        if wear_cfg.tread_hollowing_mm:
            prof = wear.tread_hollowing(prof, wear_cfg.tread_hollowing_mm)
    else:
        if wear_cfg.vertical_mm:
            prof = wear.rail_vertical_wear(prof, wear_cfg.vertical_mm)
        if wear_cfg.side_mm:
            prof = wear.rail_side_wear(prof, wear_cfg.side_mm)
    return prof


def _thinned(wheel: Profile, thickness_mm: float, key: str, path: str | None) -> Profile:
    """``wheel`` with its flange thinned by ``thickness_mm``, or a ConfigError naming ``key`` and
    the largest thinning this wheel takes: the thinning tapers to zero at the flange tip, which
    stays, so the face above the Sd height steepens with it until it folds over itself or passes
    the placement's slope limit, beyond which the flange tip would be no contact candidate."""
    from lutmpi.geometry.track import MAX_SLOPE_DEG, WheelCut
    from lutmpi.profiles import wear

    def worn_or_why(t: float) -> Profile | str:
        try:
            worn = wear.flange_thinning(wheel, t)
        except ProfileError:
            return "folds the flange face over itself"
        # WheelGeometry.place cuts the wheel it places again (~1 ms, not passed on): the tread
        # hollowing applied after the thinning changes that wheel, and the scene is built from
        # profiles (Scene.from_profiles), not from cuts
        if WheelCut.of(worn).tip_dropped:
            return (f"leaves a stretch of the face steeper than {MAX_SLOPE_DEG:g} deg, beyond "
                    "which the flange tip would be no contact candidate")
        return worn

    out = worn_or_why(thickness_mm)
    if isinstance(out, Profile):
        return out
    most = _last_that_works(lambda t: isinstance(worn_or_why(t), Profile), thickness_mm)
    raise ConfigError(f"{thickness_mm:g} mm is more than the wheel {wheel.name} takes: the "
                      f"thinning tapers to zero at the flange tip, which stays, and at "
                      f"{thickness_mm:g} mm it {out}; every thinning up to {most:.2f} mm works "
                      "for this wheel", key=key, path=path)


def _last_that_works(works, upto: float) -> float:
    """The largest multiple of 0.01 below ``upto`` up to which ``works`` holds at every step of
    0.1, then 0.01 (a scan, not a bisection: the spline's steepest slope on the face wiggles by
    ~0.2 deg with the thinning, so the thinnings past the limit are not one interval)."""
    good = 0.0
    for step in (0.1, 0.01):
        t = round(good + step, 2)
        while t < upto and works(t):
            good, t = t, round(t + step, 2)
    return good
