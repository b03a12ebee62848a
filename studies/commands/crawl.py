"""`softcrawl crawl`: the robot's crawl in FE, two grooved feet in a rigid pipe.

The model: docs/decisions/051-crawl-model.md.

    softcrawl crawl [--body reduced|fe] [--pipe straight|vertical-up|vertical-down|elbow|bellows]
                    [--bend-radius MM] [--bellows-depth MM] [--bellows-pitch MM] [--pipe-diameter 70]
                    [--gait inflate|gait1|gait2|gait3]
                    [--schedule CSV]
                    [--cycles N] [--pressure KPA] [--cycle-time S] [--mu-smooth MU]
                    [--mu-grooved MU] [--slip-viscosity ETA] [--inertia] [--steps N] [--quick]
                    [--backward | --symmetric]
                    [--mesher revolved|tetwild] [--sectors N] [--layers N] [--edge-length MM]
                    [--wedge N]
                    [--material rubber-70a] [--foot-angle DEG]
                    [--gif | --animation PATH.gif] [--resume] --out DIR

--body reduced (the default): the reduced model of this docstring, FE feet and the actuators as
their axial law. --body fe: the whole robot as one FE body (three ePSAs with their winding, the
rings, the hubs and both feet; `studies.crawl_fe`, docs/decisions/076-one-body.md), in a straight,
vertical (under its weight, heading up or down) or elbow pipe (its bend of centreline radius
--bend-radius towards +x, starting 5 mm ahead of the front skirt), or a straight bellows (mean
diameter --pipe-diameter, corrugations --bellows-depth deep, peak to trough, every --bellows-pitch;
defaults 2 and 10 mm, an example: the paper does not describe its bellows;
docs/decisions/093-bellows.md); --quick is the quick body mesh, otherwise the default one (~2x the
DOFs). It writes states.csv, cycles.csv, summary.json, crawl.png
and vtu/ (`studies.crawl_fe.files`); the reduced model's feet options (--backward, --symmetric,
--mesher, --sectors, --layers, --mesh-size, --foot-angle), --insertion-cache and the GIF are
refused with --body fe (exit 2); --resume continues an FE-body run stopped at its --time-limit or
killed (`studies.crawl_fe.resume`; --cycles may grow). --gait-plan GAIT_CSV (--body fe): the gait.csv that
`softcrawl model plan` writes, replayed cycle by cycle (`studies.crawl_fe.gait_plan`). --wedge 3
(--body fe): one wedge of 120 deg of the body, ePSA 1 whole, its cuts tied exactly by the robot's
three-fold symmetry (`studies.crawl_fe.wedge`, docs/decisions/096-body-wedge.md); only where the
state keeps that symmetry: a straight or vertical pipe and equal chamber pressures (not a bellows,
where the whole body leaves the symmetric path at its snaps).

--slip-viscosity ETA (MPa s/mm, default 0): viscous slip of both feet's faces (`fem.contact_law`,
docs/decisions/088-viscous-slip.md): friction above the Coulomb limit by ETA times the slip speed,
so that a foot in gross slip keeps a stiffness along its slide; 0 is Coulomb's law.

--inertia (--body fe): the body's mass from its parts' densities, lumped, with backward Euler over
the schedule's time (`fem.inertia`, docs/decisions/089-inertia.md), so that a foot's sudden slide
is a short dynamic event rather than a state the quasi-static path cannot reach. Off by default.

The friction coefficients not given take the committed feet identification's
(`studies.foot.identify.prediction_friction`, docs/decisions/070-identify-feet.md: today 0.3 on
both faces, the sourced range's end, flagged in summary.json's sources); without that file, exit 2.

Both feet (P2-P1, Shore 70A unless --material names another rubber; the paper's 120 deg skirt
unless --foot-angle gives Fig. 21's 30-120 deg, hub thickened as `geometry.foot_design` derives
it) are inserted into the pipe (frictionless, by shrinking the wall),
friction is switched on, then the pressures follow the schedule (quasi-static steps). The three
ePSAs act between the hubs through their axial law (the paper's prototype statics, eqs. 19-24;
bending is not modelled). --backward: both feet flipped, as the paper changes the direction
(skirts everted by FE, grooved faces on the wall, held folded inside the pipe and released there;
the robot crawls towards -z; docs/decisions/067-flipped-foot.md); --symmetric: only the front
foot mirrored (the pair is symmetric under z -> -z: a check, it should not advance). The feet's
mesh: the revolved foot (48 sectors, 3 cells through the skirt; --sectors and --layers refine
it) or, with --mesher tetwild, pytetwild's (--edge-length; the mesh of the crawl results computed
before the revolved one). --quick: 4 insertion steps instead of 8 and, on the revolved mesh,
geometry.foot_meshers.quick_sectors of the foot (24 at 120 deg, 34 at 90, 42 at 60, 47 at 30) unless
--sectors is given (2 sub-steps per schedule segment stalled where the actuator force changes
sign, 4 pass, so --steps keeps 4). --wedge N (revolved feet): model one wedge of 360/N deg of
each foot, its cuts tied exactly by cyclic symmetry (`studies.foot.wedge`,
docs/decisions/083-exact-wedge.md: the quick crawl 6x faster, its strides within 2.3e-7 mm of the
whole feet's); N must divide the sectors
and leave at least 2 in the wedge; 1 (the default): the whole feet.

Prints per cycle the stride (advance of the centre) and speed = stride / cycle time beside the
paper's Table 2 speed for that diameter and the analytic `analytic.loads.crawl_speed`; writes
states.csv, cycles.csv, summary.json, vtu/ (crawl.pvd with the pipe in pipe.vtu) and crawl.png;
with --gif also crawl.gif (--animation: at PATH), the deformed feet in the pipe, one frame per
state, drawn from vtu/ off screen (`studies.crawl.animation`; GIF only: MP4 needs ffmpeg).
Exit code 1 when a stage diverges (the outputs then end at the last converged state).

Every converged state is written to OUT/checkpoints (the newest 3 kept; `studies.crawl.resume`),
removed once the outputs are written. After a kill -9, a SIGTERM, Ctrl-C or a full disk, the same
command with --resume continues from the newest state; the outputs are those of an uninterrupted
run (states.csv and cycles.csv from the state's rows, vtu/ kept up to it). Another option or
softcrawl version than the checkpoint's is refused in one line naming it (exit 2); --resume
without a checkpoint starts from the beginning (and says so), so that a job script can always
pass it; without --resume, a folder holding an unfinished run's checkpoint is refused (exit 2)
rather than overwritten.

--insertion-cache: the insertion (frictionless, so the same for every friction, schedule and
number of cycles) is read from the content-addressed cache of inserted states when it holds this
model's (`studies.crawl.insertion`: keyed by the mesh, the feet, the pipe, the material and the
solver settings), and computed and written there when it does not; the strides are those of a
computed insertion, bit for bit.
"""

