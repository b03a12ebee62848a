"""The ePSA studies of the paper as sweeps: their grids, settings, folders and output tables.

    chamber-radius (Fig. 8): no fibers, r = 2, 3, 4, 5, 6 mm, at 20-100 kPa in 20 kPa steps
    fiber-turns    (Fig. 9): r = 3 mm, N = 0, 10, 20, 25, 50, same pressures
    identify       (Section VII-A): the Table 1 ePSA under weights W on its guided top at
                   10-100 kPa (`studies.epsa.identification`)

A run writes to DIR/NAME/MATERIAL/ (MATERIAL-quick with --quick, -hSIZE with --mesh-size):
curves.csv (every grid point and pressure, with trial and row status and the failure reason),
summary.csv (one row per design, with the quantities the Table 1 rules use), NAME.png, vtu/ and
spec.json. The sweep itself (resumable, several workers) is `studies.sweeps`.
"""

from __future__ import annotations

from pathlib import Path

from softcrawl import jsonio
from softcrawl.materials import get_material
from softcrawl.paper import TABLE1
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.epsa import identification as fe_identification
from softcrawl.studies.epsa import linearity, rules
from softcrawl.studies.epsa.evaluator import EPSA_EVALUATOR, EPSA_TABLE, PAPER_PRESSURES_KPA
from softcrawl.studies.epsa.identification import LOADS_N, PRESSURES_KPA
from softcrawl.studies.epsa.model import DEFAULT_FIBERS
from softcrawl.studies.epsa.plot_curves import plot_curves
from softcrawl.studies.epsa.rules import TARGET_PRESSURE_KPA
from softcrawl.studies.epsa.sweep_objective import RULE_EVALUATOR, objective_of
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.plots.labels import parameter, study_title
from softcrawl.studies.sweeps.spec import SweepSpec, read_spec
from softcrawl.studies.sweeps.sweep import run_sweep
from softcrawl.studies.sweeps.tables import read_csv, write_csv

#: Grids of the paper's sweeps (Section V-A) and the fixed parameters of each.
GRIDS = {
    "chamber-radius": ({"chamber_radius": (2.0, 3.0, 4.0, 5.0, 6.0)}, {"fiber_turns": 0}),
    "fiber-turns": ({"fiber_turns": (0, 10, 20, 25, 50)}, {"chamber_radius": 3.0}),
    "identify": ({"end_load_n": LOADS_N}, {}),  # the Table 1 ePSA under weights
}
DEFAULT_MATERIAL = "ecoflex-00-50"


def run_tag(material: str, quick: bool, mesh_size: float | None = None) -> str:
    """Folder and study-name suffix of a run: MATERIAL[-quick][-hSIZE]."""
    return material + ("-quick" if quick else "") + (f"-h{mesh_size:g}" if mesh_size else "")


def study_folder(out, name: str, material: str, quick: bool, mesh_size: float | None = None) -> Path:
    return Path(out) / name / run_tag(material, quick, mesh_size)


def study_settings(
    name: str,
    material: str,
    quick: bool,
    mesh_size: float | None = None,
    fibers: str | None = None,
    simulator: str | None = None,
) -> dict:
    """The evaluator settings of a study run (stored with the study: a resume must match)."""
    pressures = PRESSURES_KPA if name == "identify" else PAPER_PRESSURES_KPA
    settings = {
        "material": material,
        "quick": bool(quick),
        "pressures_kpa": list(pressures),
        "fibers": fibers or DEFAULT_FIBERS,
    }
    if mesh_size is not None:
        settings["mesh_size"] = mesh_size
    if simulator:
        settings["simulate"] = simulator
    return settings


def sweep_spec(name: str, out_dir, settings: dict, storage: str | None = None):
    grid, fixed = GRIDS[name]
    tag = run_tag(settings.get("material", ""), settings.get("quick", False), settings.get("mesh_size"))
    objective = objective_of(name)  # what optuna's "best" means for this study, and why
    if objective.constraints:
        settings = settings | {"objective": name}
    if name == "fiber-turns":
        settings = settings | {"reference_turns": max(grid["fiber_turns"])}
    return SweepSpec(
        name=f"{name}-{tag}",
        grid=grid,
        fixed=fixed,
        out_dir=str(out_dir),
        evaluator=RULE_EVALUATOR if objective.constraints else EPSA_EVALUATOR,
        settings=settings,
        storage=storage,
        directions=(objective.direction,),
        metric_names=(objective.metric,),
    )


