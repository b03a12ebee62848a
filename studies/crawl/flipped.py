r"""The backward crawl's feet: both skirts flipped (everted), grooved faces on the wall.

The paper changes the crawl's direction "by changing the initial contact surfaces of each foot":
both feet start flipped. Each foot is the paper's mesh (not mirrored), folded by FE as in the foot
study (`studies.foot.flip.fold`, `studies.foot.model._flipped_stages`): its rim is rotated about
the skirt's hinge by the flip and as much more as brings it `FOLD_CLEARANCE` inside the pipe
wall, with the hub face its actuators act on held (`mesh.attach_tag`: the rear foot's hub top, the
front foot's hub bottom). Each foot's folded state is copied onto its foot of the crawl's mesh
(the nodes matched by position: the rear foot where the single foot is, the front one
`separation` ahead; the P1 pressures by their vertices), so that the copy meets the crawl's
constraints on that face (a rigid plate: equal axial, zero lateral displacements) and is an
equilibrium of the crawl's model up to the ground springs' share of the fold's reaction. A fold
with the other face held is not: the front foot's actuator face, free in that fold, is deformed
there, and its plate's penalty and lateral constraint put an imbalance of the order of the whole
force scale into the first sub-step of the insertion, whatever its size, which no cut-back
removes (at 55 mm the quick crawl's insertion stalled in it;
docs/decisions/078-backward-stall.md). Rim springs (`flip.RimSprings` on
"rear:rim" and "front:rim", `FOLD_HOLD` N/mm per dof) hold both rims there while the wall shrinks
from clear of the folded feet to the pipe; then a "release" stage takes the springs to 0
(`RimSprings.ramp`), and the crawl goes on as for the paper's feet (friction on, the cycles). The
robot then crawls towards -z: the flipped skirts lean forward (+z), so they slide easily backward.

A tight pipe crushes the fold. The rim is folded inside the wall, but the skirt between the held
hub and the held rim bows outward (29.8-30.2 mm at 55 mm, where the wall is at 27.5 mm; folding
further, up to the skirt along the axis, brings it in by less than 0.3 mm), so the closing wall
crushes that bow, and its force falls while the wall closes: a snap, where the quasi-static
insertion finds no equilibrium near its last state (records 078, 079). Where the folded feet
reach outside the pipe, the insertion and the release carry a viscous stabilisation
(`fem.stabilisation`): c0 = STABILISE E / t^2 over a pseudo-time of 1 s per stage, ramped linearly
to exactly 0 at the release's end, so that the released state, from which the
crawl goes on, is a static equilibrium (docs/decisions/094-backward-snap.md). Where the fold is
inside the wall (65 mm and above), c0 = 0 and nothing changes.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from softcrawl.fem.model import SolidModel
from softcrawl.fem.stabilisation import Stabilisation
from softcrawl.geometry.foot_meshers import mesh_foot_with
from softcrawl.studies.crawl.mesh import FEET, attach_tag
from softcrawl.studies.crawl.mesh import separation as hub_separation
from softcrawl.studies.foot import wedge
from softcrawl.studies.foot.flip import (
    FOLD_CLEARANCE,
    RimSprings,
    flipped_min_diameter,
    fold,
    fold_angle_into,
)
from softcrawl.studies.foot.model import FOLD_HOLD, FOOT_NEWTON

__all__ = [
    "FOLD_HOLD",
    "check_pipe",
    "folded_feet",
    "insert_drive",
    "outer_radius",
    "plate_hold",
    "release_drive",
    "rim_springs",
    "stabilisation_coefficient",
]

#: The viscous stabilisation of the flipped feet's insertion (`fem.stabilisation`), in units of
#: E / t^2 (E the rubber's small-strain modulus, t the skirt's thickness): c0 = STABILISE E / t^2
#: (docs/decisions/094-backward-snap.md).
STABILISE = 1.0e-2


def check_pipe(pipe_diameter: float, foot_design, error, parameter: str = "pipe_diameter") -> None:
    """An `error` (an InputError class) naming `parameter` when the flipped feet cannot be folded
    into that pipe (`flip.flipped_min_diameter`)."""
    smallest = flipped_min_diameter(foot_design)
    if not pipe_diameter > smallest:
        raise error(
            parameter,
            f"the flipped feet of --backward fold into pipes above {smallest:.4g} mm, "
            f"not {pipe_diameter:g} mm",
        )


def outer_radius(model: SolidModel, x) -> float:
    """The largest radius (mm) of the body's nodes in the state x."""
    deformed = model.nodes + model.displacement(x)
    return float(np.hypot(deformed[0], deformed[1]).max())


def stabilisation_coefficient(model: SolidModel, x0, radius: float, youngs: float, foot_design) -> float:
    """c0 (N s/mm^4) of the flipped feet's insertion: STABILISE E / t^2 where the folded feet x0
    reach outside the pipe's `radius` (the closing wall crushes the fold, record 078), else 0 (the
    wall closes onto nothing, and the insertion is the one before record 094)."""
    if outer_radius(model, x0) <= radius:
        return 0.0
    return STABILISE * youngs / foot_design.skirt_thickness**2


