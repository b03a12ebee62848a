r"""The whole robot as one FE body in a straight pipe: the model the FE-body crawl will use (issue 34).

    CrawlSetup (the reduced crawl's: pipe, feet, rubber, friction)
      -> RobotDesign(foot=setup.foot)                      the one body geometry (record 066)
      -> geometry.body_mesh.mesh_body                      one conforming mesh (record 076)
      -> P2-P1 solid (fem.model), per part as `softcrawl robot` (studies.robot_fe.model):

    part                     material                                       pressure field
    ePSAs epsa1..3           the silicone (calibrated mu = 0.0638 MPa)      one P1 field per
    seal heads, rings        ABS                                            material
    feet (hubs and skirts)   the crawl's rubber, `setup.material`

    the Kevlar winding as two fiber sheets per actuator on outer{i}; chamber i with its own
    follower pressure; both skirts in Coulomb contact with one rigid CylinderWall on the pipe axis,
    two terms per foot as the reduced crawl (`studies.crawl.model`): "rear:smooth" (front face
    and rim, mu_smooth) and "rear:grooved" (back face, mu_grooved), the same for "front";
    penalty eps_N = 10 E / h (E of the rubber, h the feet's median edge) as there. No foot is
    clamped.

Holding the rigid-body modes (`HOLDS`). A free body in a cylinder has six rigid modes; before the
wall touches the skirts all six are free, and in a frictionless cylinder the axial translation
and the twist about the axis stay free. Six linear springs (`fem.axial_link.AxialLink`) on mean
displacements of hub faces hold them, and nothing else:

    hold_x, hold_y, hold_z   ground links on the rear hub's bottom face (rear_bottom), u_x, u_y, u_z
    tilt_x, tilt_y           ground links on the front hub's top face (front_top), u_x, u_y
    twist                    an internal link on u_y between the halves x > 0 and x < 0 of
                             rear_bottom: a rotation theta about z gives Delta = theta (xbar+ - xbar-)

The front face's u_z is free (the actuators extend), and the twist link is a couple (no net
force). A rigid motion of the body is the only one that does not strain it, so six independent
springs on the six modes make the tangent regular with the wall clear, and they carry only the net
force and moment of the other loads (an isostatic support). During the frictionless insertion
they are stiff (`HOLD_STIFF`, the reduced crawl's GROUND_HOLD); when friction is switched on they
are re-based at the inserted state (their rest extension) and softened to `HOLD_SOFT` (the
reduced crawl's GROUND_SOFT, 1e-4 N/mm), so that friction holds the body and the holds' forces,
reported, are ~0 (tests/studies/crawl_fe/test_holding.py shows it under the body's weight). A wall
that pushes the body along its axis while frictionless (a bellows' slopes) leaves forces in the
stiff holds: those are kept as the soft holds' preloads when friction comes on, so that the state
stays in equilibrium, and released to zero afterwards (`studies.crawl_fe.pipe`).

One wedge (`CrawlSetup.copies` = 3; `studies.crawl_fe.wedge`, docs/decisions/096-body-wedge.md):
the body's mesh cut to one wedge of 120 deg with ePSA 1 whole, its cuts tied exactly, chamber 1
and its fiber sheets alone, the two holds the tie leaves (`wedge.HOLDS`), each link's share 1/3;
the contact penalty's edge is still the whole mesh's median.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import partial

import numpy as np

from softcrawl.fem.axial_link import AxialLink
from softcrawl.fem.errors import SolverInputError
from softcrawl.fem.inertia import Inertia, InertiaTerm
from softcrawl.fem.model import ChamberSpec, SolidModel
from softcrawl.geometry.body_mesh import BodyMeshSettings, mesh_body, settings_for
from softcrawl.geometry.design import RobotDesign
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.crawl.contacts import feet_contacts
from softcrawl.studies.crawl.model import CRAWL_NEWTON, GROUND_HOLD, GROUND_SOFT, CrawlSetup
from softcrawl.studies.crawl_fe import wedge
from softcrawl.studies.crawl_fe.wedge import wedge_mesh
from softcrawl.studies.epsa.model import solid_material
from softcrawl.studies.robot_fe.model import (
    DEFAULT_MATERIAL,
    G_MM_S2,
    RING_MATERIAL,
    SEAL_MATERIAL,
    fiber_sheets,
)

FEET = ("rear", "front")
#: The body's Newton settings: the reduced crawl's, and an attempt that makes no new lowest
#: residual in three iterations after its fourth is given up (`fem.newton_progress`). At the feet's
#: slip onset the first sub-step attempts fail that way, and waited 12 iterations for the stall
#: test; measured in docs/decisions/090-newton-progress.md.
BODY_NEWTON = replace(CRAWL_NEWTON, progress_iter=4)
HOLD_STIFF = GROUND_HOLD  # N/mm, during the frictionless insertion
HOLD_SOFT = GROUND_SOFT  # N/mm, once friction is on
#: (name, tag_b, tag_a or None for the ground, component) of the whole body's six holds (module docstring).
HOLDS = (
    ("hold_x", "rear_bottom", None, 0),
    ("hold_y", "rear_bottom", None, 1),
    ("hold_z", "rear_bottom", None, 2),
    ("tilt_x", "front_top", None, 0),
    ("tilt_y", "front_top", None, 1),
    ("twist", "rear_bottom:+x", "rear_bottom:-x", 1),
)


@dataclass
class BodyModel:
    """The solver model of the one body, its tagged mesh, the setup and materials it was built from."""

    model: SolidModel
    mesh: object = field(repr=False)  # geometry.tagged_mesh.TaggedMesh
    design: RobotDesign
    setup: CrawlSetup
    settings: BodyMeshSettings
    materials: dict  # part kind -> material name
    holds: dict = field(default_factory=dict)  # name -> AxialLinkTerm
    inertia: InertiaTerm | None = None  # the lumped mass (`build_body(inertia=True)`), or None

    @property
    def n_dofs(self) -> int:
        return int(self.model.n_dofs)

    @property
    def copies(self) -> int:
        """1 for the whole body, 3 for one wedge of it (`studies.crawl_fe.wedge`)."""
        return int(self.setup.copies)

    def contacts_of(self, foot: str) -> list:
        return [c for c in self.model.contacts if c.spec.name.startswith(foot)]

    def volumes(self, x: np.ndarray) -> tuple[float, float, float]:
        """The three chambers' volumes (mm^3); a wedge's one chamber stands for all three."""
        n = len(self.model.chambers)
        return tuple(float(self.model.chamber_volume(x, i % n)) for i in range(3))

    def pressures(self, row) -> list[float]:
        """The modelled chambers' pressures of a schedule row of three (a wedge: ePSA 1's, and the
        row's pressures must be equal: unequal ones break the symmetry the wedge assumes)."""
        row = list(row)
        if self.copies > 1 and len(set(map(float, row))) > 1:
            raise SolverInputError("wedge", f"needs equal chamber pressures, not {row} (kPa or MPa)")
        return row[: len(self.model.chambers)]

    def hold_forces(self, x: np.ndarray) -> dict[str, float]:
        """Each hold's force (N; the whole body's twist link's pair force, a wedge's twist hold's
        ground force) at state x."""
        return {name: float(t.tension(x)) for name, t in self.holds.items()}

    def set_holds(self, stiffness: float, x: np.ndarray | None = None, preloads: dict | None = None) -> None:
        """Every hold's stiffness; with `x`, re-based there (rest extension = its extension at x);
        `preloads`: each hold's force (N) kept as its preload (None: none)."""
        for name, t in self.holds.items():
            t.set_load(stiffness, (preloads or {}).get(name, 0.0), None if x is None else t.extension(x))


