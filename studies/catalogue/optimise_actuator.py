"""The actuator optimiser: NSGA-II (or TPE) over the chamber radius and the winding turns.

Search space r in [2, 6] mm and N in 0..50; three objectives at 100 kPa: maximise the extension,
minimise the radius change |dR| (the radius should stay at its design value: fibered designs
shrink slightly, and a plain "minimise dR" would reward shrinking), and minimise the Kevlar thread
length of the double helix (the fabrication cost: winding is done by hand, turn by turn, so thread
length ~ winding work; the body mass depends on r only and is reported as ``mass_g``). The Table 1
design (r = 3, N = 20) is evaluated first and marked. Outputs: trials.csv, pareto.csv, pareto.png.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl import jsonio
from studies.catalogue.actuator_studies import run_tag, study_folder
from studies.catalogue.outcome import StudyOutcome

#: Search space and budget of optimise-actuator.
SPACE = {"chamber_radius": ("float", 2.0, 6.0), "fiber_turns": ("int", 0, 50)}
TABLE1_DESIGN = {"chamber_radius": 3.0, "fiber_turns": 20}
OBJECTIVES = ("extension_mm", "radius_change_mm", "fiber_length_mm")
DIRECTIONS = ("maximize", "minimize", "minimize")
DEFAULT_TRIALS, QUICK_TRIALS = 60, 20
NAME = "optimise-actuator"


def draw_pareto(settings: dict, rows, folder) -> Path:
    """pareto.png of the trials (live, or read back from trials.csv by `softcrawl replot`)."""
    from studies.plots.labels import study_title
    from studies.plots.pareto import plot_pareto

    title = study_title(NAME, settings.get("material"), bool(settings.get("quick")))
    return plot_pareto(rows, Path(folder) / "pareto.png", reference=TABLE1_DESIGN, title=title)


def run_optimiser(
    out,
    settings: dict,
    *,
    trials: int | None = None,
    sampler: str = "nsga2",
    seed: int = 0,
    storage: str | None = None,
    workers: int = 1,
    progress: bool = True,
) -> StudyOutcome:
    """Run (or resume) the optimiser and write trials.csv, pareto.csv and pareto.png."""
    from studies.catalogue.epsa_evaluator import EPSA_EVALUATOR, SEARCH_METRICS
    from studies.sweeps.search import run_search
    from studies.sweeps.spec import SearchSpec
    from studies.sweeps.tables import write_csv

    material, quick = settings["material"], settings.get("quick", False)
    folder = study_folder(out, NAME, material, quick, settings.get("mesh_size"))
    folder.mkdir(parents=True, exist_ok=True)
    settings = settings | {"objectives": "pareto"}
    trials = trials or (QUICK_TRIALS if quick else DEFAULT_TRIALS)
    tag = run_tag(material, quick, settings.get("mesh_size"))
    spec = SearchSpec(
        name=f"{NAME}-{tag}",
        space=SPACE,
        out_dir=str(folder),
        n_trials=trials,
        directions=DIRECTIONS,
        evaluator=EPSA_EVALUATOR,
        sampler=sampler,
        seed=seed,
        fixed={},
        settings=settings,
        storage=storage,
        initial=(TABLE1_DESIGN,),
        objective_names=OBJECTIVES,
        metric_columns=SEARCH_METRICS,
    )
    jsonio.write(folder / "spec.json", spec.to_dict())
    rows = run_search(spec, workers=workers, progress=progress)
    write_csv(rows, folder / "trials.csv")
    write_csv([r for r in rows if r["pareto"]], folder / "pareto.csv")
    draw_pareto(settings, rows, folder)
    n_ok = sum(r["trial_status"] == "completed" for r in rows)
    n_pareto = sum(bool(r["pareto"]) for r in rows)
    lines = [
        f"optimise-actuator: {len(rows)} trials, {n_ok} completed, {len(rows) - n_ok} failed, "
        f"{n_pareto} Pareto-optimal"
    ]
    table1 = [r for r in rows if r.get("initial")]
    if table1:
        t = table1[0]
        verdict = (
            ", Pareto-optimal"
            if t["pareto"]
            else ", dominated"
            if t["trial_status"] == "completed"
            else f" ({t['reason']})"
        )
        lines.append(f"  Table 1 design (r = 3, N = 20): {t['trial_status']}{verdict}")
    written = (folder / "trials.csv", folder / "pareto.csv", folder / "pareto.png")
    return StudyOutcome(tuple(lines), written, True)
