"""shared/ is found through LUTMPI_SHARED, beside the repository, or /work/shared."""

from __future__ import annotations

from lutmpi import paths


def test_env_var_wins(monkeypatch, tmp_path):
    monkeypatch.setenv("LUTMPI_SHARED", str(tmp_path))
    assert paths.shared_dir() == tmp_path.resolve()


def test_env_var_pointing_nowhere_gives_none(monkeypatch, tmp_path):
    monkeypatch.setenv("LUTMPI_SHARED", str(tmp_path / "missing"))
    assert paths.shared_dir() is None


def test_sibling_of_repository(monkeypatch, tmp_path):
    (tmp_path / "shared").mkdir()
    (tmp_path / "repo").mkdir()
    monkeypatch.delenv("LUTMPI_SHARED", raising=False)
    monkeypatch.setattr(paths, "REPO_ROOT", tmp_path / "repo")
    assert paths.shared_dir() == (tmp_path / "shared").resolve()


def test_repo_root_holds_the_package():
    assert (paths.REPO_ROOT / "lutmpi" / "__init__.py").is_file()