def with_hold_tags(tagged):
    """The tagged mesh with rear_bottom's facets in x > 0 and in x < 0 as two tags (the twist hold;
    the facets touching x = 0 in neither, so that the two share no node)."""
    tris = tagged.facets["rear_bottom"]
    x = tagged.points[tris][..., 0]
    tol = 1e-9 * float(np.abs(tagged.points).max())
    east, west = np.all(x > tol, axis=1), np.all(x < -tol, axis=1)  # no node shared
    facets = dict(tagged.facets) | {"rear_bottom:+x": tris[east], "rear_bottom:-x": tris[west]}
    return replace(tagged, facets=facets)


def part_kind(region: str) -> str:
    """The part kind of a region name: epsa, seal_head, ring or foot."""
    return next(k for k in ("epsa", "seal_head", "ring", "foot") if region.startswith(k))


def part_materials(setup: CrawlSetup, silicone: str = DEFAULT_MATERIAL) -> dict[str, str]:
    """The material (a `softcrawl.materials` name) of each part kind (module docstring)."""
    return {"epsa": silicone, "seal_head": SEAL_MATERIAL, "ring": RING_MATERIAL, "foot": setup.material}


def build_body(
    setup: CrawlSetup | None = None,
    mesh: BodyMeshSettings | str = "quick",
    *,
    silicone: str = DEFAULT_MATERIAL,
    gravity: tuple[float, float, float] | None = None,
    design: RobotDesign | None = None,
    inertia: bool = False,
) -> BodyModel:
    """The body of the module docstring in `setup`'s pipe, wall clear of the skirt tips.
    `gravity`: the acceleration in units of g (e.g. (0, 0, -1): the robot heading up a vertical
    pipe), scaled by the load factor; None: none. `design`: the robot (None: Table 1's); its foot
    is replaced by `setup.foot`, so that the feet are the reduced crawl's. `inertia`: the parts'
    densities as a lumped mass with backward Euler over the schedule's time (`fem.inertia`,
    docs/decisions/089-inertia.md; the term is `BodyModel.inertia`)."""
    setup = setup or CrawlSetup()
    design = (design or RobotDesign()).replace(foot=setup.foot)
    settings = settings_for(design.foot, mesh) if isinstance(mesh, str) else mesh
    whole = mesh_body(design, settings)
    copies = int(setup.copies)
    tagged = with_hold_tags(whole) if copies == 1 else wedge_mesh(whole, copies)
    soft, body_law = solid_material(silicone)
    parts = {kind: get_material(name) for kind, name in part_materials(setup, silicone).items()}
    parts["epsa"] = soft
    laws, body, densities = {}, {}, {}
    for name in tagged.region_names.values():
        kind = part_kind(name)
        laws[name] = body_law if kind == "epsa" else solid_law(parts[kind])
        densities[name] = parts[kind].density
        if gravity is not None:
            body[name] = parts[kind].density * G_MM_S2 * np.asarray(gravity, dtype=float)
    # the penalty's edge is the whole mesh's (a wedge's tets may list their vertices otherwise)
    feet = np.isin(whole.region, [i for i, n in whole.region_names.items() if n.startswith("foot")])
    edges = np.linalg.norm(np.diff(whole.points[whole.tets[feet][:, :2]], axis=1)[:, 0], axis=1)
    edge = float(np.median(edges))
    contacts = feet_contacts(parts["foot"].law, edge, design.foot.tip_radius, setup.slip_viscosity)
    specs = HOLDS if copies == 1 else wedge.HOLDS
    # a wedge's holds take their means over one node of each orbit: the whole body's means
    pick = None if copies == 1 else partial(wedge.face_nodes, copies=copies)
    holds = [
        AxialLink(b, a, c, HOLD_STIFF, 0.0, name=name, share=1.0 / copies, nodes=pick)
        for name, b, a, c in specs
    ]
    chambers = [
        ChamberSpec((f"chamber_wall{i}", f"chamber_ends{i}"), name=f"epsa{i}")
        for i in (1, 2, 3)
        if f"chamber_wall{i}" in tagged.facets  # a wedge holds ePSA 1 only
    ]
    model = SolidModel(
        tagged.to_skfem(order=2) if copies == 1 else wedge.wedge_p2(tagged, whole),
        laws,
        chambers=chambers,
        fiber_sheets=[s for s in fiber_sheets(design, get_material("kevlar")) if s.tag in tagged.facets],
        body_forces=body or None,
        contacts=contacts,
        extra_terms=holds + ([Inertia(densities)] if inertia else []),
        ties=wedge.ties(copies),
    )
    terms = {t.name: t for t in model.terms if getattr(t, "name", None) in {h[0] for h in specs}}
    names = {k: m.name for k, m in parts.items()}
    mass = next((t for t in model.terms if isinstance(t, InertiaTerm)), None)
    return BodyModel(model, tagged, design, setup, settings, names, terms, mass)
