r"""The whole grooved foot in a pipe (paper Fig. 10(b), Fig. 4): insertion, forward and backward drag.

Model. The foot of `geometry.foot` (any tagged mesh: the study's is the revolved mesh of
`geometry.foot_revolved`; P2-P1, Shore 70A rubber), hub top face held
by the actuators: fully prescribed, (0, 0, factor * drag). The pipe wall is a rigid
`CylinderWall` on the robot axis. Two contact terms act on it, each with its own friction
coefficient: the smooth front face with the rim (mu_smooth) and the grooved back face
(mu_grooved). `forward` is +z, the direction the skirt's front face looks to; the skirt leans
back (-z), like a brush.

Stages (`fem.contact_stages`):
  insert   the wall radius shrinks from just outside the skirt tip (tip_radius + 0.5 mm) to the
           pipe radius, frictionless (an oversized foot cannot start inside the pipe);
  friction both coefficients switched on (stick points restart at the inserted state);
  drag     the hub moves by +drag (forward) or -drag (backward) from the same inserted state
           (the contact history is restored between the two).

Outputs. Per drag increment: the resistance F (N), the wall's axial force on the foot opposing
the motion (sum of both faces' friction, z component), the normal force and contact areas per
face, the tip's axial position relative to the hub top. The skirt has flipped when its tip
(mean of the rim nodes) passes in front of the hub top (z_tip > z_hub): the grooved back face
then looks outward, against the wall (Fig. 4). F_fwd and F_bwd are the largest resistances of
the two drags; the anchoring principle needs F_bwd / F_fwd > 1. A drag that stops (a sub-step
below `MIN_STEP_FRACTION` of its step, or the run's wall-time budget) after its resistance passed
a maximum reports that limit point (`limit_point`): its peak is then a lower bound of F.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

from softcrawl.analytic.pipe import Pipe
from softcrawl.errors import InputError
from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.model import Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions
from softcrawl.fem.rigid_surfaces import CylinderWall
from softcrawl.geometry.design import DesignError
from softcrawl.studies.foot import wedge
from softcrawl.studies.foot.flip import FOLD_CLEARANCE, RimSprings, fold, fold_angle_into
from softcrawl.studies.foot.outputs import face_metrics

#: Newton settings of the foot: a failing sub-step is cut back after at most 25 iterations (each
#: costs a ~50k-unknown solve), at most 8 times in a row (4 before issue 16's follow-up: the
#: backward drag in the 75 mm pipe needed more where the contact zone's edge reorganises).
FOOT_NEWTON = NewtonOptions(tol=1e-8, max_iter=25, stall_iter=12)
MAX_CUTBACKS = 8
#: Wall-time budget of one foot run (insertion and both drags), s. A drag that grinds in ever
#: smaller sub-steps (a jammed skirt) stops there as a recorded failure with the curve so far,
#: instead of holding a sweep worker for hours; about 5x an idle run on the default mesh.
FOOT_MAX_WALL_S = 900.0
#: A drag stops once its sub-steps fall below this share of its step (1 mm: 1 um), where the
#: cut-backs alternate with tiny converged sub-steps at a limit point.
MIN_STEP_FRACTION = 1e-3
#: A drag that stopped after its resistance fell more than this share below its largest value
#: has passed a limit point (docs/decisions/041-revolved-foot.md); its largest resistance is a lower bound.
LIMIT_DROP = 1e-3

#: The flipped foot (`flipped=True`, `studies.foot.flip`): its rim is folded to FOLD_CLEARANCE
#: inside the pipe wall, held there by rim springs of FOLD_HOLD N/mm per dof (far stiffer than the
#: skirt, ~10 N/mm in all) while the wall is set, then released in the pipe.
FOLD_HOLD = 1.0e3

FACES = {"smooth": ("front", "rim"), "grooved": ("back",)}
#: Uzawa loop of the foot runs: 10 um of penetration (1/300 of the skirt) is far below the
#: deformations of interest; each further update costs a solve at ~50k unknowns.
AUGMENT = {"penetration_tol": 0.01, "max_augment": 2}
#: eps_T / eps_N of the foot (docs/decisions/036-contact.md).
TANGENTIAL_RATIO = 1.0
#: Gap band (mm) over which the normal contact law's kink is rounded (`fem.contact_law`). 0: the
#: exact law of the committed results. 0.01 mm (the Uzawa tolerance) removed the contact-edge
#: chatter of the 75 mm backward drag but moved its path (+6 % normal force at 2.1 mm) without
#: making it finish, so it is not the default (docs/decisions/040-contact-fixes.md).
SMOOTHING = 0.0
#: Width w of the rounded Coulomb cone, a share of mu p_N (`fem.contact_law`). With the exact
#: cone the 75 mm backward drag and the crawl's retraction at mu = 0.5 stalled in stick/slip
#: cycles of a few points; 0.05 lowers the traction of points on the band by at most 0.6 % of
#: mu p_N and leaves full slip and the Coulomb limit exact (docs/decisions/037-coulomb-cone.md). Also the
#: crawl's contact law (`studies.crawl.model`).
SLIP_BAND = 0.05


def small_strain_youngs(law) -> float:
    """E = 9 K mu / (3 K + mu) of a solver law with shear modulus mu and bulk modulus K [MPa]:
    the modulus every contact penalty of the feet scales with."""
    return 9.0 * law.bulk * law.mu / (3.0 * law.bulk + law.mu)


def foot_model(
    mesh,
    material,
    design,
    pipe_radius: float,
    drag: float,
    penalty: float | None = None,
    tangential_ratio: float = TANGENTIAL_RATIO,
    extra_terms=(),
    copies: int = 1,
):
    """The foot on `mesh` (skfem MeshTet2 with the foot's tags), wall clear of the tip; the
    tangential penalty is `tangential_ratio` x the normal one; `extra_terms` go to the model (the
    flipped foot's rim springs); `copies` > 1: `mesh` is a wedge of the foot, its cuts tied
    (`studies.foot.wedge`)."""
    youngs = small_strain_youngs(material)
    size = float(np.median(np.linalg.norm(np.diff(mesh.p[:, mesh.t[:2]], axis=1)[:, 0], axis=0)))
    eps = penalty if penalty is not None else 10.0 * youngs / size
    wall = CylinderWall(design.tip_radius + 0.5)
    specs = [
        ContactSpec(
            tags,
            wall,
            penalty=eps,
            tangential_penalty=tangential_ratio * eps,
            name=name,
            smoothing=SMOOTHING,
            slip_band=SLIP_BAND,
        )
        for name, tags in FACES.items()
    ]
    bcs = [Dirichlet("hub_top", (0, 1, 2), (0.0, 0.0, drag))]
    ties = wedge.ties(copies)
    return SolidModel(mesh, material, dirichlet=bcs, contacts=specs, extra_terms=extra_terms, ties=ties)


@dataclass(frozen=True)
class DragCurve:
    direction: str
    converged: bool
    message: str
    drag: np.ndarray  # (n,) hub displacement magnitude (mm)
    resistance: np.ndarray  # (n,) N, opposing the motion
    tip_ahead: np.ndarray  # (n,) z_tip - z_hub (mm); > 0: flipped
    grooved_share: np.ndarray  # (n,) share of the normal force on the grooved face
    flipped_at: float | None  # drag (mm) at which the tip first passed the hub top
    limit_point: tuple[float, float] | None = None  # (drag mm, resistance N), see `limit_point`

    @property
    def peak(self) -> float:
        return float(self.resistance.max()) if self.resistance.size else float("nan")


def limit_point(drag: np.ndarray, resistance: np.ndarray) -> tuple[float, float] | None:
    """The maximum a stopped drag passed: (drag, resistance) of its largest computed state; None
    unless the last state lies more than `LIMIT_DROP` below it (the resistance fell: the drag
    passed a limit point, and a quasi-static drag under hub displacement control stops where the
    path snaps back). The value is an equilibrium that was computed, so it is a lower bound of the
    resistance; the true maximum lies between that state's neighbours and was not interpolated."""
    if resistance.size < 2:
        return None
    i = int(np.argmax(resistance))
    peak = float(resistance[i])
    if not (i < resistance.size - 1 and resistance[-1] < (1.0 - LIMIT_DROP) * peak):
        return None
    return float(drag[i]), peak


@dataclass(frozen=True)
class FootResult:
    pipe_diameter: float
    converged: bool
    message: str
    normal_force: float  # N, after insertion (both faces)
    contact_area: float  # mm^2, deformed
    mean_pressure: float  # MPa
    max_pressure: float  # MPa
    face_forces: dict  # per face: normal force after insertion
    metrics: dict  # stress and strain on the front and back faces after insertion
    forward: DragCurve | None
    backward: DragCurve | None
    wall_s: float
    n_dofs: int
    iterations: dict = field(default_factory=dict)  # Newton iterations per increment, per stage
    flipped: bool = False  # the skirt started everted (the backward crawl's foot, `studies.foot.flip`)

    @property
    def ratio(self) -> float:
        if self.forward is None or self.backward is None or not self.forward.peak > 0:
            return float("nan")
        return self.backward.peak / self.forward.peak


def insertion_wall(pipe: Pipe, clear_radius: float):
    """The wall of the straight `pipe` during the frictionless insertion, as a function of the stage
    parameter s in [0, 1]: the rigid cylinder shrinks from `clear_radius` (clear of the tip of an
    oversized foot) to the pipe's radius."""
    if pipe.kind == "elbow":
        raise InputError("pipe", "the FE wall is a straight cylinder: an elbow has no FE model")

    def wall_at(s):
        return CylinderWall(clear_radius + s * (pipe.radius - clear_radius))

    return wall_at


def _insert_stages(model, design, pipe: Pipe, mu_smooth, mu_grooved, steps):
    wall_at = insertion_wall(pipe, design.tip_radius + 0.5)
    surfaces = {i: wall_at for i in range(len(model.contacts))}
    return [
        Stage("insert", surfaces=surfaces, steps=steps),
        Stage("friction", friction={0: mu_smooth, 1: mu_grooved}),
    ]


def _flipped_stages(mesh, material, design, pipe: Pipe, mu_smooth, mu_grooved, steps, drag):
    """(model, folded state, message, stages) of the flipped foot: the rim folded by the flip and
    as much more as brings it `FOLD_CLEARANCE` inside the wall (`flip.fold`), the wall shrunk from
    clear of the folded foot to the pipe (rim springs on), the springs released in `steps`, friction
    on. The folded state is None (and the message says why) when the fold did not converge."""
    insertion_wall(pipe, design.tip_radius + 0.5)  # refuses an elbow before the fold
    springs = RimSprings(np.zeros(0))
    model = foot_model(mesh, material, design, pipe.radius, drag, extra_terms=[springs])
    phi = fold_angle_into(design, model.nodes[:, model.boundary_nodes("rim")], pipe.radius - FOLD_CLEARANCE)
    folded = fold(mesh, material, design, phi, options=FOOT_NEWTON)
    if not folded.converged:
        return model, None, folded.message, []
    springs.target, springs.stiffness = folded.rim_target, FOLD_HOLD
    deformed = model.nodes + model.displacement(folded.x)
    clear = max(float(np.hypot(deformed[0], deformed[1]).max()) + 0.5, pipe.radius)
    wall_at = insertion_wall(pipe, clear)
    surfaces = {i: wall_at for i in range(len(model.contacts))}
    at_pipe = {i: (lambda s: wall_at(1.0)) for i in range(len(model.contacts))}
    return (
        model,
        folded.x,
        folded.message,
        [
            Stage("insert", surfaces=surfaces, steps=steps),
            Stage("release", surfaces=at_pipe, steps=steps, drive=springs.ramp(FOLD_HOLD)),
            Stage("friction", friction={0: mu_smooth, 1: mu_grooved}),
        ],
    )


def _drag(model, x0, snapshot, direction, distance, steps, ends, on_state=None, budget=None, copies=1):
    """One drag from the inserted state; `ends`: (the rim's, the hub top's) nodes."""
    tip_nodes, hub_nodes = ends
    for term, (lam, stick, surface) in zip(model.contacts, snapshot):
        term.multiplier, term.stick, term.surface = lam.copy(), stick.copy(), surface
    sign = 1.0 if direction == "forward" else -1.0
    rows = []

    def record(step):
        reps = [c.report(step.x) for c in model.contacts]
        fz = copies * sum(r.friction_force[2] for r in reps)  # a wedge's share times copies
        u = model.displacement(step.x)
        z = model.nodes[2] + u[2]
        normal = sum(r.normal_force for r in reps)
        rows.append(
            (
                abs(step.factor) * distance,
                -sign * fz,
                z[tip_nodes].mean() - z[hub_nodes].mean(),
                reps[1].normal_force / normal if normal > 0 else 0.0,
            )
        )
        if on_state is not None:
            on_state(f"{direction}_{len(rows):03d}", model, step.x, abs(step.factor) * distance)

    stage = Stage(direction, factor=sign, steps=steps)
    res = run_stages(
        model,
        [stage],
        x0=x0,
        options=FOOT_NEWTON,
        max_cutbacks=MAX_CUTBACKS,
        on_step=record,
        max_wall_s=budget,
        min_step_fraction=MIN_STEP_FRACTION,
        **AUGMENT,
    )
    arr = np.array(rows).reshape(-1, 4)
    ahead = arr[:, 2]
    flipped = np.nonzero(ahead > 0)[0]
    top = None if res.converged else limit_point(arr[:, 0], arr[:, 1])
    message = res.message
    if top is not None:
        message = (
            f"limit point: the largest resistance, {top[1]:.4g} N at {top[0]:.4g} mm, fell to "
            f"{arr[-1, 1]:.4g} N at {arr[-1, 0]:.4g} mm, where the quasi-static drag stopped (under hub "
            f"displacement control it cannot follow the path past a snap; the resistance beyond is not "
            f"computed, F >= {top[1]:.4g} N): {res.message}"
        )
    return DragCurve(
        direction,
        res.converged,
        message,
        arr[:, 0],
        arr[:, 1],
        ahead,
        arr[:, 3],
        float(arr[flipped[0], 0]) if flipped.size else None,
        top,
    ), res


def run_foot(
    mesh,
    material,
    design,
    pipe: Pipe,
    *,
    mu_smooth: float,
    mu_grooved: float,
    drag: float = 10.0,
    insert_steps: int = 8,
    drag_steps: int = 10,
    on_state=None,
    max_wall_s: float | None = FOOT_MAX_WALL_S,
    flipped: bool = False,
    directions: tuple[str, ...] = ("forward", "backward"),
    copies: int = 1,
) -> FootResult:
    """Insert the foot into the pipe and drag it both ways (module docstring; `directions`: the
    drags to run, in order); stop, not converged, once `max_wall_s` seconds have passed (None: no
    limit). `flipped`: the skirt starts everted, grooved face out (`_flipped_stages`).
    `copies` > 1: `mesh` is a wedge of 2 pi / copies of the foot (`studies.foot.wedge`); the
    forces reported are the whole foot's."""
    if copies > 1 and flipped:
        raise DesignError("copies", "the flipped foot is folded whole: a wedge of it is not modelled")
    if ("cut_start" in mesh.boundaries) != (copies > 1):
        raise DesignError("copies", f"{copies} does not match the mesh (a wedge has cut faces)")
    started = time.perf_counter()

    def budget():
        return None if max_wall_s is None else max(max_wall_s - (time.perf_counter() - started), 1e-6)

    x0 = None
    if flipped:
        model, x0, message, stages = _flipped_stages(
            mesh, material, design, pipe, mu_smooth, mu_grooved, insert_steps, drag
        )
        if x0 is None:
            nan = float("nan")
            return FootResult(pipe.diameter, False, message, nan, nan, nan, nan, {}, {}, None, None,
                              time.perf_counter() - started, 0, flipped=True)  # fmt: skip
    else:
        model = foot_model(mesh, material, design, pipe.radius, drag, copies=copies)
        stages = _insert_stages(model, design, pipe, mu_smooth, mu_grooved, insert_steps)
    res = run_stages(
        model,
        stages,
        x0=x0,
        options=FOOT_NEWTON,
        max_cutbacks=MAX_CUTBACKS,
        max_wall_s=budget(),
        min_step_fraction=MIN_STEP_FRACTION,
        **AUGMENT,
    )
    its = {"insert": [s.iterations[0] for s in res.steps]}
    empty = FootResult(
        pipe.diameter, False, res.message, *([float("nan")] * 4), {}, {}, None, None, 0.0, 0, flipped=flipped
    )
    if not res.converged:
        return empty
    x0 = res.x
    reps = [c.report(x0) for c in model.contacts]
    if on_state is not None:
        on_state("inserted", model, x0)
    snapshot = [(c.multiplier.copy(), c.stick.copy(), c.surface) for c in model.contacts]
    tip, hub = wedge.off_cut(model, "rim", copies), wedge.off_cut(model, "hub_top", copies)
    curves, wall = {}, res.wall_s
    for direction in directions:
        curve, r = _drag(
            model, x0, snapshot, direction, drag, drag_steps, (tip, hub), on_state, budget(), copies
        )
        curves[direction] = curve
        its[direction] = [s.iterations[0] for s in r.steps]
        wall += r.wall_s
    normal = copies * sum(r.normal_force for r in reps)
    area = copies * sum(r.area_current for r in reps)
    metrics = face_metrics(model, x0, "front", "hub_top") | face_metrics(model, x0, "back", "hub_top")
    ok = all(c.converged for c in curves.values())
    return FootResult(
        pipe_diameter=pipe.diameter,
        converged=ok,
        message="; ".join(f"{d}: {c.message}" for d, c in curves.items()),
        normal_force=normal,
        contact_area=area,
        mean_pressure=normal / area if area > 0 else 0.0,
        max_pressure=max(r.max_pressure for r in reps),
        face_forces={r.name: copies * r.normal_force for r in reps},
        metrics=metrics,
        forward=curves.get("forward"),
        backward=curves.get("backward"),
        wall_s=wall,
        n_dofs=int(model.n_dofs),
        iterations=its,
        flipped=flipped,
    )
