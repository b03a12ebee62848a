"""The design review's section on the whole robot crawling in FE (`studies.review.report`).

Reads the committed runs of `softcrawl crawl --body fe` (results/crawl-fe/*/summary.json, written
by `studies.crawl_fe.files`) and returns HTML: the folder's README (what the runs show and how they
were made), one table row per run (pipe, cycles reached, strides and speeds beside the paper's,
the turn, the body's mass, the solver's effort) and the runs' figures. No FE solve.
"""

from __future__ import annotations

import json
from pathlib import Path

from softcrawl.studies.html import esc, figure, figure_grid, markdown, missing, table

FOLDER = "crawl-fe"
STRAIGHT = "softcrawl crawl --body fe --quick --cycles 2 --time-limit 55 --out results/crawl-fe/straight-70"
#: Width of a run's figure in the page (pixels).
WIDTH = 640


def _numbers(values, spec: str = ".2f") -> str:
    return ", ".join(format(v, spec) for v in values) if values else "none"


def _seconds(values) -> str:
    """Each cycle's wall time; "not recorded" for runs (or cycles) before it was kept."""
    if not values:
        return "not recorded"
    return ", ".join("not recorded" if v is None else f"{v:.0f}" for v in values)


def run_row(name: str, s: dict) -> dict:
    pipe = s["pipe"]
    where = pipe["kind"] + (f", R {pipe['bend_radius_mm']:g} mm" if pipe["bend_radius_mm"] else "")
    if pipe.get("corrugation_mm"):  # a bellows: depth and pitch
        where += ", corrugations {:g} x {:g} mm".format(*pipe["corrugation_mm"])
    paper = s["paper_speed_mm_s"]
    v = s["solver"]
    return {
        "run": name,
        "pipe": f"{where}, {pipe['diameter_mm']:g} mm",
        # one wedge of 120 deg by the three-fold symmetry (docs/decisions/096-body-wedge.md)
        "mesh": s["mesh"] + (f", wedge 360/{s['wedge']} deg" if s.get("wedge", 1) > 1 else ""),
        "friction (smooth / grooved)": f"{s['friction']['mu_smooth']:g} / {s['friction']['mu_grooved']:g}",
        # runs before viscous slip existed were Coulomb's (docs/decisions/088-viscous-slip.md)
        "slip viscosity (MPa s/mm)": f"{s['friction'].get('slip_viscosity_mpa_s_mm', 0.0):g}",
        # runs before inertia existed were quasi-static (docs/decisions/089-inertia.md)
        "inertia": "backward Euler" if s.get("inertia") else "none (quasi-static)",
        "cycles reached / asked": f"{len(s['strides_mm'])} / {s['cycles']}",
        "strides (mm)": _numbers(s["strides_mm"]),
        "speeds (mm/s)": _numbers(s["speeds_mm_s"]),
        "paper (mm/s)": f"none: {s['paper_source']}" if paper is None else f"{paper:g} ({s['paper_source']})",
        "turns (deg)": _numbers(s["turns_deg"], "+.2f"),
        # runs before each cycle's time was kept (docs/decisions/092-cycle-time.md) have none
        "wall per cycle (s)": _seconds(s.get("cycle_wall_s")),
        "mass (g; prototype 70.2)": f"{s['mass']['total_g']:.1f}",
        "Newton iterations": v["newton_iterations"],
        "factorisations": v.get("factorizations", "not recorded"),  # runs before they were counted
        "contact assembly (of wall)": f"{v['contact_share']:.0%}" if "contact_share" in v else "not recorded",
        "wall (s)": f"{v['wall_s']:.0f}",
        "peak (GB)": f"{v['peak_rss_gb']:.2f}",
        "ended": s["message"],
    }


def crawl_fe(results: Path) -> str:
    """Every committed FE-body run (module docstring), or a note naming the command."""
    folder = Path(results) / FOLDER
    runs = {}
    for path in sorted(folder.glob("*/summary.json")):
        s = json.loads(path.read_text())
        if s.get("model") == "fe-body":
            runs[path.parent] = s
    if not runs:
        return missing("The whole robot crawling in FE", STRAIGHT)
    out = []
    if (folder / "README.md").exists():
        out.append(markdown((folder / "README.md").read_text()))
    silicone = {s["materials"]["epsa"] for s in runs.values()}
    moduli = {s["silicone_shear_modulus_mpa"] for s in runs.values()}
    out.append(
        f"<p>The body's silicone: {esc(', '.join(sorted(silicone)))} (shear modulus "
        f"{esc(', '.join(f'{m:g}' for m in sorted(moduli)))} MPa).</p>"
    )
    out.append(table([run_row(run.name, s) for run, s in runs.items()]))
    pngs = [run for run in runs if (run / "crawl.png").exists()]
    out.append(
        figure_grid([figure(run / "crawl.png", f"{FOLDER}/{run.name}/crawl.png", WIDTH) for run in pngs])
    )
    return "".join(out)
