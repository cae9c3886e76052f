"""Wheelset dynamics on the lookup table (§6). Pure numerics: numpy/scipy only."""

from lutmpi.dynamics.creep import kalker_coefficients, linear_creep_forces, saturation_factor

__all__ = ["kalker_coefficients", "linear_creep_forces", "saturation_factor"]
