r"""The one body's gait cycles in its straight pipe: the three chambers follow a pressure schedule.

After `studies.crawl_fe.pipe.into_pipe` (inserted, friction on, holds soft), every segment of the
schedule (rows k -> k + 1 of `Schedule.times` and `.pressures_kpa`, one cycle) is one
`fem.contact_stages.Stage` that moves the three chamber pressures linearly to the next row's
(kPa converted to MPa once, here) in `steps` sub-steps, cut back where Newton needs it. Each
chamber has its own pressure, so a schedule with unequal pressures bends the body.

Outputs per segment end (`BodyState`): the time in the cycle, the pressures and the chamber
volumes, each foot's axial displacement and its position on the pipe's centreline, the body's
lateral drift, bend and heading, each foot's wall normal force and axial friction force, the
holds' largest force. A foot is placed by the hub face that the holds use (`rear_bottom`,
`front_top`; +z is forward, the direction the skirts' front faces look to): its axial
displacement is the face's mean u_z, its centreline position the arc length s of the point of
the pipe's centreline nearest to the face's deformed centroid (`ElbowPipe.locate`; on a straight
pipe the centroid's coordinate along the axis). The lateral drift is the mean (u_x, u_y) of both
faces. Each face is flat, so its deformed nodes' best-fit plane (the smallest singular vector of
the centred points) gives its normal n_f: the body's bend is the angle between the two faces'
normals, its heading the angle of the front face's normal to +z (the entry leg's axis). The
stride of a cycle is the advance of the body along the centreline, the mean of both feet's
advances in s over it (equal to either foot's once the cycle's gait closes: the actuators back at
their start length); its turn the change of the heading; its time the wall-clock seconds from the
previous cycle's last converged sub-step to its own, failed attempts included (a resumed run counts
from the checkpoint it continued from, so work lost to a stop is not in it).
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.contact_stages import Cursor, Stage, run_stages
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.studies.crawl.model import MAX_CUTBACKS
from softcrawl.studies.crawl.schedule import Schedule
from softcrawl.studies.crawl_fe.model import BODY_NEWTON, FEET, BodyModel
from softcrawl.studies.crawl_fe.pipe import record
from softcrawl.studies.crawl_fe.wedge import face_nodes, whole_points
from softcrawl.studies.foot.model import AUGMENT
from softcrawl.units import kpa_to_mpa

#: The hub face whose mean displacement places each foot (module docstring).
FOOT_FACES = {"rear": "rear_bottom", "front": "front_top"}


@dataclass(frozen=True)
class BodyState:
    cycle: int  # from 1 (0: the ramp to a schedule's first row)
    t: float  # s, in the cycle
    pressures_kpa: tuple[float, float, float]
    volumes: tuple[float, float, float]  # chamber volumes (mm^3)
    z: dict  # foot -> axial displacement (mm)
    arc: dict  # foot -> position on the centreline (mm)
    drift: tuple[float, float]  # mean lateral displacement (mm)
    bend_deg: float  # angle between the two hub faces' normals
    heading_deg: float  # angle of the front hub face's normal to +z
    normal: dict  # foot -> wall normal force (N)
    friction_z: dict  # foot -> axial friction force of the wall (N)
    holds_max: float  # N
    newton: int  # iterations of the segment
    x: np.ndarray = field(repr=False)


@dataclass
class CycleLog:
    """The bookkeeping of `crawl_cycles` so far (what a checkpoint stores besides the solver's state):
    the states recorded, the strides and turns of the cycles completed, where the current cycle
    began (each foot's centreline position, the heading), the Newton iterations of the current
    segment's converged sub-steps, the wall time of each completed cycle and the current one's so
    far (s; None for a cycle completed before checkpoints held it)."""

    start: tuple[dict, float]
    states: list[BodyState] = field(default_factory=list)
    strides: list[float] = field(default_factory=list)
    turns: list[float] = field(default_factory=list)
    segment: int = 0
    seconds: list[float | None] = field(default_factory=list)
    clock: float = 0.0


@dataclass(frozen=True)
class BodyCrawl:
    converged: bool
    message: str
    states: tuple[BodyState, ...]
    strides: tuple[float, ...]  # mm per completed cycle, along the centreline
    turns: tuple[float, ...]  # deg per completed cycle, the heading's change
    newton_iterations: int
    assembly_s: float
    solve_s: float
    wall_s: float
    factorizations: int = 0
    cycle_s: tuple[float | None, ...] = ()  # wall time per completed cycle (module docstring)


class FootProbe:
    """Each foot's axial displacement and centreline position, the lateral drift, the bend and
    the heading at a state (module docstring), on the discretisation `space` of the body's model
    in the pipe `wall` (any surface with `arc_length`: `CylinderWall`, `ElbowPipe`,
    `CorrugatedPipe`; None: a pipe on the z axis). A wedge of 2 pi / `copies`
    (`studies.crawl_fe.wedge`) reads one node of each orbit of a hub face, turned into all
    copies: the whole body's face (`wedge.face_nodes`)."""

    def __init__(self, space, wall=None, copies: int = 1):
        self.copies = int(copies)
        self.nodes = {foot: face_nodes(space, tag, self.copies) for foot, tag in FOOT_FACES.items()}
        self.points = {foot: whole_points(np.asarray(space.nodes)[:, n].T, self.copies)
                       for foot, n in self.nodes.items()}  # fmt: skip
        self.wall = CylinderWall(1.0) if wall is None else wall  # only its centreline is read

    def displacement(self, x: np.ndarray, foot: str) -> np.ndarray:
        """(n, 3) displacements of the whole hub face of `foot`."""
        n = self.nodes[foot]
        return whole_points(np.column_stack([x[3 * n], x[3 * n + 1], x[3 * n + 2]]), self.copies)

    def z(self, x: np.ndarray) -> dict:
        return {foot: float(x[3 * n + 2].mean()) for foot, n in self.nodes.items()}

    def deformed(self, x: np.ndarray, foot: str) -> np.ndarray:
        return self.points[foot] + self.displacement(x, foot)

    def arc(self, x: np.ndarray) -> dict:
        out = {}
        for foot in self.nodes:
            c = self.deformed(x, foot).mean(axis=0)
            out[foot] = float(self.wall.arc_length(c)[0])  # each pipe owns its centreline
        return out

    def normal(self, x: np.ndarray, foot: str) -> np.ndarray:
        p = self.deformed(x, foot)
        n = np.linalg.svd(p - p.mean(axis=0), full_matrices=False)[2][-1]
        return n if n[2] >= 0 else -n

    def angles(self, x: np.ndarray) -> tuple[float, float]:
        """(bend, heading) in degrees (module docstring)."""
        rear, front = self.normal(x, "rear"), self.normal(x, "front")
        bend = np.degrees(np.arccos(np.clip(rear @ front, -1.0, 1.0)))
        return float(bend), float(np.degrees(np.arccos(np.clip(front[2], -1.0, 1.0))))

    def drift(self, x: np.ndarray) -> tuple[float, float]:
        u = np.vstack([self.displacement(x, foot) for foot in self.nodes])
        return float(u[:, 0].mean()), float(u[:, 1].mean())


def crawl_cycles(
    bm: BodyModel,
    x0: np.ndarray,
    schedule: Schedule | Sequence[Schedule],
    *,
    cycles: int = 1,
    steps: int = 4,
    max_wall_s: float | None = None,
    on_step=None,
    factor: float = 0.0,
    wall=None,
    log: CycleLog | None = None,
    start: Cursor | None = None,
    on_cursor=None,
) -> BodyCrawl:
    """`cycles` cycles of `schedule` from the inserted state x0 (module docstring). All segments
    are the stages of one `run_stages` call, so that each starts from the pressures where the last
    ended; the outputs are read at each stage's end, with the contact history of that state.
    `factor`: the load factor held (x0's: 1 once the body's weight is on); `wall`: the pipe
    (`FootProbe`). `schedule` may be a sequence of schedules, one per cycle (a gait plan,
    `studies.crawl_fe.gait_plan`): then `cycles` is its length. Resuming (`studies.crawl_fe.resume`):
    `on_cursor(cursor, log)` is called after every converged sub-step with where the run stands and
    its bookkeeping so far; `start` and `log` (a stored cursor and its log, the model's history
    restored) continue from there, the stages before `start.stage` skipped."""
    if not isinstance(schedule, Schedule):
        per_cycle = list(schedule)
        cycles = len(per_cycle)
    if int(cycles) != cycles or cycles < 1:
        raise SolverInputError("cycles", f"a whole number of cycles >= 1, not {cycles!r}")
    if isinstance(schedule, Schedule):
        per_cycle = [schedule] * int(cycles)
    model, probe = bm.model, FootProbe(bm.model.space, wall, bm.copies)
    pressures = [np.asarray(sch.pressures_kpa, dtype=float) for sch in per_cycle]
    # (cycle, row): the inserted state is at zero pressure, so a schedule that starts elsewhere
    # is first ramped to its first row (cycle 0), then each cycle moves through rows 1..last
    plan = [(0, 0)] if np.any(pressures[0][0] != 0.0) else []
    plan += [(c, k) for c in range(1, cycles + 1) for k in range(1, len(pressures[c - 1]))]

    def of(cycle: int) -> tuple[Schedule, np.ndarray]:
        return per_cycle[max(cycle, 1) - 1], pressures[max(cycle, 1) - 1]

    def duration(cycle: int, row: int) -> float | None:
        """The segment's time (s), which viscous slip reads; the ramp to a first row has none."""
        times = of(cycle)[0].times
        return float(times[row] - times[row - 1]) if cycle >= 1 and times[row] > times[row - 1] else None

    stages = [
        Stage(
            f"cycle{c}-row{k}",
            pressure=[kpa_to_mpa(p) for p in bm.pressures(of(c)[1][k])],
            steps=steps,
            duration=duration(c, k),
        )
        for c, k in plan
    ]
    where = {stage.name: item for stage, item in zip(stages, plan)}
    log = log or CycleLog(start=(probe.arc(x0), probe.angles(x0)[1]))
    states, strides, turns = log.states, log.strides, log.turns

    def at_step(step) -> None:
        if on_step is not None:
            on_step(step)
        if step.s < 1.0 - 1e-12:
            return
        cycle, row = where[step.stage]
        sch, P = of(cycle)
        last = len(P) - 1
        x = step.x
        pipe = record(bm, step.stage, x)  # the contact history is this state's here
        arc, (bend, heading) = probe.arc(x), probe.angles(x)
        states.append(
            BodyState(
                cycle,
                float(sch.times[row]),
                tuple(float(p) for p in P[row]),
                bm.volumes(x),
                probe.z(x),
                arc,
                probe.drift(x),
                bend,
                heading,
                pipe.normal,
                {foot: float(pipe.friction[foot][2]) for foot in FEET},
                max(abs(v) for v in pipe.holds.values()),
                log.segment,
                x,
            )
        )
        if cycle >= 1 and row == last:
            strides.append(float(np.mean([arc[f] - log.start[0][f] for f in FEET])))
            turns.append(heading - log.start[1])
            log.seconds.append(log.clock)
        if row == last or cycle == 0:
            log.start, log.clock = (arc, heading), 0.0  # the next cycle begins here
        log.segment = 0

    mark = [time.perf_counter()]

    def count(step) -> None:
        log.segment += sum(step.iterations)
        now = time.perf_counter()
        log.clock, mark[0] = log.clock + now - mark[0], now
        at_step(step)

    res = run_stages(
        model,
        stages,
        x0=x0,
        factor0=factor,
        options=BODY_NEWTON,
        max_cutbacks=MAX_CUTBACKS,
        max_wall_s=max_wall_s,
        on_step=count,
        start=start,
        on_cursor=None if on_cursor is None else (lambda cursor: on_cursor(cursor, log)),
        **AUGMENT,
    )
    message = f"{cycles} cycle(s) reached" if res.converged else res.message
    return BodyCrawl(
        res.converged,
        message,
        tuple(states),
        tuple(strides),
        tuple(turns),
        res.newton_iterations,
        res.assembly_s,
        res.solve_s,
        res.wall_s,
        res.factorizations,
        tuple(log.seconds),
    )
