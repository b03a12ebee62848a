"""What a sweep or a search is: its points, its evaluator, and how its table is laid out.

A **sweep** evaluates every point of a grid (the Cartesian product of `SweepSpec.grid`, the last
parameter varying fastest) on top of fixed parameters. A **search** lets an optuna sampler
propose points in a box (`SearchSpec.space`) until `n_trials` results exist. Both name their
evaluator as a ``"module:function"`` string, so that spawned worker processes can import it:

    evaluator(params: dict, fixed: dict, settings: dict) -> Evaluation

The engine knows nothing of the model being evaluated: the evaluator and the `TableLayout` (which
user attributes become which CSV columns) come from the study catalogue.
"""

from __future__ import annotations

import dataclasses
import importlib
import itertools
import json
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from softcrawl.errors import InputError

#: Seconds between two heartbeats of a running trial (optuna's heartbeat thread).
DEFAULT_HEARTBEAT_S = 10
#: A running trial whose last heartbeat is older than this (s) belongs to a dead worker.
DEFAULT_GRACE_S = 60
#: Samplers of a search.
SAMPLERS = ("nsga2", "tpe")


class StudyError(InputError):
    """Invalid study input (user error); ``parameter`` names the offending option."""


@dataclass(frozen=True)
class Evaluation:
    """What an evaluator returns. ``ok = False`` makes the trial FAIL with ``message`` as reason."""

    ok: bool
    values: tuple[float, ...] = ()
    attrs: Mapping[str, Any] = field(default_factory=dict)
    message: str = ""


@dataclass(frozen=True)
class TableLayout:
    """How `studies.sweeps.tables.collect` turns a point's user attributes into CSV rows.

    Columns, in order: study, ``settings_columns`` (values of the spec's settings), the fixed and
    grid parameters, ``reference_columns`` (keys of the dict attribute ``reference``, e.g. the
    undeformed design), trial, trial_status, reason, ``point_columns`` (scalar attributes), the
    ``row_columns`` of each row of the list attribute ``rows`` (one CSV row per entry, renamed by
    ``renamed``), then those ``scalar_columns`` that the evaluator stored, in its order."""

    settings_columns: tuple[str, ...] = ()
    reference: str = ""
    reference_columns: tuple[str, ...] = ()
    point_columns: tuple[str, ...] = ()
    rows: str = ""
    row_columns: tuple[str, ...] = ()
    renamed: Mapping[str, str] = field(default_factory=dict)
    scalar_columns: tuple[str, ...] = ()


@dataclass(frozen=True)
class SweepSpec:
    """One sweep: a grid (param -> values) on top of fixed params, evaluated by ``evaluator``.

    ``storage`` is an RDB URL; ``None`` means ``sqlite:///<out_dir>/study.db``. ``settings`` are
    passed to the evaluator unchanged. ``directions`` are the optuna directions of the values the
    evaluator returns, ``metric_names`` their names (optuna's ``set_metric_names``: what
    ``optuna best-trial`` and optuna-dashboard show); the study's declaration says why its
    objective makes optuna's "best" the design its rule picks (decision 063).
    """

    name: str
    grid: Mapping[str, Sequence[Any]]
    out_dir: str
    evaluator: str
    fixed: Mapping[str, Any] = field(default_factory=dict)
    settings: Mapping[str, Any] = field(default_factory=dict)
    storage: str | None = None
    directions: tuple[str, ...] = ("maximize",)
    heartbeat_interval: int = DEFAULT_HEARTBEAT_S
    grace_period: int = DEFAULT_GRACE_S
    metric_names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.grid:
            raise StudyError("grid", "is empty")
        grid = {}
        for key, values in self.grid.items():
            values = tuple(values)
            if not values:
                raise StudyError(f"grid.{key}", "has no values")
            if len(set(values)) != len(values):
                raise StudyError(f"grid.{key}", f"repeats a value: {values}")
            grid[str(key)] = values
        object.__setattr__(self, "grid", grid)
        _normalise(self)
        object.__setattr__(self, "metric_names", _names(self.metric_names, self.directions))
        _check_heartbeat(self)

    @property
    def storage_url(self) -> str:
        return _storage_url(self)

    def points(self) -> list[dict[str, Any]]:
        """Every grid point, in grid order (the last parameter varies fastest)."""
        keys = list(self.grid)
        return [dict(zip(keys, combo)) for combo in itertools.product(*self.grid.values())]

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self) | {"grid": {k: list(v) for k, v in self.grid.items()}}


