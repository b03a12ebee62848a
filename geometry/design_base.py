"""What every design dataclass shares: number checks, serialisation, hashing, design files.

`DesignBase` is the base of the frozen, keyword-only design dataclasses of `geometry.design`: their
dict (nested for the robot's parts), a stable hash of the canonical JSON (mesh cache keys, study
names), `replace` with validation, and `save` / `load` to .json or .toml. `check_number` is the
validation every numeric field goes through: a real number, finite, positive or above a minimum,
an integer where one is meant; it names the field in the `DesignError`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
from dataclasses import fields
from pathlib import Path
from typing import Any, ClassVar, Self

from geometry.design_files import read_design_file, to_toml
from geometry.errors import DesignError

#: Angular positions psi_i of the three actuators on the circle of radius d (degrees).
ACTUATOR_ANGLES_DEG: tuple[float, float, float] = (90.0, 210.0, 330.0)
#: Smallest material ligament accepted between holes or edges of rigid parts (mm).
MIN_LIGAMENT = 0.5


def check_number(
    obj: object, name: str, *, positive: bool = True, integer: bool = False, minimum: float | None = None
) -> None:
    value = getattr(obj, name)
    pname = name
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DesignError(pname, f"must be a number, got {value!r}")
    if integer:
        if isinstance(value, float):
            if not value.is_integer():
                raise DesignError(pname, f"must be an integer, got {value!r}")
            object.__setattr__(obj, name, int(value))
            value = int(value)
    elif isinstance(value, int):
        object.__setattr__(obj, name, float(value))
    if not math.isfinite(value):
        raise DesignError(pname, f"must be finite, got {value!r}")
    if positive and value <= 0:
        raise DesignError(pname, f"must be positive, got {value!r}")
    if minimum is not None and value < minimum:
        raise DesignError(pname, f"must be >= {minimum}, got {value!r}")


class DesignBase:
    """Shared serialisation, hashing and file I/O of the design dataclasses."""

    kind: ClassVar[str] = ""
    _nested: ClassVar[dict[str, type]] = {}

    def to_dict(self) -> dict[str, Any]:
        out: dict[str, Any] = {}
        for f in fields(self):
            value = getattr(self, f.name)
            out[f.name] = value.to_dict() if isinstance(value, DesignBase) else value
        return out

    @classmethod
    def from_dict(cls, data: dict[str, Any], _prefix: str = "") -> Self:
        data = dict(data)
        kind = data.pop("kind", cls.kind)
        if kind != cls.kind:
            raise DesignError(_prefix + "kind", f"expected {cls.kind!r}, got {kind!r}")
        names = {f.name for f in fields(cls)}
        for key in data:
            if key not in names:
                raise DesignError(_prefix + key, f"unknown parameter of {cls.__name__}")
        for key, sub in cls._nested.items():
            if isinstance(data.get(key), dict):
                try:
                    data[key] = sub.from_dict(data[key], _prefix=f"{_prefix}{key}.")
                except DesignError as exc:
                    if exc.parameter.startswith(f"{_prefix}{key}."):
                        raise
                    raise DesignError(f"{_prefix}{key}.{exc.parameter}", exc.detail) from None
        try:
            return cls(**data)
        except TypeError as exc:  # a missing/extra argument that slipped through
            raise DesignError(_prefix or "design", str(exc)) from None

    def replace(self, **changes: Any) -> Self:
        """A copy with some fields changed (validated again)."""
        return dataclasses.replace(self, **changes)

    def canonical_json(self) -> str:
        return json.dumps({"kind": self.kind, **self.to_dict()}, sort_keys=True, separators=(",", ":"))

    def short_hash(self) -> str:
        """12 hex characters of the sha256 of the canonical JSON; stable across processes."""
        return hashlib.sha256(self.canonical_json().encode()).hexdigest()[:12]

    def save(self, path: str | Path) -> Path:
        """Write the design to ``.json`` or ``.toml``."""
        path = Path(path)
        data = {"kind": self.kind, **self.to_dict()}
        if path.suffix == ".json":
            path.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
        elif path.suffix == ".toml":
            path.write_text(to_toml(data))
        else:
            raise DesignError("path", f"unsupported design file type {path.suffix!r} (use .json or .toml)")
        return path

    @classmethod
    def load(cls, path: str | Path) -> Self:
        """Read a design from ``.json`` or ``.toml`` (the inverse of :meth:`save`)."""
        return cls.from_dict(read_design_file(path))
