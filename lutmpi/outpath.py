"""Checks of an output path made by every command *before* its work (issue 13): a command that
would fail to write its result after minutes of compute fails at once instead, naming the path.

The checks: the folder exists and takes a new file (``access(2)``, which reports a read-only file
system, then an empty probe file created and removed: root passes ``access`` on ``/proc``), and
what already sits at the path is a regular file (a device node, a folder or a socket is never
replaced).
"""

from __future__ import annotations

import os
import uuid
from pathlib import Path

from lutmpi.errors import OutputError


def check_output_file(path: str | os.PathLike[str] | None, what: str = "output file",
                      inputs: tuple[str | os.PathLike[str] | None, ...] = ()) -> Path:
    """Raise unless ``path`` can be written as a file and is none of the command's ``inputs``
    (writing it would destroy the input: ``lutmpi query T.h5 -o T.h5``); return it as a
    :class:`Path`.

    Raises
    ------
    OutputError
        Empty name, an existing folder / device / other non-regular file at the path, a missing
        or unwritable parent folder, the path of an input.
    """
    if path is None or not str(path).strip() or not Path(path).name:
        raise OutputError(f"the {what} path {'' if path is None else str(path)!r} names no file")
    p = Path(path)
    check_not_input(p, what, inputs)
    if p.is_dir():
        raise OutputError(f"{p} ({what}) is a folder; give a file name")
    if p.exists() and not p.is_file():
        raise OutputError(f"{p} ({what}) exists and is not a regular file; it is never replaced")
    _writable_folder(p.parent if str(p.parent) else Path("."), what)
    return p


def check_not_input(path: str | os.PathLike[str], what: str,
                    inputs: tuple[str | os.PathLike[str] | None, ...]) -> None:
    """Raise :class:`OutputError` where ``path`` names one of ``inputs`` (the same file by
    inode, or the same absolute path): writing it would destroy that input (a build's ``-o``
    given its own config or a profile file; ``-`` and ``None`` are no file)."""
    p = Path(path)
    for src in inputs:
        if src is not None and str(src) != "-" and _same_file(p, Path(src)):
            raise OutputError(f"{p} ({what}) is the command's input {src}: writing it would "
                              "destroy the input; give another output path")


def check_figure_file(path: str | os.PathLike[str] | None, what: str = "figure",
                      inputs: tuple[str | os.PathLike[str] | None, ...] = ()) -> Path:
    """:func:`check_output_file`, and the file's extension one that matplotlib writes (``.png``,
    ``.pdf``, ``.svg``, ...), not found out after the work."""
    p = check_output_file(path, what, inputs)
    from matplotlib.backend_bases import FigureCanvasBase

    kinds = FigureCanvasBase.get_supported_filetypes()
    if p.suffix.lstrip(".").lower() not in kinds:
        raise OutputError(f"{p} ({what}): a figure file needs one of the extensions "
                          f"{', '.join('.' + k for k in sorted(kinds))}, got "
                          f"{p.suffix or 'none'!r}")
    return p


def check_output_dir(path: str | os.PathLike[str] | None, what: str = "output folder") -> Path:
    """Raise unless ``path`` is a writable folder or can be created as one; return it."""
    if path is None or not str(path).strip():
        raise OutputError(f"the {what} path is empty")
    p = Path(path)
    if p.exists():
        if not p.is_dir():
            raise OutputError(f"{p} ({what}) exists and is not a folder")
        _writable_folder(p, what)
        return p
    parent = next((a for a in p.absolute().parents if a.exists()), Path("/"))
    if not parent.is_dir():
        raise OutputError(f"{p} ({what}) cannot be created: {parent} is not a folder")
    _writable_folder(parent, what)
    return p


def _writable_folder(folder: Path, what: str) -> None:
    if not folder.is_dir():
        raise OutputError(f"the folder {folder} of the {what} does not exist or is not a folder")
    if not os.access(folder, os.W_OK | os.X_OK):
        raise OutputError(f"the folder {folder} of the {what} is not writable")
    probe = folder / f".lutmpi-probe-{uuid.uuid4().hex}"
    try:
        os.close(os.open(probe, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600))
    except OSError as exc:
        raise OutputError(f"the folder {folder} of the {what} is not writable "
                          f"({exc.strerror or exc})") from None
    try:
        probe.unlink()
    except OSError:         # the probe was made; a failed cleanup must not hide anything
        pass


def _same_file(a: Path, b: Path) -> bool:
    """Whether ``a`` and ``b`` name one file (the same inode where both exist, else the same
    absolute path)."""
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.absolute() == b.absolute()
