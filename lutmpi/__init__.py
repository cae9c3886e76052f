"""lutmpi: MPI-parallel wheel-rail contact lookup tables."""

__version__ = "0.1.0"


def __getattr__(name: str):
    # lazy: ``import lutmpi`` stays light; ``lutmpi.Table`` loads the table API on first use
    if name == "Table":
        from lutmpi.table import Table

        return Table
    raise AttributeError(f"module 'lutmpi' has no attribute {name!r}")
