"""What made a result: the softcrawl version and the git commit of the checkout it ran from.

`write_summary` is the one way a `summary.json` is written: it adds ``"provenance": {"softcrawl":
VERSION, "commit": SHA or "unknown"}`` to the summary (tests/test_provenance.py checks that no
module writes a summary.json any other way). The commit is "unknown" outside a git checkout (an
installed wheel) or without git; "+ local changes" marks a checkout with uncommitted edits of
tracked files, so that a result made from edited code says so.
"""

from __future__ import annotations

import subprocess
from functools import lru_cache
from pathlib import Path

from softcrawl import __version__, jsonio

#: The folder whose git checkout is asked (the source tree: softcrawl/ sits at its top).
SOURCE = Path(__file__).resolve().parents[1]


@lru_cache(maxsize=1)
def git_commit(folder: Path = SOURCE) -> str:
    """The full commit of the checkout holding `folder` (with " + local changes" when tracked
    files differ from it), or "unknown"."""
    try:
        head = subprocess.run(
            ["git", "-C", str(folder), "rev-parse", "HEAD"], capture_output=True, text=True, timeout=10
        )
        if head.returncode != 0:
            return "unknown"
        dirty = subprocess.run(
            ["git", "-C", str(folder), "status", "--porcelain", "--untracked-files=no"],
            capture_output=True,
            text=True,
            timeout=10,
        ).stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return head.stdout.strip() + (" + local changes" if dirty else "")


def provenance() -> dict:
    """{"softcrawl": version, "commit": the git commit or "unknown"}."""
    return {"softcrawl": __version__, "commit": git_commit()}


def write_summary(path, summary: dict, **kwargs) -> Path:
    """Write `summary` (strict JSON, `softcrawl.jsonio.write`) with its ``provenance`` added."""
    jsonio.write(path, {**summary, "provenance": provenance()}, **kwargs)
    return Path(path)
