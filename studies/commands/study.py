"""`softcrawl study NAME`: the finite element studies (ePSA, contact, robot, crawl) as resumable sweeps.

    softcrawl study NAME [--quick] [--material M] [--storage URL] [--workers N] [...] --out DIR

The studies are those of the registry (`studies.registry`), each declared once in its feature
folder (`studies/<feature>/study.py`); this command names none of them. The list below is built
from their declarations.

Results go to DIR/FOLDER/MATERIAL/ (MATERIAL-quick with --quick, -hSIZE with --mesh-size): curves.csv
(every grid point and pressure, with trial and row status and the failure reason), summary.csv (one
row per design), NAME.png, vtu/ (the last computed shape of each design, when the evaluator can
return its model), spec.json and, without --storage, the SQLite study study.db. Running the same
command again resumes: only missing points are computed. --storage postgresql://... lets workers on
several machines share one study (start the same command on each).
"""

from __future__ import annotations

import argparse
import sys
import textwrap

from softcrawl import console
from softcrawl.studies import registry
from softcrawl.studies.declaration import StudyRequest, resolve
from softcrawl.studies.epsa.study import DEFAULT_TRIALS, QUICK_TRIALS  # the declarations: light
from softcrawl.studies.foot.study import FEET_QUICK_TRIALS, FEET_TRIALS

# Project modules are imported inside the functions that use them: softcrawl --help stays fast.

#: Most worker processes: each is a process with its own solver (0.3-1 GB on the default mesh);
#: more workers than cores only share the cores, and the sweeps have 5-60 points.
MAX_WORKERS = 64
#: Most trials of the optimiser: 60 take about an hour on the default mesh (2 cores); 10,000 would
#: take a week and more.
MAX_TRIALS = 10_000
#: Largest --max-memory (GB): far above any machine this runs on; a larger number is a typo.
MAX_MEMORY_GB = 4096.0
#: Most designs `--confirm` crawls: each is a two-cycle crawl of 20-60 min on a loaded machine.
MAX_CONFIRM = 10
#: Largest sampler seed: numpy's random generators take seeds below 2^32.
MAX_SEED = 2**32 - 1


def _epilog() -> str:
    """The module docstring's body, then one paragraph per registered study."""
    lines = __doc__.splitlines()[1:]
    for study in registry.studies():
        lines += ["", textwrap.fill(study.help or f"{study.name}: {study.summary}", width=100)]
    return "\n".join(lines)


def _material_defaults() -> str:
    defaults: dict[str, list[str]] = {}
    for study in registry.studies():
        if study.default_material is not None:
            defaults.setdefault(study.default_material, []).append(study.name)
    return "; ".join(f"{m} for {', '.join(names)}" for m, names in defaults.items())


