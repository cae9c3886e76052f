"""lutmpi: MPI-parallel wheel-rail contact lookup tables."""

__version__ = "0.1.0"
