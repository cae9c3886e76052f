"""Profiles: the normalized :class:`Profile`, readers (format registry), generators and wear."""

from __future__ import annotations

from pathlib import Path

from lutmpi.errors import ProfileError
from lutmpi.profiles.model import Profile
from lutmpi.profiles.readers import READERS, read_profile, register_reader
from lutmpi.profiles.standard import GENERATORS, generate, s1002, uic60


def load_profile(spec_path: str | Path | None = None, generator: str | None = None,
                 format: str | None = None, kind: str | None = None, *,
                 cant_rad: float | None = None, smoothing: float | None = None) -> Profile:
    """The profile a config names: a file (``profile = ...``) or a generator (``generator = ...``).

    Parameters
    ----------
    spec_path : str or Path, optional
        Profile file (already resolved against the config's folder).
    generator : str, optional
        A name in :data:`GENERATORS` (``"S1002"``, ``"UIC60"``, ``"60E1"``).
    format : str, optional
        Reader name for the file; None detects it.
    kind : {"wheel", "rail"}, optional
        Expected kind; a profile of the other kind raises.
    cant_rad, smoothing : float, optional
        Passed to :func:`read_profile` (files only).

    Raises
    ------
    ProfileError
        Neither or both of ``spec_path`` and ``generator``, an unknown generator, the wrong kind,
        or any reader error.
    """
    if (spec_path is None) == (generator is None):
        raise ProfileError("give exactly one of a profile file or a generator, got "
                           f"profile={spec_path!r}, generator={generator!r}")
    if spec_path is not None:
        return read_profile(spec_path, kind=kind, format=format, cant_rad=cant_rad,
                            smoothing=smoothing)
    prof = generate(generator)
    if kind is not None and prof.kind != kind:
        raise ProfileError(f"generator {generator!r} makes a {prof.kind}, but a {kind} is expected",
                           path=f"generator:{generator}")
    return prof


__all__ = ["GENERATORS", "READERS", "Profile", "generate", "load_profile", "read_profile",
           "register_reader", "s1002", "uic60"]
