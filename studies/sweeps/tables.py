"""A sweep as a table: one row per (grid point, evaluator row), every grid point present.

The columns are the catalogue's (`studies.sweeps.spec.TableLayout`); the engine adds the study
name, the trial number, the point's status (completed | failed | running | waiting | missing) and
the failure reason, and at the end the peak resident memory of the point's worker while it was
evaluated (``peak_rss_gb``, `studies.sweeps.memory`). A point without rows gets one row with empty
row columns, so failed and missing points are never dropped. CSV files are written atomically
(`softcrawl.files`).
"""

from __future__ import annotations

import csv
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

from softcrawl.files import atomic_path
from softcrawl.studies.sweeps import queue
from softcrawl.studies.sweeps.spec import StudyError, SweepSpec, TableLayout, point_key


def flat_attrs(trial: Any) -> dict[str, Any]:
    """A trial's user attributes with the ``metrics`` dict merged in (one level)."""
    attrs = dict(trial.user_attrs) if trial is not None else {}
    metrics = attrs.get("metrics")
    return {**metrics, **attrs} if isinstance(metrics, dict) else attrs


def blank(value: Any) -> Any:
    return "" if value is None else value


def number_cell(value: Any, fmt: str) -> str:
    """A Markdown table cell: `value` formatted by `fmt`, "-" when missing (None, "", NaN)."""
    return "-" if value is None or value == "" or value != value else format(value, fmt)


def collect(study: Any, spec: SweepSpec, layout: TableLayout | None = None) -> list[dict[str, Any]]:
    """The rows of a sweep (see the module docstring and `TableLayout`)."""
    layout = layout or TableLayout()
    status = queue.statuses(study, spec)
    rows = []
    for params in spec.points():
        state, trial = status[point_key(params)]
        attrs = flat_attrs(trial)
        base = {"study": spec.name} | {k: spec.settings.get(k, "") for k in layout.settings_columns}
        base |= dict(spec.fixed) | dict(params)
        reference = attrs.get(layout.reference) if layout.reference else None
        for key in layout.reference_columns:
            if key not in base and isinstance(reference, dict):
                base[key] = reference.get(key, "")
        base |= {
            "trial": trial.number if trial is not None else "",
            "trial_status": state,
            "reason": attrs.get("failure", "") if state == "failed" else "",
        }
        base |= {k: blank(attrs.get(k)) for k in layout.point_columns}
        scalars = {k: blank(v) for k, v in attrs.items() if k in layout.scalar_columns}
        for row in (attrs.get(layout.rows) if layout.rows else None) or [None]:
            out = dict(base)
            for col in layout.row_columns:
                out[layout.renamed.get(col, col)] = blank(row.get(col, "") if row else "")
            rows.append(out | scalars | {"peak_rss_gb": blank(attrs.get("peak_rss_gb"))})
    return rows


def input_failure(study: Any, spec: SweepSpec) -> StudyError | None:
    """If every grid point failed on bad input (an `InputError` of the evaluator), that error:
    the study evaluated nothing, and the command says so in one line."""
    found = []
    for state, trial in queue.statuses(study, spec).values():
        if state != "failed" or "input_error" not in trial.user_attrs:
            return None
        found.append(trial)
    if not found:
        return None
    first = found[0].user_attrs["input_error"]
    return StudyError(first["parameter"], f"{first['detail']} (no point of the study could be evaluated)")


def write_csv(rows: Sequence[Mapping[str, Any]], path: str | Path) -> Path:
    """Write dict rows to CSV (union of the keys, first-seen order), atomically."""
    path = Path(path)
    columns: list[str] = []
    for row in rows:
        columns += [k for k in row if k not in columns]
    with atomic_path(path) as temp, open(temp, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=columns)
        writer.writeheader()
        writer.writerows(rows)
    return path


def read_csv(path: str | Path) -> list[dict[str, str]]:
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))
