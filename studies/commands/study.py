"""`softcrawl study NAME`: the paper's ePSA finite element studies as resumable optuna studies.

    softcrawl study chamber-radius    [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study fiber-turns       [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study identify          [--quick] [--material M] [--storage URL] [--workers N] --out DIR
    softcrawl study optimise-actuator [--quick] [--material M] [--storage URL] [--workers N]
                                      [--trials T] [--sampler nsga2|tpe] [--seed S] --out DIR

chamber-radius (paper Fig. 8): no fibers, r = 2, 3, 4, 5, 6 mm. fiber-turns (Fig. 9): r = 3 mm,
N = 0, 10, 20, 25, 50. Both at 20, 40, 60, 80, 100 kPa. identify (Section VII-A): the Table 1
ePSA under weights W = 0, 0.5, 1 N on its guided top at 10-100 kPa; k_p(P) and f_p(P) fitted as the
paper does and compared with eqs. 19-24 (studies/catalogue/fe_identification.py). optimise-actuator: NSGA-II (or TPE) over
r in [2, 6] mm and N in 0..50 for three objectives at 100 kPa: maximise extension, minimise the radius
change |dR| (the radius should stay at its design value: fibered designs shrink slightly, and a
plain "minimise dR" would reward shrinking), minimise the Kevlar thread length of the double helix (the fabrication cost: winding is
done by hand, turn by turn, so thread length ~ winding work; the body mass depends on r only and is
reported as ``mass_g``). The Table 1 design (r = 3, N = 20) is evaluated first and marked.

Results go to DIR/NAME/MATERIAL/ (MATERIAL-quick with --quick, -hSIZE with --mesh-size): curves.csv (every grid point and
pressure, with trial and row status and the failure reason), summary.csv (one row per design),
NAME.png, vtu/ (the last computed shape of each design, when the evaluator can return its model),
spec.json and, without --storage, the SQLite study study.db. Running the same command
again resumes: only missing points are computed. --storage postgresql://... lets workers on several
machines share one study (start the same command on each).
"""
from __future__ import annotations

import argparse
import sys

from studies.catalogue.epsa_evaluator import PAPER_PRESSURES_KPA
from studies.catalogue.fe_identification import LOADS_N, PRESSURES_KPA

STUDIES = ("chamber-radius", "fiber-turns", "identify", "optimise-actuator")
#: Grids of the paper's sweeps (Section V-A) and the fixed parameters of each.
GRIDS = {
    "chamber-radius": ({"chamber_radius": (2.0, 3.0, 4.0, 5.0, 6.0)}, {"fiber_turns": 0}),
    "fiber-turns": ({"fiber_turns": (0, 10, 20, 25, 50)}, {"chamber_radius": 3.0}),
    "identify": ({"end_load_n": LOADS_N}, {}),                # the Table 1 ePSA under weights
}
#: Search space and budget of optimise-actuator.
SPACE = {"chamber_radius": ("float", 2.0, 6.0), "fiber_turns": ("int", 0, 50)}
TABLE1_DESIGN = {"chamber_radius": 3.0, "fiber_turns": 20}
OBJECTIVES = ("extension_mm", "radius_change_mm", "fiber_length_mm")
DIRECTIONS = ("maximize", "minimize", "minimize")
DEFAULT_TRIALS, QUICK_TRIALS = 60, 20
DEFAULT_MATERIAL = "ecoflex-00-50"


def register(subparsers) -> None:
    from studies.parts.epsa_model import FIBER_MODELS

    parser = subparsers.add_parser("study", help="ePSA finite element studies (sweeps, optimiser)",
                                   description=__doc__.splitlines()[0],
                                   formatter_class=argparse.RawDescriptionHelpFormatter,
                                   epilog="\n".join(__doc__.splitlines()[1:]))
    parser.add_argument("name", choices=STUDIES, help="which study")
    parser.add_argument("--out", required=True, help="results folder (DIR/NAME/MATERIAL/...)")
    parser.add_argument("--quick", action="store_true",
                        help="coarse meshes (minutes on 2 cores); results go to MATERIAL-quick")
    parser.add_argument("--material", default=DEFAULT_MATERIAL,
                        help=f"silicone of the ePSA body (default {DEFAULT_MATERIAL}; see "
                             "`softcrawl material list`)")
    parser.add_argument("--storage", default=None,
                        help="optuna RDB URL shared by all workers (default: SQLite in the "
                             "output folder)")
    parser.add_argument("--workers", type=int, default=1, help="worker processes (default 1)")
    parser.add_argument("--mesh-size", type=float, default=None, help="element size (mm)")
    parser.add_argument("--fibers", choices=FIBER_MODELS, default=None,
                        help="Kevlar winding model (default: studies.parts.epsa_model.DEFAULT_FIBERS; see softcrawl epsa)")
    parser.add_argument("--trials", type=int, default=None,
                        help=f"optimise-actuator: total trials (default {DEFAULT_TRIALS}, "
                             f"{QUICK_TRIALS} with --quick)")
    parser.add_argument("--sampler", default="nsga2", choices=("nsga2", "tpe"),
                        help="optimise-actuator: optuna sampler (default nsga2)")
    parser.add_argument("--seed", type=int, default=0, help="optimise-actuator: sampler seed")
    parser.add_argument("--simulator", default=None, metavar="MODULE:FUNCTION",
                        help="replace studies.parts.epsa_model:simulate_epsa (same signature), e.g. a "
                             "surrogate or a test fake")
    parser.add_argument("--retry-failed", action="store_true",
                        help="sweeps: evaluate the failed points again (after an evaluator fix); "
                             "otherwise a failed evaluation is a result and is kept")
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.set_defaults(func=run)


