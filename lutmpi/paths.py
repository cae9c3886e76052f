"""Where the project's files are: the repository root and the optional ``shared/`` beside it."""

from __future__ import annotations

import os
from pathlib import Path

REPO_ROOT = Path(__file__).resolve().parents[1]


def shared_dir() -> Path | None:
    """Locate the ``shared/`` folder (paper, reference profiles), or ``None`` when absent.

    Tried in order: the ``LUTMPI_SHARED`` environment variable, ``<repo>/../shared`` (CI's clone has
    it beside the repository), ``/work/shared``. Only an existing directory counts; a set but wrong
    ``LUTMPI_SHARED`` is not silently replaced by another folder, it gives ``None``.

    Returns
    -------
    pathlib.Path or None
        The directory, resolved.
    """
    env = os.environ.get("LUTMPI_SHARED")
    if env:
        path = Path(env).expanduser()
        return path.resolve() if path.is_dir() else None
    for candidate in (REPO_ROOT.parent / "shared", Path("/work/shared")):
        if candidate.is_dir():
            return candidate.resolve()
    return None
