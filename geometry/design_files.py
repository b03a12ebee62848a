"""Design files: the dict of a design read from, or written to, ``.json`` or ``.toml``.

The dataclasses of `geometry.design` call these for `save` / `load`; a file holds the design's
``kind`` and its fields (nested tables for the parts of a robot).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from geometry.errors import DesignError


def read_design_file(path: str | Path) -> dict[str, Any]:
    path = Path(path)
    if path.suffix == ".json":
        return json.loads(path.read_text())
    if path.suffix == ".toml":
        import tomllib

        return tomllib.loads(path.read_text())
    raise DesignError("path", f"unsupported design file type {path.suffix!r} (use .json or .toml)")


def _toml_scalar(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value)
    raise TypeError(f"cannot write {value!r} to TOML")


def to_toml(data: dict[str, Any], _table: str = "") -> str:
    """Minimal TOML writer for nested tables of scalars (enough for the designs)."""
    lines = [f"{k} = {_toml_scalar(v)}" for k, v in data.items() if not isinstance(v, dict)]
    text = "\n".join(lines) + ("\n" if lines else "")
    for key, value in data.items():
        if isinstance(value, dict):
            name = f"{_table}.{key}" if _table else key
            text += f"\n[{name}]\n" + to_toml(value, name)
    return text