@dataclass(frozen=True)
class SearchSpec:
    """An optimisation: the same storage, evaluator and failure handling as a sweep, but optuna's
    TPE or NSGA-II sampler proposes the points. ``space``: param -> ("float"|"int", low, high)
    or ("categorical", choices).
    ``initial`` points (e.g. the paper's Table 1 design) are enqueued once and evaluated first.
    ``n_trials`` is the study's total budget (finished trials, failed ones included), so a
    restarted search only tops up what is missing. ``objective_names`` name the values in the
    table; ``metric_columns`` are the evaluator's attributes copied to it."""

    name: str
    space: Mapping[str, tuple[str, float, float]]
    out_dir: str
    n_trials: int
    directions: tuple[str, ...]
    evaluator: str
    sampler: str = "nsga2"
    seed: int | None = 0
    fixed: Mapping[str, Any] = field(default_factory=dict)
    settings: Mapping[str, Any] = field(default_factory=dict)
    storage: str | None = None
    initial: tuple[Mapping[str, Any], ...] = ()
    objective_names: tuple[str, ...] = ()
    metric_columns: tuple[str, ...] = ()
    heartbeat_interval: int = DEFAULT_HEARTBEAT_S
    grace_period: int = DEFAULT_GRACE_S

    def __post_init__(self) -> None:
        if self.sampler not in SAMPLERS:
            raise StudyError("sampler", f"unknown sampler {self.sampler!r}; valid: {', '.join(SAMPLERS)}")
        if isinstance(self.n_trials, bool) or not isinstance(self.n_trials, int) or self.n_trials < 1:
            raise StudyError("trials", f"must be a positive integer, got {self.n_trials!r}")
        object.__setattr__(self, "space", {str(k): _dimension(k, v) for k, v in self.space.items()})
        object.__setattr__(self, "initial", tuple(dict(p) for p in self.initial))
        object.__setattr__(self, "objective_names", _names(self.objective_names, self.directions))
        object.__setattr__(self, "metric_columns", tuple(self.metric_columns))
        _normalise(self)
        _check_heartbeat(self)

    @property
    def storage_url(self) -> str:
        return _storage_url(self)

    @property
    def metric_names(self) -> tuple[str, ...]:
        return self.objective_names

    def to_dict(self) -> dict[str, Any]:
        return dataclasses.asdict(self)


def _dimension(key: str, value: Sequence[Any]) -> tuple[Any, ...]:
    """One dimension of a search space: ("float" | "int", low, high) with low < high, or
    ("categorical", (choice, ...)) with distinct str, int or float choices (optuna's
    ``suggest_categorical``; the order is kept)."""
    value = tuple(value)
    if len(value) == 2 and value[0] == "categorical":
        choices = tuple(value[1]) if isinstance(value[1], (list, tuple)) else ()
        plain = all(isinstance(c, (str, int, float)) and not isinstance(c, bool) for c in choices)
        if not choices or not plain or len(set(choices)) != len(choices):
            raise StudyError(f"space.{key}", f"needs distinct str or number choices, got {value[1]!r}")
        return ("categorical", choices)
    if len(value) != 3 or value[0] not in ("float", "int") or not value[1] < value[2]:
        raise StudyError(f"space.{key}", f"bad range {value!r}")
    return value


