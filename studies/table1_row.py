"""A Table 1 row decided by a study of its own (groove height h, foot radius d, connecting rings),
read from that study's committed outputs under the results folder, never recomputed.

Each such study declares a ``table1`` function (`studies.declaration.Study`) that returns its rows
as `StudyRow`s keyed by Table 1 parameter; `softcrawl table1` collects them from the registry. A full
run is preferred over a ``-quick`` one of the same study; a missing study gives a "pending" row
that says which command produces it. These rows do not depend on the silicone of the ePSA tables:
each names the material its own study used, so `table1` computes them once and shows them in every
material's table.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

from softcrawl.studies.epsa.rules import Selection

QUICK_SUFFIX = "-quick"


@dataclass(frozen=True)
class StudyRow:
    """One Table 1 row decided by a robot-level or foot study."""

    selection: Selection
    material: str  #: the material the study ran with ("-" when there is no study)
    source: Path | None  #: the file the decision was read from
    quick: bool  #: the study ran on its quick mesh
    evidence_lines: tuple[str, ...] = ()  #: Markdown of the evidence, where the rule writes its own


def pick_run(results: str | Path, pattern: str) -> Path | None:
    """The full run's file matching `pattern`, else the quick run's, else None."""
    found = sorted(Path(results).glob(pattern))
    full = [p for p in found if not p.parent.name.endswith(QUICK_SUFFIX)]
    return (full or found or [None])[0]


def material_of(source: Path | None) -> tuple[str, bool]:
    """(material, quick) of the run folder that holds `source`."""
    if source is None:
        return "-", False
    name = source.parent.name
    quick = name.endswith(QUICK_SUFFIX)
    return (name[: -len(QUICK_SUFFIX)] if quick else name), quick


def fmt_value(value) -> str:
    if isinstance(value, float):
        return "n/a" if not math.isfinite(value) else f"{value:.4g}"
    return "n/a" if value is None else str(value)
