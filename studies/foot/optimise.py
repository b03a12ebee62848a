r"""`softcrawl study optimise-feet`: a foot that anchors and slides in every pipe, and is light.

A resumable two-objective optuna search (NSGA-II by default; `studies.sweeps.search`):

    maximise  the worst-case anchoring margin over the pipes (`studies.foot.anchoring`: Fig. 4's
              two inequalities against the bundle's forces of record 062, from one insertion and
              a forward and a backward drag per pipe, `studies.foot.optimise_evaluator`)
    minimise  the foot's mass (g): the revolved volume x 1.15 g/cm^3

over the design variables (`SPACE`), with their sources:

  angle            30-120 deg   the range of paper Fig. 21 (every angle builds, record 066);
  skirt_thickness  1.5-3.5 mm   lower: the 1 mm groove (Table 1's h) plus `MIN_LIGAMENT` (0.5 mm)
                                of skirt behind it, the foot's own design rule (a 1.5 mm wall is
                                printable in rubber-like photopolymer and by FFF with a 0.4 mm
                                nozzle); upper: the 3.5 mm between the hub rim (24 mm) and the
                                wall of the 55 mm pipe (27.5 mm) that a skirt folded against that
                                wall lies in (record 066); the paper's foot has 3 mm;
  hardness         rubber-50a / rubber-60a / rubber-70a: Fig. 21's range, moduli from Gent's
                                Shore-A relation (`softcrawl.materials`, record 001), not fitted.

The feet's rubber is therefore a design variable, not an input: `softcrawl study optimise-feet`
refuses --material (exit 2, one line naming it), as every study declared with no default material
does (`studies.commands.study`); before, the option was accepted and silently ignored.

The tip stays at 39 mm (the prototype's 78 mm maximum: every foot of Fig. 21 reached the 70 mm
wall, record 066). The friction coefficients are the identified ones
(`studies.foot.identify.study_friction(OUT)`: OUT/identify/feet/feet.json), flagged in every
output: today both are the sourced range's lower end, 0.3, because the measurement lies outside
the range (record 070). They were identified on the Shore-70A feet (rubber-70a) and are applied
unchanged to the 50A and 60A designs: a stated assumption, not a measurement. Pipes: 55, 60, 65,
70 and 75 mm (`softcrawl.paper.PIPE_DIAMETERS_MM`); --quick: 55 and 75 mm only (the extremes,
where the slide and the hold inequalities are tightest) on the quick foot mesh
(`studies.foot.simulate`: 24+ sectors, 2 mm drags).

The paper's foot (120 deg, 3 mm, 70A) is enqueued as the first trial. Outputs in
DIR/optimise-feet/rubber[-quick][-wedgeN]/: spec.json, trials.csv (one row per trial: status and failure
reason, both objectives, the forces per pipe), pareto.png (`studies.foot.optimise_plot`),
summary.md (the front, the paper's foot against it, the flags), study.db without --storage.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl import jsonio
from softcrawl.paper import PIPE_DIAMETERS_MM
from softcrawl.studies.declaration import StudyRequest, resolve
from softcrawl.studies.foot.identify import study_friction
from softcrawl.studies.foot.model import FOOT_MAX_WALL_S
from softcrawl.studies.foot.optimise_evaluator import metric_columns
from softcrawl.studies.foot.optimise_plot import front, plot_front
from softcrawl.studies.foot.study import FEET_QUICK_TRIALS, FEET_TRIALS
from softcrawl.studies.html import esc, figure, markdown
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.plots.style import number
from softcrawl.studies.sweeps.search import run_search
from softcrawl.studies.sweeps.spec import SearchSpec, StudyError, read_spec
from softcrawl.studies.sweeps.tables import read_csv, write_csv

NAME = "optimise-feet"
#: The confirm stage (`--confirm N`), by name: it crawls, and the crawl imports the foot's modules,
#: so an import from here would close a cycle between the two features.
CONFIRM = "softcrawl.studies.crawl.confirm_feet:confirm_best"
EVALUATOR = "optimise-feet"  # its registry name (studies/foot/study.py)
HARDNESS = ("rubber-50a", "rubber-60a", "rubber-70a")
SPACE = {
    "angle": ("float", 30.0, 120.0),
    "skirt_thickness": ("float", 1.5, 3.5),
    "hardness": ("categorical", HARDNESS),
}
PAPER_FOOT = {"angle": 120.0, "skirt_thickness": 3.0, "hardness": "rubber-70a"}
OBJECTIVES = ("margin", "mass_g")
DIRECTIONS = ("maximize", "minimize")
QUICK_PIPES = (55.0, 75.0)
#: Wall-time budget of one pipe (s): four times the foot's own (`FOOT_MAX_WALL_S`). Twice it
#: (1800 s) stopped a 57.6 deg quick design in its 55 mm backward drag at a load of 10-13 on two
#: cores (record 072); the budget ends a stalled drag, it must not end a slow machine's.
MAX_WALL_S = 4.0 * FOOT_MAX_WALL_S


def folder_of(out, quick: bool, wedge: int = 1) -> Path:
    """OUT/optimise-feet/rubber[-quick][-wedgeN] (a wedge of the foot: `studies.foot.wedge`)."""
    return (
        Path(out) / NAME / ("rubber" + ("-quick" if quick else "") + (f"-wedge{wedge}" if wedge > 1 else ""))
    )


def identified_mu(out) -> dict:
    """mu_smooth, mu_grooved and their flags from OUT/identify/feet/feet.json."""
    friction = study_friction(out)
    return {k: friction[k] for k in ("mu_smooth", "mu_grooved", "mu_smooth_flag", "mu_grooved_flag")}


def _stored_trials(folder: Path) -> int | None:
    """The trial budget of the search already in `folder` (its spec.json), or None. A resume or a
    `--confirm N` without --trials keeps it: the default (40) once silently extended a finished
    20-trial search by 20 more trials when only its confirm crawls were asked for."""
    if not (folder / "spec.json").is_file():
        return None
    try:
        return int(read_spec(folder)["n_trials"])
    except (ValueError, KeyError, TypeError):
        return None


def search_spec(
    out, *, quick=False, trials=None, sampler="nsga2", seed=0, storage=None, simulator=None, wedge=1
):
    folder = folder_of(out, quick, wedge)
    pipes = QUICK_PIPES if quick else tuple(float(d) for d in PIPE_DIAMETERS_MM)
    settings = {"pipes": list(pipes), "quick": bool(quick), "max_wall_s": MAX_WALL_S} | identified_mu(out)
    settings |= {"copies": int(wedge)} if wedge > 1 else {}
    if simulator:
        settings["simulator"] = simulator
    return SearchSpec(
        name=f"{NAME}-{folder.name}",
        space=SPACE,
        out_dir=str(folder),
        n_trials=trials or _stored_trials(folder) or (FEET_QUICK_TRIALS if quick else FEET_TRIALS),
        directions=DIRECTIONS,
        evaluator=EVALUATOR,
        sampler=sampler,
        seed=seed,
        settings=settings,
        storage=storage,
        initial=(PAPER_FOOT,),
        objective_names=OBJECTIVES,
        metric_columns=metric_columns(pipes),
    )


def mark_front(rows: list[dict]) -> list[dict]:
    """The "front" column: completed trials that no other completed trial dominates (as heavy or
    lighter and at least as large a margin); recomputed from the table, so a replot agrees."""
    done = [r for r in rows if r.get("trial_status") == "completed" and number(r.get("margin")) is not None]
    best = set(front([(number(r["mass_g"]), number(r["margin"])) for r in done]))
    for r in rows:
        r["front"] = r in done and (number(r["mass_g"]), number(r["margin"])) in best
    return rows


def _design(r: dict) -> str:
    return f"{float(r['angle']):.1f} deg, {float(r['skirt_thickness']):.2f} mm, {r['hardness']}"


def summary_lines(rows: list[dict], settings: dict) -> list[str]:
    """summary.md: the flags, the front (best margin first), the paper's foot against it."""
    pipes = ", ".join(f"{float(d):g}" for d in settings.get("pipes", ()))
    done = [r for r in rows if r["trial_status"] == "completed"]
    lines = [
        f"# {NAME}" + (" (quick)" if settings.get("quick") else ""),
        "",
        f"Pipes {pipes} mm. Friction: mu_smooth = {settings.get('mu_smooth')} "
        f"({settings.get('mu_smooth_flag')}), mu_grooved = {settings.get('mu_grooved')} "
        f"({settings.get('mu_grooved_flag')}).",
        f"{len(rows)} trials: {len(done)} completed, {len(rows) - len(done)} failed. Margin > 0: "
        "in every pipe the foot holds the bundle's 24.39 N backward and slides forward below 15.19 N.",
        "",
        "| design (angle, skirt, hardness) | margin | decided by | mass (g) | front |",
        "|---|---|---|---|---|",
    ]
    for r in sorted(done, key=lambda r: -float(r["margin"])):
        decided = f"{r.get('deciding_inequality', '')} at {number(r.get('deciding_pipe_mm')) or 0:g} mm"
        star = " (the paper's foot)" if str(r.get("initial")) == "True" else ""
        lines.append(
            f"| {_design(r)}{star} | {float(r['margin']):+.3f} | {decided} | {float(r['mass_g']):.2f} | "
            f"{'yes' if str(r['front']) == 'True' else ''} |"
        )
    for r in rows:
        if r["trial_status"] != "completed":
            lines.append(f"| {_design(r)} | failed | {r.get('reason', '')} | | |")
    paper = [r for r in rows if str(r.get("initial")) == "True"]
    lines.append("")
    if not paper or paper[0]["trial_status"] != "completed":
        lines.append("The paper's foot: " + (paper[0].get("reason", "failed") if paper else "not evaluated"))
    else:
        p = paper[0]
        better = [
            r
            for r in done
            if float(r["margin"]) > float(p["margin"]) and float(r["mass_g"]) <= float(p["mass_g"])
        ]
        lines.append(
            f"The paper's foot: margin {float(p['margin']):+.3f}, {float(p['mass_g']):.2f} g; "
            + ("on the front." if str(p["front"]) == "True" else f"dominated by {len(better)} trial(s) "
               "with a larger margin at no more mass.")
        )  # fmt: skip
    return lines


