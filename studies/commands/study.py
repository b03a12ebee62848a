"""`softcrawl study NAME`: the paper's ePSA finite element studies as resumable optuna studies.

    softcrawl study chamber-radius    [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study fiber-turns       [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study identify          [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study optimise-actuator [--quick] [--material M] [--storage URL] [--workers N]
                                      [--trials T] [--sampler nsga2|tpe] [--seed S] --out DIR
    softcrawl study rings             [--quick] [--material M] [--workers N] --out DIR
    softcrawl study foot-radius       [--quick] [--material M] [--workers N] --out DIR
    softcrawl study workspace         [--quick] [--material M] --out DIR

rings (Fig. 11(c)), foot-radius (Section V-C) and workspace (Fig. 11(d)) are the robot-level
studies on the tied assembly (studies.catalogue.robot_studies, robot_workspace); they write to
DIR/robot-NAME/MATERIAL[-quick]/ and decide their Table 1 rows by the rules of
studies.review.robot_rules.

chamber-radius (paper Fig. 8): no fibers, r = 2, 3, 4, 5, 6 mm. fiber-turns (Fig. 9): r = 3 mm, N =
0, 10, 20, 25, 50. Both at 20, 40, 60, 80, 100 kPa. identify (Section VII-A): the Table 1 ePSA under
weights W = 0, 0.5, 1 N on its guided top at 10-100 kPa; k_p(P) and f_p(P) fitted as the paper does
and compared with eqs. 19-24 (studies/catalogue/fe_identification.py). optimise-actuator: NSGA-II
(or TPE) over r in [2, 6] mm and N in 0..50 for three objectives at 100 kPa: maximise extension,
minimise the radius change |dR| (the radius should stay at its design value: fibered designs shrink
slightly, and a plain "minimise dR" would reward shrinking), minimise the Kevlar thread length of
the double helix (the fabrication cost: winding is done by hand, turn by turn, so thread length ~
winding work; the body mass depends on r only and is reported as ``mass_g``). The Table 1 design (r
= 3, N = 20) is evaluated first and marked.

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

from studies.catalogue.actuator_studies import DEFAULT_MATERIAL, GRIDS
from studies.catalogue.optimise_actuator import DEFAULT_TRIALS, QUICK_TRIALS
from studies.catalogue.optimise_actuator import NAME as OPTIMISER

#: The robot-level studies (studies.catalogue.robot_studies, robot_workspace).
ROBOT_STUDIES = ("rings", "foot-radius", "workspace")
STUDIES = (*GRIDS, OPTIMISER, *ROBOT_STUDIES)


def register(subparsers) -> None:
    from studies.parts.epsa_model import FIBER_MODELS

    parser = subparsers.add_parser(
        "study",
        help="ePSA finite element studies (sweeps, optimiser)",
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
        help=f"silicone of the ePSA body (default {DEFAULT_MATERIAL}; robot studies: the calibrated "
        "modulus of studies.parts.robot_model.DEFAULT_MATERIAL; see `softcrawl material list`)",
    )
    parser.add_argument(
        "--storage",
        default=None,
        help="optuna RDB URL shared by all workers (default: SQLite in the output folder)",
    )
    parser.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    parser.add_argument("--mesh-size", type=float, default=None, help="element size (mm)")
    parser.add_argument(
        "--fibers",
        choices=FIBER_MODELS,
        default=None,
        help="Kevlar winding model (default: studies.parts.epsa_model.DEFAULT_FIBERS; see softcrawl epsa)",
    )
    parser.add_argument(
        "--trials",
        type=int,
        default=None,
        help=f"optimise-actuator: total trials (default {DEFAULT_TRIALS}, {QUICK_TRIALS} with --quick)",
    )
    parser.add_argument(
        "--sampler",
        default="nsga2",
        choices=("nsga2", "tpe"),
        help="optimise-actuator: optuna sampler (default nsga2)",
    )
    parser.add_argument("--seed", type=int, default=0, help="optimise-actuator: sampler seed")
    parser.add_argument(
        "--simulator",
        default=None,
        metavar="MODULE:FUNCTION",
        help="replace studies.parts.epsa_response:simulate_epsa (same signature), e.g. a "
        "surrogate or a test fake; for rings and foot-radius, studies.catalogue.robot_studies:run_cases",
    )
    parser.add_argument(
        "--retry-failed",
        action="store_true",
        help="sweeps: evaluate the failed points again (after an evaluator fix); "
        "otherwise a failed evaluation is a result and is kept",
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def _check(args) -> None:
    from materials import get_material
    from studies.sweeps.engine import StudyError

    get_material(args.material)  # MaterialError (parameter "material") for an unknown name
    if args.workers < 1:
        raise StudyError("workers", f"must be >= 1, got {args.workers}")
    if args.mesh_size is not None and not args.mesh_size > 0:
        raise StudyError("mesh-size", f"must be positive, got {args.mesh_size}")
    if args.trials is not None and args.trials < 1:
        raise StudyError("trials", f"must be >= 1, got {args.trials}")
    if args.storage is not None and "://" not in args.storage:
        raise StudyError(
            "storage",
            f"expected a database URL such as sqlite:///PATH or "
            f"postgresql://USER@HOST/DB, got {args.storage!r}",
        )
    if args.simulator is not None and ":" not in args.simulator:
        raise StudyError("simulator", f"expected MODULE:FUNCTION, got {args.simulator!r}")


def run(args: argparse.Namespace) -> int:
    from studies.catalogue.actuator_studies import run_sweep_study, study_settings
    from studies.catalogue.optimise_actuator import run_optimiser
    from studies.sweeps.engine import SweepInterrupted

    if args.material is None:
        from studies.parts.robot_model import DEFAULT_MATERIAL as ROBOT_MATERIAL

        args.material = ROBOT_MATERIAL if args.name in ROBOT_STUDIES else DEFAULT_MATERIAL
    _check(args)
    if args.name in ROBOT_STUDIES:
        return _run_robot_study(args)
    settings = study_settings(
        args.name, args.material, args.quick, args.mesh_size, args.fibers, args.simulator
    )
    progress = not args.no_progress
    try:
        if args.name == OPTIMISER:
            outcome = run_optimiser(
                args.out,
                settings,
                trials=args.trials,
                sampler=args.sampler,
                seed=args.seed,
                storage=args.storage,
                workers=args.workers,
                progress=progress,
            )
        else:
            outcome = run_sweep_study(
                args.name,
                args.out,
                settings,
                storage=args.storage,
                workers=args.workers,
                progress=progress,
                retry=args.retry_failed,
            )
    except SweepInterrupted as exc:
        print(f"softcrawl study {args.name}: interrupted: {exc}", file=sys.stderr)
        return 1
    for line in outcome.lines:
        print(line)
    for line in outcome.problems:
        print(line, file=sys.stderr)
    print("wrote " + ", ".join(map(str, outcome.written)))
    return 0 if outcome.ok else 1


def _run_robot_study(args) -> int:
    """rings and foot-radius (sweeps, studies.catalogue.robot_studies) and workspace
    (studies.catalogue.robot_workspace)."""
    from studies.sweeps.engine import SweepInterrupted

    progress = not args.no_progress
    try:
        if args.name == "workspace":
            from studies.catalogue.robot_workspace import run_workspace

            outcome = run_workspace(args.out, args.material, args.quick, print if progress else None)
        else:
            from studies.catalogue.robot_studies import run_robot_study

            outcome = run_robot_study(
                args.name, args.out, args.material, args.quick, workers=args.workers, progress=progress,
                retry=args.retry_failed, runner=args.simulator,
            )  # fmt: skip
    except SweepInterrupted as exc:
        print(f"softcrawl study {args.name}: interrupted: {exc}", file=sys.stderr)
        return 1
    for line in outcome.lines:
        print(line)
    for line in outcome.problems:
        print(line, file=sys.stderr)
    print("wrote " + ", ".join(map(str, outcome.written)))
    return 0 if outcome.ok else 1
