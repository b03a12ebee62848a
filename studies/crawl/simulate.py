"""The crawl from its settings to its result, in one call: `simulate_crawl` (the public API's).

    pipe diameter + pressure schedule (a gait preset in kPa, a CSV file or a `Schedule`) + feet
    -> the two feet's mesh (`mesh.crawl_mesh`, the Table 1 robot's feet) -> `model.build` ->
    `model.run_crawl` (insertion, friction on, the cycles) -> `CrawlResult`

What `softcrawl crawl` does from its options (`files.run_and_write`), without the files: no
states.csv, VTU or plot; `progress(line)` gets the command's line per converged state. The
actuators act through the paper's prototype axial law (`schedule.AxialLaw`), so the ePSA design is
not an input here. `foot`: both feet's `FootDesign` (None: the paper's, 120 deg); `material`: their
rubber. `quick=True`: 4 insertion steps instead of 8 and, on the revolved feet,
`geometry.foot_meshers.quick_sectors(foot)` sectors (24 at 120 deg: about 90 s per inflate cycle
on one core).
"""

from __future__ import annotations

from pathlib import Path

from softcrawl.checks import number
from softcrawl.geometry.design import RobotDesign
from softcrawl.geometry.foot_design import FootDesign
from softcrawl.geometry.foot_meshers import quick_sectors
from softcrawl.materials import Material, get_material
from softcrawl.materials.fem_law import solid_law
from softcrawl.studies.crawl.files import MATERIAL, progress_line
from softcrawl.studies.crawl.flipped import check_pipe
from softcrawl.studies.crawl.insertion import insertion_cache_for
from softcrawl.studies.crawl.mesh import crawl_mesh
from softcrawl.studies.crawl.model import CrawlSetup, build, run_crawl
from softcrawl.studies.crawl.outputs import CrawlResult
from softcrawl.studies.crawl.schedule import Schedule, ScheduleError, preset, read_csv
from softcrawl.studies.foot.identify import prediction_friction

#: Pipe inner diameters (mm, both open) the crawl accepts, as `softcrawl crawl`: the hub is 48 mm
#: across, the skirt tip 78 mm.
MIN_DIAMETER, MAX_DIAMETER = 50.0, 78.0
FEET = ("paper", "backward", "symmetric")


def crawl_schedule(schedule, gait: str, pressure_kpa: float, cycle_time_s: float) -> Schedule:
    """`schedule` itself, read from a CSV path, or (None) the `gait` preset at `pressure_kpa`."""
    if schedule is None:
        return preset(gait, pressure_kpa, cycle_time_s)
    if isinstance(schedule, Schedule):
        return schedule
    if isinstance(schedule, str | Path):
        return read_csv(schedule)
    raise ScheduleError("schedule", f"give a Schedule, a CSV path or None, not {type(schedule).__name__}")


def simulate_crawl(
    pipe_diameter: float = 70.0,
    *,
    gait: str = "inflate",
    schedule=None,
    pressure_kpa: float = 100.0,
    cycle_time_s: float = 2.0,
    cycles: int = 1,
    mu_smooth: float | None = None,
    mu_grooved: float | None = None,
    feet: str = "paper",
    foot: FootDesign | None = None,
    quick: bool = False,
    steps: int = 4,
    mesher: str = "revolved",
    sectors: int | None = None,
    thickness_layers: int | None = None,
    edge_length: float | None = None,
    material=MATERIAL,
    max_wall_s: float | None = None,
    progress=None,
    insertion_cache=False,
) -> CrawlResult:
    """The robot's two grooved feet crawling in a rigid pipe of `pipe_diameter` mm for `cycles`
    cycles of the pressure schedule (kPa) -> `CrawlResult` (`strides`, per-cycle speed, states).
    `mu_smooth`, `mu_grooved`: None takes the committed feet identification's
    (`studies.foot.identify.prediction_friction`, docs/decisions/070-identify-feet.md);
    `feet`: "paper" (skirts lean back), "backward" (both flipped: grooved faces on the wall,
    `studies.crawl.flipped`), "symmetric" (front mirrored);
    `material`: the feet's rubber, a preset name or a `Material`; `insertion_cache`: True (the
    default folder) or a folder to take the inserted state from, or write it to
    (`studies.crawl.insertion`; the same strides as a computed insertion), False to compute it."""
    number(pipe_diameter, "pipe_diameter", minimum=MIN_DIAMETER, maximum=MAX_DIAMETER, min_open=True,
           max_open=True, unit="mm", error=ScheduleError)  # fmt: skip
    foot = RobotDesign(foot=foot).foot if foot is not None else RobotDesign().foot
    if feet == "backward":
        check_pipe(float(pipe_diameter), foot, ScheduleError)
    if mu_smooth is None or mu_grooved is None:
        identified = prediction_friction()
        mu_smooth = identified["mu_smooth"] if mu_smooth is None else mu_smooth
        mu_grooved = identified["mu_grooved"] if mu_grooved is None else mu_grooved
    for name, value in (("mu_smooth", mu_smooth), ("mu_grooved", mu_grooved)):
        number(value, name, minimum=0.0, maximum=5.0, error=ScheduleError)
    number(cycles, "cycles", minimum=1, maximum=100, integer=True, error=ScheduleError)
    number(steps, "steps", minimum=1, maximum=200, integer=True, error=ScheduleError)
    if feet not in FEET:
        raise ScheduleError("feet", f"{feet!r} is not one of {', '.join(FEET)}")
    plan = crawl_schedule(schedule, gait, pressure_kpa, cycle_time_s)
    if sectors is None and quick and mesher == "revolved":
        sectors = quick_sectors(foot)
    setup = CrawlSetup(
        pipe_diameter=float(pipe_diameter),
        mu_smooth=float(mu_smooth),
        mu_grooved=float(mu_grooved),
        feet=feet,
        foot=foot,
        insert_steps=4 if quick else 8,
        steps=int(steps),
        cycles=int(cycles),
        max_wall_s=max_wall_s,
        mesher=mesher,
        sectors=sectors,
        thickness_layers=thickness_layers,
        edge_length=edge_length,
        material=material.name if isinstance(material, Material) else str(material),
    )
    mat = material if isinstance(material, Material) else get_material(material)
    design, mesh = crawl_mesh(setup.mirrored, foot=setup.foot, **setup.mesh_options())
    law = solid_law(mat, hyperelastic_only=True)
    cm = build(mesh, law, design, setup)
    insertion = insertion_cache_for(insertion_cache, cm, mesh, design, law)

    def on_state(row, model, x):
        if progress is not None:
            progress(progress_line(row))

    return run_crawl(cm, plan, on_state=on_state, insertion=insertion)
