"""The actuator optimiser: the paper's selection as a constrained problem (optuna, TPE or NSGA-II).

Minimise the Kevlar thread length of the double helix (the paper: "Taking the fabrication process
and the weight of the ePSA prototype into consideration"; winding is done by hand, turn by turn,
so thread length ~ winding work and thread weight), over the chamber radius r in {2, ..., 6} mm
(the paper's grid; integer, so each radius has one reference design) and the turns N in 0..50,
subject to (optuna's constraints_func; a value <= 0 is feasible):

(`studies.epsa.constrained_objective`)

1. it withstands the target pressure (100 kPa, `studies.epsa.rules.TARGET_PRESSURE_KPA`): no
   limit point and a computed state there; otherwise (target - reached) / target;
2. the radius stays put: |dR| / R0 - MAX_RADIUS_CHANGE_REL ("the fiber winding wire effectively
   suppresses the radial expansion");
3. the extension differs little from the best: |e - e_ref| / e_ref - SIMILAR_EXTENSION_REL, with
   e_ref the extension of the most-turned design (N = 50) of the same radius, the N rule's
   reference (`studies.epsa.rules`), evaluated once per radius and cached.

A design that does not withstand the target has unknown |dR| and extension: constraints 2 and 3
are then 1 (infeasible). The optimum is the feasible trial with the least thread (ties: smaller
|dR|); it is compared with the Table 1 design in the output. The Table 1 design (r = 3, N = 20)
is evaluated first. Outputs: trials.csv (with the constraints and "feasible"), optimum.json,
pareto.png (extension against |dR|, the optimum outlined).
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl import jsonio
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.epsa.constrained_objective import MAX_RADIUS_CHANGE_REL
from softcrawl.studies.epsa.evaluator import SEARCH_METRICS
from softcrawl.studies.epsa.grid_studies import run_tag, study_folder, study_settings
from softcrawl.studies.epsa.plot_pareto import plot_pareto
from softcrawl.studies.epsa.study import DEFAULT_TRIALS, QUICK_TRIALS
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.plots.labels import study_title
from softcrawl.studies.sweeps.search import run_search
from softcrawl.studies.sweeps.spec import SearchSpec, read_spec
from softcrawl.studies.sweeps.tables import read_csv, write_csv

#: Search space of optimise-actuator (its trial budget is declared in studies/epsa/study.py).
SPACE = {"chamber_radius": ("int", 2, 6), "fiber_turns": ("int", 0, 50)}
TABLE1_DESIGN = {"chamber_radius": 3, "fiber_turns": 20}
OBJECTIVES = ("thread_length_mm",)
DIRECTIONS = ("minimize",)
NAME = "optimise-actuator"
CONSTRAINED_EVALUATOR = "epsa-constrained"  # its registry name (studies/epsa/study.py)


def draw_pareto(settings: dict, rows, folder) -> Path:
    """pareto.png of the trials (live, or read back from trials.csv by `softcrawl replot`)."""
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
    """Run (or resume) the optimiser and write trials.csv, optimum.json and pareto.png."""
    material, quick = settings["material"], settings.get("quick", False)
    folder = study_folder(out, NAME, material, quick, settings.get("mesh_size"))
    folder.mkdir(parents=True, exist_ok=True)
    settings = settings | {"objective_names": list(OBJECTIVES)}
    trials = trials or (QUICK_TRIALS if quick else DEFAULT_TRIALS)
    tag = run_tag(material, quick, settings.get("mesh_size"))
    spec = SearchSpec(
        name=f"{NAME}-{tag}",
        space=SPACE,
        out_dir=str(folder),
        n_trials=trials,
        directions=DIRECTIONS,
        sampler=sampler,
        seed=seed,
        fixed={},
        settings=settings,
        storage=storage,
        initial=(TABLE1_DESIGN,),
        evaluator=CONSTRAINED_EVALUATOR,
        objective_names=OBJECTIVES,
        metric_columns=SEARCH_METRICS,
    )
    jsonio.write(folder / "spec.json", spec.to_dict())
    rows = mark_optimum(run_search(spec, workers=workers, progress=progress))
    write_csv(rows, folder / "trials.csv")
    best = [r for r in rows if r["pareto"]]
    jsonio.write(folder / "optimum.json", optimum_record(best, material))
    draw_pareto(settings, rows, folder)
    n_ok = sum(r["trial_status"] == "completed" for r in rows)
    n_feasible = sum(bool(r["feasible"]) for r in rows)
    lines = [
        f"optimise-actuator: {len(rows)} trials, {n_ok} completed, {len(rows) - n_ok} failed, "
        f"{n_feasible} feasible; " + optimum_record(best, material)["verdict"]
    ]
    table1 = [r for r in rows if r.get("initial")]
    if table1:
        t = table1[0]
        verdict = (
            ", the optimum"
            if t["pareto"]
            else ", feasible"
            if t["feasible"]
            else f", infeasible (constraints {t.get('constraints', '')})"
            if t["trial_status"] == "completed"
            else f" ({t['reason']})"
        )
        lines.append(f"  Table 1 design (r = 3, N = 20): {t['trial_status']}{verdict}")
    written = (folder / "trials.csv", folder / "optimum.json", folder / "pareto.png")
    return StudyOutcome(tuple(lines), written, True)


def mark_optimum(rows: list[dict]) -> list[dict]:
    """Flag "feasible" (every constraint <= 0) and the optimum ("pareto" column, for the plot):
    the least thread among feasible trials, then the smaller |dR|."""
    for r in rows:
        cons = json.loads(r.get("constraints") or "[]")
        r["feasible"] = r["trial_status"] == "completed" and bool(cons) and all(c <= 0.0 for c in cons)
        r["pareto"] = False
    feasible = [r for r in rows if r["feasible"]]
    if feasible:
        best = min(
            feasible, key=lambda r: (float(r["thread_length_mm"]), abs(float(r["radial_expansion_mm"])))
        )
        best["pareto"] = True
    return rows


def optimum_record(best: list[dict], material: str) -> dict:
    """optimum.json: the optimum design and its comparison with Table 1 (r = 3, N = 20)."""
    if not best:
        return {"material": material, "optimum": None, "verdict": "no feasible design found"}
    b = best[0]
    r, n = float(b["chamber_radius"]), int(b["fiber_turns"])
    same = r == TABLE1_DESIGN["chamber_radius"] and n == TABLE1_DESIGN["fiber_turns"]
    return {
        "material": material,
        "optimum": {"chamber_radius": r, "fiber_turns": n, "thread_length_mm": float(b["thread_length_mm"])},
        "extension_mm": b.get("extension_mm"),
        "radial_expansion_mm": b.get("radial_expansion_mm"),
        "constraints": json.loads(b.get("constraints") or "[]"),
        "max_radius_change_rel": MAX_RADIUS_CHANGE_REL,
        "verdict": f"optimum r = {r:g} mm, N = {n}: "
        + ("the paper's Table 1 design" if same else "not the paper's r = 3 mm, N = 20"),
    }


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study optimise-actuator` (the registry's entry point)."""
    settings = study_settings(
        NAME, request.material, request.quick, request.mesh_size, request.fibers, request.simulator
    )
    return run_optimiser(
        request.out,
        settings,
        trials=request.trials,
        sampler=request.sampler,
        seed=request.seed,
        storage=request.storage,
        workers=request.workers,
        progress=request.progress,
    )


def replot_folder(folder: Path) -> list[Path]:
    """pareto.png of an optimiser run from its spec.json and trials.csv."""
    if not (folder / "trials.csv").exists():
        return []
    return [draw_pareto(read_spec(folder).get("settings", {}), read_csv(folder / "trials.csv"), folder)]
