r"""The crawl in FE: two grooved feet in a rigid pipe, coupled by the three ePSAs' axial law.

Model (docs/decisions/051-crawl-model.md). Both feet are the `geometry.foot` mesh of
`CrawlSetup.foot` (P2-P1, the rubber `CrawlSetup.material`: Shore 70A by default), placed as on
the robot (`studies.crawl.mesh`), each skirt in frictional contact with one rigid `CylinderWall`
on the pipe axis through two terms per foot (smooth front face + rim with mu_smooth, grooved back
face with mu_grooved, as in `studies.foot.model`). Neither foot is
clamped. The hub face each foot's actuators act on is a rigid plate: its nodes share one axial
displacement (`fem.equal_displacement.EqualDisplacement`) and its lateral displacements are held
at 0 (the robot's axis stays on the pipe axis: the stiff ePSA bundle and rings are not modelled,
and this also removes the lateral and twist rigid modes, which only friction would hold). Between
the two plates acts the actuators' axial law F(P, Delta) (`studies.crawl.schedule`) as a
`fem.axial_link.AxialLink` whose stiffness and preload follow the pressure schedule.

Ground springs. One `AxialLink` to the ground on each plate: stiff (GROUND_HOLD) while the wall
shrinks frictionless (axial position otherwise undetermined), then, once friction is on, re-based
at the inserted position and softened to GROUND_SOFT, so that the axial rigid mode is held by
friction alone; their forces are reported (and compared with the friction forces).

The flipped feet (`studies.crawl.flipped`). Their plates are held while their wall closes and
their rim springs are released (docs/decisions/079-backward-plates.md): each plate's ground
spring is k_hold = n k_p, as stiff as the plate's penalty holds its n nodes together, so the plate
is held in all three directions up to its own constraint error (on GROUND_HOLD Newton wandered);
friction takes over as from GROUND_HOLD. Where their fold reaches outside the pipe, the closing
wall crushes it through a snap, and the insertion and the release are stabilised
(`fem.stabilisation`, c ramped to 0 over the release; docs/decisions/094-backward-snap.md).

Wedge (`CrawlSetup.copies` > 1; `studies.foot.wedge`, docs/decisions/082-crawl-wedge.md and 083):
one wedge of 2 pi / copies of each foot, its cuts tied exactly by cyclic symmetry, carrying
1 / copies of the links.

Stages: insert (the wall shrinks from clear of the tip to the pipe radius, frictionless), friction
(coefficients on), a ramp to the schedule's start pressures when they are not zero, then each
cycle of the schedule, segment by segment (`steps` sub-steps per segment at least; run_stages
refines a hard one). Every converged state is recorded (`studies.crawl.outputs`).
"""

from __future__ import annotations

import contextlib
import time
from dataclasses import dataclass, field, replace

import numpy as np

from softcrawl.analytic.pipe import Pipe
from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.equal_displacement import EqualDisplacement
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.fem.stabilisation import Stabilisation
from softcrawl.geometry.foot_design import FootDesign
from softcrawl.studies.crawl import flipped
from softcrawl.studies.crawl.contacts import feet_contacts
from softcrawl.studies.crawl.mesh import FEET, attach_tag
from softcrawl.studies.crawl.outputs import CrawlResult, StateRecorder
from softcrawl.studies.crawl.resume import Totals
from softcrawl.studies.crawl.schedule import AxialLaw, Schedule
from softcrawl.studies.foot import wedge
from softcrawl.studies.foot.model import (
    AUGMENT,
    FOOT_NEWTON,
    MIN_STEP_FRACTION,
    insertion_wall,
    small_strain_youngs,
)

#: Halvings of a sub-step before a stage is given up: the unloading of a skirt reverses slip
#: over part of its contact (points flip between stick and slip), which needs sub-steps down to
#: 1/256 of a schedule segment (4 halvings, the foot study's, stopped at 56 kPa on the way down).
MAX_CUTBACKS = 8

