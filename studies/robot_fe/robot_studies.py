"""The robot-level studies of the paper as sweeps: connecting rings (Fig. 11(c)) and foot radius d.

    rings        n = 1..5 equally spaced rings; load cases "equal" (P1 = P2 = P3 = 20..100 kPa)
                 and "asymmetric" (P2 = 40 and P3 = 60 kPa first, then P1 = 20..100 kPa)
    foot-radius  d = 11..16 mm (the actuators intersect below 2 R0 / sqrt(3) = 10.4 mm plus the
                 ring's ligament; above 16 mm the rings no longer fit a 55 mm pipe), the
                 asymmetric load case

A run writes to DIR/robot-NAME/MATERIAL[-quick]/: curves.csv (every design and load step: the
outputs of `studies.robot_fe.response`), summary.csv (one row per design: the quantities the
rules of `studies.robot_fe.rules` use), decision.json (the rule's value, reason and
evidence), NAME.png and spec.json. The sweep is `studies.sweeps` (resumable; a failed design is
a row with its reason). Every evaluation also writes points/KEY.json, the table's source, so
the table never depends on the sweep store's internals.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

from softcrawl import jsonio
from softcrawl.files import write_text_atomic
from softcrawl.geometry.design import RobotDesign
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.robot_fe import rules
from softcrawl.studies.robot_fe.model import build_robot_model
from softcrawl.studies.robot_fe.plots import plot_robot_study
from softcrawl.studies.robot_fe.response import simulate_robot
from softcrawl.studies.robot_fe.rules import foot_radius_rule, ring_rule
from softcrawl.studies.sweeps.spec import Evaluation, SweepSpec, load_callable, sweep_spec_from_file
from softcrawl.studies.sweeps.sweep import run_sweep
from softcrawl.studies.sweeps.tables import write_csv
from softcrawl.units import kpa_to_mpa

EVALUATOR = "robot"  # its registry name (studies/robot_fe/study.py)
#: Load cases (kPa): the paper's Fig. 11(c) case, sequential (P2 = 40 and P3 = 60 kPa first, then
#: P1 ramped in 10 kPa targets), and equal pressures. Newton's quadratic convergence sets in late
#: on the bending robot (r_{k+1} ~ 700 r_k^2 at the quick mesh), so a segment needs small
#: sub-steps; targets 10 kPa apart keep the number of cut-backs per segment low.
LOAD_CASES_KPA = {
    "equal": [(50.0, 50.0, 50.0), (100.0, 100.0, 100.0)],
    "asymmetric": [(0.0, 20.0, 30.0), (0.0, 40.0, 60.0)] + [(10.0 * k, 40.0, 60.0) for k in range(1, 11)],
}
GRIDS = {
    "rings": ({"n_rings": (1, 2, 3, 4, 5)}, ("equal", "asymmetric")),
    "foot-radius": ({"d": (11.0, 12.0, 13.0, 14.0, 15.0, 16.0)}, ("asymmetric",)),
}


def _design(params):
    kwargs = {}
    if "n_rings" in params:
        kwargs["n_rings"] = int(params["n_rings"])
    if "d" in params:
        kwargs["d"] = float(params["d"])
    return RobotDesign(**kwargs)


def point_name(params) -> str:
    return ",".join(f"{k}={params[k]:g}" for k in sorted(params))


def run_cases(design, material: str, mesh: str, cases) -> dict:
    """The FE robot of `design` under each load case: rows (one per converged state), whether
    every case converged, the messages, the DOFs and the path time."""
    robot = build_robot_model(design, material, mesh)
    rows, ok, messages, wall = [], True, [], 0.0
    for case in cases:
        run = simulate_robot(robot, [tuple(kpa_to_mpa(p) for p in P) for P in LOAD_CASES_KPA[case]])
        wall += run.seconds
        rows += [{"case": case, "step": k} | state.row() for k, state in enumerate(run.states)]
        ok &= run.converged
        messages.append(f"{case}: {run.message}")
    return {"rows": rows, "converged": ok, "message": "; ".join(messages), "wall_s": wall,
            "n_dofs": robot.n_dofs, "material": robot.materials}  # fmt: skip


def evaluate_robot(params, fixed, settings) -> Evaluation:
    """Build the robot of the grid point and follow each load case of `settings["cases"]`
    (`settings["runner"]`, "module:function" with the signature of `run_cases`, replaces the FE
    in tests)."""
    runner = load_callable(settings["runner"], parameter="simulator") if settings.get("runner") else run_cases
    attrs = runner(_design(params), settings["material"], settings["mesh"], settings["cases"])
    folder = Path(settings["out_dir"]) / "points"
    folder.mkdir(parents=True, exist_ok=True)
    jsonio.write(folder / f"{point_name(params)}.json", {"params": dict(params)} | attrs, indent=1)
    last = [r for r in attrs["rows"] if r["case"] == settings["cases"][-1]]
    ok = bool(attrs["converged"])
    theta = last[-1]["theta_deg"] if last and ok else math.nan
    if ok and settings.get("objective"):
        attrs = attrs | rule_constraints(settings["objective"], params, attrs)
    return Evaluation(ok=ok and math.isfinite(theta), values=(theta,), attrs=attrs, message=attrs["message"])


def rule_constraints(name: str, params, attrs) -> dict:
    """What optuna's "best" means (decision 063): the objective is the bending angle theta
    at the asymmetric load, maximised, as both rules rank by it; the constraints are each rule's
    per-design test, so that a design its rule rejects is never best. rings: the actuators act as
    one body (splay and arc-fit RMS within `rules`' bounds); foot-radius: the central channel
    holds the endoscope camera. What optuna cannot see: the rules' tie-breaks (rings: no more than
    2 % loss of bending and extension goes to the fewest rings; d: 1 % ties go to the smaller d)
    compare designs, so best_trial is the rule's pick or a feasible design within that tie."""

    row = summary_row(params, attrs)
    flat = {k: row[k] for k in ("theta_asym_deg", "extension_equal_mm", "splay_max_mm", "arc_rms_max_mm")}
    names, values = design_tests(name, row)
    return flat | {"constraints": values, "constraint_names": names}


