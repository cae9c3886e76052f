"""A table is self-describing for tools other than lutmpi: h5dump (Debian's hdf5-tools, installed
by scripts/setup.sh) shows the units of every dataset and the resolved config (issue 4)."""

from __future__ import annotations

import re
import shutil
import subprocess
from pathlib import Path

import pytest

from lutmpi.cli import main

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.skipif(shutil.which("h5dump") is None, reason="h5dump (hdf5-tools) not installed")
def test_h5dump_sees_units_and_config(tmp_path):
    out = tmp_path / "t.h5"
    assert main(["build", str(ROOT / "configs" / "small_test.toml"), "-o", str(out)]) == 0
    text = subprocess.run(["h5dump", "-A", str(out)], capture_output=True, text=True,
                          check=True).stdout
    assert 'ATTRIBUTE "config_toml"' in text and "[wheel]" in text
    n_datasets = len(re.findall(r'^\s*DATASET "', text, flags=re.M))
    n_units = text.count('ATTRIBUTE "units"')
    assert n_datasets > 10 and n_units == n_datasets, (n_datasets, n_units)
    assert '"m"' in text and '"rad"' in text
