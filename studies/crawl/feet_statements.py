r"""Fig. 21's two statements (paper Section VII-C), checked on the FE speeds of `study feet`.

The statements, as printed (`softcrawl.paper`, FIG21_*), and what each check computes from the
study's rows (one per hardness S (Shore A) and foot angle a (deg), with a status and the steady
speed v(S, a) in mm/s):

1. "greater than 10 mm/s ... using material hardness between 50A and 70A and foot angle between 30
   and 120 deg": over the grid points with 50 <= S <= 70 and 30 <= a <= 120,
       holds      when every point was computed and v > 10 mm/s at each (strictly, as printed);
       fails      when any computed point has v <= 10 mm/s (one is enough, whatever is missing);
       undecided  otherwise (every computed point above, some not computed).
   Its detail gives the count "k of n points above 10 mm/s".
2. "With 70A hardness, the crawling speed ... increases with the increase in the foot angle": at
   S = 70, over the angles in increasing order, every step must rise by more than
   `SPEED_RESOLUTION_MM_S`:
       holds      when every angle of the grid was computed and v(a_(i+1)) - v(a_i) > resolution
                  for every consecutive pair (at least two angles);
       fails      when two consecutive computed angles (no grid angle between them missing) do not
                  rise by more than the resolution;
       undecided  otherwise.
   The resolution: where no foot slides, the committed crawl study's "speeds" are 0.001-0.006 mm/s
   (results/crawl/rubber-70a-quick, the 60 and 65 mm pipes): stride noise of a robot that does
   not move. A rise below 0.01 mm/s cannot tell a faster robot from two that stand still.

Failed points (the FE did not complete the cycles) are "not computed": their reason is in the
study's table, never a speed.
"""

from __future__ import annotations

from dataclasses import dataclass

from softcrawl.paper import (
    FIG21_ANGLE_DEG,
    FIG21_HARDNESS_SHORE_A,
    FIG21_MIN_SPEED_MM_S,
    FIG21_RISING_SHORE_A,
)

#: Least rise (mm/s) between consecutive angles that counts as "increases" (module docstring).
SPEED_RESOLUTION_MM_S = 0.01

ABOVE = (
    f"> {FIG21_MIN_SPEED_MM_S:g} mm/s over {FIG21_HARDNESS_SHORE_A[0]:g}A-{FIG21_HARDNESS_SHORE_A[1]:g}A and "
    + (f"{FIG21_ANGLE_DEG[0]:g}-{FIG21_ANGLE_DEG[1]:g} deg")
)
RISES = f"rises with angle at {FIG21_RISING_SHORE_A:g}A"


@dataclass(frozen=True)
class Verdict:
    """One statement's check: `verdict` is "holds", "fails" or "undecided"; `detail` says why."""

    statement: str
    verdict: str
    detail: str

    def text(self) -> str:
        return f'"{self.statement}": {self.verdict} ({self.detail})'


def _computed(row: dict) -> bool:
    return row.get("status") == "completed" and row.get("speed_mm_s") == row.get("speed_mm_s")


def _in_range(row: dict) -> bool:
    (s0, s1), (a0, a1) = FIG21_HARDNESS_SHORE_A, FIG21_ANGLE_DEG
    return s0 <= float(row["shore_a"]) <= s1 and a0 <= float(row["angle_deg"]) <= a1


def above_speed(rows) -> Verdict:
    """Statement 1 (module docstring)."""
    points = [r for r in rows if _in_range(r)]
    done = [r for r in points if _computed(r)]
    above = [r for r in done if float(r["speed_mm_s"]) > FIG21_MIN_SPEED_MM_S]
    missing = len(points) - len(done)
    count = f"{len(above)} of {len(points)} points above {FIG21_MIN_SPEED_MM_S:g} mm/s"
    if len(above) < len(done):
        slow = min(done, key=lambda r: float(r["speed_mm_s"]))
        at = f"{slow['shore_a']:g}A, {slow['angle_deg']:g} deg"
        worst = f"; slowest {float(slow['speed_mm_s']):.3g} mm/s at {at}"
        more = f", {missing} not computed" if missing else ""
        return Verdict(ABOVE, "fails", count + more + worst)
    if missing or not points:
        return Verdict(ABOVE, "undecided", f"{count}, {missing} not computed")
    return Verdict(ABOVE, "holds", count)


def rises_with_angle(rows) -> Verdict:
    """Statement 2 (module docstring)."""
    at = sorted(
        (r for r in rows if float(r["shore_a"]) == FIG21_RISING_SHORE_A), key=lambda r: float(r["angle_deg"])
    )
    steps = []
    for lo, hi in zip(at, at[1:]):
        if not (_computed(lo) and _computed(hi)):
            continue
        rise = float(hi["speed_mm_s"]) - float(lo["speed_mm_s"])
        steps.append((lo["angle_deg"], hi["angle_deg"], rise))
    text = ", ".join(f"{a:g}->{b:g} deg {rise:+.3g} mm/s" for a, b, rise in steps) or "no pair computed"
    if any(rise <= SPEED_RESOLUTION_MM_S for _, _, rise in steps):
        return Verdict(RISES, "fails", text)
    if len(at) < 2 or len(steps) < len(at) - 1:
        missing = sum(not _computed(r) for r in at)
        return Verdict(RISES, "undecided", f"{text}; {missing} of {len(at)} angles not computed")
    return Verdict(RISES, "holds", text)


def verdicts(rows) -> tuple[Verdict, Verdict]:
    """Both statements' checks on the study's rows."""
    rows = list(rows)
    return above_speed(rows), rises_with_angle(rows)
