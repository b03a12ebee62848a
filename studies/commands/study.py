"""`softcrawl study NAME`: the finite element studies (ePSA, contact, robot, crawl) as resumable sweeps.

    softcrawl study chamber-radius    [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study fiber-turns       [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study identify          [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study optimise-actuator [--quick] [--material M] [--storage URL] [--workers N]
                                      [--trials T] [--sampler nsga2|tpe] [--seed S] --out DIR
    softcrawl study groove            [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study foot              [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study rings             [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study foot-radius       [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study workspace         [--quick] [--material M] --out DIR
    softcrawl study crawl             [--quick] [--storage URL] [--workers N] --out DIR
    softcrawl study paper-material    --out DIR
    softcrawl study kp-mismatch       --out DIR

paper-material: which material (Neo-Hookean, Yeoh, Gent; every shape and shear modulus) reproduces
the paper's own FE observations of Figs. 8-9; no FE (studies/material/paper_material.py).
kp-mismatch: the identify studies under DIR against the confined and unconfined tube stiffness
(studies/epsa/kp_mismatch.py), DIR/identify/kp-mismatch.md.

rings (Fig. 11(c)), foot-radius (Section V-C) and workspace (Fig. 11(d)) are the robot-level
studies on the tied assembly (studies.robot_fe.robot_studies, robot_workspace); they write to
DIR/robot-NAME/MATERIAL[-quick]/ and decide their Table 1 rows by the rules of
studies.robot_fe.rules.

chamber-radius (paper Fig. 8): no fibers, r = 2, 3, 4, 5, 6 mm. fiber-turns (Fig. 9): r = 3 mm, N =
0, 10, 20, 25, 50. Both at 20, 40, 60, 80, 100 kPa. identify (Section VII-A): the Table 1 ePSA under
weights W = 0, 0.5, 1 N on its guided top at 10-100 kPa; k_p(P) and f_p(P) fitted as the paper does
and compared with eqs. 19-24 (studies/epsa/identification.py).
optimise-actuator: the paper's selection as a
constrained problem (optuna TPE or NSGA-II with trial constraints): the least Kevlar thread over r in
{2..6} mm and N in 0..50 that withstands 100 kPa, keeps |dR| within 5 % of R0 and extends within the N
rule's tolerance of the N = 50 design of its radius (studies/epsa/optimiser.py). The
Table 1 design (r = 3, N = 20) is evaluated first and marked.

crawl (issue 17): stride and anchoring of the FE crawl (two feet, the ePSAs' axial law) over pipe
diameter and friction coefficient (studies/crawl/crawl_study.py), DIR/crawl/rubber-70a[-quick]/.

groove (Fig. 10(a)) and foot (Fig. 10(b)): contact with the pipe wall, Coulomb friction; see
studies/foot/contact_studies.py for the grids and the stated friction coefficients.

Results go to DIR/NAME/MATERIAL/ (MATERIAL-quick with --quick, -hSIZE with --mesh-size): curves.csv
(every grid point and pressure, with trial and row status and the failure reason), summary.csv (one
row per design), NAME.png, vtu/ (the last computed shape of each design, when the evaluator can
return its model), spec.json and, without --storage, the SQLite study study.db. Running the same
command again resumes: only missing points are computed. --storage postgresql://... lets workers on
several machines share one study (start the same command on each).
"""

from __future__ import annotations

import argparse
import sys

from softcrawl.studies.epsa.grid_studies import DEFAULT_MATERIAL, GRIDS
from softcrawl.studies.epsa.optimiser import DEFAULT_TRIALS, QUICK_TRIALS
from softcrawl.studies.epsa.optimiser import NAME as OPTIMISER

PAPER_MATERIAL = "paper-material"
KP_MISMATCH = "kp-mismatch"
CONTACT_STUDIES = ("groove", "foot")  # studies.foot.contact_studies
#: The robot-level studies (studies.robot_fe.robot_studies, robot_workspace).
ROBOT_STUDIES = ("rings", "foot-radius", "workspace")
CRAWL = "crawl"  # studies.crawl.crawl_study
STUDIES = (*GRIDS, OPTIMISER, PAPER_MATERIAL, KP_MISMATCH, *CONTACT_STUDIES, *ROBOT_STUDIES, CRAWL)


#: Most worker processes: each is a process with its own solver (0.3-1 GB on the default mesh);
#: more workers than cores only share the cores, and the sweeps have 5-60 points.
MAX_WORKERS = 64
#: Most trials of the optimiser: 60 take about an hour on the default mesh (2 cores); 10,000 would
#: take a week and more.
MAX_TRIALS = 10_000
#: Largest sampler seed: numpy's random generators take seeds below 2^32.
MAX_SEED = 2**32 - 1


