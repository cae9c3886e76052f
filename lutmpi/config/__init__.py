"""Run configuration: TOML → frozen dataclasses (``model.py``), strict loading (``load.py``) and
pure sweep expansion (``sweep.py``). No MPI, no HDF5 here."""

from lutmpi.config.load import config_from_dict, config_to_toml, load_config
from lutmpi.config.model import Config
from lutmpi.config.sweep import RunSpec, expand_sweep

__all__ = ["Config", "RunSpec", "config_from_dict", "config_to_toml", "expand_sweep", "load_config"]
