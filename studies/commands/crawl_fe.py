"""`softcrawl crawl --body fe`: the whole robot as one FE body crawling in a pipe.

The options are `softcrawl crawl`'s (studies/commands/crawl.py); this module checks the ones that
apply to the FE body, refuses those that do not (exit 2, one line naming the option, before any
work) and runs `studies.crawl_fe.files.run_and_write`. The friction not given is the committed
feet identification's, as for the reduced crawl, so that the two crawl models differ only in how
the body is modelled. The body's silicone is `studies.robot_fe.model.DEFAULT_MATERIAL` (the
calibrated mu = 0.0638 MPa), stated in summary.json.

Checkpoints (`studies.crawl_fe.resume`): the inserted state and every converged sub-step of the
cycles go to OUT/checkpoints (the newest 3 kept). A run that ends clears them; one stopped at
its `--time-limit` (or killed) keeps them, and the same command with --resume continues from the
newest, with more `--cycles` if wanted (the count is not part of the checkpoint's key).
"""

from __future__ import annotations

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.

#: Options of the reduced crawl that the FE body does not take: (dest, option, default).
REDUCED_ONLY = (
    ("backward", "backward", False),
    ("symmetric", "symmetric", False),
    ("mesher", "mesher", "revolved"),
    ("sectors", "sectors", None),
    ("layers", "layers", None),
    ("edge_length", "mesh-size", None),
    ("foot_angle", "foot-angle", 120.0),
    ("insertion_cache", "insertion-cache", False),
    ("gif", "gif", False),
    ("animation", "animation", None),
)
#: Why each is refused.
WHY = {
    "backward": "the FE body crawls forward only so far",
    "symmetric": "the FE body has the paper's feet only so far",
    "foot-angle": "the FE body has the paper's 120 deg feet only so far",
    "insertion-cache": "the cache holds the reduced model's insertions",
    "gif": "the FE body's states are in vtu/crawl.pvd (open them in ParaView)",
    "animation": "the FE body's states are in vtu/crawl.pvd (open them in ParaView)",
}


def check_options(args) -> None:
    """Exit 2 (CommandLineError) for an option the FE body does not take, an elbow without a bend
    radius it can have, or a pipe's option given for another pipe."""
    from softcrawl.studies.commands.options import CommandLineError

    for dest, option, default in REDUCED_ONLY:
        if getattr(args, dest) != default:
            why = WHY.get(
                option, "it sets the reduced model's feet mesh; the FE body meshes itself (--quick)"
            )
            raise CommandLineError(option, f"not with --body fe: {why}")
    if args.pipe == "elbow":
        from softcrawl.geometry.foot_design import FootDesign
        from softcrawl.studies.crawl_fe.pipe import INSERT_CLEARANCE

        if args.bend_radius is None:
            raise CommandLineError("bend-radius", "--pipe elbow needs the bend's centreline radius (mm)")
        # the insertion starts with the wall clear of the skirt tips, a radius the bend must exceed
        clear = FootDesign().tip_radius + INSERT_CLEARANCE
        if not args.bend_radius > clear:
            raise CommandLineError(
                "bend-radius",
                f"must exceed {clear:g} mm, not {args.bend_radius:g} mm: the insertion starts with the wall "
                "clear of the skirt tips, and a bend radius at or below it folds the bend's inner wall",
            )
    elif args.bend_radius is not None:
        raise CommandLineError("bend-radius", "applies to --pipe elbow only")
    if args.wedge not in (None, 1):
        from softcrawl.studies.crawl_fe.wedge import COPIES

        if args.wedge != COPIES:
            raise CommandLineError(
                "wedge", f"the FE body's wedge is 360/{COPIES} deg (its three ePSAs), not 360/{args.wedge}"
            )
        if args.pipe in ("elbow", "bellows") or args.gait_plan is not None:
            why = {
                "elbow": "an elbow breaks it",
                "bellows": "the whole body leaves it at a bellows' snaps (docs/decisions/096-body-wedge.md)",
            }.get(args.pipe, "a gait plan's unequal pressures break it")
            raise CommandLineError("wedge", f"needs a state with the three-fold symmetry: {why}")
    if args.pipe != "bellows":
        for option, value in (("bellows-depth", args.bellows_depth), ("bellows-pitch", args.bellows_pitch)):
            if value is not None:
                raise CommandLineError(option, "applies to --pipe bellows only")


