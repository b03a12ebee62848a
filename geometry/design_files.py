"""Design files: the dict of a design read from, or written to, ``.json`` or ``.toml``.

The dataclasses of `geometry.design` call these for `save` / `load`; a file holds the design's
``kind`` and its fields (nested tables for the parts of a robot).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from softcrawl.geometry.errors import DesignError

#: Largest design file read (bytes). A design is a few hundred bytes; anything near this size is
#: not a design file, and reading it whole would only cost memory.
MAX_DESIGN_FILE_BYTES = 1_000_000


def read_design_file(path: str | Path, parameter: str = "path") -> dict[str, Any]:
    """The table of a ``.json`` or ``.toml`` design file. A file that is missing, unreadable, too
    large, not valid JSON / TOML or not a table raises `DesignError` named `parameter`."""
    path = Path(path)
    if path.suffix not in (".json", ".toml"):
        raise DesignError(parameter, f"unsupported design file type {path.suffix!r} (use .json or .toml)")
    try:
        size = path.stat().st_size
        if size > MAX_DESIGN_FILE_BYTES:
            raise DesignError(
                parameter, f"{path} has {size} bytes; a design file has at most {MAX_DESIGN_FILE_BYTES}"
            )
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise DesignError(parameter, f"cannot read {path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise DesignError(parameter, f"{path} is not a text file") from None
    try:
        if path.suffix == ".json":
            data = json.loads(text)
        else:
            import tomllib

            data = tomllib.loads(text)
    except (ValueError, RecursionError) as exc:  # json.JSONDecodeError, tomllib.TOMLDecodeError
        kind = "JSON" if path.suffix == ".json" else "TOML"
        raise DesignError(parameter, f"{path} is not valid {kind}: {str(exc).splitlines()[0]}") from None
    if not isinstance(data, dict):
        raise DesignError(
            parameter, f"{path} must hold a table of design fields, not a {type(data).__name__}"
        )
    return data


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
