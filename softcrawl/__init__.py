"""The project core shared by every package: the input-error base class and the version.

It imports nothing heavy and nothing of the project, so `geometry`, `fem`, `materials`, `robot` and
`studies` can all depend on it without an upward import (docs/DESIGN.md#layer-rules).
"""

from __future__ import annotations

from importlib import metadata

try:
    __version__ = metadata.version("softcrawl")
except metadata.PackageNotFoundError:  # a source checkout on PYTHONPATH, not installed
    __version__ = "0+unknown"
