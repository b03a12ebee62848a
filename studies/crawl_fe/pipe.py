r"""The one body put into its straight pipe: the frictionless insertion, then friction, then loads.

The pipe (`PIPES`, `pipe_wall`): the straight CylinderWall on the body's axis z, the same pipe
vertical with the body's weight heading up (gravity -z) or down (+z), the `fem.pipe_surfaces.
ElbowPipe` whose entry leg holds the body and whose bend (radius R, towards +x) starts `ELBOW_AHEAD`
mm ahead of the front skirt's tip, or the straight `fem.corrugated_pipe.CorrugatedPipe` (a
bellows: wall radius r0 + (d / 2) cos(2 pi z / p), depth d and pitch p, widest at z = 0 of the
body's mesh, 4 mm ahead of the rear hub's bottom face; `BELLOWS_CORRUGATION`). The straight pipe
is horizontal without gravity, so that it compares with the reduced crawl, which has none (the
0.7 N weight against wall forces of ~50 N per foot: the vertical pipes show its effect).

Phases (each a `fem.contact_stages.run_stages` call, as the reduced crawl's `studies.crawl.model`):

    insert     the wall (any of the pipes, its radius moved by `with_radius`) shrinks from clear
               of the skirt tips (its narrowest radius at the tip radius + 0.5 mm: a bellows'
               ridges) to the pipe's radius in `insert_steps`
               sub-steps, frictionless, the holds stiff (`model.HOLD_STIFF`; six, a wedge's
               two): in a frictionless pipe they alone fix the axial translation and the twist;
    friction   the holds re-based at the inserted state and softened to `model.HOLD_SOFT`, the
               friction coefficients of `setup` switched on (mu_smooth on the front faces and
               rims, mu_grooved on the grooved back faces): from here friction holds the body;
               holds that carry more than `HOLD_RELEASE_N` (a bellows' slopes push the feet
               along the axis) keep their force as a preload, so the state stays balanced;
    release    (only then) those preloads ramped to zero in `RELEASE_STEPS` sub-steps: the
               wall's friction takes the load, or the feet slide into the corrugations;
    load       (optional) the load factor ramped 0 -> 1 in `load_steps`: the body's weight when
               the model was built with gravity.

After every phase the holds' forces and each foot's wall forces (normal force, friction force
vector) are recorded (`PipeState`), so that the holds' share of the load is seen: with the
body's weight on, the wall's axial friction must carry it, the holds ~0.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.corrugated_pipe import CorrugatedPipe
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.pipe_surfaces import ElbowPipe
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.geometry.design_base import ACTUATOR_ANGLES_DEG
from softcrawl.studies.crawl.model import MAX_CUTBACKS
from softcrawl.studies.crawl_fe.model import BODY_NEWTON, FEET, HOLD_SOFT, BodyModel
from softcrawl.studies.crawl_fe.wedge import whole_force
from softcrawl.studies.foot.model import AUGMENT

#: The pipes of the FE-body crawl: name -> gravity in units of g (None: none; module docstring).
PIPES = {
    "straight": None,
    "vertical-up": (0.0, 0.0, -1.0),
    "vertical-down": (0.0, 0.0, 1.0),
    "elbow": None,
    "bellows": None,
}
#: (depth, pitch) in mm of the bellows' corrugations when not given. The paper's bellows is
#: described by its 75 mm diameter only (Section VII-E), so these are an example, not its values:
#: the corrugations of fem.corrugated_pipe's tests (docs/decisions/073-pipe-surfaces.md), about
#: those of a small flexible duct; `softcrawl crawl --bellows-depth/--bellows-pitch` set them.
BELLOWS_CORRUGATION = (2.0, 10.0)
#: N: the largest force of the stiff holds at the insertion's end above which they are released
#: gradually once friction is on (module docstring). A straight pipe's or an elbow's entry leg
#: puts no axial force on a foot: their holds carry about 2e-9 N there (every committed run's
#: states.csv), so they take no release stage and their runs are unchanged.
HOLD_RELEASE_N = 1e-3
#: Sub-steps of the holds' release.
RELEASE_STEPS = 4
#: mm between the skirt tips and the wall when the insertion starts.
INSERT_CLEARANCE = 0.5
#: mm between the front skirt's tip (undeformed) and the start of the elbow's bend.
ELBOW_AHEAD = 5.0
#: Azimuth (deg from +x about the pipe's axis) the elbow of a replayed gait plan turns towards:
#: ePSA 1's. The analytic planner rolls the robot so that ePSA 1 faces the inside of the bend
#: (`softcrawl.analytic.cycle.elbow_roll`), and its pressure triples bend the body in that plane; the
#: FE body's ePSA 1 is at 90 deg (`geometry.design_base.ACTUATOR_ANGLES_DEG`). The inflate runs'
#: elbows turn towards +x (0 deg), between ePSAs 3 and 1.
PLAN_TURN_DEG = ACTUATOR_ANGLES_DEG[0]


def pipe_wall(
    kind: str,
    radius: float,
    *,
    front_tip: float = 0.0,
    bend_radius: float | None = None,
    turn_deg: float = 0.0,
    corrugation: tuple[float, float] | None = None,
):
    """The rigid wall of pipe `kind` (`PIPES`) of inner `radius`; for the elbow, its bend of
    centreline radius `bend_radius` starts ELBOW_AHEAD past `front_tip` (the front skirt's largest
    z, mm) and turns towards the azimuth `turn_deg` (deg from +x; `PLAN_TURN_DEG` for a gait plan);
    for the bellows, `radius` is its mean inner radius and `corrugation` its (depth, pitch) in mm
    (None: `BELLOWS_CORRUGATION`)."""
    if kind not in PIPES:
        raise SolverInputError("pipe", f"one of {', '.join(PIPES)}, not {kind!r}")
    if kind == "bellows":
        depth, pitch = corrugation or BELLOWS_CORRUGATION
        return CorrugatedPipe(radius, 0.5 * depth, pitch)
    if kind != "elbow":
        return CylinderWall(radius)
    if bend_radius is None:
        raise SolverInputError("bend_radius", "an elbow needs its bend radius (mm)")
    a = math.radians(turn_deg)  # cos 0 = 1 and sin 0 = 0 exactly: the inflate runs' +x
    turn = (math.cos(a), math.sin(a), 0.0)
    return ElbowPipe(radius, bend_radius, entry=max(front_tip + ELBOW_AHEAD, 0.0), turn=turn)


@dataclass(frozen=True)
class PipeState:
    """The state at the end of a phase: holds' forces (N), per foot the wall's normal force (N)
    and friction force vector (N), and the body's load (the weight vector at factor 1, N)."""

    phase: str
    holds: dict
    normal: dict
    friction: dict
    x: np.ndarray = field(repr=False)

    @property
    def wall_friction(self) -> np.ndarray:
        """The friction force of the wall on both skirts, summed (N)."""
        return np.sum([np.asarray(v) for v in self.friction.values()], axis=0)


