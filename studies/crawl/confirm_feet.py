r"""The confirm stage of `softcrawl study optimise-feet --confirm N`: full crawls of the N best designs.

It lives with the crawl (the crawl imports the foot's modules, so the foot's optimiser reaches this
stage by name, `studies.foot.optimise.CONFIRM`, and no import cycle forms).

The search ranks designs by a proxy: one foot's resistances against the bundle's forces
(`studies.foot.anchoring`). The crawl (`studies.crawl`) is the whole robot: two such feet on the
prototype's axial law, cycling. So the N completed trials with the largest margin (the front's
first, `best_designs`) are crawled at 70 mm, the pipe of Fig. 21 and of the identification:

    CrawlSetup(pipe_diameter=70, foot=FootDesign(angle, skirt_thickness), material=hardness,
               mu_smooth, mu_grooved = the study's identified values, cycles=2, insert_steps=4,
               sectors = the quick foot mesh's, `geometry.foot_meshers.quick_sectors`)
    "inflate" schedule, 100 kPa, 2 s cycles (paper Section VII-D)

and each design's steady stride (the second cycle's) and speed go to confirm.csv and confirm.md in
the study's folder, beside the margin that chose it: a design whose margin is positive should
crawl (stride > 0), one whose margin is negative may still crawl where the deciding pipe is not
70 mm. A crawl that does not complete is a row with its reason. Each crawl writes its files
(states.csv, cycles.csv, summary.json; no VTU) to confirm/<design>/; a design already crawled
(its summary.json there) is read back, not crawled again.
"""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path

from softcrawl import jsonio
from softcrawl.geometry.design import FootDesign
from softcrawl.geometry.foot_meshers import quick_sectors
from softcrawl.studies.crawl.files import run_and_write
from softcrawl.studies.crawl.model import CrawlSetup
from softcrawl.studies.crawl.outputs import steady_stride
from softcrawl.studies.crawl.schedule import preset
from softcrawl.studies.foot.wedge import wedge_sectors
from softcrawl.studies.plots.style import number
from softcrawl.studies.sweeps.tables import write_csv

#: The confirm crawl's pipe (mm), cycles and wall-time budget per design (s).
CONFIRM_PIPE_MM, CONFIRM_CYCLES, CONFIRM_WALL_S = 70.0, 2, 3600.0
#: The crawl's minimum sectors (`studies.crawl.mesh.QUICK_SECTORS`, the quick crawl's feet).
MIN_SECTORS = 24


def best_designs(rows: list[dict], n: int) -> list[dict]:
    """The n completed trials with the largest margins, front members first; one per design."""
    done = [r for r in rows if r.get("trial_status") == "completed" and number(r.get("margin")) is not None]
    done.sort(key=lambda r: (str(r.get("front")) != "True", -float(r["margin"])))
    out, seen = [], set()
    for r in done:
        key = design_stem(r)
        if key not in seen:
            seen.add(key)
            out.append(r)
    return out[:n]


def design_stem(row: dict) -> str:
    return f"a{float(row['angle']):.2f}-t{float(row['skirt_thickness']):.3f}-{row['hardness']}"


def crawl_setup(row: dict, settings: dict):
    """The `CrawlSetup` of one design (module docstring): the crawl takes the foot and material."""
    design = FootDesign(angle=float(row["angle"]), skirt_thickness=float(row["skirt_thickness"]))
    copies = int(settings.get("copies", 1))  # the search's wedge (`studies.foot.wedge`)
    sectors = wedge_sectors(max(MIN_SECTORS, quick_sectors(design)), copies)
    return CrawlSetup(
        pipe_diameter=CONFIRM_PIPE_MM,
        mu_smooth=float(settings["mu_smooth"]),
        mu_grooved=float(settings["mu_grooved"]),
        insert_steps=4,
        steps=4,
        cycles=CONFIRM_CYCLES,
        max_wall_s=CONFIRM_WALL_S,
        sectors=sectors,
        copies=copies,
        foot=design,
        material=str(row["hardness"]),
    )


def run_crawl(setup, folder: Path) -> dict:
    """Crawl one setup into `folder` (`studies.crawl.files.run_and_write`) -> its row's numbers."""
    result, summary = run_and_write(setup, preset("inflate", 100.0, 2.0), folder, quick=True, vtu=False)
    return {
        "converged": result.converged,
        "message": result.message,
        "strides_mm": ";".join(f"{s:.4f}" for s in result.strides),
        "steady_stride_mm": steady_stride(result),
        "speed_mm_s": summary["comparison"]["speed_mm_s"],
        "wall_s": result.wall_s,
    }


def confirm_best(folder: Path, rows: list[dict], settings: dict, n: int,
                 crawl: Callable[[object, Path], dict] = run_crawl) -> list[dict]:  # fmt: skip
    """Crawl the n best designs of a run (module docstring); writes confirm.csv and confirm.md."""
    folder = Path(folder)
    out = []
    for r in best_designs(rows, n):
        stem = design_stem(r)
        target = folder / "confirm" / stem
        done = target / "confirm.json"
        if done.exists():
            numbers = json.loads(done.read_text())
        else:
            try:
                numbers = crawl(crawl_setup(r, settings), target)
            except Exception as exc:  # noqa: BLE001 - one design's failure is its row, not the stage's end
                numbers = {"converged": False, "message": f"{type(exc).__name__}: {exc}"}
            target.mkdir(parents=True, exist_ok=True)
            done.write_text(jsonio.dumps(numbers, indent=1) + "\n")  # a NaN speed is null
        keep = ("trial", "angle", "skirt_thickness", "hardness", "margin", "mass_g", "front")
        out.append({k: r.get(k, "") for k in keep} | {"pipe_mm": CONFIRM_PIPE_MM} | numbers)
    write_csv(out, folder / "confirm.csv")
    (folder / "confirm.md").write_text("\n".join(confirm_lines(out, settings)) + "\n")
    return out


def confirm_lines(rows: list[dict], settings: dict) -> list[str]:
    lines = [
        f"# optimise-feet: the best designs crawled at {CONFIRM_PIPE_MM:g} mm",
        "",
        f"{CONFIRM_CYCLES} cycles of the inflate schedule (100 kPa, 2 s), quick feet, mu_smooth = "
        f"{settings.get('mu_smooth')} ({settings.get('mu_smooth_flag')}), mu_grooved = "
        f"{settings.get('mu_grooved')}.",
        "",
        "| design (angle, skirt, hardness) | margin | mass (g) | strides (mm) | steady speed (mm/s) | note |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:
        speed = number(r.get("speed_mm_s"))
        ok = r.get("converged") in (True, "True")
        lines.append(
            f"| {float(r['angle']):.1f} deg, {float(r['skirt_thickness']):.2f} mm, {r['hardness']} | "
            f"{float(r['margin']):+.3f} | {float(r['mass_g']):.2f} | {r.get('strides_mm', '')} | "
            f"{'' if speed is None else f'{speed:.3f}'} | {'' if ok else r.get('message', '')} |"
        )
    return lines