def write_outputs(spec_settings: dict, rows: list[dict], folder: Path) -> tuple[Path, ...]:
    rows = mark_front(rows)
    write_csv(rows, folder / "trials.csv")
    (folder / "summary.md").write_text("\n".join(summary_lines(rows, spec_settings)) + "\n")
    plot_front(rows, folder / "pareto.png", title=_title(spec_settings))
    return folder / "trials.csv", folder / "summary.md", folder / "pareto.png"


def _title(settings: dict) -> str:
    quick = ", quick mesh" if settings.get("quick") else ""
    return f"optimise-feet: margin against mass, mu {settings.get('mu_smooth')} (flagged){quick}"


def run_optimise_feet(out, *, quick=False, trials=None, sampler="nsga2", seed=0, storage=None,
                      workers=1, progress=True, simulator=None, wedge=1) -> StudyOutcome:  # fmt: skip
    spec = search_spec(
        out, quick=quick, trials=trials, sampler=sampler, seed=seed, storage=storage, simulator=simulator,
        wedge=wedge,
    )  # fmt: skip
    folder = Path(spec.out_dir)
    folder.mkdir(parents=True, exist_ok=True)
    jsonio.write(folder / "spec.json", spec.to_dict())
    rows = run_search(spec, workers=workers, progress=progress)
    written = write_outputs(dict(spec.settings), rows, folder)
    text = summary_lines(mark_front(rows), dict(spec.settings))
    return StudyOutcome((text[3], text[-1]), written, True)


