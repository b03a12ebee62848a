r"""Pressure schedules of the crawl and the actuators' axial law (`studies.crawl.model`).

Schedules. Piecewise linear pressures (kPa) of the three ePSAs against time, one cycle, repeated.
  inflate  all three 0 -> P in half the cycle, then P -> 0 (the paper's horizontal crawl: 2 s cycles).
  gait1-3  the paper's Fig. 25 caption, read as valve timings with a constant fill rate P / 1.5 s
           and a constant release rate (gait 1: "deflated for 2 s", taken as P / 2 s, full; gaits
           2 and 3: "fully deflated for 0.5 s", P / 0.5 s):
             gait1  all three inflated 1.5 s (to P), deflated 2 s (to 0): 3.5 s;
             gait2  ePSA 2, 3 inflated 1.5 s (to P), ePSA 1 for 0.3 s (to 0.2 P), then all released
                    for 0.2 s "not fully" (each loses 0.4 P: 0, 0.6 P, 0.6 P held into the next
                    cycle, whose fill stops at P): 1.7 s;
             gait3  as gait2, then fully released in 0.5 s: 2.0 s.
           These rates are this module's reading of the caption (the paper gives no pressure
           traces); the quasi-static model uses the times only to order the states.
  A schedule that starts at non-zero pressures (gait2's held state, a CSV) is reached from 0 by
  one ramp before the first cycle.
  CSV      rows time_s, P1_kpa, P2_kpa, P3_kpa (header required), times increasing from 0: one
           cycle, repeated; linear between rows.

Axial law (source: the paper's prototype statics, eqs. 19-24, the coefficient-wise mean of ePSA
1-3, `analytic.prototype.nominal_epsa`; gravity off, a horizontal pipe). The FE identification of
the Table 1 ePSA (results/identify) is not used: its k_p is 5-7x the prototype's
(results/identify/kp-mismatch.md), so the robot it describes is not the one of Table 2. Each ePSA
is eq. 3 along the axis, f_i = f_p(P_i) - k_p(P_i) Delta; the three act in parallel between the
two hubs (bending is not modelled: a schedule's unequal pressures act through their sum), so

    F(P, Delta) = sum_i [f_p(P_i) - f_p(0)] - sum_i k_p(P_i) Delta,

Delta the change of the hub-to-hub distance from the as-inserted robot. f_p(0) (-0.18 N per
actuator, the intercept of the fitted line) is removed so that the robot as built is free of
force at zero pressure. The axial law keeps no chamber radius, so the outputs give the ePSA length
l0 + Delta and, as an estimate, each chamber's volume pi r0^2 (l_c + Delta) at the Table 1
radius r0 (`AxialLaw.chamber_volume`; the radial growth under pressure is left out).
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from softcrawl.analytic.loads import crawl_speed
from softcrawl.analytic.prototype import actuator_set, nominal_epsa
from softcrawl.errors import InputError
from softcrawl.geometry.design import EPSADesign

#: The preset schedules. gait1-3 keep the paper's names (its "gaits", Fig. 25) and the CLI option
#: is `softcrawl crawl --gait`; in code they are schedules: a gait is `analytic.gait`'s planned
#: pressure sequence, a different thing.
SCHEDULES = ("inflate", "gait1", "gait2", "gait3")
FILL_S = 1.5  # time to fill from 0 to P (the valve-timed presets gait1-3)
RELEASE_S = {"gait1": 2.0, "gait2": 0.5, "gait3": 0.5}  # time to release from P to 0
MAX_ROWS = 10_000
LAW_SOURCE = "paper eqs. 19-24 (prototype statics, mean of ePSA 1-3; analytic.prototype.nominal_epsa)"


def analytic_speed(pressure_kpa: float, cycle_s: float, friction_n: float) -> float:
    return crawl_speed(actuator_set("nominal"), pressure_kpa, friction_n, cycle_s).speed_mm_s


class ScheduleError(InputError):
    """A bad pressure schedule (names the parameter)."""


@dataclass(frozen=True)
class Schedule:
    name: str
    times: np.ndarray  # (n,) s, from 0, one cycle
    pressures_kpa: np.ndarray  # (n, 3)
    source: str

    @property
    def cycle_s(self) -> float:
        return float(self.times[-1] - self.times[0])


def _valve_rows(name: str, p: float):
    """(time, P1, P2, P3) breakpoints of one cycle of a valve-timed preset (gait1-3): each ePSA
    follows its valve phases (start, end, rate) from the held start state, clipped to [0, p], on a
    1 ms grid; the rows kept are the grid points where a pressure's slope changes."""
    fill, release = p / FILL_S, -p / RELEASE_S[name]
    if name == "gait1":
        phases = [[(0.0, FILL_S, fill), (FILL_S, FILL_S + 2.0, release)]] * 3
        start = np.zeros(3)
    else:
        dt = 0.2 if name == "gait2" else 0.5
        out = (FILL_S, FILL_S + dt, release)
        phases = [[(0.0, 0.3, fill), out], [(0.0, FILL_S, fill), out], [(0.0, FILL_S, fill), out]]
        start = np.array([0.0, 0.6 * p, 0.6 * p]) if name == "gait2" else np.zeros(3)
    end_ms = round(1000 * max(ph[-1][1] for ph in phases))
    t = np.arange(end_ms + 1) / 1000.0
    P = np.empty((t.size, 3))
    for i in range(3):
        rate = np.zeros(t.size - 1)
        for t0, t1, r in phases[i]:
            rate[(t[:-1] >= t0 - 1e-9) & (t[:-1] < t1 - 1e-9)] = r
        value = start[i]
        P[0, i] = value
        for k in range(t.size - 1):
            value = min(max(value + rate[k] * 1e-3, 0.0), p)
            P[k + 1, i] = value
    slope = np.diff(P, axis=0)
    bend = np.any(np.abs(np.diff(slope, axis=0)) > 1e-9 * p, axis=1)
    keep = np.concatenate([[True], bend, [True]])
    return np.column_stack([t[keep], P[keep]])