def register(subparsers) -> None:
    parser = subparsers.add_parser(
        "study",
        help="FE studies as resumable sweeps: ePSA, foot contact, robot, crawl",
        description=__doc__.splitlines()[0],
        formatter_class=argparse.RawDescriptionHelpFormatter,
        epilog=_epilog(),
    )
    parser.add_argument("name", choices=registry.names(), help="which study")
    parser.add_argument("--out", required=True, help="results folder (DIR/NAME/MATERIAL/...)")
    parser.add_argument(
        "--quick",
        action="store_true",
        help="coarse meshes (minutes on 2 cores); results go to MATERIAL-quick",
    )
    parser.add_argument(
        "--material",
        default=None,
        help="silicone of the ePSA body, the feet's rubber or the robot's silicone, by study (default: "
        f"{_material_defaults()}; the other studies take none); see `softcrawl material list`",
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
        default=None,
        default_text="1",
        minimum=1,
        maximum=MAX_WORKERS,
        integer=True,
    )
    add_number(
        parser,
        "--max-memory",
        help="resident memory per worker; a point above it is a failed result 'out of memory at N GB' and "
        "the sweep goes on (the tables' peak_rss_gb column shows each point's peak)",
        unit="GB",
        default_text="no limit",
        minimum=0.0,
        min_open=True,
        maximum=MAX_MEMORY_GB,
        metavar="GB",
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
        help="optimise-actuator and optimise-feet: total trials",
        default_text=f"{DEFAULT_TRIALS} and {FEET_TRIALS}, --quick {QUICK_TRIALS} and {FEET_QUICK_TRIALS}",
        minimum=1,
        maximum=MAX_TRIALS,
        integer=True,
    )
    parser.add_argument(
        "--sampler",
        default=None,
        choices=("nsga2", "tpe"),
        help="optimise-actuator, optimise-feet: optuna sampler (default nsga2)",
    )
    add_number(
        parser,
        "--seed",
        help="optimise-actuator, optimise-feet: sampler seed",
        default=None,
        default_text="0",
        minimum=0,
        maximum=MAX_SEED,
        integer=True,
    )

    add_number(
        parser,
        "--confirm",
        help="optimise-feet: crawl the N best designs at 70 mm (2 cycles, quick feet) after the search",
        default=None,
        default_text="none",
        minimum=1,
        maximum=MAX_CONFIRM,
        integer=True,
        metavar="N",
    )
    add_number(
        parser,
        "--wedge",
        help="crawl, feet, optimise-feet: model one wedge of 360/N deg of the feet, tied cyclically "
        "(docs/decisions/082-crawl-wedge.md)",
        default=None,
        default_text="1, the whole feet",
        minimum=1,
        maximum=48,
        integer=True,
        metavar="N",
    )


def _check(args) -> None:
    """Every option checked before the sweep starts: a bad one is one line and exit code 2, not a
    sweep in which every point fails."""
    from softcrawl.geometry.design import EPSADesign
    from softcrawl.studies.commands.options import body_material, output_folder
    from softcrawl.studies.epsa.model import resolve_mesh
    from softcrawl.studies.sweeps.memory import available as memory_available
    from softcrawl.studies.sweeps.spec import StudyError

    study = registry.get(args.name)
    _applies(args, study)
    registry.refuse_material(study, args.material)
    args.workers = 1 if args.workers is None else args.workers
    args.sampler = args.sampler or "nsga2"
    args.seed = 0 if args.seed is None else args.seed
    if args.material is None:
        args.material = study.default_material or "ecoflex-00-50"
    body_material(args.material)  # MaterialError (parameter "material") for an unknown name
    if args.workers < 1:
        raise StudyError("workers", f"must be >= 1, got {args.workers}")
    if args.max_memory is not None and not memory_available():
        raise StudyError("max-memory", "needs /proc/self/status to measure the resident memory (Linux)")
    if args.mesh_size is not None:
        for radius in (2.0, 3.0):  # the thickest wall of the grids needs the most cells
            resolve_mesh(EPSADesign(chamber_radius=radius), mesh_size=args.mesh_size)
    if args.trials is not None and args.trials < 1:
        raise StudyError("trials", f"must be >= 1, got {args.trials}")
    if args.simulator is not None:
        _check_simulator(args.simulator, study)
    if args.storage is not None and "://" not in args.storage:
        raise StudyError(
            "storage",
            f"expected a database URL such as sqlite:///PATH or "
            f"postgresql://USER@HOST/DB, got {args.storage!r}",
        )
    output_folder(args.out)
    if study.check is not None:
        resolve(study.check)(_request(args))


#: Option of `studies.declaration.OPTIONS` -> the value that means "not given" (argparse's default).
_NOT_GIVEN = {"retry_failed": False}


