r"""The one body's gait cycles in its straight pipe: the three chambers follow a pressure schedule.

After `studies.crawl_fe.pipe.into_pipe` (inserted, friction on, holds soft), every segment of the
schedule (rows k -> k + 1 of `Schedule.times` and `.pressures_kpa`, one cycle) is one
`fem.contact_stages.Stage` that moves the three chamber pressures linearly to the next row's
(kPa converted to MPa once, here) in `steps` sub-steps, cut back where Newton needs it. Each
chamber has its own pressure, so a schedule with unequal pressures bends the body.

Outputs per segment end (`BodyState`): the time in the cycle, the pressures, each foot's axial
position and the body's lateral drift, each foot's wall normal force and axial friction force,
the holds' largest force. A foot's axial position is the mean u_z of its hub face that the
holds use (`rear_bottom`, `front_top`; +z is forward, the direction the skirts' front faces
look to); the lateral drift is the mean (u_x, u_y) of both faces. The stride of a cycle is the
advance of the body, the mean of both feet's advances over it (equal to either foot's once the
cycle's gait closes: the actuators back at their start length).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.errors import SolverInputError
from softcrawl.studies.crawl.model import CRAWL_NEWTON, MAX_CUTBACKS
from softcrawl.studies.crawl.schedule import Schedule
from softcrawl.studies.crawl_fe.model import FEET, BodyModel
from softcrawl.studies.crawl_fe.pipe import record
from softcrawl.studies.foot.model import AUGMENT
from softcrawl.units import kpa_to_mpa

#: The hub face whose mean displacement places each foot (module docstring).
FOOT_FACES = {"rear": "rear_bottom", "front": "front_top"}


@dataclass(frozen=True)
class BodyState:
    cycle: int  # from 1 (0: the ramp to a schedule's first row)
    t: float  # s, in the cycle
    pressures_kpa: tuple[float, float, float]
    z: dict  # foot -> axial position (mm)
    drift: tuple[float, float]  # mean lateral displacement (mm)
    normal: dict  # foot -> wall normal force (N)
    friction_z: dict  # foot -> axial friction force of the wall (N)
    holds_max: float  # N
    newton: int  # iterations of the segment
    x: np.ndarray = field(repr=False)


@dataclass(frozen=True)
class BodyCrawl:
    converged: bool
    message: str
    states: tuple[BodyState, ...]
    strides: tuple[float, ...]  # mm per completed cycle
    newton_iterations: int
    assembly_s: float
    solve_s: float
    wall_s: float


class FootProbe:
    """Each foot's axial position and the lateral drift at a state (module docstring), on the
    discretisation `space` of the body's model."""

    def __init__(self, space):
        self.nodes = {foot: space.boundary_nodes(tag) for foot, tag in FOOT_FACES.items()}

    def z(self, x: np.ndarray) -> dict:
        return {foot: float(x[3 * n + 2].mean()) for foot, n in self.nodes.items()}

    def drift(self, x: np.ndarray) -> tuple[float, float]:
        nodes = np.concatenate(list(self.nodes.values()))
        return float(x[3 * nodes].mean()), float(x[3 * nodes + 1].mean())


def crawl_cycles(
    bm: BodyModel,
    x0: np.ndarray,
    schedule: Schedule,
    *,
    cycles: int = 1,
    steps: int = 4,
    max_wall_s: float | None = None,
    on_step=None,
) -> BodyCrawl:
    """`cycles` cycles of `schedule` from the inserted state x0 (module docstring). All segments
    are the stages of one `run_stages` call, so that each starts from the pressures where the last
    ended; the outputs are read at each stage's end, with the contact history of that state."""
    if int(cycles) != cycles or cycles < 1:
        raise SolverInputError("cycles", f"a whole number of cycles >= 1, not {cycles!r}")
    model, probe = bm.model, FootProbe(bm.model.space)
    P = np.asarray(schedule.pressures_kpa, dtype=float)
    last = len(P) - 1
    # (cycle, row): the inserted state is at zero pressure, so a schedule that starts elsewhere
    # is first ramped to its first row (cycle 0), then each cycle moves through rows 1..last
    plan = [(0, 0)] if np.any(P[0] != 0.0) else []
    plan += [(c, k) for c in range(1, cycles + 1) for k in range(1, last + 1)]
    stages = [Stage(f"cycle{c}-row{k}", pressure=[kpa_to_mpa(p) for p in P[k]], steps=steps) for c, k in plan]
    where = {stage.name: item for stage, item in zip(stages, plan)}
    states: list[BodyState] = []
    strides: list[float] = []
    segment = [0]  # Newton iterations of the converged sub-steps of the current segment
    start = [probe.z(x0)]

    def at_step(step) -> None:
        if on_step is not None:
            on_step(step)
        if step.s < 1.0 - 1e-12:
            return
        cycle, row = where[step.stage]
        x = step.x
        pipe = record(bm, step.stage, x)  # the contact history is this state's here
        z = probe.z(x)
        states.append(
            BodyState(
                cycle,
                float(schedule.times[row]),
                tuple(float(p) for p in P[row]),
                z,
                probe.drift(x),
                pipe.normal,
                {foot: float(pipe.friction[foot][2]) for foot in FEET},
                max(abs(v) for v in pipe.holds.values()),
                segment[0],
                x,
            )
        )
        if cycle >= 1 and row == last:
            strides.append(float(np.mean([z[f] - start[0][f] for f in FEET])))
        if row == last or cycle == 0:
            start[0] = z  # the next cycle begins here
        segment[0] = 0

    def count(step) -> None:
        segment[0] += sum(step.iterations)
        at_step(step)

    res = run_stages(
        model,
        stages,
        x0=x0,
        options=CRAWL_NEWTON,
        max_cutbacks=MAX_CUTBACKS,
        max_wall_s=max_wall_s,
        on_step=count,
        **AUGMENT,
    )
    message = f"{cycles} cycle(s) reached" if res.converged else res.message
    return BodyCrawl(
        res.converged,
        message,
        tuple(states),
        tuple(strides),
        res.newton_iterations,
        res.assembly_s,
        res.solve_s,
        res.wall_s,
    )