#: Relative residual at which a stalled Newton iteration is accepted (`fem.newton`, "Stalled
#: residuals"). On the revolved feet (164k DOFs) the retraction's first sub-steps settle at
#: 5e-8 against the 1e-8 target: points on the normal law's kink flip between contact and no
#: contact. 1e-6 of the force scale is far below the forces reported (the momentum balance of
#: every state, printed, shows the axial imbalance that remains).
STALL_TOL = 1.0e-6
CRAWL_NEWTON = replace(FOOT_NEWTON, stall_tol=STALL_TOL)

GROUND_HOLD = 1.0e3  # N/mm: holds the plates during the frictionless insertion
GROUND_SOFT = 1.0e-4  # N/mm: after friction is on (<< the skirts' axial stiffness, ~10 N/mm)
#: The plates' penalty (`EqualDisplacement`), per node, in units of E h (h the median edge).
PLATE_PENALTY = 1.0e3


@dataclass(frozen=True)
class CrawlSetup:
    pipe_diameter: float = 70.0
    mu_smooth: float = 0.5
    mu_grooved: float = 0.5
    #: viscous slip of both feet's faces, MPa s/mm (`fem.contact_law`; 0: Coulomb, the default;
    #: docs/decisions/088-viscous-slip.md); each schedule segment's sub-steps get their time
    slip_viscosity: float = 0.0
    feet: str = "paper"  # "paper" (both lean back), "backward" (both flipped), "symmetric"
    foot: FootDesign = FootDesign()  # both feet's design (the paper's: 120 deg; Fig. 21 varies the angle)
    material: str = "rubber-70a"  # both feet's rubber, a `softcrawl.materials` preset name
    insert_steps: int = 8
    steps: int = 4  # sub-steps per schedule segment
    cycles: int = 1
    max_wall_s: float | None = None  # give the schedule up after this wall time (None: no limit)
    mesher: str = "revolved"  # the feet's mesher (geometry.foot_meshers.FOOT_MESHERS)
    sectors: int | None = None  # revolved: sectors around the axis (None: 48)
    thickness_layers: int | None = None  # revolved: cells through the skirt (None: 3)
    edge_length: float | None = None  # tetwild: foot mesh edge (mm; None: the pytetwild default)
    copies: int = 1  # one wedge of 2 pi / copies: the feet's (`studies.foot.wedge`), or the FE body's (3)

    @property
    def pipe(self) -> Pipe:
        """The straight pipe of the crawl (its wall and the VTU's come from it)."""
        return Pipe(diameter=self.pipe_diameter)

    def mesh_options(self) -> dict:
        """The keyword arguments of `studies.crawl.mesh.crawl_mesh` for this setup."""
        return {
            "mesher": self.mesher,
            "sectors": self.sectors,
            "thickness_layers": self.thickness_layers,
            "edge_length": self.edge_length,
            "copies": self.copies,
        }

    @property
    def mirrored(self) -> tuple[bool, bool]:
        return {"paper": (False, False), "backward": (False, False), "symmetric": (False, True)}[self.feet]

    @property
    def flipped(self) -> bool:
        """Both skirts start everted, grooved faces on the wall (`studies.crawl.flipped`)."""
        return self.feet == "backward"


@dataclass
class CrawlModel:
    model: SolidModel
    law: AxialLaw
    setup: CrawlSetup
    tip_radius: float
    terms: dict = field(default_factory=dict)  # "actuator", "ground_rear", "ground_front" -> term
    springs: object = None  # the flipped feet's rim springs (`studies.crawl.flipped`), else None
    ground_hold: float = GROUND_HOLD  # N/mm: the ground springs until friction (module docstring)
    folded: np.ndarray | None = field(default=None, repr=False)  # the flipped feet's start state
    fold_message: str = ""
    stabilisation: Stabilisation | None = None  # the flipped feet's insertion (record 094), else None
    stabilise: float = 0.0  # its coefficient c0 while the wall closes, N s/mm^4

    def contacts_of(self, foot: str) -> list:
        return [c for c in self.model.contacts if c.spec.name.startswith(foot)]


