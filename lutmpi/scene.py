"""The scene: each wheel and each rail placed on the track and meshed, the rigid-contact solver
and the numbers of the solve — everything a pose solve needs, built once and shared by all
points. Typed and frozen; pure (no MPI, no files, no config after construction) and picklable.

Each side (``"left"``, ``"right"``) has its own :class:`SideScene`: wheel and rail geometry, their
meshes and the flange-stiffness radii. A symmetric wheelset on a symmetric track is the special
case where both sides are built from the same profiles (mirrored). The config is read only by
:func:`lutmpi.scene_config.scene_from_config` (the edge).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from functools import cached_property
from typing import TypeVar

import numpy as np

from lutmpi.contact.locus import LocusSampling, LocusSolver
from lutmpi.contact.mesh import RailMesh, WheelMesh
from lutmpi.equilibrium.solver import EquilibriumOptions
from lutmpi.errors import GeometryError
from lutmpi.geometry.track import SIDES, PlacedRail, WheelGeometry
from lutmpi.profiles.model import Profile

T = TypeVar("T")


@dataclass(frozen=True)
class SolveSettings:
    """Settings of a pose solve (SI)."""

    method: str = "load_centre"
    max_contacts: int = 2
    window: bool = True
    window_gap: float = 2e-5  # m, rigid gap depth of the window beyond the penetration
    flange: bool = True
    chi: float = 1.0
    hold_roll: bool = False  # reference only: roll held at zero (EN 15302 Annex E's Δr)


@dataclass(frozen=True, eq=False)
class SideScene:
    """One wheel on its rail: placed geometry, meshes and the §4.5 flange radii (SI).

    ``flange_base_radius`` / ``flange_tip_radius`` bound the flange-stiffness interpolation;
    ``samp`` are the locus samples of the wheel (radius at every 0.1 mm of ``s``)."""

    name: str
    sign: float
    wheel: WheelGeometry
    rail: PlacedRail
    wheel_mesh: WheelMesh
    rail_mesh: RailMesh
    flange_base_radius: float
    flange_tip_radius: float
    samp: LocusSampling

    @cached_property
    def rail_point_args(self) -> tuple:
        """``(ppolys, u_min, u_max)`` of the placed rail for
        :func:`lutmpi.pose.rigid._rail_points` (made once: every reference pose reads them,
        and the rail's properties build them per call)."""
        rail = self.rail
        return rail.ppolys, rail.u_min, rail.u_max

    @cached_property
    def record_args(self) -> tuple:
        """The side's arguments of :func:`lutmpi.contact.records.record_geometry` after the
        contacts' own (the wheel's and placed rail's splines and constants, the curvature's
        half base), made once: every pose's records read them."""
        from lutmpi.contact.records import CURV_BASE

        wheel, rail = self.wheel, self.rail
        return (wheel.profile.ppolys, wheel.r0, wheel.s_min, wheel.s_max, rail.ppolys,
                (rail.u_min, rail.u_max, rail.gauge, rail.v_gp, rail.w_top, rail.inclination),
                CURV_BASE)


@dataclass(frozen=True, eq=False)
class Scene:
    """Both sides, the reference (locus) solver, the equilibrium and the solve settings."""

    sides: Mapping[str, SideScene]
    locus: LocusSolver
    equilibrium: EquilibriumOptions
    settings: SolveSettings

    def side(self, name: str) -> SideScene:
        return self.sides[name]

    @property
    def lever(self) -> float:
        """Mean tape-circle distance of the two wheels from the wheelset centre, m."""
        return 0.5 * (self.sides["left"].wheel.d + self.sides["right"].wheel.d)

    @property
    def symmetric(self) -> bool:
        """True when both sides share the same wheel and rail geometry (mirrored)."""
        left, right = self.sides["left"], self.sides["right"]
        return left.wheel is right.wheel and left.rail is right.rail

    def _mirrored(self, attr: str):
        if not self.symmetric:
            raise AttributeError(f"Scene.{attr}: the two sides differ; use scene.side(name)")
        return getattr(self.sides["left"], attr)

    # shortcuts for a mirrored scene (tests, scripts); pure code uses scene.side(name)
    wheel = property(lambda self: self._mirrored("wheel"))
    rail = property(lambda self: self._mirrored("rail"))
    wheel_mesh = property(lambda self: self._mirrored("wheel_mesh"))
    rail_mesh = property(lambda self: self._mirrored("rail_mesh"))

    @classmethod
    def from_profiles(
        cls,
        wheel: Profile | Mapping[str, Profile],
        rail: Profile | Mapping[str, Profile],
        *,
        r0: float | Mapping[str, float] = 0.46,
        tape_half_distance: float | Mapping[str, float] = 0.75,
        inclination: float | Mapping[str, float] = np.arctan(1 / 20),
        gauge: float = 1.435,
        gauge_depth: float | Mapping[str, float] = 0.014,
        gauge_v: float | None | Mapping[str, float | None] = None,
        spacing: tuple[float, float, float, float] = (2.5e-4, 5e-4, 2.5e-4, 5e-4),
        equilibrium: EquilibriumOptions | None = None,
        settings: SolveSettings | None = None,
        flange_base_height: float = 0.002,
        locus_ds: float = 1e-4,
    ) -> Scene:
        """Build a scene from profiles (SI).

        Every geometric argument is one value for both sides (mirrored) or a mapping
        ``{"left": ..., "right": ...}``. ``spacing`` = (wheel lateral, wheel circumferential,
        rail lateral, rail longitudinal), m. ``gauge_v``: the rail profile's own lateral
        coordinate of the gauge point (None: found ``gauge_depth`` below the top of rail)."""
        eq = equilibrium or EquilibriumOptions()
        st = settings or SolveSettings()
        per = {k: _per_side(v) for k, v in dict(
            wheel=wheel, rail=rail, r0=r0, d=tape_half_distance, inc=inclination,
            depth=gauge_depth, gv=gauge_v).items()}
        wheels = {"left": _on_side("left", WheelGeometry.place, per["wheel"]["left"],
                                   per["r0"]["left"], per["d"]["left"])}
        rails = {"left": _on_side("left", PlacedRail.place, per["rail"]["left"],
                                  per["inc"]["left"], gauge, per["depth"]["left"],
                                  gauge_v=per["gv"]["left"])}
        # a mirrored right side shares the left side's objects
        if all(per[k]["right"] is per[k]["left"] or per[k]["right"] == per[k]["left"]
               for k in ("r0", "d")) and per["wheel"]["right"] is per["wheel"]["left"]:
            wheels["right"] = wheels["left"]
        else:
            wheels["right"] = _on_side("right", WheelGeometry.place, per["wheel"]["right"],
                                       per["r0"]["right"], per["d"]["right"])
        if all(per[k]["right"] == per[k]["left"] for k in ("inc", "depth", "gv")) \
                and per["rail"]["right"] is per["rail"]["left"]:
            rails["right"] = rails["left"]
        else:
            rails["right"] = _on_side("right", PlacedRail.place, per["rail"]["right"],
                                      per["inc"]["right"], gauge, per["depth"]["right"],
                                      gauge_v=per["gv"]["right"])
        locus = LocusSolver(wheels, rails, ds=locus_ds, double_tol=eq.allowed_indentation,
                            max_contacts=st.max_contacts, hold_roll=st.hold_roll)
        meshes: dict[int, object] = {}
        sides = {}
        for name in SIDES:
            w, r = wheels[name], rails[name]
            wm = meshes.get(id(w)) or WheelMesh.build(w, spacing[0], spacing[1])
            rm = meshes.get(id(r)) or RailMesh.build(r, spacing[2], spacing[3])
            meshes[id(w)], meshes[id(r)] = wm, rm
            sides[name] = SideScene(
                name=name, sign=SIDES[name], wheel=w, rail=r, wheel_mesh=wm, rail_mesh=rm,
                flange_base_radius=w.r0 + flange_base_height,
                flange_tip_radius=w.flange_tip_radius(), samp=locus.sides[name].samp)
        return cls(sides=sides, locus=locus, equilibrium=eq, settings=st)

    @classmethod
    def from_config(cls, cfg) -> Scene:
        """The scene of a :class:`~lutmpi.config.model.Config` (see :mod:`lutmpi.scene_config`)."""
        from lutmpi.scene_config import scene_from_config

        return scene_from_config(cfg)


def _per_side(value: T | Mapping[str, T]) -> dict[str, T]:
    if isinstance(value, Mapping):
        if set(value) != set(SIDES):
            raise ValueError(f"expected a value per side {list(SIDES)}, got {list(value)}")
        return dict(value)
    return {name: value for name in SIDES}


def _on_side(side: str, place, *args, **kw):
    """``place(*args, **kw)`` (a wheel's or a rail's placement); a :class:`GeometryError` it
    raises carries ``side`` (``"left"``/``"right"``), so that an error of two sides with one
    profile file names the side's own config key (:func:`lutmpi.scene_config.scene_from_config`)."""
    try:
        return place(*args, **kw)
    except GeometryError as exc:
        exc.side = side
        raise
