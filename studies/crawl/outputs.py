r"""What the crawl records (`studies.crawl.model`): per converged state and per cycle.

Per state: time, the three pressures, the actuator's stiffness, preload and force T (N, > 0
pushing the hubs apart), the hub-to-hub change Delta, the ePSA length l0 + Delta and each
chamber's volume, estimated at the Table 1 chamber radius (`AxialLaw.chamber_volume`), and per
foot: the axial displacement of its hub plate from the reference (mm), the wall's normal force and
axial friction force on it (N), the slipping share of its contact area, the skirt tip's lead over
the hub top along the skirt's opening direction (mm; > 0: the skirt has flipped, as in
`studies.foot.model`), the ground spring's force; and the axial momentum balance: the sum of
the wall's axial friction forces and the ground springs' forces on both feet, and with flipped
feet the rim springs' (`rim_springs_n`, 0 once released) and the stabilisation's resultant
(`stabilisation_n`, the artificial force of the insertion's last sub-step, 0 once released;
`fem.stabilisation`) (0 at equilibrium, within the Newton tolerance).

Per cycle: each foot's advance and the stride (advance of the centre, the mean of the two hub
plates), speed = stride / cycle time; for each phase (extend: pressures rising, retract: falling)
each foot's displacement and whether it slid: its slipping share reached SLID_SHARE (gross slip
of the whole contact area, from the contact term's stick/slip state) in that phase.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from softcrawl.studies.crawl.mesh import FEET
from softcrawl.studies.foot import wedge

SLID_SHARE = 0.95


@dataclass(frozen=True)
class CrawlResult:
    converged: bool
    message: str
    states: tuple  # dicts, one per converged state
    cycles: tuple  # dicts, one per completed cycle
    n_dofs: int
    increments: int
    newton_iterations: int
    wall_s: float
    assembly_s: float
    solve_s: float
    ground_max_n: float  # largest ground-spring force once friction is on
    friction_max_n: float  # largest axial friction force on a foot
    momentum_max_n: float  # largest |sum of axial friction + ground forces| over the states

    @property
    def strides(self) -> list[float]:
        return [c["stride_mm"] for c in self.cycles]


class StateRecorder:
    def __init__(self, cm, on_state=None) -> None:
        self.cm, self.on_state = cm, on_state
        m = cm.model
        copies = cm.setup.copies  # a wedge: its means skip the cut at 2 pi / copies
        self.tips = {f: wedge.off_cut(m, f"{f}:rim", copies) for f in FEET}
        self.tops = {f: wedge.off_cut(m, f"{f}:hub_top", copies) for f in FEET}
        self.opening = {f: (-1.0 if mirror else 1.0) for f, mirror in zip(FEET, cm.setup.mirrored)}
        self.states: list[dict] = []
        self.cycles: list[dict] = []
        self.start: dict | None = None
        self._cycle_from = 0

    def _positions(self, x) -> dict:
        return {f: self.cm.terms[f"ground_{f}"].extension(x) for f in FEET}

    def record(self, step, cycle: int, t: float, pressures, phase: str) -> None:
        cm, x = self.cm, step.x
        m = cm.model
        act = cm.terms["actuator"]
        z = m.nodes[2] + m.displacement(x)[2]
        row = {
            "index": len(self.states),
            "stage": step.stage,
            "cycle": cycle + 1,
            "phase": phase,
            "time_s": float(t),
            **{f"p{i + 1}_kpa": float(pressures[i]) for i in range(3)},
            "actuator_stiffness_n_mm": act.stiffness,
            "actuator_preload_n": act.preload,
            "actuator_force_n": act.tension(x),
            "delta_mm": act.extension(x),
            "epsa_length_mm": cm.law.l0 + act.extension(x),
            "chamber_volume_mm3": cm.law.chamber_volume(act.extension(x)),
            "newton": int(step.iterations[0]),
            "penetration_mm": float(step.penetration),
        }
        balance = 0.0
        copies = cm.setup.copies  # a wedge's contact forces are 1 / copies of the feet's
        for f in FEET:
            reps = [c.report(x) for c in cm.contacts_of(f)]
            area = sum(r.area_reference for r in reps)
            friction = copies * float(sum(r.friction_force[2] for r in reps))
            ground = cm.terms[f"ground_{f}"].tension(x)
            balance += friction + ground
            row |= {
                f"{f}_u_mm": cm.terms[f"ground_{f}"].extension(x),
                f"{f}_normal_n": copies * float(sum(r.normal_force for r in reps)),
                f"{f}_friction_n": friction,
                f"{f}_slip_share": float(sum(r.slip_fraction * r.area_reference for r in reps) / area)
                if area > 0
                else 0.0,
                f"{f}_tip_lead_mm": self.opening[f] * float(z[self.tips[f]].mean() - z[self.tops[f]].mean()),
                f"{f}_ground_n": ground,
            }
        row["centre_u_mm"] = 0.5 * (row["rear_u_mm"] + row["front_u_mm"])
        springs = getattr(cm, "springs", None)
        if springs is not None:  # the flipped feet's rim springs act on the body until released
            row["rim_springs_n"] = copies * springs.axial_force(x)
            balance += row["rim_springs_n"]
        if getattr(cm, "stabilise", 0.0) > 0:  # their insertion's artificial force (record 094)
            row["stabilisation_n"] = copies * float(cm.stabilisation.force[2])
            balance += row["stabilisation_n"]
        row["momentum_n"] = balance
        self.states.append(row)
        if self.on_state is not None:
            self.on_state(row, self.cm.model, x)

    def mark_start(self, x) -> None:
        self.start = self._positions(x)

    def begin_cycle(self, cycle: int, x) -> None:
        self._cycle_from = len(self.states)
        self._cycle_start = self._positions(x)

    def end_cycle(self, cycle: int, x, cycle_s: float) -> None:
        end = self._positions(x)
        adv = {f: end[f] - self._cycle_start[f] for f in FEET}
        stride = 0.5 * (adv["rear"] + adv["front"])
        row = {
            "cycle": cycle + 1,
            "rear_advance_mm": adv["rear"],
            "front_advance_mm": adv["front"],
            "stride_mm": stride,
            "cycle_s": cycle_s,
            "speed_mm_s": stride / cycle_s,
        }
        rows = self.states[self._cycle_from :]
        prev = self.states[self._cycle_from - 1] if self._cycle_from > 0 else None
        for phase in ("extend", "retract"):
            for f in FEET:
                moved, slid = 0.0, False
                last = prev
                for r in rows:
                    if r["phase"] == phase and last is not None:
                        moved += r[f"{f}_u_mm"] - last[f"{f}_u_mm"]
                        slid |= r[f"{f}_slip_share"] >= SLID_SHARE
                    last = r
                row[f"{phase}_{f}_moved_mm"] = moved
                row[f"{phase}_{f}_slid"] = bool(slid)
        row["max_tip_lead_rear_mm"] = max(r["rear_tip_lead_mm"] for r in rows)
        row["max_tip_lead_front_mm"] = max(r["front_tip_lead_mm"] for r in rows)
        self.cycles.append(row)

    def result(self, ok: bool, message: str, stats, wall_s: float) -> CrawlResult:
        crawl = [s for s in self.states if s["cycle"] > 0]
        friction = [abs(s[f"{f}_friction_n"]) for s in crawl for f in FEET]
        return CrawlResult(
            converged=ok,
            message=message,
            states=tuple(self.states),
            cycles=tuple(self.cycles),
            n_dofs=int(self.cm.model.n_dofs),
            increments=len(self.states),
            newton_iterations=int(sum(r.newton_iterations for r in stats)),
            wall_s=wall_s,
            assembly_s=float(sum(r.assembly_s for r in stats)),
            solve_s=float(sum(r.solve_s for r in stats)),
            ground_max_n=max((abs(s[f"{f}_ground_n"]) for s in crawl for f in FEET), default=0.0),
            friction_max_n=max(friction, default=0.0),
            momentum_max_n=max(
                (abs(s["momentum_n"]) for s in self.states if s["stage"] != "insert"), default=0.0
            ),
        )


def steady_stride(result: CrawlResult) -> float:
    """Mean stride of the cycles after the first (the first starts from the unloaded robot); the
    first cycle's stride when there is only one; NaN without a cycle."""
    s = result.strides
    if not s:
        return float("nan")
    return float(np.mean(s[1:])) if len(s) > 1 else float(s[0])
