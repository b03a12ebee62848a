"""The actuator optimiser: the paper's selection as a constrained problem (optuna, TPE or NSGA-II).

Minimise the Kevlar thread length of the double helix (the paper: "Taking the fabrication process
and the weight of the ePSA prototype into consideration"; winding is done by hand, turn by turn,
so thread length ~ winding work and thread weight), over the chamber radius r in {2, ..., 6} mm
(the paper's grid; integer, so each radius has one reference design) and the turns N in 0..50,
subject to (optuna's constraints_func; a value <= 0 is feasible):

1. it withstands the target pressure (100 kPa, `studies.review.rules.TARGET_PRESSURE_KPA`): no
   limit point and a computed state there; otherwise (target - reached) / target;
2. the radius stays put: |dR| / R0 - MAX_RADIUS_CHANGE_REL ("the fiber winding wire effectively
   suppresses the radial expansion");
3. the extension differs little from the best: |e - e_ref| / e_ref - SIMILAR_EXTENSION_REL, with
   e_ref the extension of the most-turned design (N = 50) of the same radius, the N rule's
   reference (`studies.review.rules`), evaluated once per radius and cached.

A design that does not withstand the target has unknown |dR| and extension: constraints 2 and 3
are then 1 (infeasible). The optimum is the feasible trial with the least thread (ties: smaller
|dR|); it is compared with the Table 1 design in the output. The Table 1 design (r = 3, N = 20)
is evaluated first. Outputs: trials.csv (with the constraints and "feasible"), optimum.json,
pareto.png (extension against |dR|, the optimum outlined).
"""

from __future__ import annotations

import functools
import json

from studies.catalogue.actuator_studies import run_tag, study_folder
from studies.catalogue.outcome import StudyOutcome

#: Search space and budget of optimise-actuator.
SPACE = {"chamber_radius": ("int", 2, 6), "fiber_turns": ("int", 0, 50)}
TABLE1_DESIGN = {"chamber_radius": 3, "fiber_turns": 20}
OBJECTIVES = ("thread_length_mm",)
DIRECTIONS = ("minimize",)
DEFAULT_TRIALS, QUICK_TRIALS = 60, 20
NAME = "optimise-actuator"
#: The most-turned design of the N study (paper Fig. 9: N = 50), the extension reference.
REFERENCE_TURNS = 50
#: Bound on |dR| / R0 at the target pressure: 5 % of the outer radius (0.45 mm for R0 = 9 mm).
#: The paper states no number ("relatively small radial expansion"); a 5 % bulge is what a
#: crawler in a pipe a few mm wider than the robot can afford. Stated, not tuned.
MAX_RADIUS_CHANGE_REL = 0.05


def constrained_evaluation(attrs, design, settings, target, length0, radius0, packed):
    """The `Evaluation` of one trial in "constrained" mode (module docstring)."""
    from studies.catalogue.epsa_evaluator import response_at
    from studies.review.rules import SIMILAR_EXTENSION_REL
    from studies.sweeps.engine import Evaluation

    thread = float(attrs["fiber_length_mm"])
    at = response_at(attrs["rows"], target)
    limit = attrs["limit_pressure_kpa"]
    withstands = bool(attrs["converged"]) and at is not None and (limit is None or limit >= target)
    if not attrs["converged"]:
        return Evaluation(ok=False, attrs=packed(attrs), message=f"diverged: {attrs['message']}")
    if not withstands:
        reached = max(
            [r["pressure_kpa"] for r in attrs["rows"] if r.get("status") == "converged"], default=0.0
        )
        attrs["constraints"] = [max((target - reached) / target, 1e-3), 1.0, 1.0]
        return Evaluation(ok=True, values=(thread,), attrs=packed(attrs))
    ext, dr = at["length_mm"] - length0, abs(at["outer_radius_mm"] - radius0)
    ref = reference_extension(
        design.chamber_radius, settings.get("simulate", ""), json.dumps(settings, sort_keys=True, default=str)
    )
    c_ext = 1.0 if ref is None else abs(ext - ref) / abs(ref) - SIMILAR_EXTENSION_REL
    attrs["constraints"] = [0.0, dr / radius0 - MAX_RADIUS_CHANGE_REL, c_ext]
    attrs["reference_extension_mm"] = ref
    return Evaluation(ok=True, values=(thread,), attrs=packed(attrs))


@functools.lru_cache(maxsize=16)
def reference_extension(chamber_radius: float, simulate: str, settings_json: str) -> float | None:
    """Extension at the target of the REFERENCE_TURNS design of this radius (None if it does
    not withstand the target), with the trial's own simulator and settings."""
    from geometry.design import EPSADesign
    from studies.catalogue.epsa_evaluator import evaluate_epsa

    settings = json.loads(settings_json) | {"objectives": "pareto"}
    params = {"chamber_radius": chamber_radius, "fiber_turns": REFERENCE_TURNS}
    EPSADesign(**params)  # a bad radius raises here, not inside the cache
    result = evaluate_epsa(params, {}, settings)
    return float(result.values[0]) if result.ok else None


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
    from studies.plots.pareto import plot_pareto
    from studies.sweeps import engine

    material, quick = settings["material"], settings.get("quick", False)
    folder = study_folder(out, NAME, material, quick, settings.get("mesh_size"))
    folder.mkdir(parents=True, exist_ok=True)
    settings = settings | {"objectives": "constrained", "objective_names": list(OBJECTIVES)}
    trials = trials or (QUICK_TRIALS if quick else DEFAULT_TRIALS)
    tag = run_tag(material, quick, settings.get("mesh_size"))
    spec = engine.SearchSpec(
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
        constrained=True,
    )
    (folder / "spec.json").write_text(json.dumps(spec.to_dict(), indent=2) + "\n")
    rows = mark_optimum(engine.run_search(spec, workers=workers, progress=progress))
    engine.write_csv(rows, folder / "trials.csv")
    best = [r for r in rows if r["pareto"]]
    (folder / "optimum.json").write_text(json.dumps(optimum_record(best, material), indent=2) + "\n")
    plot_pareto(
        rows,
        folder / "pareto.png",
        reference=TABLE1_DESIGN,
        title=f"optimise-actuator, material {material}" + (" (quick mesh)" if quick else ""),
    )
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