from __future__ import annotations

import argparse

from softcrawl.console import progress
from softcrawl.geometry.foot_meshers import FOOT_MESHERS
from softcrawl.studies.crawl.mesh import MAX_FOOT_ANGLE, MIN_FOOT_ANGLE, QUICK_SECTORS
from softcrawl.studies.crawl.schedule import SCHEDULES

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.

IDENTIFIED = "the committed feet identification (results/identify/feet/feet.json)"
MIN_DIAMETER, MAX_DIAMETER = 50.0, 78.0  # hub 48 mm; the skirt tip reaches 78 mm
BODIES = ("reduced", "fe")
PIPE_KINDS = ("straight", "vertical-up", "vertical-down", "elbow", "bellows")  # studies.crawl_fe.pipe.PIPES


def register(subparsers) -> None:
    from softcrawl.studies.commands.options import add_alias, add_number, add_vtu_precision

    p = subparsers.add_parser(
        "crawl",
        help="the crawl in FE: two grooved feet in a pipe, stride and speed",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="\n".join(__doc__.splitlines()[1:]),
    )
    p.add_argument(
        "--body", default="reduced", choices=BODIES,
        help="reduced: FE feet, actuators as their axial law (default); fe: the whole robot in FE",
    )  # fmt: skip
    p.add_argument(
        "--pipe", default="straight", choices=PIPE_KINDS,
        help="the pipe of --body fe (default straight; the reduced model's is straight)",
    )  # fmt: skip
    add_number(p, "--bend-radius", help="--pipe elbow: the bend's centreline radius", unit="mm",
               default_text="none: needed with --pipe elbow",
               minimum=0.0, min_open=True, maximum=1000.0)  # fmt: skip
    # ranges with margin around flexible ducts' corrugations (a few mm deep, 5-30 mm apart)
    add_number(p, "--bellows-depth", help="--pipe bellows: corrugation depth, peak to trough", unit="mm",
               default_text="2", minimum=0.0, min_open=True, maximum=10.0)  # fmt: skip
    add_number(p, "--bellows-pitch", help="--pipe bellows: corrugation pitch", unit="mm",
               default_text="10", minimum=2.0, maximum=100.0)  # fmt: skip
    add_number(p, "--pipe-diameter", help="pipe inner diameter", unit="mm", default=70.0,
               minimum=MIN_DIAMETER, maximum=MAX_DIAMETER, min_open=True, max_open=True)  # fmt: skip
    p.add_argument(
        "--gait", default="inflate", choices=SCHEDULES, help="pressure schedule preset (default inflate)"
    )
    p.add_argument(
        "--schedule", default=None, help="CSV time_s,P1_kpa,P2_kpa,P3_kpa (one cycle; replaces --gait)"
    )
    p.add_argument(
        "--gait-plan", default=None, metavar="GAIT_CSV",
        help="--body fe: replay the gait.csv of `softcrawl model plan`, one planned cycle per cycle "
        "(all its cycles, --cycle-time each; replaces --gait, --schedule and --cycles)",
    )  # fmt: skip
    add_number(p, "--cycles", help="number of cycles", default=2, minimum=1, maximum=100, integer=True)
    add_number(p, "--pressure", help="peak pressure of the presets", unit="kPa", default=100.0,
               minimum=0.0, min_open=True, maximum=100.0)  # fmt: skip
    add_number(p, "--cycle-time", help="cycle time of the inflate preset", unit="s", default=2.0,
               minimum=0.0, min_open=True, maximum=1e4)  # fmt: skip
    # Default: the committed identification (issue 29 step 9, docs/decisions/070-identify-feet.md).
    add_number(p, "--mu-smooth", help="friction of the smooth face and rim", default_text=IDENTIFIED,
               minimum=0.0, maximum=5.0)  # fmt: skip
    add_number(p, "--mu-grooved", help="friction of the grooved face", default_text=IDENTIFIED,
               minimum=0.0, maximum=5.0)  # fmt: skip
    # Off by default: every committed crawl is Coulomb's (docs/decisions/088-viscous-slip.md).
    add_number(p, "--slip-viscosity", help="viscous slip of the feet: traction above Coulomb's per mm/s of "
               "slip speed", unit="MPa s/mm", default=0.0, minimum=0.0, maximum=1.0)  # fmt: skip
    add_number(p, "--steps", help="sub-steps per schedule segment", default_text="4",
               minimum=1, maximum=200, integer=True)  # fmt: skip
    p.add_argument(
        "--mesher", default="revolved", choices=FOOT_MESHERS, help="the feet's mesher (default revolved)"
    )
    # At least 24: below it scikit-fem cannot place the contact faces' quadrature points in the
    # curved P2 tets of the skirt (fem.discretisation.Discretisation.facet_basis; 20 sectors failed).
    add_number(p, "--sectors", help="revolved feet: sectors around the axis", default_text="48, --quick 24",
               minimum=24, maximum=256, integer=True)  # fmt: skip
    add_number(p, "--layers", help="revolved feet: cells through the skirt", default_text="3",
               minimum=1, maximum=12, integer=True)  # fmt: skip
    add_number(p, "--wedge", help="one wedge of 360/N deg, tied cyclically (the feet's; --body fe: 3)",
               default_text="1, the whole", minimum=1, maximum=64, integer=True)  # fmt: skip
    edge = add_number(p, "--mesh-size", help="tetwild feet: the mesh edge", unit="mm", dest="edge_length",
                      default_text="pytetwild's, 0.05 x the diagonal", minimum=1.0, maximum=20.0)  # fmt: skip
    add_alias(p, edge, "--edge-length")
    p.add_argument(
        "--material", default="rubber-70a", help="the feet's rubber, a preset (default rubber-70a; Fig. 21: "
        "rubber-50a, rubber-60a, rubber-70a; see `softcrawl material list`)"
    )  # fmt: skip
    add_number(p, "--foot-angle", help="included angle of both feet's conical skirt", unit="deg",
               default=120.0, minimum=MIN_FOOT_ANGLE, maximum=MAX_FOOT_ANGLE, metavar="DEG")  # fmt: skip
    add_number(p, "--time-limit", help="--body fe: stop after this wall time and write the states so far",
               unit="min", default_text="none", minimum=0.0, min_open=True, maximum=1e5)  # fmt: skip
    p.add_argument(
        "--inertia", action="store_true",
        help="--body fe: the body's lumped mass, backward Euler over the schedule (default: quasi-static)",
    )  # fmt: skip
    p.add_argument("--quick", action="store_true", help=f"4 insertion steps, {QUICK_SECTORS} sectors")
    feet = p.add_mutually_exclusive_group()
    feet.add_argument("--backward", action="store_true", help="both feet flipped: grooved faces on the wall")
    feet.add_argument("--symmetric", action="store_true", help="front foot mirrored: a symmetric pair")
    movie = p.add_mutually_exclusive_group()
    movie.add_argument("--gif", action="store_true", help="also write OUT/crawl.gif of the deformed feet")
    movie.add_argument("--animation", default=None, metavar="PATH", help="write that GIF at PATH (.gif)")
    add_vtu_precision(p)
    p.add_argument("--out", required=True, help="output folder")
    p.add_argument(
        "--resume", action="store_true", help="continue from the last state in OUT/checkpoints (same options)"
    )
    p.add_argument(
        "--insertion-cache",
        action="store_true",
        help="take the inserted state from the cache of insertions ($SOFTCRAWL_CACHE/insertions or "
        "~/.cache/softcrawl/meshes/insertions), computing and writing it there when it is not",
    )
    p.set_defaults(func=run)