def register(subparsers) -> None:
    from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL as ROBOT_MATERIAL

    parser = subparsers.add_parser(
        "study",
        help="FE studies as resumable sweeps: ePSA, foot contact, robot, crawl",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog="\n".join(__doc__.splitlines()[1:]),
    )
    parser.add_argument("name", choices=STUDIES, help="which study")
    parser.add_argument("--out", required=True, help="results folder (DIR/NAME/MATERIAL/...)")
    parser.add_argument(
        "--quick",
        action="store_true",
        help="coarse meshes (minutes on 2 cores); results go to MATERIAL-quick",
    )
    parser.add_argument(
        "--material",
        default=None,
        help=f"silicone of the ePSA body (default {DEFAULT_MATERIAL}), the foot's rubber for groove "
        "and foot (default rubber-70a), or the robot studies' silicone (default "
        f"{ROBOT_MATERIAL}, the calibrated modulus); see `softcrawl material list`",
    )
    parser.add_argument(
        "--storage",
        default=None,
        help="optuna RDB URL shared by all workers (default: SQLite in the output folder; for several "
        "machines postgresql://USER:PASSWORD@HOST/DB, with pip install -e '.[postgres]')",
    )
    _add_run_options(parser)
    parser.add_argument(
        "--simulator",
        default=None,
        metavar="MODULE:FUNCTION",
        help="replace studies.epsa.response:simulate_epsa (same signature), e.g. a "
        "surrogate or a test fake; for rings and foot-radius, studies.robot_fe.robot_studies:run_cases",
    )
    parser.add_argument(
        "--retry-failed",
        action="store_true",
        help="sweeps: evaluate the failed points again (after an evaluator fix); "
        "otherwise a failed evaluation is a result and is kept",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def _add_run_options(parser) -> None:
    """Workers, mesh, winding and the optimiser's options."""
    from softcrawl.studies.commands.options import add_number
    from softcrawl.studies.epsa.model import DEFAULT_FIBERS, FIBER_MODELS, MIN_MESH_SIZE

    add_number(
        parser,
        "--workers",
        help="worker processes",
        default=1,
        minimum=1,
        maximum=MAX_WORKERS,
        integer=True,
    )
    add_number(
        parser,
        "--mesh-size",
        help="element size",
        unit="mm",
        default_text="the converged preset (about 5 mm)",
        minimum=MIN_MESH_SIZE,
        maximum=1000.0,
    )
    parser.add_argument(
        "--fibers",
        choices=FIBER_MODELS,
        default=None,
        help=f"Kevlar winding model (default {DEFAULT_FIBERS}; see softcrawl epsa)",
    )
    add_number(
        parser,
        "--trials",
        help="optimise-actuator: total trials",
        default_text=f"{DEFAULT_TRIALS}, {QUICK_TRIALS} with --quick",
        minimum=1,
        maximum=MAX_TRIALS,
        integer=True,
    )
    parser.add_argument(
        "--sampler",
        default="nsga2",
        choices=("nsga2", "tpe"),
        help="optimise-actuator: optuna sampler (default nsga2)",
    )
    add_number(
        parser,
        "--seed",
        help="optimise-actuator: sampler seed",
        default=0,
        minimum=0,
        maximum=MAX_SEED,
        integer=True,
    )


def _check(args) -> None:
    """Every option checked before the sweep starts: a bad one is one line and exit code 2, not a
    sweep in which every point fails."""
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.commands.options import body_material, output_folder
    from softcrawl.studies.epsa.model import resolve_mesh
    from softcrawl.studies.sweeps.spec import StudyError

    if args.material is None:
        from softcrawl.studies.robot_fe.model import DEFAULT_MATERIAL as ROBOT_MATERIAL

        feet = (*CONTACT_STUDIES, CRAWL)
        defaults = dict.fromkeys(feet, "rubber-70a") | dict.fromkeys(ROBOT_STUDIES, ROBOT_MATERIAL)
        args.material = defaults.get(args.name, DEFAULT_MATERIAL)
    body_material(args.material)  # MaterialError (parameter "material") for an unknown name
    if args.name == CRAWL and args.material != "rubber-70a":
        raise StudyError("material", "the crawl study's feet are rubber-70a (the foot study's rubber)")
    if args.workers < 1:
        raise StudyError("workers", f"must be >= 1, got {args.workers}")
    if args.mesh_size is not None:
        for radius in (2.0, 3.0):  # the thickest wall of the grids needs the most cells
            resolve_mesh(EPSADesign(chamber_radius=radius), mesh_size=args.mesh_size)
    if args.trials is not None and args.trials < 1:
        raise StudyError("trials", f"must be >= 1, got {args.trials}")
    if args.simulator is not None:
        _check_simulator(args.simulator)
    if args.storage is not None and "://" not in args.storage:
        raise StudyError(
            "storage",
            f"expected a database URL such as sqlite:///PATH or "
            f"postgresql://USER@HOST/DB, got {args.storage!r}",
        )
    output_folder(args.out)


def _check_simulator(ref: str) -> None:
    """MODULE:FUNCTION must import and name a callable (the evaluator would fail every point)."""
    from softcrawl.checks import brief
    from softcrawl.studies.sweeps.spec import StudyError, load_callable

    if ":" not in ref:
        raise StudyError("simulator", f"expected MODULE:FUNCTION, got {brief(ref)}")
    try:
        load_callable(ref, parameter="simulator")
    except StudyError as exc:
        if "is not callable" in exc.detail:
            raise StudyError("simulator", f"{brief(ref)} is not a function") from None
        cause = exc.__cause__
        why = f"{type(cause).__name__}: {cause}" if cause is not None else exc.detail
        raise StudyError("simulator", f"cannot load {brief(ref)}: {why}") from None


def run(args: argparse.Namespace) -> int:
    from softcrawl.studies.sweeps.faults import SweepStopped, machine_fault

    _check(args)
    if args.name == KP_MISMATCH:  # reads the identify studies under --out (studies.epsa.kp_mismatch)
        from softcrawl.studies.epsa.kp_mismatch import write_report

        print("wrote " + ", ".join(map(str, write_report(args.out))))
        return 0
    if args.name == PAPER_MATERIAL:  # no FE: the closed-end tube theory (studies.material.paper_material)
        from softcrawl.studies.material.paper_material import run_paper_material

        lines, written = run_paper_material(args.out)
        print("\n".join(lines))
        print("wrote " + ", ".join(map(str, written)))
        return 0
    try:
        outcome = _run_study(args)
    except SweepStopped as exc:  # a signal, a full disk, a lost database: one line, then resume
        print(f"softcrawl study {args.name}: {exc.line}", file=sys.stderr)
        return exc.exit_code
    except OSError as exc:  # writing the tables: the results are safe in the study's database
        line = machine_fault(exc)
        if line is None:
            raise
        print(
            f"softcrawl study {args.name}: error: {line}; run the same command to write the tables",
            file=sys.stderr,
        )
        return 1
    for line in outcome.lines:
        print(line)
    for line in outcome.problems:
        print(line, file=sys.stderr)
    print("wrote " + ", ".join(map(str, outcome.written)))
    return 0 if outcome.ok else 1


def _run_study(args):
    """The study's outcome (`studies.outcome.StudyOutcome`)."""
    from softcrawl.studies.epsa.grid_studies import run_sweep_study, study_settings
    from softcrawl.studies.epsa.optimiser import run_optimiser

    progress = not args.no_progress
    if args.name in ROBOT_STUDIES:
        return _run_robot_study(args, progress)
    if args.name == CRAWL:
        from softcrawl.studies.crawl.crawl_study import run_crawl_study

        return run_crawl_study(
            args.out,
            quick=args.quick,
            storage=args.storage,
            workers=args.workers,
            progress=progress,
            retry=args.retry_failed,
        )
    if args.name in CONTACT_STUDIES:
        from softcrawl.studies.foot.runs import run_contact_study

        return run_contact_study(
            args.name,
            args.out,
            material=args.material,
            quick=args.quick,
            storage=args.storage,
            workers=args.workers,
            progress=progress,
            retry=args.retry_failed,
        )
    settings = study_settings(
        args.name, args.material, args.quick, args.mesh_size, args.fibers, args.simulator
    )
    if args.name == OPTIMISER:
        return run_optimiser(
            args.out,
            settings,
            trials=args.trials,
            sampler=args.sampler,
            seed=args.seed,
            storage=args.storage,
            workers=args.workers,
            progress=progress,
        )
    return run_sweep_study(
        args.name,
        args.out,
        settings,
        storage=args.storage,
        workers=args.workers,
        progress=progress,
        retry=args.retry_failed,
    )


def _run_robot_study(args, progress: bool):
    """rings and foot-radius (sweeps, studies.robot_fe.robot_studies) and workspace
    (studies.robot_fe.workspace)."""
    if args.name == "workspace":
        from softcrawl.studies.robot_fe.workspace import run_workspace

        return run_workspace(args.out, args.material, args.quick, print if progress else None)
    from softcrawl.studies.robot_fe.robot_studies import run_robot_study

    return run_robot_study(
        args.name, args.out, args.material, args.quick, workers=args.workers, progress=progress,
        retry=args.retry_failed, runner=args.simulator, storage=args.storage,
    )  # fmt: skip
