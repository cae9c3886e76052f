"""The files a report wrote into its folder, so that a report made again into the same folder
removes those of the earlier one that it does not write again: a figure the new report did not
draw (another ``--at-y-mm``, a member no longer in the sweep) would otherwise stay beside the
new ``report.md`` and look current.

Only files a report listed are ever removed: :data:`MANIFEST` (one name a line, written at the end
of every report), or, for a folder written before it existed, the figures linked from an earlier
``report.md`` whose first line is a lutmpi report's title. Anything else in the folder is the
user's and is left alone.
"""

from __future__ import annotations

import logging
import re
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

log = logging.getLogger(__name__)

#: the list of the files the last report wrote, in the report folder
MANIFEST = ".lutmpi-report-files"
#: first lines of the ``report.md`` of :mod:`lutmpi.reports.table_report` and
#: :mod:`lutmpi.reports.report` (a folder from before :data:`MANIFEST`)
TITLES = ("# Contact geometry: ", "# Sweep report: ")
_LINK = re.compile(r"!\[[^\]]*\]\(([^)/\\]+)\)")


def _plain_name(name: str) -> bool:
    """A file name in the folder itself (never a path out of it)."""
    return bool(name) and name not in (".", "..") and "/" not in name and "\\" not in name


def earlier_files(folder: Path) -> list[str]:
    """The names of the files an earlier report wrote into ``folder`` (:data:`MANIFEST`, else
    the figures linked from a lutmpi ``report.md``), ``report.md`` included."""
    manifest = folder / MANIFEST
    try:
        if manifest.is_file():
            names = manifest.read_text(encoding="utf-8").splitlines()
        else:
            text = (folder / "report.md").read_text(encoding="utf-8")
            if not text.startswith(TITLES):
                return []
            names = ["report.md", *_LINK.findall(text)]
    except (OSError, UnicodeDecodeError):
        return []
    return [n for n in dict.fromkeys(names) if _plain_name(n)]


@contextmanager
def report_files(folder: Path) -> Iterator[None]:
    """Around the writing of a report into ``folder`` (existing): first remove the files an
    earlier report wrote there (:func:`earlier_files`; regular files only), then record in
    :data:`MANIFEST` the files this report wrote (those not there before it began; also when
    it fails part way, so that the next report removes them too)."""
    removed = []
    for name in earlier_files(folder):
        path = folder / name
        if path.is_file() and not path.is_symlink():
            path.unlink()
            removed.append(name)
    (folder / MANIFEST).unlink(missing_ok=True)
    if removed:
        log.info("removed the %d files of the earlier report in %s: %s", len(removed), folder,
                 ", ".join(removed))
    before = {p.name for p in folder.iterdir()}
    try:
        yield
    finally:
        written = sorted(p.name for p in folder.iterdir() if p.name not in before)
        (folder / MANIFEST).write_text("".join(f"{n}\n" for n in written), encoding="utf-8")