def run(args) -> int:
    from pathlib import Path

    from softcrawl.geometry.foot_design import FootDesign
    from softcrawl.studies.commands.options import CommandLineError, body_material, checkpoint, output_folder
    from softcrawl.studies.crawl.files import run_and_write
    from softcrawl.studies.crawl.model import CrawlSetup
    from softcrawl.studies.crawl.resume import FOLDER, CrawlStore, crawl_options
    from softcrawl.studies.crawl.schedule import preset, read_csv

    if args.body == "fe":
        from softcrawl.studies.commands.crawl_fe import run_body

        return run_body(args, friction_settings)
    if args.pipe != "straight" or args.bend_radius is not None:
        raise CommandLineError(
            "pipe" if args.pipe != "straight" else "bend-radius",
            "the reduced crawl has a straight horizontal pipe only: add --body fe",
        )
    for option, value in (("gait-plan", args.gait_plan), ("time-limit", args.time_limit),
                          ("inertia", args.inertia or None), ("bellows-depth", args.bellows_depth),
                          ("bellows-pitch", args.bellows_pitch)):  # fmt: skip
        if value is not None:
            raise CommandLineError(option, "applies to the FE body only: add --body fe")
    mesh = mesh_settings(args)  # before any folder is made
    friction = friction_settings(args)  # before any folder is made
    body_material(args.material, "material")  # a preset the FE law takes, before any work
    foot = FootDesign(angle=args.foot_angle)
    if args.backward:
        from softcrawl.studies.crawl.flipped import check_pipe  # lazy: loads the solver

        check_pipe(args.pipe_diameter, foot, CommandLineError, "pipe-diameter")
    schedule = read_csv(args.schedule) if args.schedule else preset(args.gait, args.pressure, args.cycle_time)
    out = output_folder(args.out)
    animation = animation_path(args, Path(out))
    feet = "backward" if args.backward else "symmetric" if args.symmetric else "paper"
    steps = args.steps or 4
    setup = CrawlSetup(
        **mesh,
        pipe_diameter=args.pipe_diameter,
        mu_smooth=friction["mu_smooth"],
        mu_grooved=friction["mu_grooved"],
        feet=feet,
        foot=foot,
        material=args.material,
        insert_steps=4 if args.quick else 8,
        steps=steps,
        cycles=args.cycles,
        slip_viscosity=args.slip_viscosity,
    )
    store = CrawlStore(Path(out) / FOLDER, crawl_options(setup, schedule, setup.material))
    resumed = checkpoint(store, args.resume)
    print(f"crawl: {schedule.name} ({schedule.source}), {setup.cycles} cycle(s), feet {feet}; every state:")
    result, summary = run_and_write(
        setup,
        schedule,
        Path(out),
        quick=args.quick,
        progress=progress,
        precision=args.vtu_precision,
        store=store,
        resumed=resumed,
        insertion_cache=args.insertion_cache,
        friction_source=friction["source"],
    )
    print(summary["text"])
    if animation is not None:
        write_animation(Path(out), animation)
    return 0 if result.converged else 1


