"""The robot-level sections of the design review (`studies.review.report`): the tied robot at the
Fig. 11 load, its FE workspace against the constant-curvature model, and the crawl in a pipe.

Each function reads committed results only (no FE solve) and returns HTML, or a note naming the
command that makes what is missing. The crawl table takes its figures from each run's
`summary.json` (`studies.crawl.files`): the stride of the first cycle, its speed at the
schedule's cycle time, and the two references the run itself recorded (Table 2 and the analytic
`analytic.loads.crawl_speed`).
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl.geometry.foot_revolved import N_THETA, THICKNESS_LAYERS
from softcrawl.studies.html import csv_rows, esc, figure, figure_grid, markdown, missing, table

#: Width of the crawl's figures in the page (pixels): three to a row.
GRID_WIDTH = 640

ROBOT_TABLE1 = "softcrawl robot --mesh quick --first 0,40,60 --pressures 100,40,60 --out results/robot-table1"
WORKSPACE = 'softcrawl study workspace --quick --material "ecoflex-00-50@mu=0.0638" --out results/'
CRAWL = (
    "softcrawl crawl --cycles 2 --mu-smooth 0.3 --mu-grooved 0.3 --out results/crawl/forward-70-mu0.3-2cycles"
)


def _last_row(path: Path) -> dict | None:
    rows = csv_rows(path)
    return rows[-1] if rows else None


def robot(results: Path) -> str:
    """The Table 1 robot at P = (100, 40, 60) kPa and the FE-vs-CC workspace."""
    out = []
    folder = results / "robot-table1"
    if (folder / "states.csv").exists():
        out.append(f"<p>Command: <code>{esc(ROBOT_TABLE1)}</code></p>")
        if (folder / "robot.png").exists():
            out.append(figure(folder / "robot.png", "robot-table1/robot.png"))
        last = _last_row(folder / "states.csv")
        if last:
            out.append("<p>Last converged state:</p>" + table([last]))
    else:
        out.append(missing("The Table 1 robot run", ROBOT_TABLE1))
    runs = sorted((results / "robot-workspace").glob("*/summary.json"))
    if not runs:
        out.append(missing("The FE workspace against the constant-curvature model", WORKSPACE))
    for path in runs:
        s = json.loads(path.read_text())
        name = path.parent.name
        out.append(f"<h3>Workspace: {esc(name)}</h3>")
        if s.get("partial"):
            out.append("<p><b>Partial</b>: the run stopped before the whole grid converged.</p>")
        rows = [
            {"quantity": k, "value": s[k]}
            for k in sorted(s)
            if isinstance(s[k], (int, float)) and not isinstance(s[k], bool)
        ]
        out.append(table(rows))
        for problem in s.get("problems", []):
            out.append(f"<p>Problem: {esc(problem)}</p>")
        if (path.parent / "workspace.png").exists():
            out.append(figure(path.parent / "workspace.png", f"robot-workspace/{name}/workspace.png"))
    return "".join(out)


def feet_mesh(setup: dict) -> str:
    """The feet's mesh of a crawl run's setup; runs from before the mesher field were pytetwild's."""
    if setup.get("mesher", "tetwild") == "tetwild":
        edge = setup.get("edge_length")
        return "pytetwild" + (f", {edge:g} mm edge" if edge else "")
    sectors, layers = setup.get("sectors") or N_THETA, setup.get("thickness_layers") or THICKNESS_LAYERS
    return f"revolved, {sectors} sectors, {layers} cells"


def _crawl_row(folder: Path, summary: dict) -> dict:
    setup, comparison = summary.get("setup", {}), summary.get("comparison", {})
    return {
        "run": folder.name,
        "pipe (mm)": setup.get("pipe_diameter"),
        "feet": setup.get("feet"),
        "feet mesh": feet_mesh(setup),
        "mu smooth / grooved": f"{setup.get('mu_smooth')} / {setup.get('mu_grooved')}",
        "schedule": summary.get("schedule", {}).get("name"),
        "cycles done": len(summary.get("cycles", [])),
        "stride (mm)": comparison.get("stride_mm"),
        "speed (mm/s)": comparison.get("speed_mm_s"),
        "Table 2 (mm/s)": comparison.get("table2_mm_s"),
        "analytic (mm/s)": comparison.get("analytic_fe_friction_mm_s"),
        "ended": summary.get("message"),
    }


def crawl(results: Path) -> str:
    """Every committed crawl run (one row each), its figure, and the crawl study when present."""
    folder = results / "crawl"
    summaries = {p.parent: json.loads(p.read_text()) for p in sorted(folder.glob("*/summary.json"))}
    runs = {run: s for run, s in summaries.items() if "setup" in s}  # a crawl run, not a study
    if not runs:
        return missing("The crawl in FE", CRAWL)
    out = []
    if (folder / "README.md").exists():
        out.append(markdown((folder / "README.md").read_text()))
    out.append(table([_crawl_row(run, summary) for run, summary in runs.items()]))
    out.append(
        figure_grid(
            [
                figure(run / "crawl.png", f"crawl/{run.name}/crawl.png", GRID_WIDTH)
                for run in runs
                if (run / "crawl.png").exists()
            ]
        )
    )
    for study in sorted(folder.glob("*/summary.csv")):
        out.append(f"<h3>Crawl study: {esc(study.parent.name)}</h3>" + table(csv_rows(study)))
        pngs = sorted(study.parent.glob("*.png"))
        out.append(
            figure_grid([figure(png, f"crawl/{study.parent.name}/{png.name}", GRID_WIDTH) for png in pngs])
        )
    return "".join(out)