def preset(name: str, pressure_kpa: float = 100.0, cycle_s: float = 2.0) -> Schedule:
    """The named schedule at peak pressure `pressure_kpa` (module docstring)."""
    if name not in SCHEDULES:  # the parameter is named as the CLI option that gives it, --gait
        raise ScheduleError("gait", f"{name!r} is not one of {', '.join(SCHEDULES)}")
    if not (math.isfinite(pressure_kpa) and 0 < pressure_kpa <= 100.0):
        raise ScheduleError(
            "pressure", f"must be in (0, 100] kPa (the prototype's range), got {pressure_kpa!r}"
        )
    p = float(pressure_kpa)
    if name == "inflate":
        if not (math.isfinite(cycle_s) and cycle_s > 0):
            raise ScheduleError("cycle_time", f"must be a positive number of seconds, got {cycle_s!r}")
        rows = [(0.0, 0, 0, 0), (cycle_s / 2, p, p, p), (cycle_s, 0, 0, 0)]
        source = f"all three 0 -> {p:g} -> 0 kPa in {cycle_s:g} s"
    elif name == "gait1":
        rows = _valve_rows(name, p)
        source = "paper Fig. 25 gait1 (inflate 1.5 s, deflate 2 s)"
    else:
        rows = _valve_rows(name, p)
        source = f"paper Fig. 25 {name} (fill rate P/1.5 s, release rate P/0.5 s: this module's reading)"
    arr = np.array(rows, dtype=float)
    return Schedule(name, arr[:, 0], arr[:, 1:], source)


def read_csv(path: str | Path) -> Schedule:
    """A user schedule: header time_s,P1_kpa,P2_kpa,P3_kpa, then one cycle of rows."""
    path = Path(path)
    if not path.is_file():
        raise ScheduleError("schedule", f"{path} is not a file")
    try:
        with path.open(newline="") as fh:
            reader = csv.reader(fh)
            header = [h.strip() for h in next(reader, [])]
            rows = [[float(v) for v in r] for r in reader if r and any(c.strip() for c in r)]
    except (ValueError, UnicodeDecodeError) as exc:
        raise ScheduleError("schedule", f"{path.name}: not a table of numbers ({exc})") from None
    if header != ["time_s", "P1_kpa", "P2_kpa", "P3_kpa"]:
        raise ScheduleError("schedule", f"{path.name}: the header must be time_s,P1_kpa,P2_kpa,P3_kpa")
    if not 2 <= len(rows) <= MAX_ROWS or any(len(r) != 4 for r in rows):
        raise ScheduleError("schedule", f"{path.name}: give 2 to {MAX_ROWS} rows of 4 numbers")
    arr = np.array(rows)
    if not np.all(np.isfinite(arr)):
        raise ScheduleError("schedule", f"{path.name}: every value must be finite")
    if arr[0, 0] != 0 or np.any(np.diff(arr[:, 0]) <= 0):
        raise ScheduleError("schedule", f"{path.name}: times must start at 0 and increase")
    if np.any(arr[:, 1:] < 0) or np.any(arr[:, 1:] > 100.0):
        raise ScheduleError("schedule", f"{path.name}: pressures must be in [0, 100] kPa")
    return Schedule(path.stem, arr[:, 0], arr[:, 1:], f"user CSV {path.name}")


@dataclass(frozen=True)
class AxialLaw:
    """The three ePSAs' axial force between the hubs (module docstring)."""

    source: str = LAW_SOURCE

    def _actuator(self):
        return nominal_epsa()

    def stiffness_preload(self, pressures_kpa) -> tuple[float, float]:
        """(sum k_p(P_i) in N/mm, sum [f_p(P_i) - f_p(0)] in N)."""
        a = self._actuator()
        p = np.asarray(pressures_kpa, dtype=float)
        return float(np.sum(a.k_p(p))), float(np.sum(a.f_p(p) - a.f_p(0.0)))

    def force(self, pressures_kpa, delta_mm: float) -> float:
        k, f0 = self.stiffness_preload(pressures_kpa)
        return f0 - k * delta_mm

    @property
    def l0(self) -> float:
        return float(self._actuator().l0)

    def chamber_volume(self, delta_mm: float) -> float:
        """One ePSA's chamber volume (mm^3) at the hub-to-hub change delta: pi r0^2 (l_c + delta),
        the Table 1 chamber (`geometry.design.EPSADesign`, r0 = 3 mm, l_c = 90 mm) lengthened by
        delta at its radius. An estimate: the axial law keeps no radius, so the chamber's radial
        growth under pressure (held small by the winding) is left out, and the end caps are taken
        as not stretching."""
        epsa = EPSADesign()
        return epsa.chamber_volume + math.pi * epsa.chamber_radius**2 * float(delta_mm)