def check_request(request: StudyRequest) -> None:
    """Before any work: the identification the run reads exists; a wedge leaves 2 sectors."""
    if (request.wedge or 1) > 12:
        raise StudyError(
            "wedge", f"at most 12 (the quick foot's 24 sectors in wedges of 2), got {request.wedge}"
        )
    identified_mu(request.out)


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study optimise-feet` (the registry's entry point)."""
    outcome = run_optimise_feet(
        request.out,
        quick=request.quick,
        trials=request.trials,
        sampler=request.sampler,
        seed=request.seed,
        storage=request.storage,
        workers=request.workers,
        progress=request.progress,
        simulator=request.simulator,
        wedge=request.wedge or 1,
    )
    if not request.confirm:
        return outcome
    folder = folder_of(request.out, request.quick, request.wedge or 1)
    settings = read_spec(folder)["settings"]
    rows = resolve(CONFIRM)(folder, read_csv(folder / "trials.csv"), settings, request.confirm)
    done = sum(r.get("converged") is True for r in rows)
    line = f"confirm: {len(rows)} designs crawled at 70 mm, {done} completed (confirm.md)"
    written = (*outcome.written, folder / "confirm.csv", folder / "confirm.md")
    return StudyOutcome((*outcome.lines, line), written, outcome.ok, outcome.problems)


def replot_folder(folder: Path) -> list[Path]:
    """pareto.png and summary.md of a run from its spec.json and trials.csv."""
    folder = Path(folder)
    if not (folder / "trials.csv").exists():
        return []
    rows = read_csv(folder / "trials.csv")
    settings = read_spec(folder).get("settings", {})
    plot_front(mark_front(rows), folder / "pareto.png", title=_title(settings))
    return [folder / "pareto.png"]


def report_block(folder: Path) -> str:
    """The run's block in the design review (`softcrawl report`): command, figure, summary.md and
    the confirm crawls' confirm.md where they were run."""
    folder = Path(folder)
    settings = read_spec(folder).get("settings", {})
    copies = int(settings.get("copies") or 1)
    command = (
        f"softcrawl study {NAME}"
        + (" --quick" if settings.get("quick") else "")
        + (f" --wedge {copies}" if copies > 1 else "")
        + " --workers 2 --out results/"
    )
    body = [f"<h3>{esc(NAME)}: {esc(folder.name)}</h3>", f"<p>Command: <code>{esc(command)}</code></p>"]
    if (folder / "pareto.png").exists():
        body.append(figure(folder / "pareto.png", f"{NAME}/{folder.name}/pareto.png"))
    for name in ("summary.md", "confirm.md"):
        if (folder / name).exists():
            body.append(markdown((folder / name).read_text()))
    return "".join(body)
