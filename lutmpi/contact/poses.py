"""Reading pose lists (the input edge of ``lutmpi solve``): mm in files, SI inside. The results
are written by ``lutmpi.commands.solve`` with the schema's columns.

:func:`read_csv_records` is the shared text edge of the small CSV inputs (pose lists, the Δr
file of ``lutmpi conicity --dr``): UTF-8 only, comment and blank lines skipped, every record with
its line number, every fault a :class:`~lutmpi.errors.ConfigError` naming the file and line."""

from __future__ import annotations

import csv
import io
import math
import re
from pathlib import Path

from lutmpi.errors import ConfigError

#: the largest |y_g| (mm) and |yaw| (rad) a pose may have: the config's grid limits
Y_MAX_MM, YAW_MAX_RAD = 100.0, 0.5

#: byte-order marks of the UTF-16/32 encodings (a spreadsheet's "Unicode text"), longest first
_WIDE_BOMS = ((b"\xff\xfe\x00\x00", "UTF-32"), (b"\x00\x00\xfe\xff", "UTF-32"),
              (b"\xff\xfe", "UTF-16"), (b"\xfe\xff", "UTF-16"))


def check_pose(y_mm: float, yaw: float, where: str, path: str | None = None) -> None:
    """Raise :class:`ConfigError` naming ``where`` (a file line, a command-line option) when a
    pose is not finite or lies beyond :data:`Y_MAX_MM` / :data:`YAW_MAX_RAD`."""
    if not (math.isfinite(y_mm) and math.isfinite(yaw)) or abs(y_mm) > Y_MAX_MM \
            or abs(yaw) > YAW_MAX_RAD:
        raise ConfigError(f"{where}: pose out of range (|y| <= {Y_MAX_MM:g} mm, |yaw| <= "
                          f"{YAW_MAX_RAD:g} rad), got y_mm={y_mm}, yaw_rad={yaw}", path=path)


def _decode(data: bytes, path: str, what: str) -> str:
    """``data`` as UTF-8 text (a leading BOM dropped: Excel's CSV); anything else is a
    :class:`ConfigError` naming the line and byte of the first fault."""
    for bom, name in _WIDE_BOMS:
        if data.startswith(bom):
            raise ConfigError(f"{what} is {name} text (byte-order mark {bom.hex(' ')}); "
                              "expected UTF-8: save it as 'CSV UTF-8'", path=path)
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        line = data.count(b"\n", 0, exc.start) + 1
        raise ConfigError(f"line {line}: {what} is not UTF-8 text (byte 0x{data[exc.start]:02x} "
                          f"at byte {exc.start}: a Latin-1 or Windows-1252 'µ', 'é', ...?); "
                          "save it as UTF-8", path=path) from None
    if "\x00" in text:
        line = text.count("\n", 0, text.index("\x00")) + 1
        raise ConfigError(f"line {line}: {what} holds NUL characters (UTF-16 text without a "
                          "byte-order mark?); expected UTF-8 text", path=path)
    return text


def read_csv_records(path: str | Path, what: str) -> list[tuple[int, list[str]]]:
    """The records of a small UTF-8 CSV input, each with the line it starts on.

    Blank lines and lines whose first field starts with ``#`` are skipped wherever they are.

    Parameters
    ----------
    path : str or Path
        The file.
    what : str
        What the file is, for the messages (``"poses file"``, ``"Δr file"``).

    Returns
    -------
    list of (int, list of str)
        ``(line number from 1, fields)``; the fields are as the CSV holds them (not stripped).

    Raises
    ------
    ConfigError
        The file cannot be read, is not UTF-8 text, or is not valid CSV (names file and line).
    """
    path = str(path)
    try:
        data = Path(path).read_bytes()
    except OSError as exc:
        raise ConfigError(f"cannot read {what}: {exc.strerror or exc}", path=path) from None
    reader = csv.reader(io.StringIO(_decode(data, path, what), newline=""))
    out: list[tuple[int, list[str]]] = []
    start = 1
    try:
        for row in reader:
            if row and not (len(row) == 1 and not row[0].strip()) \
                    and not row[0].lstrip().startswith("#"):
                out.append((start, row))
            start = reader.line_num + 1
    except csv.Error as exc:
        raise ConfigError(f"line {start}: not valid CSV ({exc})", path=path) from None
    return out


def _decimal_comma(fields: list[str]) -> bool:
    """Whether two neighbouring fields read as one number written with a decimal comma."""
    return any(re.fullmatch(r"\s*[+-]?\d+", a) and re.fullmatch(r"\d+([eE][+-]?\d+)?\s*", b)
               for a, b in zip(fields, fields[1:], strict=False))


def check_field_count(line: int, fields: list[str], header: list[str], path: str) -> None:
    """Raise :class:`ConfigError` unless a data row has as many fields as the header (an extra
    field is never dropped: ``1.5,0,005`` is a decimal comma, not yaw 0); empty fields after
    the header's (a spreadsheet's trailing comma, ``1.5,0.005,``) are no data and pass."""
    if len(fields) == len(header) or (len(fields) > len(header)
                                      and not any(f.strip() for f in fields[len(header):])):
        return
    hint = ""
    if len(fields) > len(header) and _decimal_comma(fields):
        hint = " (a decimal comma? write 0.005, not 0,005)"
    raise ConfigError(f"line {line}: expected {len(header)} fields ({','.join(header)}), got "
                      f"{len(fields)}: {fields}{hint}", path=path)


def read_poses(path: str | Path) -> list[tuple[float, float]]:
    """Poses (y in m, yaw in rad) from a CSV with columns ``y_mm,yaw_rad``.

    The columns may come in any order and other named columns are ignored, but every data row
    must have as many fields as the header. Comment (``#``) and blank lines are skipped. Errors
    name the file and line.

    Parameters
    ----------
    path : str or Path
        UTF-8 CSV file, y in mm, yaw in rad.

    Returns
    -------
    list of (float, float)
        ``(y in m, yaw in rad)`` per data row, in file order.
    """
    path = str(path)
    rows = read_csv_records(path, "poses file")
    if not rows:
        raise ConfigError("no header and no poses; expected a header 'y_mm,yaw_rad'", path=path)
    head_line, header = rows[0][0], [h.strip() for h in rows[0][1]]
    missing = [c for c in ("y_mm", "yaw_rad") if c not in header]
    if missing:
        hint = " (';' is not the separator: use ',')" if any(";" in h for h in header) else ""
        raise ConfigError(f"line {head_line}: header lacks {missing}; expected columns "
                          f"'y_mm,yaw_rad', got {header}{hint}", path=path)
    twice = sorted({c for c in ("y_mm", "yaw_rad") if header.count(c) > 1})
    if twice:
        raise ConfigError(f"line {head_line}: the header names {twice} more than once, got "
                          f"{header}", path=path)
    iy, iyaw = header.index("y_mm"), header.index("yaw_rad")
    out = []
    for line, r in rows[1:]:
        check_field_count(line, r, header, path)
        try:
            y, yaw = float(r[iy]), float(r[iyaw])
        except ValueError:
            raise ConfigError(f"line {line}: expected two numbers y_mm, yaw_rad, got {r}",
                              path=path) from None
        check_pose(y, yaw, f"line {line}", path)
        out.append((y * 1e-3, yaw))
    if not out:
        raise ConfigError("the file has a header but no poses", path=path)
    return out