def _applies(args: argparse.Namespace, study) -> None:
    """An option the study does not take (its declaration's `Study.options`) is an error naming
    it: silently ignoring it would let a user believe, say, that --trials shortened a grid study."""
    from softcrawl.studies.declaration import OPTIONS
    from softcrawl.studies.sweeps.spec import StudyError

    for name in sorted(OPTIONS):
        value = getattr(args, name, None)
        if name not in study.options and value != _NOT_GIVEN.get(name) and value is not None:
            flag = "--" + name.replace("_", "-")
            takes = ", ".join("--" + o.replace("_", "-") for o in sorted(study.options)) or "none"
            raise StudyError(
                name.replace("_", "-"), f"{flag} does not apply to study {study.name} (its options: {takes})"
            )


def _request(args: argparse.Namespace) -> StudyRequest:
    return StudyRequest(
        study=args.name,
        out=args.out,
        quick=args.quick,
        material=args.material,
        storage=args.storage,
        workers=args.workers,
        progress=not args.no_progress and console.LEVEL >= 0,
        retry=args.retry_failed,
        mesh_size=args.mesh_size,
        fibers=args.fibers,
        trials=args.trials,
        sampler=args.sampler,
        seed=args.seed,
        simulator=args.simulator,
        max_memory_gb=args.max_memory,
        confirm=args.confirm,
        wedge=args.wedge,
    )


#: How the evaluators call a --simulator: the robot studies' `run_cases(design, material, mesh,
#: cases)`, the ePSA studies' `simulate_epsa(design, *, material, pressures_kpa, mesh_size, quick)`
#: (the identify study adds end_load_n), optimise-feet's `simulate_foot(design, pipe_diameter, *,
#: material, mu_smooth, mu_grooved, quick, max_wall_s)`.
_ROBOT_CALL = ((None, None, None, None), {})
_EPSA_CALL = ((None,), {"material": None, "pressures_kpa": (), "mesh_size": None, "quick": False})
_FOOT_CALL = ((None, 70.0), {"material": None, "mu_smooth": 0.3, "mu_grooved": 0.3, "quick": False,
                             "max_wall_s": None})  # fmt: skip


def _simulator_call(study) -> tuple[tuple, dict]:
    if "robot" in study.evaluators:
        return _ROBOT_CALL
    if "optimise-feet" in study.evaluators:
        return _FOOT_CALL
    args, kwargs = _EPSA_CALL
    return args, kwargs | ({"end_load_n": 0.0} if study.name == "identify" else {})


def _check_simulator(ref: str, study) -> None:
    """MODULE:FUNCTION must import, name a callable, and accept the call the study's evaluator
    makes (probed with `inspect.signature`): otherwise every point would fail and the study would
    end as if it had run."""
    import inspect

    from softcrawl.checks import brief
    from softcrawl.studies.sweeps.spec import StudyError, load_callable

    if ":" not in ref:
        raise StudyError("simulator", f"expected MODULE:FUNCTION, got {brief(ref)}")
    try:
        function = load_callable(ref, parameter="simulator")
    except StudyError as exc:
        if "is not callable" in exc.detail:
            raise StudyError("simulator", f"{brief(ref)} is not a function") from None
        cause = exc.__cause__
        why = f"{type(cause).__name__}: {cause}" if cause is not None else exc.detail
        raise StudyError("simulator", f"cannot load {brief(ref)}: {why}") from None
    args, kwargs = _simulator_call(study)
    try:
        signature = inspect.signature(function)
    except (TypeError, ValueError):
        return  # a builtin without a signature: nothing to probe
    try:
        signature.bind(*args, **kwargs)
    except TypeError as exc:
        shape = ", ".join(["design", *("material", "mesh", "cases")[: len(args) - 1], *kwargs])
        raise StudyError(
            "simulator",
            f"{brief(ref)}{signature} cannot be called as study {study.name} calls it ({shape}): {exc}",
        ) from None


def run(args: argparse.Namespace) -> int:
    from softcrawl.studies.sweeps.faults import SweepStopped, machine_fault
    from softcrawl.studies.sweeps.memory import worker_memory_limit

    _check(args)
    try:
        with worker_memory_limit(args.max_memory):
            outcome = resolve(registry.get(args.name).run)(_request(args))
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