def design_tests(name: str, row) -> tuple[list[str], list[float]]:
    """The rule's per-design tests on one summary row, as optuna constraints (<= 0 passes)."""
    if name == "rings":
        values = [
            float(row["splay_max_mm"]) - rules.SPLAY_MAX_FRACTION_OF_D * 14.0,
            float(row["arc_rms_max_mm"]) - rules.ARC_RMS_MAX_FRACTION_OF_L * 100.0,
        ]
        return ["splay_within_bound", "one_arc"], [v if math.isfinite(v) else 1.0 for v in values]
    return ["camera_fits"], [0.0 if rules.channel_admits_camera(float(row["d"]), 9.0) else 1.0]


def best_trial_note(name: str, summary, value) -> str | None:
    """A line when optuna's best_trial (the largest theta among the designs that pass the
    per-design tests) is not the rule's pick, which its tie-break can make: optuna compares one
    design at a time, the tie-break compares designs (decision 063). None when they agree."""
    key = "n_rings" if name == "rings" else "d"
    passing = [
        r
        for r in summary
        if math.isfinite(float(r["theta_asym_deg"])) and max(design_tests(name, r)[1]) <= 0.0
    ]
    if value is None or not passing:
        return None
    best = max(passing, key=lambda r: float(r["theta_asym_deg"]))
    if float(best[key]) == float(value):
        return None
    return (
        f"note: optuna's best_trial is {key} = {float(best[key]):g} (the largest bending that "
        f"passes the per-design tests); the rule's tie-break prefers {key} = {float(value):g} "
        f"(decision 063)"
    )


def summary_row(params, data) -> dict:
    """One design: its parameters and the quantities the rules use (NaN where not computed)."""
    rows = data.get("rows", []) if data else []

    def final(case):  # the last state of a load case; null (strict JSON's NaN) read as NaN
        done = [r for r in rows if r["case"] == case]
        return {k: math.nan if v is None else v for k, v in done[-1].items()} if done else {}

    asym, equal = final("asymmetric"), final("equal")
    out = dict(params)
    out |= {
        "converged": data.get("converged", False) if data else False,
        "theta_asym_deg": asym.get("theta_deg", math.nan),
        "phi_asym_deg": asym.get("phi_deg", math.nan),
        "phi_cc_asym_deg": asym.get("phi_cc_deg", math.nan),
        "d_eff_asym_mm": asym.get("d_eff_mm", math.nan),
        "extension_asym_mm": asym.get("extension_mm", math.nan),
        "extension_equal_mm": equal.get("extension_mm", math.nan),
        "theta_equal_deg": equal.get("theta_deg", math.nan),
        "splay_max_mm": _largest(r.get("splay_mm") for r in rows),
        "arc_rms_max_mm": _largest(r.get("arc_rms_mm") for r in rows),
        "n_dofs": data.get("n_dofs", "") if data else "",
        "wall_s": data.get("wall_s", "") if data else "",
        "message": data.get("message", "not computed") if data else "not computed",
    }
    return out


