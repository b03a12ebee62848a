r"""The FE model of the whole robot: the tied multi-material assembly with three chamber pressures.

    RobotDesign -> conforming swept mesh (geometry.robot_mesh; parts share their interface nodes,
    which ties them exactly) -> P2-P1 solid (fem.model) with

    part                          material (default)                  pressure field
    ePSA bodies epsa1..3          silicone `material`, mixed u-p      one P1 field per material
    seal heads, rings             ABS (Neo-Hookean with its mu, K)    (fem.discretisation pressure
    foot hubs                     3D-printed rubber, Shore 70A        groups): none is continuous
                                                                      across a material jump

    the Kevlar double helix of each ePSA as two fiber sheets on its outer cylinder outer{i}, over
    the whole length 0 <= z <= L (under the rings too: there the sheet lies on the tied interface);
    chamber i (chamber_wall{i} + chamber_ends{i}) with its own follower pressure P_i; the rear
    foot hub's bottom face clamped; gravity optional (density times g, scaled by the load factor).

The robot is open to extra terms (contact: `SolidModel.terms`) and to other supports: `clamp`
None leaves both feet free for a term that holds them.

Materials are stated in every result (`RobotModel.materials`). With the tensile-range modulus
(mu = 0.03 MPa) the paper's Fig. 11 load case bends the robot into a loop
(docs/decisions/046-robot-material.md); the robot studies run with the calibrated modulus unless told
otherwise.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from softcrawl.fem.model import ChamberSpec, Dirichlet, SolidModel
from softcrawl.fem.sheets import FiberSheet
from softcrawl.geometry.design import DesignError, RobotDesign
from softcrawl.geometry.epsa_shape import helix_families
from softcrawl.geometry.robot_mesh import MESH_PRESETS, RobotMeshSettings, mesh_robot_swept
from softcrawl.materials import get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.epsa.model import solid_material

#: The robot studies' silicone: the calibrated modulus of `softcrawl calibrate`
#: (docs/decisions/001-materials.md), at which the Fig. 11 load case bends the robot ~120 deg instead of a
#: full loop.
DEFAULT_MATERIAL = "ecoflex-00-50@mu=0.0638"
RING_MATERIAL = "abs"
SEAL_MATERIAL = "abs"
FOOT_MATERIAL = "rubber-70a"
G_MM_S2 = 9810.0  # standard gravity, mm/s^2


@dataclass(frozen=True)
class RobotModel:
    """The solver model and what the outputs need: design, tagged mesh, materials per part."""

    design: RobotDesign
    model: object = field(repr=False)  # fem.model.SolidModel
    mesh: object = field(repr=False)  # geometry.tagged_mesh.TaggedMesh
    settings: RobotMeshSettings
    materials: dict  # part kind -> material name

    @property
    def n_dofs(self) -> int:
        return int(self.model.n_dofs)


def fiber_sheets(design: RobotDesign, kevlar) -> list:
    """Two helix families per actuator on outer{i}, the directions of `helix_families` moved to
    the actuator's axis."""
    import math

    e = design.epsa
    axial = kevlar.youngs_modulus * math.pi * e.fiber_diameter**2 / 4
    sheets = []
    for i, centre in enumerate(design.actuator_centres, start=1):
        c = np.array([centre[0], centre[1], 0.0])[:, None]
        for direction, density in helix_families(e):
            sheets.append(FiberSheet(f"outer{i}", lambda X, f=direction, c=c: f(X - c), axial, density))
    return sheets


def build_robot_model(
    design: RobotDesign | None = None,
    material: str = DEFAULT_MATERIAL,
    mesh: RobotMeshSettings | str = "default",
    *,
    gravity: tuple[float, float, float] | None = None,
    clamp: str | None = "rear_bottom",
) -> RobotModel:
    """The robot model of the module docstring. `gravity`: the acceleration direction and size in
    units of g, e.g. (0, -1, 0) for a robot lying in a horizontal pipe (None: no gravity)."""
    design = design or RobotDesign()
    if not isinstance(design, RobotDesign):
        raise DesignError("design", "the robot model needs a RobotDesign")
    if isinstance(mesh, str) and mesh not in MESH_PRESETS:
        raise DesignError("mesh", f"{mesh!r} is not one of {sorted(MESH_PRESETS)}")
    settings = MESH_PRESETS[mesh] if isinstance(mesh, str) else mesh
    silicone, body_law = solid_material(material)
    parts = {"epsa": silicone, "seal_head": get_material(SEAL_MATERIAL)}
    parts |= {"ring": get_material(RING_MATERIAL), "foot": get_material(FOOT_MATERIAL)}
    tagged = mesh_robot_swept(design, settings)
    laws, body = {}, {}
    for name in tagged.region_names.values():
        kind = next(k for k in parts if name.startswith(k))
        laws[name] = body_law if kind == "epsa" else solid_law(parts[kind])
        if gravity is not None:
            body[name] = parts[kind].density * G_MM_S2 * np.asarray(gravity, dtype=float)
    chambers = [ChamberSpec((f"chamber_wall{i}", f"chamber_ends{i}"), name=f"epsa{i}") for i in (1, 2, 3)]
    model = SolidModel(
        tagged.to_skfem(order=2),
        laws,
        dirichlet=[Dirichlet.fixed(clamp)] if clamp else [],
        chambers=chambers,
        fiber_sheets=fiber_sheets(design, get_material("kevlar")),
        body_forces=body or None,
    )
    names = {k: m.name for k, m in parts.items()}
    return RobotModel(design, model, tagged, settings, names)
