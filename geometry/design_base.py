"""What every design dataclass shares: number checks, serialisation, hashing, design files.

`DesignBase` is the base of the frozen, keyword-only design dataclasses of `geometry.design`: their
dict (nested for the robot's parts), a stable hash of the canonical JSON (mesh cache keys, study
names), `replace` with validation, and `save` / `load` to .json or .toml. `check_number` is the
validation every numeric field goes through (`softcrawl.checks.number`): a real number, finite,
within the design limits below (or the field's own bounds), an integer where one is meant; it
names the field in the `DesignError`.
"""

from __future__ import annotations

import dataclasses
import hashlib
import json
from dataclasses import fields
from pathlib import Path
from typing import Any, ClassVar, Self

from softcrawl.checks import brief, number
from softcrawl.geometry.design_files import read_design_file, to_toml
from softcrawl.geometry.errors import DesignError

#: Angular positions psi_i of the three actuators on the circle of radius d (degrees).
ACTUATOR_ANGLES_DEG: tuple[float, float, float] = (90.0, 210.0, 330.0)
#: Smallest material ligament accepted between holes or edges of rigid parts (mm).
MIN_LIGAMENT = 0.5
#: Largest length of any design field (mm). The robot crawls in 55-75 mm pipes and its largest
#: part, the 100 mm ePSA, is a tenth of this; a part a metre long is outside anything the paper or
#: the models describe, and its meshes (element counts grow with size / element size) would not
#: fit in memory. A typo such as 1e12 fails here, at once.
MAX_DIMENSION = 1000.0
#: Smallest positive length of any design field (mm): 10 micrometres, below the resolution of any
#: mould or printer that makes these parts (~0.05-0.1 mm) and of any mesh of them; a Kevlar
#: filament is 12 micrometres thick. Zero, where a field allows it (a bore), means "none".
MIN_FEATURE = 0.01
#: Largest count of repeated features (grooves, rings): no part of the robot has more than a few
#: tens; the geometric checks reject far smaller counts, this bound keeps their arithmetic finite.
MAX_FEATURE_COUNT = 10_000


def spec(default: float, doc: str, unit: str = "mm") -> Any:
    """A design field with its default, a one-line description and its unit (shown by the
    command-line help of `softcrawl mesh`)."""
    return dataclasses.field(default=default, metadata={"doc": doc, "unit": unit})


def check_number(
    obj: object,
    name: str,
    *,
    positive: bool = True,
    integer: bool = False,
    minimum: float | None = None,
    maximum: float | None = None,
    unit: str | None = None,
) -> None:
    """Validate field `name` of `obj` in place: a finite real number (an int for `integer`),
    stored as float (int); lengths are bounded by `MIN_FEATURE` (when `positive`) and
    `MAX_DIMENSION`, counts by `MAX_FEATURE_COUNT`, unless `minimum` / `maximum` are given."""
    if maximum is None:
        maximum = MAX_FEATURE_COUNT if integer else MAX_DIMENSION
    if minimum is None and positive:
        minimum = 1 if integer else MIN_FEATURE
    if unit is None:
        unit = "" if integer else "mm"
    value = number(
        getattr(obj, name),
        name,
        minimum=minimum,
        maximum=maximum,
        integer=integer,
        unit=unit,
        error=DesignError,
    )
    object.__setattr__(obj, name, value)


def derived_part(name: str, cls: type, sizes: dict[str, float]) -> Any:
    """A part of the robot sized from its d and R0; its errors are named ``<name>.<field>`` and say
    that the part was derived from d (the user gave no explicit part)."""
    try:
        return cls(**sizes)
    except DesignError as exc:
        raise DesignError(
            f"{name}.{exc.parameter}", f"{exc.detail} (the {name} sized from d = {sizes['d']:g} mm)"
        ) from None


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
        if not isinstance(data, dict):
            raise DesignError(
                _prefix.rstrip(".") or "design", f"must be a table of fields, got {type(data).__name__}"
            )
        data = dict(data)
        kind = data.pop("kind", cls.kind)
        if kind != cls.kind:
            raise DesignError(_prefix + "kind", f"expected {cls.kind!r}, got {brief(kind)}")
        names = {f.name for f in fields(cls)}
        for key in data:
            if key not in names:
                name = key if len(key) <= 60 else key[:57] + "..."
                raise DesignError(_prefix + name, f"unknown parameter of {cls.__name__}")
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
        names = {f.name for f in fields(self)}
        for key in changes:
            if key not in names:
                raise DesignError(key, f"unknown parameter of {type(self).__name__}")
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
    def load(cls, path: str | Path, parameter: str = "path") -> Self:
        """Read a design from ``.json`` or ``.toml`` (the inverse of :meth:`save`); a file that
        cannot be read is a `DesignError` named `parameter`."""
        return cls.from_dict(read_design_file(path, parameter))