def insert_drive(stabilisation: Stabilisation, c0: float):
    """The insertion's drive: the stabilisation at c0 while the wall closes."""

    def drive(s: float) -> None:
        stabilisation.set_coefficient(c0)

    return drive


def release_drive(springs: RimSprings, stabilisation: Stabilisation, c0: float):
    """The release's drive: the rim springs ramped from FOLD_HOLD to 0 (`RimSprings.ramp`) and the
    stabilisation linearly, c = c0 (1 - s), so that the released state (k = c = 0) is a static
    equilibrium. Over a sub-step h the regularisation is c / h: up to the last sub-step it stays
    about c0 (c0 (1 - s) / h = c0 on the one before the last), and the last one is the static
    solve (docs/decisions/094-backward-snap.md: tied to the springs' decades, c was gone by s = 0.6,
    where the 55 mm quick release stalled)."""
    ramp = springs.ramp(FOLD_HOLD)

    def drive(s: float) -> None:
        ramp(s)
        stabilisation.set_coefficient(c0 * max(1.0 - s, 0.0))

    return drive


def rim_springs() -> RimSprings:
    """The springs on both feet's rims (target set by `folded_feet`)."""
    return RimSprings(np.zeros(0), tags=tuple(f"{foot}:rim" for foot in FEET))


def plate_hold(model: SolidModel, plates, penalty: float, copies: int = 1) -> float:
    """k_hold = n k_p (N/mm): a ground spring on a plate's mean axial displacement as stiff as the
    plate's penalty `penalty` (N/mm per node) holds its n nodes together (the largest n of
    `plates`, the whole feet's; module docstring, the flipped feet's plates)."""
    return float(penalty * max(wedge.whole_nodes(model, tag, copies) for tag in plates))


def _match(points: np.ndarray, reference: np.ndarray, shifts) -> tuple[np.ndarray, np.ndarray]:
    """For each of `points` (n, 3), the index of the `reference` point (m, 3) it coincides with
    after one of the axial `shifts` (mm), and the index of that shift; every point must find one."""
    tree = cKDTree(reference)
    best = np.full(len(points), -1)
    which = np.full(len(points), -1)
    for k, dz in enumerate(shifts):
        dist, idx = tree.query(points - np.array([0.0, 0.0, dz]))
        hit = dist < 1e-6 * max(np.ptp(reference, axis=0).max(), 1.0)
        best[hit], which[hit] = idx[hit], k
    if np.any(best < 0):
        raise RuntimeError(
            f"flipped feet: {int(np.sum(best < 0))} nodes of the crawl mesh match no foot node"
        )
    return best, which


def folded_feet(
    model: SolidModel, material, foot_design, setup, springs: RimSprings
) -> tuple[np.ndarray, str]:
    """(x0, message): the crawl model's state with both feet folded, each with its actuators' hub
    face held (module docstring), and the springs' target set to it; x0 is None (the message says
    why) when a fold did not converge."""
    separation = hub_separation(foot_design)
    mesh = mesh_foot_with(foot_design, **(setup.mesh_options() | {"copies": 1})).to_skfem(2)  # whole feet
    single = SolidModel(mesh, material)
    rim = single.boundary_nodes("rim")
    phi = fold_angle_into(foot_design, single.nodes[:, rim], setup.pipe.radius - FOLD_CLEARANCE)
    states, folds = [], {}
    for foot, mirrored in zip(FEET, setup.mirrored):
        hub = attach_tag(foot, mirrored).split(":", 1)[1]
        if hub not in folds:
            folds[hub] = fold(mesh, material, foot_design, phi, options=FOOT_NEWTON, hub=hub)
        if not folds[hub].converged:
            return None, f"{foot} foot, {hub} held: {folds[hub].message}"
        states.append(folds[hub].x)
    u = np.stack([single.displacement(x) for x in states])  # (foot, 3, nodes)
    nodes, foot_of = _match(model.nodes.T, single.nodes.T, (0.0, separation))
    x0 = np.zeros(model.n_dofs)
    x0[: model.n_u] = u[foot_of, :, nodes].ravel()
    if model.mixed and single.mixed:
        p1 = np.full((len(states), mesh.p.shape[1]), np.nan)
        for k, x in enumerate(states):
            p1[k, single.space.pressure_vertex] = x[single.n_u :]
        vertices, foot_of_vertex = _match(model.mesh.p.T, mesh.p.T, (0.0, separation))
        pv = model.space.pressure_vertex
        x0[model.n_u :] = p1[foot_of_vertex[pv], vertices[pv]]
    springs.target = x0[springs.rim_dofs].copy()
    springs.stiffness = FOLD_HOLD
    return x0, "folded"