def run_sweep_study(
    name: str,
    out,
    settings: dict,
    *,
    storage: str | None = None,
    workers: int = 1,
    progress: bool = True,
    retry: bool = False,
) -> StudyOutcome:
    """Run (or resume) the sweep `name` and write its outputs. Raises
    `studies.sweeps.faults.SweepStopped` when the run stopped early (a signal, a full disk)."""
    folder = study_folder(
        out, name, settings["material"], settings.get("quick", False), settings.get("mesh_size")
    )
    folder.mkdir(parents=True, exist_ok=True)
    spec = sweep_spec(name, folder, settings | {"vtu_dir": str(folder / "vtu")}, storage)
    jsonio.write(folder / "spec.json", spec.to_dict())
    rows = run_sweep(spec, layout=EPSA_TABLE, workers=workers, progress=progress, retry=retry)
    return write_sweep_outputs(name, spec, rows, folder)


def _law_label(material) -> str:
    """The material's law and constants (every results row names its law); "" if unknown."""
    try:
        return get_material(str(material)).law_label
    except Exception:  # noqa: BLE001 - a fake material in tests
        return ""


def summary_rows(rows, param: str) -> list[dict]:
    """One row per design: status, limit pressure, the response at 100 kPa and the rule inputs."""
    summary = []
    law = _law_label(rows[0].get("material")) if rows else ""
    for value, c in sorted(rules.design_curves(rows, param).items()):
        top = c.at(rules.TARGET_PRESSURE_KPA)
        fluct, how = rules.fluctuation(c) if c.pressures else (False, "no data")
        summary.append(
            {
                param: value,
                "trial_status": c.trial_status,
                "reason": c.reason,
                "limit_pressure_kpa": "" if c.limit_pressure is None else c.limit_pressure,
                "reached_kpa": c.reached,
                "withstands_100kpa": c.withstands,
                "extension_100kpa_mm": "" if top is None else top[0] - c.length0,
                "radial_expansion_100kpa_mm": "" if top is None else top[1] - c.radius0,
                "fluctuating": fluct,
                "fluctuation": how,
                "nonlinearity": ""
                if linearity.nonlinearity(c) is None
                else round(linearity.nonlinearity(c), 6),
                "material_law": law,
            }
        )
    return summary


def draw_study_figure(name: str, param: str, fixed: dict, settings: dict, rows, folder) -> Path:
    """NAME.png of a sweep from its rows (live, or read back from curves.csv by `softcrawl replot`)."""
    symbol, _, unit = parameter(param)
    title = study_title(name, settings.get("material"), bool(settings.get("quick")), fixed)
    chosen = TABLE1[param][1] if param in TABLE1 else None
    return plot_curves(
        rows,
        param,
        Path(folder) / f"{name}.png",
        label=symbol,
        unit=unit,
        title=title,
        chosen=chosen,
        target_kpa=TARGET_PRESSURE_KPA,
    )


def write_sweep_outputs(name: str, spec, rows, folder) -> StudyOutcome:
    """curves.csv, summary.csv and the PNG of a finished (or partial) sweep."""
    if name == "identify":
        return fe_identification.write_outputs(spec, rows, folder)
    param = next(iter(spec.grid))
    write_csv(rows, folder / "curves.csv")
    summary = summary_rows(rows, param)
    write_csv(summary, folder / "summary.csv")
    draw_study_figure(name, param, dict(spec.fixed), dict(spec.settings), rows, folder)
    counts: dict[str, int] = {}
    for s in summary:
        counts[s["trial_status"]] = counts.get(s["trial_status"], 0) + 1
    lines = [f"{name}: {len(summary)} designs: " + ", ".join(f"{v} {k}" for k, v in counts.items())]
    lines += [
        f"  {param} = {s[param]:g}: {s['trial_status']} {s['reason']}"
        for s in summary
        if s["trial_status"] != "completed"
    ]
    written = (folder / "curves.csv", folder / "summary.csv", folder / f"{name}.png")
    ok = all(s["trial_status"] in ("completed", "failed") for s in summary)
    return StudyOutcome(tuple(lines), written, ok)


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study chamber-radius | fiber-turns | identify` (the registry's entry point)."""
    settings = study_settings(
        request.study, request.material, request.quick, request.mesh_size, request.fibers, request.simulator
    )
    return run_sweep_study(
        request.study,
        request.out,
        settings,
        storage=request.storage,
        workers=request.workers,
        progress=request.progress,
        retry=request.retry,
    )


def replot_folder(folder: Path) -> list[Path]:
    """NAME.png of a chamber-radius or fiber-turns run from its spec.json and curves.csv."""
    spec = read_spec(folder)
    name = next((n for n in ("chamber-radius", "fiber-turns") if spec.get("name", "").startswith(n)), None)
    if name is None or not (folder / "curves.csv").exists():
        return []
    param = next(iter(spec["grid"]))
    rows = read_csv(folder / "curves.csv")
    return [draw_study_figure(name, param, spec.get("fixed", {}), spec.get("settings", {}), rows, folder)]
