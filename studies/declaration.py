"""What a study is, declared once: `Study`, and `StudyRequest`, the options a run is given.

Each feature folder declares its studies in its own `study.py` (`studies/epsa/study.py`, ...), and
`studies.registry` lists those modules. The commands (`softcrawl study`, `replot`, `report`,
`table1`) iterate the registry and never name a study.

A declaration names its code by ``"module:function"`` strings, resolved only when used, so that
reading the registry (for `softcrawl --help` and the option choices) imports no solver:

    run(request: StudyRequest) -> StudyOutcome           compute (or resume) the study
    replot(folder: Path) -> list[Path]                    redraw its figures from its tables
    report(folder: Path) -> str                           its HTML block in the design review
    check(request: StudyRequest) -> None                  study-specific input checks (StudyError)
    table1(results: Path) -> dict[str, StudyRow]          the Table 1 rows it decides

and ``evaluators`` maps the registry names of its sweep evaluators (stored in `spec.json` and
handed to spawned workers) to their functions.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

#: Options of `softcrawl study` beyond --out, --quick, --material and --no-progress.
OPTIONS = frozenset(
    {
        "workers",
        "max_memory",
        "storage",
        "retry_failed",
        "simulator",
        "mesh_size",
        "fibers",
        "trials",
        "sampler",
        "seed",
        "confirm",
        "wedge",
    }
)


@dataclass(frozen=True)
class StudyRequest:
    """One `softcrawl study` run: the command line's options, checked, in the project's units."""

    study: str
    out: str
    quick: bool = False
    material: str | None = None
    storage: str | None = None
    workers: int = 1
    progress: bool = True
    retry: bool = False
    mesh_size: float | None = None
    fibers: str | None = None
    trials: int | None = None
    sampler: str = "nsga2"
    seed: int = 0
    simulator: str | None = None
    max_memory_gb: float | None = None
    confirm: int | None = None
    wedge: int | None = None  # crawl, feet, optimise-feet: a wedge of 360/N deg (studies.foot.wedge)

    def sweep_options(self) -> dict[str, Any]:
        """storage, workers, progress and retry: the sweep engine's options (`run_sweep`), which a
        sweep study's runner passes through, e.g. ``run_crawl_study(out, quick=..., **these)``."""
        return {
            "storage": self.storage,
            "workers": self.workers,
            "progress": self.progress,
            "retry": self.retry,
        }


@dataclass(frozen=True)
class Study:
    """One study, declared once (see the module docstring for the signatures of the references).

    ``folder`` is its results subfolder (DIR/FOLDER/MATERIAL[-quick]/), ``default_material`` the
    material it runs with when none is given (None: it takes no material), ``figure`` and
    ``tables`` the files it writes into that folder, ``rule`` the Table 1 parameters it decides,
    ``in_review`` whether the review's "Studies" section shows it (False: another section does),
    ``marker`` the file that makes a folder one of its runs.
    """

    name: str
    summary: str
    run: str
    folder: str = ""
    default_material: str | None = "ecoflex-00-50"
    options: frozenset[str] = frozenset()
    evaluators: Mapping[str, str] = field(default_factory=dict)
    figure: str = ""
    tables: tuple[str, ...] = ()
    rule: tuple[str, ...] = ()
    table1: str | None = None
    replot: str | None = None
    report: str | None = None
    check: str | None = None
    in_review: bool = True
    help: str = ""
    marker: str = "spec.json"

    def __post_init__(self) -> None:
        if not self.name or self.name != self.name.strip() or " " in self.name:
            raise ValueError(f"a study name is one word, got {self.name!r}")
        unknown = set(self.options) - OPTIONS
        if unknown:
            raise ValueError(f"study {self.name}: unknown options {sorted(unknown)}")
        for ref in (self.run, self.replot, self.report, self.check, self.table1, *self.evaluators.values()):
            if ref is not None and ":" not in ref:
                raise ValueError(f"study {self.name}: {ref!r} is not 'module:function'")
        object.__setattr__(self, "options", frozenset(self.options))
        object.__setattr__(self, "folder", self.folder or self.name)

    def results_folders(self, results: Path, nested: bool = False) -> list[Path]:
        """Its run folders under a results folder, in name order: every DIR/FOLDER/* that holds
        its marker file; with `nested`, also variants deeper down (identify/lines/MATERIAL/)."""
        root = Path(results) / self.folder
        found = root.rglob(self.marker) if nested else root.glob(f"*/{self.marker}")
        return sorted(p.parent for p in found)


def resolve(ref: str) -> Callable[..., Any]:
    """The function behind a ``"module:function"`` reference of a declaration."""
    module, _, name = ref.partition(":")
    obj: Any = importlib.import_module(module)
    for part in name.split("."):
        obj = getattr(obj, part)
    return obj