def friction_settings(args) -> dict:
    """mu_smooth, mu_grooved and their source: the options given, the committed identification
    for those not given (`studies.foot.identify.prediction_friction`; exit 2 when it is missing)."""
    from softcrawl.studies.crawl.files import FRICTION_SOURCE
    from softcrawl.studies.foot.identify import IdentificationMissing, prediction_friction

    given = {"mu_smooth": args.mu_smooth, "mu_grooved": args.mu_grooved}
    if None not in given.values():
        return given | {"source": "--mu-smooth and --mu-grooved: " + FRICTION_SOURCE}
    try:
        identified = prediction_friction()
    except IdentificationMissing as exc:
        raise exc.renamed(next(k for k, v in given.items() if v is None).replace("_", "-")) from None
    out = {k: (identified[k] if v is None else v) for k, v in given.items()}
    given_names = [k for k, v in given.items() if v is not None]
    source = identified["source"]
    if given_names:
        source += f"; {given_names[0]} given: {given[given_names[0]]:g}"
    return out | {"source": source}


def mesh_settings(args) -> dict:
    """The CrawlSetup mesh fields of the command line; a setting of the other mesher is an error."""
    from softcrawl.studies.commands.options import CommandLineError

    if args.mesher == "revolved":
        from softcrawl.geometry.foot_design import FootDesign  # lazy: the command's help stays light
        from softcrawl.geometry.foot_meshers import quick_sectors  # lazy: as above

        quick = quick_sectors(FootDesign(angle=args.foot_angle))
        if args.edge_length is not None:
            raise CommandLineError("mesh-size", "refines the tetwild feet: add --mesher tetwild")
        sectors = args.sectors if args.sectors is not None else (quick if args.quick else None)
        copies = args.wedge or 1
        n = sectors if sectors is not None else 48
        if n % copies or n // copies < 2:
            raise CommandLineError(
                "wedge", f"must divide the feet's {n} sectors and leave at least 2, got {copies}"
            )
        return {"mesher": "revolved", "sectors": sectors, "thickness_layers": args.layers, "copies": copies}
    if args.wedge not in (None, 1):
        raise CommandLineError(
            "wedge", "needs the revolved feet (the same in every sector), not --mesher tetwild"
        )
    for name, value in (("sectors", args.sectors), ("layers", args.layers)):
        if value is not None:
            raise CommandLineError(name, "refines the revolved feet, not --mesher tetwild")
    return {"mesher": "tetwild", "edge_length": args.edge_length}


def animation_path(args, out):
    """Where the GIF goes (None without --gif/--animation), checked before the crawl runs."""
    from pathlib import Path

    from softcrawl.studies.commands.options import CommandLineError, output_file

    if args.animation is None:
        return out / "crawl.gif" if args.gif else None
    path = Path(args.animation)
    if path.suffix.lower() != ".gif":
        raise CommandLineError("animation", f"{path} must end in .gif (GIF only: MP4 would need ffmpeg)")
    return output_file(path, "animation")


def write_animation(out, path) -> None:
    """The GIF from out/vtu; a rendering failure (no off-screen OpenGL) costs the GIF, not the crawl."""
    from softcrawl.studies.commands.options import make_folder
    from softcrawl.studies.crawl.animation import write_crawl_gif

    make_folder(path.parent, "animation")
    try:
        write_crawl_gif(out / "vtu", path, out / "states.csv")
    except Exception as exc:  # noqa: BLE001 - VTK/EGL errors have no common class; the files are written
        print(f"crawl: animation not written: {type(exc).__name__}: {exc}")
        return
    print(f"crawl: animation {path}")