def build(mesh, material, foot_design, setup: CrawlSetup, law: AxialLaw | None = None) -> CrawlModel:
    """The two-feet model on `mesh` (skfem MeshTet2 of `crawl_mesh.two_feet`), wall clear of the tips."""
    law = law or AxialLaw()
    youngs = small_strain_youngs(material)
    size = float(np.median(np.linalg.norm(np.diff(mesh.p[:, mesh.t[:2]], axis=1)[:, 0], axis=0)))
    contacts = feet_contacts(material, size, foot_design.tip_radius, setup.slip_viscosity)
    rear, front = (attach_tag(f, m) for f, m in zip(FEET, setup.mirrored))
    k0, _ = law.stiffness_preload((0.0, 0.0, 0.0))
    share = 1.0 / setup.copies
    terms = [
        AxialLink(front, rear, 2, k0, 0.0, name="actuator", share=share),
        AxialLink(rear, None, 2, GROUND_HOLD, name="ground_rear", share=share),
        AxialLink(front, None, 2, GROUND_HOLD, name="ground_front", share=share),
        EqualDisplacement(rear, 2, PLATE_PENALTY * youngs * size),
        EqualDisplacement(front, 2, PLATE_PENALTY * youngs * size),
    ]
    bcs = [Dirichlet(tag, (0, 1), (0.0, 0.0)) for tag in (rear, front)]
    springs = flipped.rim_springs() if setup.flipped else None
    terms += [springs, Stabilisation()] if springs is not None else []
    ties = wedge.ties(setup.copies, FEET)
    model = SolidModel(mesh, material, dirichlet=bcs, contacts=contacts, extra_terms=terms, ties=ties)
    links = {
        t.name: t
        for t in model.terms
        if getattr(t, "name", None) in ("actuator", "ground_rear", "ground_front")
    }
    cm = CrawlModel(model, law, setup, foot_design.tip_radius, links, springs)
    if springs is not None:
        cm.ground_hold = flipped.plate_hold(model, (rear, front), PLATE_PENALTY * youngs * size, setup.copies)
        for name in ("ground_rear", "ground_front"):
            links[name].set_load(cm.ground_hold, 0.0)
        cm.folded, cm.fold_message = flipped.folded_feet(model, material, foot_design, setup, springs)
        cm.stabilisation = next(t for t in model.terms if isinstance(t, Stabilisation))
        if cm.folded is not None:
            cm.stabilise = flipped.stabilisation_coefficient(
                model, cm.folded, setup.pipe.radius, youngs, foot_design
            )
    return cm


def _clear_radius(cm: CrawlModel) -> float:
    """The insertion wall's start: clear of the skirt tips, or of the folded feet (never inside the pipe)."""
    if cm.folded is None:
        return cm.tip_radius + 0.5
    return max(flipped.outer_radius(cm.model, cm.folded) + 0.5, cm.setup.pipe.radius)


class WallBudgetExceeded(Exception):
    """Raised before a solve attempt once CrawlSetup.max_wall_s has passed (a stall in cut-backs)."""


def _cycle_stages(
    cm: CrawlModel, schedule: Schedule, cycle: int, steps: int, deadline: float
) -> tuple[list, list]:
    """One Stage per schedule segment; and per stage (t0, t1, P0, P1) for the recorder. Every
    solve attempt calls `drive` first, so the wall-time budget is checked there: a stage that
    grinds in cut-backs (each failed attempt up to 25 Newton iterations) stops within one attempt."""
    actuator = cm.terms["actuator"]
    stages, spans = [], []
    t, P = schedule.times, schedule.pressures_kpa
    for j in range(len(t) - 1):
        p0, p1 = P[j].copy(), P[j + 1].copy()

        def drive(s, p0=p0, p1=p1):
            if time.perf_counter() > deadline:
                raise WallBudgetExceeded
            actuator.set_load(*cm.law.stiffness_preload(p0 + s * (p1 - p0)))

        span = float(t[j + 1] - t[j])  # the segment's time, which viscous slip reads
        stages.append(
            Stage(f"cycle{cycle}-seg{j}", drive=drive, steps=steps, duration=span if span > 0 else None)
        )
        base = cycle * schedule.cycle_s
        spans.append((base + t[j], base + t[j + 1], p0, p1))
    return stages, spans