def run_tag(material: str, quick: bool, mesh_size: float | None = None) -> str:
    """Folder and study-name suffix of a run: MATERIAL[-quick][-hSIZE]."""
    return material + ("-quick" if quick else "") + (f"-h{mesh_size:g}" if mesh_size else "")


def study_folder(out, name: str, material: str, quick: bool, mesh_size: float | None = None):
    from pathlib import Path

    return Path(out) / name / run_tag(material, quick, mesh_size)


def _settings(args) -> dict:
    from studies.sweeps import engine as runner
    from studies.parts.epsa_model import DEFAULT_FIBERS

    pressures = PRESSURES_KPA if args.name == "identify" else PAPER_PRESSURES_KPA
    settings = {"material": args.material, "quick": bool(args.quick), "pressures_kpa": list(pressures),
                "fibers": args.fibers or DEFAULT_FIBERS}
    if args.mesh_size is not None:
        settings["mesh_size"] = args.mesh_size
    if args.simulator:
        settings["simulate"] = args.simulator
    return settings


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
        raise StudyError("storage", f"expected a database URL such as sqlite:///PATH or "
                                    f"postgresql://USER@HOST/DB, got {args.storage!r}")
    if args.simulator is not None and ":" not in args.simulator:
        raise StudyError("simulator", f"expected MODULE:FUNCTION, got {args.simulator!r}")


def run(args: argparse.Namespace) -> int:
    _check(args)
    if args.name == "optimise-actuator":
        return _run_optimise(args)
    return _run_sweep(args)


def sweep_spec(name: str, out_dir, settings: dict, storage: str | None = None):
    from studies.sweeps.engine import SweepSpec

    grid, fixed = GRIDS[name]
    tag = run_tag(settings.get("material", ""), settings.get("quick", False),
                  settings.get("mesh_size"))
    return SweepSpec(name=f"{name}-{tag}", grid=grid, fixed=fixed, out_dir=str(out_dir),
                     settings=settings, storage=storage)


def _run_sweep(args) -> int:
    import json

    from studies.sweeps import engine as runner

    folder = study_folder(args.out, args.name, args.material, args.quick, args.mesh_size)
    folder.mkdir(parents=True, exist_ok=True)
    spec = sweep_spec(args.name, folder, _settings(args) | {"vtu_dir": str(folder / "vtu")},
                      args.storage)
    (folder / "spec.json").write_text(json.dumps(spec.to_dict(), indent=2) + "\n")
    try:
        rows = runner.run_sweep(spec, workers=args.workers, progress=not args.no_progress,
                                retry=args.retry_failed)
    except runner.SweepInterrupted as exc:
        print(f"softcrawl study {args.name}: interrupted: {exc}", file=sys.stderr)
        return 1
    return write_sweep_outputs(args.name, spec, rows, folder)


def write_identify_outputs(spec, rows, folder) -> int:
    """curves.csv, identify.png (length per weight), identification.csv/.json and
    identification.png (k_p, f_p against eqs. 19-24)."""
    import json

    from studies.sweeps import engine as runner
    from studies.catalogue import fe_identification as identify
    from studies.plots.curves import plot_curves
    from studies.plots.identification import plot_identification

    runner.write_csv(rows, folder / "curves.csv")
    material = spec.settings.get("material")
    quick = " (quick mesh)" if spec.settings.get("quick") else ""
    plot_curves(rows, "end_load_n", folder / "identify.png", label="W", unit=" N",
                      title=f"identify: Table 1 ePSA under weights W; material {material}{quick}")
    ident = identify.identify_from_rows(rows)
    table = identify.comparison_rows(ident)
    laws = identify.fitted_laws(ident) | {"material": material, "quick": bool(spec.settings.get("quick"))}
    (folder / "identification.json").write_text(json.dumps(laws, indent=2) + "\n")
    written = [folder / "curves.csv", folder / "identify.png", folder / "identification.json"]
    for p, why in ident.skipped:
        print(f"  P = {p:g} kPa not used: {why}")
    if not table:
        print(f"identify: no identification: {ident.message}", file=sys.stderr)
        print("wrote " + ", ".join(map(str, written)))
        return 1
    runner.write_csv(table, folder / "identification.csv")
    plot_identification(table, folder / "identification.png",
                              title=f"FE identification (material {material}{quick}) vs the prototype")
    written += [folder / "identification.csv", folder / "identification.png"]
    for name, key in (("k_p (N/m)", "k_p_n_per_m"), ("f_p (N)", "f_p_n")):
        text = "; ".join(f"{b['slope']:.4g} P {'-' if b['intercept'] < 0 else '+'} {abs(b['intercept']):.4g}"
                         + ("" if b["p_max_kpa"] is None else f" (P <= {b['p_max_kpa']:g})")
                         for b in laws[key])
        print(f"identify: FE {name} = {text}")
    if ident.message:
        print(f"identify: {ident.message}")
    print("wrote " + ", ".join(map(str, written)))
    return 0


