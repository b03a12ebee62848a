"""Strict JSON for every file and every `--json` output of the project.

Python's `json` writes NaN and Infinity as bare words, which strict parsers (JavaScript's
`JSON.parse`, jq, most other languages) reject. Here a float that is not finite becomes `null`,
numpy scalars and arrays become numbers and lists, tuples lists, and `json.dumps` runs with
`allow_nan=False`, so a missed case fails loudly instead of writing invalid JSON.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

from softcrawl.files import write_text_atomic


def plain(value: Any) -> Any:
    """`value` with non-finite floats as None and numpy types as Python numbers and lists."""
    if isinstance(value, dict):
        return {str(k): plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [plain(v) for v in value]
    if hasattr(value, "tolist") and not isinstance(value, (str, bytes)):  # numpy scalar or array
        return plain(value.tolist())
    if isinstance(value, bool) or value is None or isinstance(value, (int, str)):
        return value
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Path):
        return str(value)
    try:
        number = float(value)
    except (TypeError, ValueError):
        return str(value)
    return number if math.isfinite(number) else None


def dumps(value: Any, **kwargs) -> str:
    """Strict JSON text of `value` (module docstring); keyword arguments go to `json.dumps`."""
    return json.dumps(plain(value), allow_nan=False, **kwargs)


def write(path, value: Any, indent: int = 2) -> Path:
    """Write strict JSON (with a final newline) to `path`, creating its folder, atomically."""
    return write_text_atomic(path, dumps(value, indent=indent) + "\n")