def _run(cm, stages, spans, x0, recorder, cycle, deadline=np.inf, start=None, on_cursor=None):
    """run_stages with the recorder on every converged sub-step, stopped (not converged) at the
    wall-clock `deadline` (time.perf_counter() seconds); from the cursor `start` when resumed.
    The setup stages (cycle < 0: insert, release, friction, start) also stop, as a recorded
    failure, when a sub-step falls below `MIN_STEP_FRACTION` of the stage's step (the foot
    study's guard): an insertion that grinds in sub-steps of 1e-4 mm of wall travel (record 078)
    ends there instead of running until it is killed. The cycles are left as they were: their
    grinding is bounded by `CrawlSetup.max_wall_s` (`WallBudgetExceeded`)."""
    names = [s.name for s in stages]

    def on_step(step):
        t0, t1, p0, p1 = spans[names.index(step.stage)]
        rise = float(np.sum(p1) - np.sum(p0))
        phase = "setup" if cycle < 0 else ("extend" if rise > 0 else "retract" if rise < 0 else "hold")
        recorder.record(step, cycle, t0 + step.s * (t1 - t0), p0 + step.s * (p1 - p0), phase)

    budget = None if not np.isfinite(deadline) else max(deadline - time.perf_counter(), 1e-6)
    return run_stages(
        cm.model,
        stages,
        x0=x0,
        options=CRAWL_NEWTON,
        max_cutbacks=MAX_CUTBACKS,
        on_step=on_step,
        max_wall_s=budget,
        min_step_fraction=MIN_STEP_FRACTION if cycle < 0 else None,
        start=start,
        on_cursor=on_cursor,
        **AUGMENT,
    )


