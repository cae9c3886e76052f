"""Profiles: the normalized :class:`Profile`, readers (format registry) and generators."""

from lutmpi.profiles.model import Profile

__all__ = ["Profile"]