def corrugation(args) -> tuple[float, float] | None:
    """A bellows' (depth, pitch) in mm, each the option's or `pipe.BELLOWS_CORRUGATION`'s; None
    for the other pipes."""
    if args.pipe != "bellows":
        return None
    from softcrawl.studies.crawl_fe.pipe import BELLOWS_CORRUGATION

    given = (args.bellows_depth, args.bellows_pitch)
    return tuple(d if v is None else float(v) for v, d in zip(given, BELLOWS_CORRUGATION))


def run_body(args, friction_settings) -> int:
    """The FE-body crawl of the command line (module docstring); 1 when a stage diverged."""
    from pathlib import Path

    from softcrawl.console import progress
    from softcrawl.studies.commands.options import CommandLineError, body_material, checkpoint, output_folder
    from softcrawl.studies.crawl.model import CrawlSetup
    from softcrawl.studies.crawl.schedule import preset, read_csv
    from softcrawl.studies.crawl_fe.files import run_and_write
    from softcrawl.studies.crawl_fe.gait_plan import read_gait_plan
    from softcrawl.studies.crawl_fe.resume import FOLDER, BodyStore, body_options
    from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL

    check_options(args)
    friction = friction_settings(args)
    body_material(args.material, "material")
    if args.gait_plan is not None:
        if args.schedule is not None:
            raise CommandLineError("gait-plan", "replaces --schedule: give one of them")
        schedule = read_gait_plan(args.gait_plan, args.cycle_time)
    elif args.schedule:
        schedule = read_csv(args.schedule)
    else:
        schedule = preset(args.gait, args.pressure, args.cycle_time)
    copies = args.wedge or 1
    if copies > 1:
        rows = schedule.pressures_kpa
        if any(len(set(map(float, row))) > 1 for row in rows):
            raise CommandLineError(
                "wedge", f"needs equal chamber pressures in every row; {schedule.name} has others"
            )
    out = Path(output_folder(args.out))
    setup = CrawlSetup(
        pipe_diameter=args.pipe_diameter,
        mu_smooth=friction["mu_smooth"],
        mu_grooved=friction["mu_grooved"],
        material=args.material,
        insert_steps=4 if args.quick else 8,
        steps=args.steps or 4,
        cycles=args.cycles,
        slip_viscosity=args.slip_viscosity,
        copies=copies,
    )
    mesh = "quick" if args.quick else "default"
    schedules = schedule if args.gait_plan else (schedule,)
    corrugated = corrugation(args)
    key = body_options(setup, schedules, pipe=args.pipe, bend_radius=args.bend_radius, mesh=mesh,
                       silicone=DEFAULT_MATERIAL, design=None, inertia=args.inertia,
                       corrugation=corrugated)  # fmt: skip
    store = BodyStore(out / FOLDER, key)
    resumed = checkpoint(store, args.resume)
    what = (
        f"gait plan {args.gait_plan}, {len(schedule)}"
        if args.gait_plan
        else f"{schedule.name}, {setup.cycles}"
    )
    dynamics = ", with inertia" if args.inertia else ""
    dynamics += ", one wedge of 120 deg" if copies > 1 else ""
    progress(f"crawl --body fe: {what} cycle(s), {args.pipe} pipe, {mesh} mesh{dynamics}")
    converged, summary = run_and_write(
        setup,
        schedule,
        out,
        pipe=args.pipe,
        bend_radius=args.bend_radius,
        mesh=mesh,
        precision=args.vtu_precision,
        progress=progress,
        friction_source=friction["source"],
        max_wall_s=None if args.time_limit is None else 60.0 * args.time_limit,
        store=store,
        resumed=resumed,
        inertia=args.inertia,
        corrugation=corrugated,
    )
    print(summary["text"])
    if store.unfinished():
        print(f"crawl: stopped at the time limit; the same command with --resume continues ({store.folder})")
    return 0 if converged else 1