@dataclass(frozen=True)
class PipeRun:
    converged: bool
    message: str
    states: tuple[PipeState, ...]
    newton_iterations: int
    assembly_s: float
    solve_s: float
    wall_s: float
    n_dofs: int
    factorizations: int = 0


def record(bm: BodyModel, phase: str, x: np.ndarray) -> PipeState:
    """The state's outputs, the whole body's (a wedge's forces turned into all its copies,
    `studies.crawl_fe.wedge`)."""
    normal, friction = {}, {}
    for foot in FEET:
        reports = [c.report(x) for c in bm.contacts_of(foot)]
        normal[foot] = bm.copies * float(sum(r.normal_force for r in reports))
        friction[foot] = whole_force(np.sum([r.friction_force for r in reports], axis=0), bm.copies)
    return PipeState(phase, bm.hold_forces(x), normal, friction, x)


def into_pipe(
    bm: BodyModel,
    *,
    insert_steps: int | None = None,
    load_steps: int = 0,
    max_wall_s: float | None = None,
    on_step=None,
    wall=None,
) -> PipeRun:
    """Insert, switch friction on, then (load_steps > 0) ramp the load factor (module docstring).
    `on_step`: called with every converged `fem.contact_stages.StagedStep` (progress lines);
    `wall`: the pipe's surface at its radius (`pipe_wall`; None: the straight pipe of `bm.setup`)."""
    setup, model = bm.setup, bm.model
    t0 = time.perf_counter()
    wall = wall or CylinderWall(setup.pipe.radius)
    # the wall's narrowest radius starts clear of the skirt tips (a bellows' ridges: amplitude)
    clear = bm.design.foot.tip_radius + INSERT_CLEARANCE + getattr(wall, "amplitude", 0.0)
    radius = wall.radius
    if not clear < getattr(wall, "bend_radius", np.inf):
        raise SolverInputError(
            "bend_radius", f"must exceed {clear:g} mm, the insertion's first wall radius (skirt tips clear)"
        )

    def wall_at(s: float):
        return wall.with_radius(clear + s * (radius - clear))

    n = len(model.contacts)
    mu = {
        i: (setup.mu_smooth if c.spec.name.endswith("smooth") else setup.mu_grooved)
        for i, c in enumerate(model.contacts)
    }
    phases = [
        (
            "insert",
            [
                Stage(
                    "insert",
                    surfaces=dict.fromkeys(range(n), wall_at),
                    steps=insert_steps or setup.insert_steps,
                )
            ],
        )
    ]
    phases.append(("friction", [Stage("friction", friction=mu)]))
    carried: dict[str, float] = {}  # the holds' forces at the insertion's end, when released

    def release(s: float) -> None:
        bm.set_holds(HOLD_SOFT, preloads={k: (1.0 - s) * v for k, v in carried.items()})

    phases.append(("release", [Stage("release", steps=RELEASE_STEPS, drive=release)]))
    if load_steps:
        phases.append(("load", [Stage("load", factor=1.0, steps=load_steps)]))
    x, states, totals, factorizations = None, [], [0, 0.0, 0.0], 0
    for name, stages in phases:
        if name == "friction":
            forces = bm.hold_forces(x)
            if max(abs(v) for v in forces.values()) > HOLD_RELEASE_N:
                carried.update(forces)
            bm.set_holds(HOLD_SOFT, x, preloads=carried)
        if name == "release" and not carried:
            continue
        budget = None if max_wall_s is None else max(max_wall_s - (time.perf_counter() - t0), 1e-6)
        res = run_stages(
            model,
            stages,
            x0=x,
            options=BODY_NEWTON,
            max_cutbacks=MAX_CUTBACKS,
            max_wall_s=budget,
            on_step=on_step,
            **AUGMENT,
        )
        totals = [totals[0] + res.newton_iterations, totals[1] + res.assembly_s, totals[2] + res.solve_s]
        factorizations += res.factorizations
        if not res.converged:
            return PipeRun(
                False,
                f"{name}: {res.message}",
                tuple(states),
                *totals,
                time.perf_counter() - t0,
                model.n_dofs,
                factorizations,
            )
        x = res.x
        states.append(record(bm, name, x))
    wall = time.perf_counter() - t0
    return PipeRun(True, "inserted", tuple(states), *totals, wall, model.n_dofs, factorizations)
