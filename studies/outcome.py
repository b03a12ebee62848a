"""What a study run hands back to the command line: lines to print, files written, success."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class StudyOutcome:
    """`lines` go to stdout, `problems` to stderr; `ok` False makes the command exit with 1."""

    lines: tuple[str, ...] = ()
    written: tuple[Path, ...] = ()
    ok: bool = True
    problems: tuple[str, ...] = ()
