"""Lookup tables: schema, grid, compute, HDF5 I/O and the :class:`Table` reader/interpolator."""

from lutmpi.table.api import Table

__all__ = ["Table"]
