r"""A gait plan of the analytic planner replayed in FE (`softcrawl crawl --body fe --gait-plan`).

`softcrawl model plan` writes OUT/gait.csv: per planned cycle c two rows, the pressures it
inflates to and those it deflates to (kPa; columns cycle, phase, P1_kpa, P2_kpa, P3_kpa, then the
planner's foot positions, which the FE does not read: it finds its own). Each planned cycle
becomes one schedule of three rows over the cycle time T,

    t = 0:     the pressures the last cycle ended at (0 before the first),
    t = T / 2: the inflated pressures,
    t = T:     the deflated pressures,

so that consecutive cycles join where the plan's deflation left the chambers (the planner's
"held" deflation keeps some pressure). The quasi-static FE reads the times only to order the
states. `studies.crawl_fe.cycle.crawl_cycles` runs the list, one schedule per cycle.
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from softcrawl.studies.crawl.schedule import MAX_ROWS, Schedule, ScheduleError

COLUMNS = ("cycle", "phase", "P1_kpa", "P2_kpa", "P3_kpa")


def read_gait_plan(path: str | Path, cycle_s: float) -> tuple[Schedule, ...]:
    """The planned cycles of `softcrawl model plan`'s gait.csv at `path` as schedules of
    `cycle_s` seconds each (module docstring); ScheduleError naming "gait-plan" for a file that
    is not one."""
    path = Path(path)
    if not path.is_file():
        raise ScheduleError("gait-plan", f"{path} is not a file")
    try:
        with path.open(newline="") as fh:
            rows = list(csv.DictReader(fh))
    except (UnicodeDecodeError, csv.Error) as exc:
        raise ScheduleError("gait-plan", f"{path.name}: not a CSV table ({exc})") from None
    if not rows or any(c not in rows[0] for c in COLUMNS):
        raise ScheduleError(
            "gait-plan", f"{path.name}: needs the columns {','.join(COLUMNS)} (model plan's gait.csv)"
        )
    if len(rows) > MAX_ROWS or len(rows) % 2:
        raise ScheduleError(
            "gait-plan", f"{path.name}: give pairs of inflate and deflate rows, at most {MAX_ROWS}"
        )
    try:
        P = np.array([[float(r[f"P{i}_kpa"]) for i in (1, 2, 3)] for r in rows])
    except (TypeError, ValueError) as exc:
        raise ScheduleError("gait-plan", f"{path.name}: pressures must be numbers ({exc})") from None
    if not np.all(np.isfinite(P)) or np.any(P < 0) or np.any(P > 100.0):
        raise ScheduleError("gait-plan", f"{path.name}: pressures must be in [0, 100] kPa")
    phases = [r["phase"].strip() for r in rows]
    if phases != ["inflate", "deflate"] * (len(rows) // 2):
        raise ScheduleError("gait-plan", f"{path.name}: rows must alternate inflate, deflate")
    times = np.array([0.0, 0.5 * cycle_s, cycle_s])
    start = np.zeros(3)
    out = []
    for k in range(0, len(rows), 2):
        pressures = np.vstack([start, P[k], P[k + 1]])
        out.append(Schedule(f"{path.stem}-cycle{k // 2 + 1}", times, pressures, f"gait plan {path.name}"))
        start = P[k + 1]
    return tuple(out)