def _largest(values) -> float:
    """The largest of the numbers among `values` (None and NaN skipped), NaN if none."""
    numbers = [float(v) for v in values if v is not None and math.isfinite(float(v))]
    return max(numbers) if numbers else math.nan


def run_robot_study(name: str, out, material: str, quick: bool, *, workers: int = 1, progress: bool = True,
                    retry: bool = False, runner: str | None = None, storage: str | None = None,
                    ) -> StudyOutcome:  # fmt: skip
    """Run (or resume) the robot study `name` and write its tables, decision and figure."""
    spec = study_spec(name, out, material, quick, runner, storage)
    run_sweep(spec, workers=workers, progress=progress, retry=retry)
    return write_tables(name, spec, material)


def point_rows(spec: SweepSpec, material: str) -> tuple[list[dict], list[dict]]:
    """(curves, summary) rows of a study from the points/ files of its folder."""
    folder = Path(spec.out_dir)
    curves, summary = [], []
    for params in spec.points():
        path = folder / "points" / f"{point_name(params)}.json"
        data = json.loads(path.read_text()) if path.exists() else None
        summary.append(summary_row(params, data))
        for row in (data or {}).get("rows", []) or [{}]:
            curves.append(dict(params) | {"material": material} | row)
    return curves, summary


def write_tables(name: str, spec: SweepSpec, material: str) -> StudyOutcome:
    """curves.csv, summary.csv, decision.json, spec.json and the figure from the points/ files of
    the study folder (the points computed so far; a missing one is a row that says so)."""
    folder = Path(spec.out_dir)
    curves, summary = point_rows(spec, material)
    written = [write_csv(curves, folder / "curves.csv"), write_csv(summary, folder / "summary.csv")]
    decision = ring_rule(summary) if name == "rings" else foot_radius_rule(summary)
    write_text_atomic(folder / "decision.json", decision.to_json() + "\n")
    jsonio.write(folder / "spec.json", spec.to_dict())
    written += [
        folder / "decision.json",
        folder / "spec.json",
        plot_robot_study(name, summary, curves, folder),
    ]
    missing = [point_name(p) for p, s in zip(spec.points(), summary) if not s["converged"]]
    lines = [f"{name} ({material}, {spec.settings['mesh']} mesh): {decision.parameter} = {decision.value}",
             decision.reason]  # fmt: skip
    note = best_trial_note(name, summary, decision.value)
    lines += [note] if note else []
    problems = tuple(f"not converged or missing: {m}" for m in missing)
    return StudyOutcome(tuple(lines), tuple(written), ok=decision.value is not None, problems=problems)


def study_spec(name: str, out, material: str, quick: bool, runner: str | None = None,
               storage: str | None = None) -> SweepSpec:  # fmt: skip
    grid, cases = GRIDS[name]
    folder = Path(out) / f"robot-{name}" / (material + ("-quick" if quick else ""))
    settings = {"material": material, "mesh": "quick" if quick else "default", "cases": list(cases),
                "out_dir": str(folder)}  # fmt: skip
    if runner:
        settings["runner"] = runner
    settings["objective"] = name  # theta maximised under the rule's constraints (`rule_constraints`)
    return SweepSpec(
        name=f"robot-{name}", grid=grid, out_dir=str(folder), evaluator=EVALUATOR, settings=settings,
        storage=storage, metric_names=("theta_asym_deg",),
    )  # fmt: skip


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study rings | foot-radius` (the registry's entry point)."""
    return run_robot_study(
        request.study, request.out, request.material, request.quick, workers=request.workers,
        progress=request.progress, retry=request.retry, runner=request.simulator, storage=request.storage,
    )  # fmt: skip


def replot_folder(folder: Path) -> list[Path]:
    """NAME.png of a rings or foot-radius run from its spec.json and points/ files."""
    spec = sweep_spec_from_file(folder)
    name = spec.name.removeprefix("robot-")
    curves, summary = point_rows(spec, spec.settings["material"])
    return [plot_robot_study(name, summary, curves, folder)]
