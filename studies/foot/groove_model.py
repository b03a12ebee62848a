r"""The groove-segment model of paper Fig. 10(a): a strip of the grooved foot face pressed on the
pipe wall and dragged.

Model. A strip of the foot's skirt, `thickness` thick (z), `n_grooves` pitches long (x, the drag
direction, across the circumferential grooves) and `width` wide (y, plane strain: both y faces
are symmetry planes). Its bottom face carries rectangular grooves of depth h and width w, at
every multiple of the pitch (half grooves at the two ends), so that `n_grooves` full lands (the
teeth between grooves, pitch - w wide) touch the wall. Ending the strip in half lands instead
lets the free end tooth, half as wide, tip over its leading corner (h = 2 mm, mu = 0.3: it
folds after 1.9 mm of drag), an artefact of the cut, not of the foot. The wall is
the rigid plane z = 0 (the pipe radius, 27.5-37.5 mm, is ten times the strip's size). The top
face is glued to a rigid backing (the rest of the foot): it moves in x by the drag and stays at
y = 0, and its nodes share one z displacement (`fem.equal_displacement`, a penalty: the face
stays plane and level); a follower pressure p acts on it. Because the top keeps its footprint
and orientation, the pressure's total normal force is p A exactly (A = length x width): the
normal contact force must equal it at equilibrium (`normal_error`). Without the level
constraint the strip tilts under the friction moment mu N H and lifts its trailing lands (at
mu = 0.5 after ~0.6 mm of drag), a rotation the foot's backing does not allow.

Stages (`fem.contact_stages`): press to p frictionless; switch friction mu on; drag the top by
`drag`, the first 10 % in ten fine steps (the stick-to-slip transition), the rest in about
`drag_steps` increments (cut-back on divergence). Every increment records the friction
force, normal force, contact and slip fractions: the friction-displacement curve, whose
plateau (mean over the last half of the drag) is compared with mu N.

Mesh. A structured grid with lines on the groove edges and at z = h (`cell` mm cells), the cells
of the grooves removed, six tetrahedra per cell, P2-P1 (nearly incompressible rubber).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
import skfem

from softcrawl.fem.contact import ContactSpec
from softcrawl.fem.contact_stages import Stage, run_stages
from softcrawl.fem.equal_displacement import EqualDisplacement
from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.newton import NewtonOptions
from softcrawl.fem.rigid_surfaces import Plane
from softcrawl.fem.structured import tag_boundaries
from softcrawl.studies.foot.model import small_strain_youngs
from softcrawl.studies.foot.outputs import solid_metrics
from softcrawl.studies.sweeps.spec import StudyError

#: Pitch of the default foot's grooves (FootDesign: back face 15.59 mm, 5 grooves -> 6 pitches).
DEFAULT_PITCH = 2.6


@dataclass(frozen=True)
class GrooveSegment:
    groove_height: float = 1.0  # h (mm)
    groove_width: float = 1.0  # w (mm)
    pitch: float = DEFAULT_PITCH  # groove spacing (mm)
    n_grooves: int = 2
    thickness: float = 3.0  # skirt thickness (mm)
    width: float = 0.5  # strip width, plane strain (mm)
    cell: float = 0.2  # element size (mm)

    def __post_init__(self):
        for name in ("groove_height", "groove_width", "pitch", "thickness", "width", "cell"):
            value = getattr(self, name)
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise StudyError(name, f"must be a positive number of mm, got {value!r}")
        if self.groove_height >= self.thickness:
            raise StudyError(
                "groove_height", f"{self.groove_height} mm cuts through the {self.thickness} mm skirt"
            )
        if self.groove_width >= self.pitch:
            raise StudyError(
                "groove_width", f"{self.groove_width} mm leaves no land in a {self.pitch} mm pitch"
            )

    @property
    def length(self) -> float:
        return self.n_grooves * self.pitch

    @property
    def area(self) -> float:
        """Footprint of the strip (mm^2): the area the backing pressure acts on."""
        return self.length * self.width


def _axis(breaks, cell):
    pts = [breaks[0]]
    for a, b in zip(breaks[:-1], breaks[1:]):
        n = max(1, int(math.ceil((b - a) / cell - 1e-9)))
        pts += list(np.linspace(a, b, n + 1)[1:])
    return np.array(pts)


def groove_mesh(seg: GrooveSegment) -> skfem.MeshTet:
    """The strip with its grooves; boundaries top, contact (everything below z = h + tol but the
    y faces), y0, y1."""
    half = seg.groove_width / 2
    grooves = [
        (max(i * seg.pitch - half, 0.0), min(i * seg.pitch + half, seg.length))
        for i in range(seg.n_grooves + 1)
    ]
    xb = sorted({0.0, seg.length, *[v for g in grooves for v in g]})
    zb = [0.0, seg.groove_height, seg.thickness]
    grid = skfem.MeshTet.init_tensor(_axis(xb, seg.cell), np.array([0.0, seg.width]), _axis(zb, seg.cell))
    c = grid.p[:, grid.t].mean(axis=1)
    in_groove = np.zeros(grid.t.shape[1], dtype=bool)
    for a, b in grooves:
        in_groove |= (c[0] > a) & (c[0] < b) & (c[2] < seg.groove_height)
    t = grid.t[:, ~in_groove]
    used = np.unique(t)
    renumber = np.full(grid.p.shape[1], -1)
    renumber[used] = np.arange(used.size)
    mesh = skfem.MeshTet(grid.p[:, used], renumber[t])
    tol = 1e-8 * seg.length
    mesh = tag_boundaries(
        mesh,
        {
            "top": lambda x: np.abs(x[2] - seg.thickness) < tol,
            "y0": lambda x: np.abs(x[1]) < tol,
            "y1": lambda x: np.abs(x[1] - seg.width) < tol,
            "low": lambda x: x[2] < seg.groove_height + tol,
        },
    )
    b = dict(mesh.boundaries)
    b["contact"] = np.setdiff1d(b.pop("low"), np.concatenate([b["y0"], b["y1"]]))
    return replace(mesh, _boundaries=b)


@dataclass(frozen=True)
class GrooveResult:
    groove_height: float
    mu: float
    pressure: float  # MPa
    converged: bool
    message: str
    drag: np.ndarray  # (n,) mm
    friction: np.ndarray  # (n,) N, the wall's force on the strip opposing the drag (positive)
    normal: np.ndarray  # (n,) N
    contact_fraction: np.ndarray  # (n,) contact area / apparent area L W (lands only: 1 - w / pitch)
    slip_fraction: np.ndarray  # (n,)
    normal_force: float  # at the end of the press (N)
    normal_error: float  # |N - p A| / (p A)
    plateau: float  # mean friction over the last half of the drag (N)
    plateau_over_mu_n: float
    metrics: dict  # von Mises, strain (raw max and p99), deformation at the end of the drag
    iterations: tuple[int, ...]  # Newton iterations per drag increment (first solve)
    n_dofs: int
    wall_s: float


def groove_model(seg: GrooveSegment, material, drag: float, penalty: float | None = None) -> SolidModel:
    """The strip on the wall z = 0; `material` a `fem.neohooke.NeoHookean`."""
    youngs = small_strain_youngs(material)
    eps = penalty if penalty is not None else youngs / seg.cell
    spec = ContactSpec(("contact",), Plane(), penalty=eps, name="grooved face")
    bcs = [Dirichlet("top", (0, 1), (drag, 0.0)), Dirichlet.symmetry("y0", 1), Dirichlet.symmetry("y1", 1)]
    plate = EqualDisplacement("top", 2, 1e3 * youngs * seg.cell)  # the top stays plane and level
    return SolidModel(
        groove_mesh(seg),
        material,
        dirichlet=bcs,
        chambers=ChamberSpec(("top",)),
        contacts=[spec],
        extra_terms=[plate],
    )


#: Newton settings of the contact runs: stick/slip and contact-set changes make the first
#: iterations of an increment semi-smooth, so the residual is given longer to start halving.
CONTACT_NEWTON = NewtonOptions(tol=1e-8, max_iter=40, stall_iter=16)


def run_groove(
    seg: GrooveSegment,
    material,
    mu: float,
    *,
    pressure=0.1,
    drag=5.0,
    drag_steps=20,
    penalty=None,
    on_state=None,
) -> GrooveResult:
    """Press, switch friction on, drag (module docstring). `on_state(label, model, x, time=None)`
    sees the pressed state and every drag increment (time: the drag in mm; VTU output)."""
    model = groove_model(seg, material, drag, penalty)
    term = model.contacts[0]
    rec = {k: [] for k in ("drag", "friction", "normal", "contact", "slip")}

    def record(step):
        rep = term.report(step.x)
        if step.stage == "press":
            rec["press"] = rep.normal_force
            if step.s == 1.0:  # the curve starts at the pressed state
                for key, v in zip(rec, (0.0, 0.0, rep.normal_force, rep.area_reference / seg.area, 0.0)):
                    rec[key].append(v)
            return
        rec["drag"].append(step.factor * drag)
        rec["friction"].append(-rep.friction_force[0])
        rec["normal"].append(rep.normal_force)
        rec["contact"].append(rep.area_reference / seg.area)
        rec["slip"].append(rep.slip_fraction)
        if on_state is not None:
            on_state(f"drag_{len(rec['drag']):03d}", model, step.x, step.factor * drag)

    onset = 0.1  # the first 10 % of the drag in fine steps: the stick-to-slip transition
    stages = [
        Stage("press", pressure=pressure, steps=2),
        Stage("onset", factor=onset, friction={0: mu}, steps=10),
        Stage("drag", factor=1.0, steps=max(1, round(drag_steps * (1 - onset)))),
    ]
    res = run_stages(
        model, stages, penetration_tol=1e-3, max_augment=3, options=CONTACT_NEWTON, on_step=record
    )
    press = [s for s in res.steps if s.stage == "press"]
    if on_state is not None and press:
        on_state("pressed", model, press[-1].x)
    pA = pressure * seg.area
    friction = np.array(rec["friction"])
    half = np.array(rec["drag"]) >= 0.5 * drag
    plateau = float(friction[half].mean()) if half.any() else float("nan")
    n_end = rec["normal"][-1] if rec["normal"] else float("nan")
    n_press = rec.get("press", float("nan"))
    return GrooveResult(
        groove_height=seg.groove_height,
        mu=mu,
        pressure=pressure,
        converged=res.converged,
        message=res.message,
        drag=np.array(rec["drag"]),
        friction=friction,
        normal=np.array(rec["normal"]),
        contact_fraction=np.array(rec["contact"]),
        slip_fraction=np.array(rec["slip"]),
        normal_force=n_press,
        normal_error=abs(n_press - pA) / pA,
        plateau=plateau,
        plateau_over_mu_n=plateau / (mu * n_end) if mu > 0 else float("nan"),
        metrics=solid_metrics(model, res.x, backing="top") if res.steps else {},
        iterations=tuple(s.iterations[0] for s in res.steps if s.stage != "press"),
        n_dofs=int(model.n_dofs),
        wall_s=res.wall_s,
    )