def _normalise(spec: SweepSpec | SearchSpec) -> None:
    object.__setattr__(spec, "fixed", dict(spec.fixed))
    object.__setattr__(spec, "settings", dict(spec.settings))
    object.__setattr__(spec, "out_dir", str(spec.out_dir))
    object.__setattr__(spec, "directions", tuple(spec.directions))
    if not isinstance(spec.evaluator, str) or not spec.evaluator.strip():
        raise StudyError(
            "evaluator", f"expected a registry name or 'module:function', got {spec.evaluator!r}"
        )


def _names(names: Sequence[str], directions: Sequence[str]) -> tuple[str, ...]:
    """One name per objective (``value_0``, ... where none is given)."""
    names = tuple(str(n) for n in names) or tuple(f"value_{i}" for i in range(len(directions)))
    if len(names) != len(directions) or len(set(names)) != len(names):
        raise StudyError("metric_names", f"need {len(directions)} distinct names, got {list(names)}")
    return names


def _check_heartbeat(spec: SweepSpec | SearchSpec) -> None:
    if spec.heartbeat_interval < 1 or spec.grace_period <= spec.heartbeat_interval:
        raise StudyError(
            "grace_period", "needs heartbeat_interval >= 1 and grace_period > heartbeat_interval"
        )


def _storage_url(spec: SweepSpec | SearchSpec) -> str:
    if spec.storage:
        return spec.storage
    return f"sqlite:///{Path(spec.out_dir).resolve() / 'study.db'}"


def point_key(params: Mapping[str, Any]) -> str:
    """Canonical identity of a grid point (floats and equal ints compare equal)."""

    def norm(v: Any) -> Any:
        return float(v) if isinstance(v, (int, float)) and not isinstance(v, bool) else v

    return json.dumps({k: norm(v) for k, v in sorted(params.items())}, sort_keys=True)


def load_callable(ref: str, parameter: str = "evaluator") -> Callable:
    """Import ``"module:function"``, or the evaluator of that registry name (``"epsa"``, or an
    import path of a study computed before the registry); a reference that does not import is an
    input error that names ``parameter`` (the option the reference came from)."""
    if isinstance(ref, str) and parameter == "evaluator":
        ref = _registry().evaluator_reference(ref) if ":" not in ref or _legacy(ref) else ref
    if not isinstance(ref, str) or ":" not in ref:
        raise StudyError(parameter, f"expected 'module:function', got {ref!r}")
    module, _, name = ref.partition(":")
    try:
        obj = importlib.import_module(module)
        for part in name.split("."):
            obj = getattr(obj, part)
    except (ImportError, AttributeError) as exc:
        raise StudyError(parameter, f"cannot import {ref!r}: {exc}") from exc
    if not callable(obj):
        raise StudyError(parameter, f"{ref!r} is not callable")
    return obj


def _registry() -> Any:
    """`studies.registry`, imported by name: the registry sits above this engine (it lists the
    features, which use the engine), so the engine looks evaluator names up late, as a plug-in
    lookup, in whichever process (a spawned worker too) runs the evaluation."""
    return importlib.import_module("softcrawl.studies.registry")


def _legacy(ref: str) -> bool:
    return ref in _registry().LEGACY_EVALUATORS


def jsonable(value: Any) -> Any:
    """``value`` with non-finite floats as None and tuples as lists (what JSON can store)."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    if isinstance(value, dict):
        return {str(k): jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    return value


def read_spec(folder: str | Path) -> dict[str, Any]:
    """The spec.json of a study folder, as stored."""
    return json.loads((Path(folder) / "spec.json").read_text())


def sweep_spec_from_file(folder: str | Path) -> SweepSpec:
    """The `SweepSpec` stored in a study folder's spec.json (to rebuild its tables or figure); its
    output folder is the folder it was read from, wherever the study was computed."""
    data = read_spec(folder) | {"out_dir": str(folder)}
    data["grid"] = {k: tuple(v) for k, v in data["grid"].items()}
    data["directions"] = tuple(data.get("directions", ("maximize",)))
    data["metric_names"] = tuple(data.get("metric_names", ()))
    return SweepSpec(**data)