def run_crawl(
    cm: CrawlModel, schedule: Schedule, on_state=None, store=None, resumed=None, insertion=None
) -> CrawlResult:
    """Insert, switch friction on, follow `schedule` for `setup.cycles` cycles (module docstring).

    `store` (a `studies.crawl.resume.CrawlStore`): every converged state is written to it;
    `resumed` (its `load()`): the run continues from that state (the phases before it are
    skipped, their effects being in the state; the recorder's rows are the state's).
    `insertion` (a `studies.crawl.insertion.InsertionCache`), for a run not resumed: the inserted
    state is taken from it when it holds one (a resume at the end of the insertion), else the
    insertion is computed and its last state written to it, under the key's lock."""
    setup, model = cm.setup, cm.model
    t0 = time.perf_counter()
    recorder = StateRecorder(cm, on_state)
    lock = contextlib.ExitStack()
    if resumed is None and insertion is not None:
        lock.enter_context(insertion.locked())
        resumed = insertion.load()
        insertion.hit = resumed is not None
        if resumed is not None:
            lock.close()
            insertion.store.restore(cm, recorder, resumed)
    elif resumed is not None:
        store.restore(cm, recorder, resumed)
    carried = Totals() if resumed is None else resumed.totals
    deadline = t0 - carried.wall_s + (setup.max_wall_s if setup.max_wall_s is not None else np.inf)
    stats: list = [carried]

    def elapsed() -> float:
        return carried.wall_s + time.perf_counter() - t0

    start = schedule.pressures_kpa[0]
    ramp = bool(np.any(start > 0))
    release = ["release"] if cm.springs is not None else []
    plan = (
        ["insert", *release, "friction"]
        + (["start"] if ramp else [])
        + [f"cycle{k}" for k in range(setup.cycles)]
    )
    first = 0 if resumed is None else resumed.phase
    x = cm.folded if resumed is None else resumed.cursor.x
    if cm.springs is not None:
        if cm.folded is None:
            return recorder.result(False, f"the flipped feet: {cm.fold_message}", stats, elapsed())
        cm.springs.stiffness = flipped.FOLD_HOLD if plan[first] == "insert" else 0.0  # "release" drives it
        cm.stabilisation.rest(x)  # the last converged state is the committed one
    setup_span = [(0.0, 0.0, np.zeros(3), np.zeros(3))]
    # the insertion's and the release's pseudo-time, which the stabilisation reads (record 094)
    setup_time = 1.0 if cm.stabilise > 0 else None
    for k, name in enumerate(plan):
        if k < first:
            continue
        cursor = resumed.cursor if resumed is not None and k == first else None
        cycle = int(name[5:]) if name.startswith("cycle") else -1
        if cursor is None:  # the actions between the phases (in a resumed phase: in the state)
            if name == "friction":
                for g in (cm.terms["ground_rear"], cm.terms["ground_front"]):
                    g.set_load(GROUND_SOFT, 0.0, g.extension(x))
            if k > 0 and plan[k - 1] == "friction":
                recorder.mark_start(x)
            if cycle >= 0:
                recorder.begin_cycle(cycle, x)
        if name == "insert":
            wall_at = insertion_wall(setup.pipe, _clear_radius(cm))
            surfaces = {i: wall_at for i in range(len(model.contacts))}
            drive = None if cm.springs is None else flipped.insert_drive(cm.stabilisation, cm.stabilise)
            stages = [
                Stage("insert", surfaces=surfaces, steps=setup.insert_steps, drive=drive, duration=setup_time)
            ]
            spans = setup_span
        elif name == "release":
            at_pipe = {i: (lambda s: CylinderWall(setup.pipe.radius)) for i in range(len(model.contacts))}
            drive = flipped.release_drive(cm.springs, cm.stabilisation, cm.stabilise)
            stages = [
                Stage("release", surfaces=at_pipe, drive=drive, steps=setup.insert_steps, duration=setup_time)
            ]
            spans = setup_span
        elif name == "friction":
            mu = {
                i: (setup.mu_smooth if c.spec.name.endswith("smooth") else setup.mu_grooved)
                for i, c in enumerate(model.contacts)
            }
            stages, spans = [Stage("friction", friction=mu)], setup_span
        elif name == "start":

            def drive(s, actuator=cm.terms["actuator"]):
                actuator.set_load(*cm.law.stiffness_preload(s * start))

            stages = [Stage("start", drive=drive, steps=setup.steps)]
            spans = [(0.0, 0.0, np.zeros(3), start)]
        else:
            stages, spans = _cycle_stages(cm, schedule, cycle, setup.steps, deadline)
        on_cursor = None
        if store is not None or (name == "insert" and insertion is not None and not insertion.hit):
            done = Totals(
                int(sum(r.newton_iterations for r in stats)),
                float(sum(r.assembly_s for r in stats)),
                float(sum(r.solve_s for r in stats)),
            )

            def on_cursor(c, k=k, name=name, done=done):
                totals = Totals(
                    done.newton_iterations + c.newton_iterations,
                    done.assembly_s + c.assembly_s,
                    done.solve_s + c.solve_s,
                    elapsed(),
                )
                if store is not None:
                    store.save(cm, recorder, k, name, c, totals)
                if name == "insert" and insertion is not None and not insertion.hit and c.t >= 1.0 - 1e-12:
                    insertion.save(cm, recorder, c, totals)

        try:
            with lock if name == "insert" else contextlib.nullcontext():
                limit = deadline if cycle < 0 else np.inf
                res = _run(cm, stages, spans, x, recorder, cycle, limit, cursor, on_cursor)
        except WallBudgetExceeded:
            last = recorder.states[-1]
            message = (
                f"cycle {cycle + 1}: stopped at the wall-time budget max_wall_s = {setup.max_wall_s:g} s "
                f"(sub-steps shrinking in cut-backs); last converged: stage {last['stage']!r} at "
                f"t = {last['time_s']:.4g} s, P = {last['p1_kpa']:.4g} kPa (the Newton iterations of "
                "this cycle are not counted)"
            )
            return recorder.result(False, message, stats, elapsed())
        stats.append(res)
        if not res.converged:
            message = res.message if cycle < 0 else f"cycle {cycle + 1}: {res.message}"
            return recorder.result(False, message, stats, elapsed())
        x = res.x
        if cycle >= 0:
            recorder.end_cycle(cycle, x, schedule.cycle_s)
    return recorder.result(True, f"{setup.cycles} cycle(s) reached", stats, elapsed())
