"""Profile readers chosen by name from a registry; one entry point, :func:`read_profile`.

========  ======================  =====================================================
name      extensions              module (its docstring documents format + orientation)
========  ======================  =====================================================
simpack   ``.prw`` ``.prr``       :mod:`lutmpi.profiles.simpack`
miniprof  ``.whl`` ``.ban``       :mod:`lutmpi.profiles.miniprof`
plain     ``.csv`` ``.txt`` ...   :mod:`lutmpi.profiles.plaintext`
========  ======================  =====================================================

Format detection: ``format=`` wins; otherwise content markers (Simpack ``point.begin`` /
``header.begin``, MiniProf ``MPTypeNo`` / ``XYPoints`` / ``MINIPROF`` ...), then the extension, then
plain text. Every reader returns a :class:`~lutmpi.profiles._raw.RawProfile` in the normalized
orientation; :func:`lutmpi.profiles.validate.build_profile` does all checks and the trimming.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from lutmpi.errors import ProfileError
from lutmpi.profiles import miniprof, plaintext, simpack
from lutmpi.profiles._raw import RawProfile
from lutmpi.profiles.model import Profile
from lutmpi.profiles.options import ReadOptions, apply_options
from lutmpi.profiles.validate import build_profile


@dataclass(frozen=True)
class Reader:
    """A profile file format.

    Attributes
    ----------
    name : str
        Registry key (``format=`` / ``[wheel] format = ...``).
    extensions : tuple of str
        Lower-case file extensions with the dot.
    sniff : callable(str) -> bool
        True when the text carries this format's markers.
    parse : callable(list[str], str) -> RawProfile
        Lines and path to points in mm, normalized orientation, file order.
    """

    name: str
    extensions: tuple[str, ...]
    sniff: Callable[[str], bool]
    parse: Callable[[list[str], str], RawProfile]


READERS: dict[str, Reader] = {}


def register_reader(reader: Reader) -> Reader:
    """Add (or replace) a reader in :data:`READERS`; returns it."""
    READERS[reader.name] = reader
    return reader


register_reader(Reader("simpack", simpack.EXTENSIONS, simpack.sniff, simpack.parse))
register_reader(Reader("miniprof", miniprof.EXTENSIONS, miniprof.sniff, miniprof.parse))
register_reader(Reader("plain", plaintext.EXTENSIONS, plaintext.sniff, plaintext.parse))


def get_reader(name: str) -> Reader:
    """The reader called ``name``; an unknown name raises and lists the valid ones."""
    if name not in READERS:
        raise ProfileError(f"unknown profile format {name!r}; valid: {', '.join(READERS)}")
    return READERS[name]


def detect_format(path: str | Path, text: str) -> str:
    """Format name from content markers, then extension, then ``"plain"``."""
    for name, reader in READERS.items():
        if name != "plain" and reader.sniff(text):
            return name
    ext = Path(path).suffix.lower()
    for name, reader in READERS.items():
        if ext in reader.extensions:
            return name
    return "plain"


def _read_text(path: Path) -> str:
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise ProfileError("profile file not found", path=str(path)) from None
    except OSError as exc:
        raise ProfileError(f"cannot read profile file: {exc.strerror}", path=str(path)) from None
    if b"\x00" in data[:4096]:
        raise ProfileError("binary file, not a text profile", path=str(path))
    data = data.removeprefix(b"\xef\xbb\xbf")   # a UTF-8 BOM would hide the first line's number
    return data.decode("latin-1")          # headers of Windows tools are not always UTF-8


def read_profile(path: str | Path, kind: str | None = None, format: str | None = None, *,
                 smoothing: float | None = None, cant_rad: float | None = None,
                 options: ReadOptions | None = None) -> Profile:
    """Read a wheel or rail profile file into a normalized :class:`Profile` (SI units).

    Parameters
    ----------
    path : str or Path
        The profile file.
    kind : {"wheel", "rail"}, optional
        The kind expected; a file of the other kind raises. None: as declared / from the shape.
    format : str, optional
        A name in :data:`READERS`; None detects it (module docstring).
    smoothing : float, optional
        Spline smoothing ``lam`` (m^3); None: 0 for exact data (Simpack, plain text), automatic for
        measured MiniProf data (:func:`lutmpi.profiles.validate.auto_smoothing`).
    cant_rad : float, optional
        Inclination already in the data (rails), rad; overrides what the file says.
    options : ReadOptions, optional
        Axis flips, offsets, origin convention (:mod:`lutmpi.profiles.options`).

    Returns
    -------
    Profile

    Raises
    ------
    ProfileError
        Unknown format, unreadable or malformed file (message names the file and the line).
    """
    p = Path(path)
    text = _read_text(p)
    name = format if format is not None else detect_format(p, text)
    reader = get_reader(name)
    raw = reader.parse(text.splitlines(), str(p))
    raw.meta.setdefault("format", name)
    raw = apply_options(raw, options, str(p))
    return build_profile(raw, str(p), kind, p.stem, smoothing=smoothing, cant_rad=cant_rad)
