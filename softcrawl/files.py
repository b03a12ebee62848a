"""Atomic file writes: a reader sees the old file or the complete new one, never a partial one.

`atomic_path(path)` hands out a temporary name in the same folder (so that the final rename
stays on one filesystem, where `os.replace` is atomic on POSIX and Windows). When the block ends
normally the temporary file replaces `path`; when it raises (a full disk, an interrupt) the
temporary file is removed and `path` is left as it was. A full disk therefore costs the new file,
never the old one, and leaves no 0-byte or truncated output behind.
"""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

#: Prefix of the temporary files (hidden, and recognisable if a power cut leaves one behind).
TEMP_PREFIX = ".partial-"


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path beside `path`; write it fully, and it replaces `path` on exit.
    The temporary name keeps the suffix, so writers that choose a format by suffix still work."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    temp = path.with_name(f"{TEMP_PREFIX}{os.getpid()}-{path.name}")
    try:
        yield temp
        os.replace(temp, path)
    except BaseException:
        with contextlib.suppress(OSError):
            temp.unlink()
        raise


def write_text_atomic(path: str | os.PathLike, text: str) -> Path:
    """`Path.write_text`, atomically."""
    with atomic_path(path) as temp:
        temp.write_text(text)
    return Path(path)
