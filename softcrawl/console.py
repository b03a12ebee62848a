"""How much a command prints: one verbosity, set once by `softcrawl -q/-v` (`studies.cli`).

-1 (``-q``): no progress lines, only results and errors; 0: progress lines; 1 and more (``-v``,
``-vv``): also details where a command has any. The progress printers of the commands call
`progress` and `detail` instead of `print`, so the level is consulted in one place.
"""

from __future__ import annotations

import sys

#: The current level: -1 quiet, 0 normal, >= 1 verbose.
LEVEL = 0


def set_level(level: int) -> None:
    global LEVEL
    LEVEL = int(level)


def progress(message: str) -> None:
    """A progress line on stdout (not with -q)."""
    if LEVEL >= 0:
        print(message, flush=True)


def detail(message: str) -> None:
    """A detail line on stdout (only with -v)."""
    if LEVEL >= 1:
        print(message, flush=True)


def warn(message: str) -> None:
    """One line on stderr, whatever the level (a deprecation, a fallback)."""
    print(message, file=sys.stderr, flush=True)
