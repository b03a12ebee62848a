r"""Running the foot studies (`studies.foot.contact_studies`) and writing their outputs.

A run writes to DIR/NAME/MATERIAL[-quick]/: spec.json, points/*.json (one full result per grid
point, written by the evaluator), summary.csv (one row per grid point: the sweep's status and
failure reason, then the result's scalars), curves.csv (every increment of every drag), NAME.png,
groove-rule.md (the Table 1 groove-height decision, `studies.foot.groove_rule`), vtu/ (the
pressed/inserted state and a .pvd series of every drag), and the SQLite study.db without --storage. Running
the same command again resumes: only missing points are computed.
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl import jsonio
from softcrawl.studies.declaration import StudyRequest
from softcrawl.studies.foot import groove_rule
from softcrawl.studies.foot.contact_studies import (
    DEFAULT_MATERIAL,
    EVALUATORS,
    FOOT,
    FOOT_FRICTION,
    FOOT_MESHER,
    GRIDS,
    GROOVE,
    OBJECTIVES,
    QUICK_GRIDS,
    point_file,
)
from softcrawl.studies.foot.plots import plot_foot, plot_groove
from softcrawl.studies.outcome import StudyOutcome
from softcrawl.studies.sweeps.spec import SweepSpec, sweep_spec_from_file
from softcrawl.studies.sweeps.sweep import run_sweep
from softcrawl.studies.sweeps.tables import write_csv


def study_folder(out, name: str, material: str, quick: bool) -> Path:
    return Path(out) / name / (material + ("-quick" if quick else ""))


def contact_spec(name: str, folder: Path, material: str, quick: bool, storage=None):
    settings = {
        "material": material,
        "quick": bool(quick),
        "out_dir": str(folder),
        "vtu_dir": str(folder / "vtu"),
        "pressure_kpa": 100.0,
    }
    if name == FOOT:
        settings |= dict(FOOT_FRICTION) | {"angle": 120.0, "mesher": FOOT_MESHER}
    if quick and name == GROOVE:
        settings["drag_steps"] = 10
    if quick and name == FOOT:
        settings |= {"drag_mm": 5.0, "drag_steps": 5}
    grid = (QUICK_GRIDS if quick else GRIDS)[name]
    if name == GROOVE:  # the rule's "at every mu": each trial checks the grid's other mus
        settings["rule_mus"] = list(grid["mu"])
    tag = material + ("-quick" if quick else "")
    metric, direction = OBJECTIVES[name]
    return SweepSpec(
        name=f"{name}-{tag}",
        grid=grid,
        out_dir=str(folder),
        evaluator=EVALUATORS[name],
        settings=settings | {"objective": name},
        storage=storage,
        directions=(direction,),
        metric_names=(metric,),
    )


def run_contact_study(
    name: str,
    out,
    *,
    material: str | None = None,
    quick: bool = False,
    storage: str | None = None,
    workers: int = 1,
    progress: bool = True,
    retry: bool = False,
) -> StudyOutcome:
    material = material or DEFAULT_MATERIAL
    folder = study_folder(out, name, material, quick)
    folder.mkdir(parents=True, exist_ok=True)
    spec = contact_spec(name, folder, material, quick, storage)
    jsonio.write(folder / "spec.json", spec.to_dict())
    rows = run_sweep(spec, workers=workers, progress=progress, retry=retry)
    return write_contact_outputs(name, spec, rows, folder)


def _status(rows, params) -> tuple[str, str]:
    for row in rows:
        if all(str(row.get(k)) == str(v) or _same(row.get(k), v) for k, v in params.items()):
            return str(row.get("trial_status", "")), str(row.get("reason", ""))
    return "missing", ""


def _same(a, b) -> bool:
    try:
        return abs(float(a) - float(b)) < 1e-12
    except (TypeError, ValueError):
        return False


def load_points(spec, rows) -> list[dict]:
    """One record per grid point: params, sweep status and reason, and the stored result (if any)."""
    out = []
    for params in spec.points():
        status, reason = _status(rows, params)
        path = point_file(spec.out_dir, spec.name.split("-")[0], params)
        data = json.loads(path.read_text()) if path.exists() else {}
        if status == "missing" and data:  # a stored result the sweep has not reported (yet)
            stored = data.get("summary", {})
            done = stored.get("converged") and stored.get("flipped_converged", True)
            status, reason = (
                ("completed", "") if done else ("failed", data.get("summary", {}).get("message", ""))
            )
        out.append({"params": params, "status": status, "reason": reason} | data)
    return out


def write_contact_outputs(name: str, spec, rows, folder: Path) -> StudyOutcome:
    points = load_points(spec, rows)
    summary = [
        p["params"] | {"trial_status": p["status"], "reason": p["reason"]} | p.get("summary", {})
        for p in points
    ]
    curves = []
    for p in points:
        for label, curve in (p.get("curves") or {"": p.get("curve", {})}).items():
            keys = [k for k, v in curve.items() if isinstance(v, list)]
            for i in range(len(curve.get("drag_mm", []))):
                row = p["params"] | ({"direction": label} if label else {})
                curves.append(row | {k: curve[k][i] for k in keys})
    written = [write_csv(summary, folder / "summary.csv"), write_csv(curves, folder / "curves.csv")]
    plot = plot_groove if name == GROOVE else plot_foot
    written.append(plot(points, folder / f"{name}.png", spec.settings))
    lines = _report_lines(name, summary)
    if name == GROOVE:
        decision = groove_rule.decide(summary)
        rule_md = folder / "groove-rule.md"
        text = groove_rule.markdown(decision, Path(folder.name) / "summary.csv")
        rule_md.write_text("\n".join(text) + "\n")
        written.append(rule_md)
        lines.append(f"Table 1 groove height: {decision.value} mm ({decision.status}): {decision.reason}")
    failed = [s for s in summary if s["trial_status"] != "completed"]
    problems = tuple(
        f"{name} {', '.join(f'{k} = {s[k]:g}' for k in spec.grid)}: {s['trial_status']}: "
        f"{s.get('reason') or s.get('message', '')}"
        for s in failed
    )
    return StudyOutcome(tuple(lines), tuple(written), not failed, problems)


def _fmt(s, key, spec=".3g") -> str:
    value = s.get(key)
    try:
        return format(float(value), spec)
    except (TypeError, ValueError):
        return "-"


def _report_lines(name: str, summary) -> list[str]:
    lines = []
    for s in summary:
        if name == GROOVE:
            lines.append(
                f"h = {s['groove_height']:g} mm, mu = {s['mu']:g}: {s['trial_status']}; "
                f"N = {_fmt(s, 'normal_force_n', '.4g')} N "
                f"(p A error {_fmt(s, 'normal_force_error', '.1e')}), "
                f"plateau / mu N = {_fmt(s, 'plateau_over_mu_n', '.4f')}, von Mises p99 = "
                f"{_fmt(s, 'von_mises_mpa_p99')} MPa, deformation = {_fmt(s, 'deformation_max_mm')} mm"
            )
        else:
            lines.append(
                f"D = {s['pipe_diameter']:g} mm: {s['trial_status']}; N = {_fmt(s, 'normal_force_n')} N, "
                f"F_fwd = {_fmt(s, 'f_fwd_n')} N, F_bwd = {_fmt(s, 'f_bwd_n')} N, "
                f"F_bwd / F_fwd = {_fmt(s, 'ratio_bwd_fwd')}, flipped (backward) at "
                f"{_fmt(s, 'flipped_bwd_at_mm')} mm"
                + "".join(
                    f", limit point ({d}) at {s[k]:.3g} mm: a lower bound"
                    for d, k in (("forward", "limit_fwd_at_mm"), ("backward", "limit_bwd_at_mm"))
                    if s.get(k) is not None
                )
                + (
                    f"; flipped foot (backward crawl): N = {_fmt(s, 'flipped_normal_force_n')} N, "
                    f"of which the grooved face {_fmt(s, 'flipped_normal_grooved_n')} N, F_bwd (sliding) = "
                    f"{_fmt(s, 'flipped_f_bwd_n')} N, F_fwd (anchoring) = {_fmt(s, 'flipped_f_fwd_n')} N"
                    if "flipped_normal_force_n" in s
                    else ""
                )
            )
    return lines


def rebuild_outputs(name: str, folder) -> StudyOutcome:
    """Tables and plot of a run from its spec.json and stored point results alone (a run that
    was stopped: the points it finished count by their own converged flag)."""
    folder = Path(folder)
    return write_contact_outputs(name, sweep_spec_from_file(folder), [], folder)


def run_request(request: StudyRequest) -> StudyOutcome:
    """`softcrawl study groove | foot` (the registry's entry point)."""
    return run_contact_study(
        request.study,
        request.out,
        material=request.material,
        quick=request.quick,
        storage=request.storage,
        workers=request.workers,
        progress=request.progress,
        retry=request.retry,
    )


def replot_folder(folder: Path) -> list[Path]:
    """groove.png or foot.png of a run from its spec.json and stored point results."""
    spec = sweep_spec_from_file(folder)
    name = GROOVE if spec.name.startswith(GROOVE) else FOOT
    plot = plot_groove if name == GROOVE else plot_foot
    return [plot(load_points(spec, []), Path(folder) / f"{name}.png", spec.settings)]
