"""One grooved foot from its design to its result, in one call: `simulate_foot` (the public API's).

    FootDesign + material + pipe diameter -> the foot's mesh (`geometry.foot_meshers`, the
    revolved mesh of the foot study by default) -> `model.run_foot` (insertion, friction on,
    forward and backward drag) -> `FootResult`

What one point of `softcrawl study foot` does (`contact_studies.evaluate_foot`), without the
files. `quick=True`: 24 sectors around the axis instead of 48 (the least at which the contact
faces' quadrature points are placed, `studies.crawl.mesh.QUICK_SECTORS`; more for a skirt of less
than 120 deg, `geometry.foot_meshers.quick_sectors`), 4 insertion steps and
2 mm of drag in 2 steps each way.
"""

from __future__ import annotations

from softcrawl.analytic.pipe import Pipe
from softcrawl.checks import number
from softcrawl.geometry.design import DesignError, FootDesign
from softcrawl.geometry.foot_meshers import mesh_foot_with, quick_sectors
from softcrawl.geometry.foot_revolved import N_THETA
from softcrawl.materials import Material, get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.foot.contact_studies import DEFAULT_MATERIAL, DRAG_MM, FOOT, FOOT_FRICTION, FOOT_MESHER
from softcrawl.studies.foot.flip import flipped_min_diameter
from softcrawl.studies.foot.model import FOOT_MAX_WALL_S, FootResult, run_foot
from softcrawl.studies.foot.wedge import wedge_sectors

#: The foot study's settings and the quick ones of the module docstring (drag in mm).
FULL = {"drag": DRAG_MM[FOOT], "drag_steps": 8, "insert_steps": 8}
QUICK = {"sectors": 24, "drag": 2.0, "drag_steps": 2, "insert_steps": 4}


def simulate_foot(
    design: FootDesign | None = None,
    pipe_diameter: float = 70.0,
    *,
    material=DEFAULT_MATERIAL,
    mu_smooth: float = FOOT_FRICTION["mu_smooth"],
    mu_grooved: float = FOOT_FRICTION["mu_grooved"],
    drag: float | None = None,
    drag_steps: int | None = None,
    insert_steps: int | None = None,
    quick: bool = False,
    mesher: str = FOOT_MESHER,
    sectors: int | None = None,
    max_wall_s: float | None = FOOT_MAX_WALL_S,
    flipped: bool = False,
    wedge: int = 1,
) -> FootResult:
    """The foot (Table 1 by default) inserted into a pipe of `pipe_diameter` mm and dragged `drag`
    mm forward and backward -> `FootResult` (normal force, resistances F_fwd, F_bwd and their
    `ratio`). `material`: a preset name (`material_names()`) or a `Material`; unset numbers take
    the foot study's values, or the quick ones with `quick=True`. `flipped`: the skirt starts
    everted, its grooved face on the wall (the backward crawl's foot, `studies.foot.flip`).
    `wedge` > 1: one wedge of 360/wedge deg of the revolved foot, its cuts tied by cyclic symmetry
    (`studies.foot.wedge`), on the sectors rounded up to a multiple of `wedge`."""
    design = design or FootDesign()
    if not isinstance(flipped, bool):
        raise DesignError("flipped", f"must be True or False, got {flipped!r}")
    if not isinstance(design, FootDesign):
        raise DesignError("design", "the foot simulation needs a FootDesign")
    between_hub_and_tip = {"minimum": 2 * design.hub_radius, "maximum": 2 * design.tip_radius}
    number(pipe_diameter, "pipe_diameter", **between_hub_and_tip, min_open=True, max_open=True, unit="mm",
           error=DesignError)  # fmt: skip
    smallest = flipped_min_diameter(design)
    if flipped and not pipe_diameter > smallest:
        message = f"the flipped foot folds into pipes above {smallest:.4g} mm, not {pipe_diameter:g} mm"
        raise DesignError("pipe_diameter", message)
    for name, value in (("mu_smooth", mu_smooth), ("mu_grooved", mu_grooved)):
        number(value, name, minimum=0.0, maximum=5.0, error=DesignError)
    given = {"drag": drag, "drag_steps": drag_steps, "insert_steps": insert_steps}
    chosen = {k: v if v is not None else (QUICK if quick else FULL)[k] for k, v in given.items()}
    drag = number(chosen.pop("drag"), "drag", minimum=0.0, min_open=True, maximum=20.0, unit="mm",
                  error=DesignError)  # fmt: skip
    count = {"minimum": 1, "maximum": 200, "integer": True, "error": DesignError}
    steps = {k: number(v, k, **count) for k, v in chosen.items()}
    number(wedge, "wedge", minimum=1, maximum=12, integer=True, error=DesignError)
    if wedge > 1 and (flipped or mesher != "revolved"):
        raise DesignError("wedge", "a wedge needs the revolved, unflipped foot (the same in every sector)")
    if sectors is None and quick and mesher == "revolved":
        sectors = max(QUICK["sectors"], quick_sectors(design))  # more for a skirt nearer the axis
    if wedge > 1:
        sectors = wedge_sectors(sectors or N_THETA, wedge)
    mat = material if isinstance(material, Material) else get_material(material)
    extra = {"copies": wedge} if wedge > 1 else {}
    mesh = mesh_foot_with(design, mesher, sectors=sectors, **extra).to_skfem(2)
    return run_foot(
        mesh,
        solid_law(mat, hyperelastic_only=True),
        design,
        Pipe(diameter=float(pipe_diameter)),
        mu_smooth=float(mu_smooth),
        mu_grooved=float(mu_grooved),
        drag=drag,
        max_wall_s=max_wall_s,
        flipped=flipped,
        copies=wedge,
        **steps,
    )
