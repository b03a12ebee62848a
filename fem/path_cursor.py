r"""Where `fem.path.load_path` stands after a converged sub-step, to continue from there after a kill.

A `PathCursor` holds what the next sub-step needs: the target being approached (its index) and
the load the segment started from, the fraction t of the segment reached and the next fraction h,
the sub-steps and attempts spent on it, the predictors' history (the last two converged states and
their loads; the tangent is recomputed from them), the step memory of the next segment, and the
path so far (the `Step` of every target reached, and the events). `to_arrays` and `from_arrays`
turn it into the arrays and JSON metadata of a `fem.checkpoint` state and back, bit for bit.

Two limits, stated where they bite: the cursor holds no contact history (`load_path` refuses to
resume a model with contact terms: `fem.contact_stages` has its own cursor), and it is emitted
only under pressure control: a path that has switched to volume control past a limit point
(`fem.continuation`) is resumed from its last pressure-controlled state, where pressure control
stalls again and volume control takes over as before.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, field

import numpy as np

from softcrawl.fem.newton import NewtonRecord, SolveStats
from softcrawl.fem.steps import Step


@dataclass(frozen=True)
class PathCursor:
    target: int  # index of the target being approached
    start: np.ndarray  # load vector the segment started from
    t: float  # fraction of the segment reached
    h: float | None  # the next fraction (None: the segment's first, from the step memory)
    n_sub: int  # converged sub-steps of this segment
    trials: int  # attempts on this segment (max_substeps)
    x: np.ndarray = field(repr=False)
    load: np.ndarray
    x_prev: np.ndarray | None = field(repr=False)
    load_prev: np.ndarray | None
    memory: tuple[float | None, np.ndarray | None]  # StepMemory (length, direction)
    steps: tuple[Step, ...] = field(repr=False)
    events: tuple[str, ...]
    stats: SolveStats  # the solver's effort and the wall time so far


def to_arrays(cursor: PathCursor) -> tuple[dict[str, np.ndarray], dict]:
    """(arrays, meta) of a `fem.checkpoint` state."""
    arrays = {"x": cursor.x, "load": np.asarray(cursor.load), "start": np.asarray(cursor.start)}
    if cursor.x_prev is not None:
        arrays["x_prev"], arrays["load_prev"] = cursor.x_prev, np.asarray(cursor.load_prev)
    length, direction = cursor.memory
    if direction is not None:
        arrays["memory_direction"] = np.asarray(direction)
    steps = []
    for k, s in enumerate(cursor.steps):
        arrays[f"step_x_{k}"] = s.x
        steps.append(
            {
                "pressure": list(s.pressure) if isinstance(s.pressure, tuple) else s.pressure,
                "factor": s.factor,
                "volume": s.volume,
                "control": s.control,
                "residuals": list(s.newton.residuals),
                "converged": s.newton.converged,
                "substeps": s.substeps,
                "past_limit": s.past_limit,
                "volumes": list(s.volumes),
            }
        )
    meta = {
        "target": cursor.target,
        "t": cursor.t,
        "h": cursor.h,
        "n_sub": cursor.n_sub,
        "trials": cursor.trials,
        "memory_length": length,
        "steps": steps,
        "events": list(cursor.events),
        "stats": asdict(cursor.stats),
    }
    return arrays, meta


def from_arrays(meta: dict, arrays: dict[str, np.ndarray]) -> PathCursor:
    """The cursor of `to_arrays` (KeyError, TypeError or ValueError for a state that is not one)."""
    steps = []
    for k, s in enumerate(meta["steps"]):
        pressure = (
            tuple(float(p) for p in s["pressure"]) if isinstance(s["pressure"], list) else s["pressure"]
        )
        steps.append(
            Step(
                pressure,
                float(s["factor"]),
                float(s["volume"]),
                arrays[f"step_x_{k}"],
                str(s["control"]),
                NewtonRecord(tuple(float(r) for r in s["residuals"]), bool(s["converged"])),
                int(s["substeps"]),
                bool(s["past_limit"]),
                tuple(float(v) for v in s["volumes"]),
            )
        )
    has_prev = "x_prev" in arrays
    return PathCursor(
        target=int(meta["target"]),
        start=arrays["start"],
        t=float(meta["t"]),
        h=None if meta["h"] is None else float(meta["h"]),
        n_sub=int(meta["n_sub"]),
        trials=int(meta["trials"]),
        x=arrays["x"],
        load=arrays["load"],
        x_prev=arrays["x_prev"] if has_prev else None,
        load_prev=arrays["load_prev"] if has_prev else None,
        memory=(meta["memory_length"], arrays.get("memory_direction")),
        steps=tuple(steps),
        events=tuple(meta["events"]),
        stats=SolveStats(**meta["stats"]),
    )
