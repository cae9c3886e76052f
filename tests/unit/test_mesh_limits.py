"""A mesh far too fine for memory is a clear error before any allocation (issue 13, item 8: a
0.001 mm mesh, inside the allowed range, ended in a MemoryError traceback)."""

from __future__ import annotations

from lutmpi.cli import main


def test_micrometre_mesh_is_a_clear_error(tmp_path, capsys):
    cfg = tmp_path / "fine.toml"
    cfg.write_text('[wheel]\ngenerator = "S1002"\n[rail]\ngenerator = "UIC60"\n[mesh]\n'
                   + "".join(f"{k} = 0.001\n" for k in (
                       "wheel_lateral_mm", "wheel_circumferential_mm", "rail_lateral_mm",
                       "rail_longitudinal_mm")))
    rc = main(["solve", str(cfg), "--pose", "0", "0"])
    err = capsys.readouterr().err
    assert rc == 1 and "Traceback" not in err
    # the window of S1002 on UIC60 at y = 0 at 1 um x 1 um: ~1.8e8 nodes, ~18 GB
    assert "contact window would hold" in err and "coarsen [mesh]" in err, err