def write_sweep_outputs(name: str, spec, rows, folder) -> int:
    """curves.csv, summary.csv and the PNG of a finished (or partial) sweep."""
    from studies.sweeps import engine as runner
    from studies.plots.curves import plot_curves
    from studies.review import rules

    if name == "identify":
        return write_identify_outputs(spec, rows, folder)
    param = next(iter(spec.grid))
    runner.write_csv(rows, folder / "curves.csv")
    summary = []
    for value, c in sorted(rules.design_curves(rows, param).items()):
        top = c.at(rules.TARGET_PRESSURE_KPA)
        fluct, how = rules.fluctuation(c) if c.pressures else (False, "no data")
        summary.append({param: value, "trial_status": c.trial_status, "reason": c.reason,
                        "limit_pressure_kpa": "" if c.limit_pressure is None else c.limit_pressure,
                        "reached_kpa": c.reached, "withstands_100kpa": c.withstands,
                        "extension_100kpa_mm": "" if top is None else top[0] - c.length0,
                        "radial_expansion_100kpa_mm": "" if top is None else top[1] - c.radius0,
                        "fluctuating": fluct, "fluctuation": how,
                        "linearity_r2": round(rules.linearity_r2(c), 6) if c.pressures else ""})
    runner.write_csv(summary, folder / "summary.csv")
    label, unit = ("r", " mm") if param == "chamber_radius" else ("N", "")
    fixed = ", ".join(f"{k} = {v:g}" for k, v in spec.fixed.items())
    plot_curves(rows, param, folder / f"{name}.png", label=label, unit=unit,
                      title=f"{name}: {fixed}; material {spec.settings.get('material')}"
                            + (" (quick mesh)" if spec.settings.get("quick") else ""))
    counts = {}
    for s in summary:
        counts[s["trial_status"]] = counts.get(s["trial_status"], 0) + 1
    print(f"{name}: {len(summary)} designs: " + ", ".join(f"{v} {k}" for k, v in counts.items()))
    for s in summary:
        if s["trial_status"] != "completed":
            print(f"  {param} = {s[param]:g}: {s['trial_status']} {s['reason']}")
    print(f"wrote {folder / 'curves.csv'}, {folder / 'summary.csv'}, {folder / (name + '.png')}")
    return 0 if all(s["trial_status"] in ("completed", "failed") for s in summary) else 1


def _run_optimise(args) -> int:
    import json

    from studies.sweeps import engine as runner
    from studies.plots.pareto import plot_pareto

    folder = study_folder(args.out, args.name, args.material, args.quick, args.mesh_size)
    folder.mkdir(parents=True, exist_ok=True)
    settings = _settings(args) | {"objectives": "pareto", "objective_names": list(OBJECTIVES)}
    trials = args.trials or (QUICK_TRIALS if args.quick else DEFAULT_TRIALS)
    tag = run_tag(args.material, args.quick, args.mesh_size)
    spec = runner.SearchSpec(name=f"{args.name}-{tag}", space=SPACE, out_dir=str(folder),
                             n_trials=trials, directions=DIRECTIONS, sampler=args.sampler,
                             seed=args.seed, fixed={}, settings=settings, storage=args.storage,
                             initial=(TABLE1_DESIGN,))
    (folder / "spec.json").write_text(json.dumps(spec.to_dict(), indent=2) + "\n")
    rows = runner.run_search(spec, workers=args.workers, progress=not args.no_progress)
    runner.write_csv(rows, folder / "trials.csv")
    runner.write_csv([r for r in rows if r["pareto"]], folder / "pareto.csv")
    plot_pareto(rows, folder / "pareto.png", reference=TABLE1_DESIGN,
                      title=f"optimise-actuator, material {args.material}"
                            + (" (quick mesh)" if args.quick else ""))
    n_ok = sum(r["trial_status"] == "completed" for r in rows)
    n_pareto = sum(bool(r["pareto"]) for r in rows)
    print(f"optimise-actuator: {len(rows)} trials, {n_ok} completed, {len(rows) - n_ok} failed, "
          f"{n_pareto} Pareto-optimal")
    table1 = [r for r in rows if r.get("initial")]
    if table1:
        t = table1[0]
        print(f"  Table 1 design (r = 3, N = 20): {t['trial_status']}"
              + (", Pareto-optimal" if t["pareto"] else ", dominated" if t["trial_status"] ==
                 "completed" else f" ({t['reason']})"))
    print(f"wrote {folder / 'trials.csv'}, {folder / 'pareto.csv'}, {folder / 'pareto.png'}")
    return 0
